"""Exact numbers as floats and every number as text: the one home for both.

Every number rprpr prints goes through this module, so that the same value always reads
the same way and two different values never read alike where it matters:

* ``number(v)``       a float for people: 6 significant digits (``digits`` to change;
                      ``CELL`` digits in a table cell or a summary);
* ``distinct(vs)``    several floats, each with as many digits as it takes to tell the
                      different ones apart (6, 10 or 17 significant digits);
* ``labels(vs)``      the same, as a mapping value -> text (the instants of one task);
* ``fixed(v)``        a float with a fixed number of decimals (durations of a run);
* ``with_unit(v, u)`` a small quantity with an SI prefix (``0.0023`` s: ``2.3 ms``);
* ``round_trip(v)``   a float for machines: the shortest text that reads back as ``v``;
* ``apart(v, m)``     a value and the margin it is compared against, told apart;
* ``rational(q)``     an exact rational: a decimal when it is one, else p/q;
* ``to_float(q)``     the double nearest an exact rational;
* ``exact_number(v)`` an exact value (a rational, or a narrow ball) like ``number``, also
                      where its double would mislead (beyond the double range).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Iterable, Sequence

from flint import arb, ctx, fmpq, fmpq_poly

DIGITS = 6  # significant digits of a number in a message
CELL = 4  # ... in a table cell or a summary figure, where width matters more
_WIDER = (6, 10, 17)  # ... widened to these where two values would otherwise read alike
_LONG = 60  # characters beyond which an exact rational is abbreviated


def to_float(q: fmpq) -> float:
    """The double nearest the rational q (correctly rounded); ±inf beyond the double range."""
    try:
        return int(q.p) / int(q.q)
    except OverflowError:  # the sign from q itself: int(q.p) may be too large for a float
        return math.inf if q > 0 else -math.inf


def number(v: float, digits: int = DIGITS, toward: int = 0, shift: int = 0) -> str:
    """``v`` with ``digits`` significant digits (Python's ``g`` format): the nearest, or
    rounded outward, up (``toward`` = 1: a printed upper bound never below the bound's
    exact value) or down (-1); with ``shift``, of v·10^shift (exactly: 1.5e-3 s in ms)."""
    return _rounded(v, shift, digits, toward)


def _rounded(v: float, shift: int, digits: int, toward: int) -> str:
    """``v`` · 10^``shift`` with ``digits`` significant digits: nearest (``toward`` 0),
    up (1) or down (-1), from the exact binary value of ``v``."""
    if not toward or not math.isfinite(v) or v == 0:
        return f"{(v * 10.0**shift if shift else v):.{digits}g}"
    from decimal import ROUND_CEILING, ROUND_FLOOR, Decimal, localcontext

    with localcontext() as c:
        c.prec = 1000
        exact = Decimal(v).scaleb(shift)
        step = Decimal(1).scaleb(exact.adjusted() - digits + 1)
        r = exact.quantize(step, rounding=ROUND_CEILING if toward > 0 else ROUND_FLOOR)
    return f"{float(r):.{digits}g}"


def distinct(values: Sequence[float], digits: int = DIGITS) -> list[str]:
    """The values with ``digits`` significant digits, or more (10, then 17) where two
    different values would otherwise read alike (all widened together, so that a column
    stays uniform)."""
    texts = [number(v, digits) for v in values]
    for wider in (digits, *(d for d in _WIDER if d > digits)):
        texts = [number(v, wider) for v in values]
        if len(set(texts)) == len(set(values)):
            break
    return texts


def outward(lo: float, hi: float, digits: int = DIGITS) -> tuple[str, str]:
    """A proven interval [lo, hi] as text: ``lo`` rounded down, ``hi`` up, with ``digits``
    significant digits or more (10, then 17) where the two would otherwise read alike."""
    for wider in (digits, *(d for d in _WIDER if d > digits)):
        a, b = number(lo, wider, -1), number(hi, wider, 1)
        if a != b or lo == hi:
            break
    return a, b


def labels(values: Iterable[float]) -> dict[float, str]:
    """Each of ``values`` -> its text, all told apart together (``distinct``): give it
    every instant of a task, so that one instant reads the same in every line."""
    vs = list(values)
    return dict(zip(vs, distinct(vs), strict=True))


def fixed(v: float, places: int = 3) -> str:
    """``v`` with ``places`` decimals (a duration in seconds: ``0.004``)."""
    return f"{v:.{places}f}"


_PREFIXES = ((1.0, ""), (1e-3, "m"), (1e-6, "µ"), (1e-9, "n"), (1e-12, "p"))


def with_unit(v: float, unit: str, digits: int = CELL, toward: int = 0) -> str:
    """``v`` [``unit``] with ``digits`` significant digits and the SI prefix (none, m, µ,
    n, p) that brings it to 1 or more: ``with_unit(0.0023, "s")`` is ``2.3 ms``; 0, a
    value of 1 or more, and one below a pico-unit keep the plain unit. ``toward`` as
    ``number``'s (an upper bound printed up)."""
    for k, (scale, prefix) in enumerate(_PREFIXES):
        text = _rounded(v, 3 * k, digits, toward) if toward else number(v / scale, digits)
        if abs(float(text)) >= 1:  # as printed: 0.9999999 s is "1 s", not "1000 ms"
            return f"{text} {prefix}{unit}"
    return f"{number(v, digits, toward)} {unit}"


def round_trip(v: float) -> str:
    """The shortest text that reads back as exactly ``v`` (Python's ``repr``; ``nan``,
    ``inf`` as such): data files, where every digit counts and none is invented."""
    return repr(float(v))


def apart(value: float, margin: float) -> tuple[str, str]:
    """``value`` and ``margin`` for a message, with enough digits to tell them apart
    (equal as doubles: both plainly)."""
    for digits in _WIDER:
        a, b = number(value, digits), number(margin, digits)
        if a != b:
            return a, b
    return number(value), number(margin)


def rational(v: fmpq) -> str:
    """An exact rational for messages: as a decimal when it is one (and prints exactly in
    at most 15 digits), else p/q; one of thousands of digits is abbreviated."""
    d = int(v.q)
    while d % 2 == 0:
        d //= 2
    while d % 5 == 0:
        d //= 5
    if d == 1:
        s = number(to_float(v), 15)
        if "e" not in s and "inf" not in s and fmpq(*_decimal_fraction(s)) == v:
            return s
    text = str(v)
    if len(text) > _LONG:  # an exact rational of thousands of digits helps nobody
        return f"{_approximately(v)} (≈; exactly a rational of {len(text)} characters)"
    return text


def _approximately(v: fmpq) -> str:
    """``v`` with 17 significant digits: its double where that is a normal one, else
    (beyond the double range, or subnormal) the same digits computed exactly."""
    return exact_number(v, 17)


def _scientific(v: fmpq, digits: int) -> str:
    """Nonzero ``v`` rounded to ``digits`` significant digits, as ``1.2345e+400``: exact
    integer arithmetic (neither a double nor a digit string of ``v`` is ever formed)."""
    p, q = abs(int(v.p)), int(v.q)
    # 10^e <= p/q < 10^(e + 1); the estimate from bit lengths is off by at most one
    e = math.floor((p.bit_length() - q.bit_length()) * math.log10(2))
    while _scaled(p, q, -e) < 1:
        e -= 1
    while _scaled(p, q, -e - 1) >= 1:
        e += 1
    m = _scaled(p, q, digits - 1 - e)
    rounded = int(m) + (1 if m - int(m) >= fmpq(1, 2) else 0)  # half up
    if rounded == 10**digits:  # 9.99...95 rounds up to the next power of ten
        rounded, e = rounded // 10, e + 1
    mantissa = str(rounded)
    mantissa = (mantissa[0] + "." + mantissa[1:]).rstrip("0").rstrip(".")
    return f"{'-' if v < 0 else ''}{mantissa}e{'+' if e >= 0 else '-'}{abs(e):02d}"


def _scaled(p: int, q: int, k: int) -> fmpq:
    """(p / q) * 10^k, exactly."""
    return fmpq(p * 10**k, q) if k >= 0 else fmpq(p, q * 10**-k)


def _decimal_fraction(s: str) -> tuple[int, int]:
    """A plain decimal text (no exponent) as numerator and denominator."""
    sign = -1 if s.startswith("-") else 1
    whole, _, frac = s.lstrip("+-").partition(".")
    return sign * int(whole + frac or "0"), 10 ** len(frac)


def faithful(v: float, zero: bool) -> bool:
    """The double ``v`` stands for its exact value (``zero``: that value is exactly 0): it is
    finite, and a normal double unless the value is 0. Beyond the double range the value
    overflows to ±inf or underflows to 0 or a subnormal double of few digits."""
    if zero:
        return v == 0
    return math.isfinite(v) and abs(v) >= sys.float_info.min


def exact_number(v: fmpq | arb, digits: int = DIGITS) -> str:
    """``number`` of an exact value: a rational, or a ball that holds it to ``digits``
    digits; where its double is not faithful (beyond the double range), the digits come
    from the exact value instead (``_scientific``; for a ball, its midpoint's):
    ``1.41421e+400``."""
    if isinstance(v, arb):
        f, zero = float(v.mid()), v.is_zero()
    else:
        f, zero = to_float(v), v == 0
    if faithful(f, zero):
        return number(f, digits)
    if not isinstance(v, arb):
        return _scientific(v, digits)
    old = ctx.prec
    ctx.prec = 4 * digits + 16
    try:
        mantissa, _, exponent = v.str(digits, radius=False).partition("e")
    finally:
        ctx.prec = old
    if "." in mantissa:
        mantissa = mantissa.rstrip("0").rstrip(".")
    return f"{mantissa}e{exponent}" if exponent else mantissa


def exact_apart(value: fmpq | arb, margin: fmpq | arb) -> tuple[str, str]:
    """``apart`` of exact values (``exact_number``): a value and its margin told apart."""
    for digits in _WIDER:
        a, b = exact_number(value, digits), exact_number(margin, digits)
        if a != b:
            return a, b
    return exact_number(value), exact_number(margin)


def polynomial(p: fmpq_poly, var: str) -> str:
    """An exact polynomial in ``var`` as the task file writes it (and the loader reads it
    back exactly): 3/2*t^2 - t + 1."""
    terms: list[str] = []
    for k in range(p.degree(), -1, -1):
        c = p[k]
        if c == 0:
            continue
        sign = "-" if c < 0 else "+"
        a = abs(c)
        power = "" if k == 0 else (var if k == 1 else f"{var}^{k}")
        body = (
            rational_text(a) if not power else (power if a == 1 else f"{rational_text(a)}*{power}")
        )
        terms.append(f"{sign} {body}")
    if not terms:
        return "0"
    text = " ".join(terms)
    return text[2:] if text.startswith("+ ") else "-" + text[2:]


def rational_text(q: fmpq) -> str:
    """An exact rational as a task file writes it: 3, -1/20."""
    return str(q.p) if q.q == 1 else f"{q.p}/{q.q}"

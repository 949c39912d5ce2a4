"""Truncated power series in ε = t - t_s, exact or in floating point.

The audit expands every quantity of the paper about a singular instant t_s. t_s is a
real root of y(t), an algebraic number: exactly, the coefficients live in the number
field K = Q[t]/(f) of the irreducible factor f of y(t) that vanishes at t_s, and an
element of K is zero exactly when its reduced representative is the zero polynomial.
``KElem`` is such an element; when t_s is rational, K = Q and the coefficients are plain
``fmpq`` (several times faster). ``Series`` works over either, with the formulas of
``dynamics``; the ball expansions near t_s (``zones``) run the same formulas on flint's
``arb`` series.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from operator import add as _add
from operator import mul as _mul
from operator import sub as _sub
from operator import truediv as _truediv
from typing import Any

from flint import arb, arb_poly, ctx, fmpq, fmpq_poly, fmpq_series

from ...model.numbers import to_float


class KElem:
    """An element of K = Q[t]/(f), f irreducible over Q; ``root`` is the arb ball of t_s."""

    __slots__ = ("field", "p")

    def __init__(self, p: fmpq_poly, field: NumberField) -> None:
        self.p = p
        self.field = field

    def _wrap(self, p: fmpq_poly) -> KElem:
        return KElem(p % self.field.f if p.degree() >= self.field.degree else p, self.field)

    def _other(self, o: Any) -> fmpq_poly:
        return o.p if isinstance(o, KElem) else fmpq_poly([o])

    def __add__(self, o: Any) -> KElem:
        return KElem(self.p + self._other(o), self.field)

    __radd__ = __add__

    def __sub__(self, o: Any) -> KElem:
        return KElem(self.p - self._other(o), self.field)

    def __rsub__(self, o: Any) -> KElem:
        return KElem(self._other(o) - self.p, self.field)

    def __neg__(self) -> KElem:
        return KElem(-self.p, self.field)

    def __mul__(self, o: Any) -> KElem:
        if isinstance(o, KElem):
            return self._wrap(self.p * o.p)
        return KElem(self.p * o, self.field)

    __rmul__ = __mul__

    def inverse(self) -> KElem:
        if self.p.is_zero():
            raise ZeroDivisionError("division by zero in K")
        g, s, _ = self.p.xgcd(self.field.f)  # s p + _ f = g, a nonzero constant
        return KElem(s / g[0], self.field)

    def __truediv__(self, o: Any) -> KElem:
        if isinstance(o, KElem):
            return self * o.inverse()
        return KElem(self.p / o, self.field)

    def __rtruediv__(self, o: Any) -> KElem:
        return self.inverse() * o

    def is_zero(self) -> bool:
        return self.p.is_zero()

    def ball(self) -> arb:
        """An arb ball containing the value at t_s (current working precision)."""
        return self.field.evaluate(self.p)

    def sign(self) -> int:
        """-1, 0 or 1, certified: the root is refined until the ball excludes zero."""
        return self.field.sign(self.p)

    def __float__(self) -> float:
        return self.field.to_float(self.p)


def accurate(value: Callable[[int], arb], bits: int = 56) -> arb:
    """value(prec), a ball computed at the working precision prec, with ``bits`` bits of
    relative accuracy or more: prec = bits + 8, doubled up to 4096 bits (then whatever
    that gives). Cancellation (an expanded polynomial where its value is small, an
    algebraic number's polynomial) is what the doubling pays for."""
    old = ctx.prec
    prec = bits + 8
    try:
        while True:
            ctx.prec = prec
            v = value(prec)
            if v.rel_accuracy_bits() >= bits or prec > 4096:
                return v
            prec *= 2
    finally:
        ctx.prec = old


class NumberField:
    """K = Q[t]/(f) with a certified isolating ball ``root`` for one real root t_s of f."""

    def __init__(self, f: fmpq_poly, root_at: Callable[[int], arb]) -> None:
        self.f = f
        self.degree = f.degree()
        self._root_at = root_at  # precision in bits -> arb ball of t_s

    def elem(self, p: fmpq_poly | fmpq | int) -> KElem:
        p = p if isinstance(p, fmpq_poly) else fmpq_poly([p])
        return KElem(p % self.f if p.degree() >= self.degree else p, self)

    def evaluate(self, p: fmpq_poly, prec: int = 128) -> arb:
        old = ctx.prec
        ctx.prec = prec
        try:
            if p.degree() <= 0:
                return arb(p[0])
            return arb_poly(p.coeffs())(self._root_at(prec))
        finally:
            ctx.prec = old

    def sign(self, p: fmpq_poly) -> int:
        if p.is_zero():
            return 0
        if p.degree() == 0:
            return 1 if p[0] > 0 else -1
        prec = 64
        while True:
            v = self.evaluate(p, prec)
            if v > 0:
                return 1
            if v < 0:
                return -1
            prec *= 2  # p(t_s) != 0 since p is nonzero of degree < deg f and f irreducible

    def accurate(self, p: fmpq_poly, bits: int = 56) -> arb:
        """p(t_s) as a ball of ``bits`` bits of relative accuracy or more (precision
        doubled up to 4096 bits; then whatever that gives)."""
        if p.is_zero():
            return arb(0)
        if p.degree() == 0:
            old = ctx.prec
            ctx.prec = bits + 8
            try:
                return arb(p[0])
            finally:
                ctx.prec = old
        return accurate(lambda prec: self.evaluate(p, prec), bits)

    def to_float(self, p: fmpq_poly) -> float:
        """p(t_s) as a double (±inf beyond the double range)."""
        if p.degree() == 0:
            return to_float(p[0])
        return float(self.accurate(p).mid())


Scalar = Any  # KElem or fmpq


class Series:
    """A power series c_0 + c_1 ε + ... truncated after ``len(c)`` terms.

    Its inverse is kept once made: the formulas divide by the same series several times,
    and an inverse in K costs an extended gcd whose numbers grow like a resultant's."""

    __slots__ = ("_head_inverse", "_inverse", "_square_of", "c")

    def __init__(self, c: Sequence[Scalar]) -> None:
        self.c = list(c)
        self._inverse: Series | None = None
        self._head_inverse: Scalar | None = None  # 1/c_0, when already known
        self._square_of: Series | None = None  # self = r * r: then 1/self = (1/r)^2

    def __len__(self) -> int:
        return len(self.c)

    def _co(self, o: Any) -> Series:
        if isinstance(o, Series):
            return o
        return Series([o] + [self.c[0] * 0] * (len(self.c) - 1))

    def __add__(self, o: Any) -> Series:
        if isinstance(o, QSeries):  # its own reflected operation
            return NotImplemented
        o = self._co(o)
        n = min(len(self), len(o))
        return Series([self.c[i] + o.c[i] for i in range(n)])

    __radd__ = __add__

    def __sub__(self, o: Any) -> Series:
        if isinstance(o, QSeries):  # its own reflected operation
            return NotImplemented
        o = self._co(o)
        n = min(len(self), len(o))
        return Series([self.c[i] - o.c[i] for i in range(n)])

    def __rsub__(self, o: Any) -> Series:
        return self._co(o) - self

    def __neg__(self) -> Series:
        return Series([-a for a in self.c])

    def __mul__(self, o: Any) -> Series:
        if isinstance(o, QSeries):  # its own reflected operation
            return NotImplemented
        if not isinstance(o, Series):
            return Series([a * o for a in self.c])
        n = min(len(self), len(o))
        a, b = self.c, o.c
        field = _one_field(a, b, n)
        if field is not None:  # in K: each coefficient reduced once (``_k_dot``)
            ap = [x.p for x in a[:n]]
            bp = ap if b is a else [x.p for x in b[:n]]
            product = Series([KElem(_k_dot(ap, bp, k, field), field) for k in range(n)])
        else:
            product = Series([_dot(a, b, k) for k in range(n)])
        if o is self:
            product._square_of = self
        return product

    __rmul__ = __mul__

    def inverse(self) -> Series:
        """1/self; the constant term must be nonzero."""
        if self._inverse is None:
            self._inverse = self._invert()
        return self._inverse

    def _invert(self) -> Series:
        if self._square_of is not None:  # exact: truncation commutes with products
            r = self._square_of.inverse()
            return r * r
        a = self.c
        b0 = 1 / a[0] if self._head_inverse is None else self._head_inverse
        field = _one_field(a, [b0], len(a))
        if field is not None:  # in K: each sum reduced once, as in ``__mul__``
            return Series(_k_invert([x.p for x in a], b0, field))
        b = [b0]
        for k in range(1, len(a)):
            acc = a[1] * b[k - 1]
            for i in range(2, k + 1):
                acc = acc + a[i] * b[k - i]
            b.append(-(acc * b0))
        return Series(b)

    def __truediv__(self, o: Any) -> Series:
        if isinstance(o, QSeries):  # its own reflected operation
            return NotImplemented
        if isinstance(o, Series):
            return self * o.inverse()
        return Series([a / o for a in self.c])

    def __rtruediv__(self, o: Any) -> Series:
        return self.inverse() * o

    def sqrt_with(self, s0: Scalar) -> Series:
        """The square root whose constant term is s0 (s0^2 = c_0, s0 nonzero)."""
        p = self.c
        s = [s0]
        half_inverse = 1 / (s0 * 2) if len(p) > 1 else None  # one inverse for every term
        field = None if half_inverse is None else _one_field(p, [s0, half_inverse], len(p))
        if field is not None and half_inverse is not None:  # in K: as in ``__mul__``
            s = _k_sqrt([x.p for x in p], s0, half_inverse, field)
        for k in range(len(s), len(p)):
            acc = p[k]
            for i in range(1, k):
                acc = acc - s[i] * s[k - i]
            s.append(acc * half_inverse)
        root = Series(s)
        if half_inverse is not None:
            root._head_inverse = half_inverse * 2
        return root

    def valuation(self) -> int:
        """Index of the first nonzero coefficient (exact series); len(self) when all vanish."""
        for i, a in enumerate(self.c):
            if not _is_zero(a):
                return i
        return len(self.c)


class QSeries:
    """``Series`` over Q by flint's ``fmpq_series`` (exact, in C: 20 times faster than
    Python lists of ``fmpq``): the same operations and truncation (an operation keeps the
    shorter operand's terms), for a rational t_s."""

    __slots__ = ("n", "s")
    s: fmpq_series

    def __init__(self, c: Sequence[Any], n: int | None = None) -> None:
        self.n = len(c) if n is None else n
        old = ctx.cap
        ctx.cap = max(self.n, 1)
        try:
            self.s = fmpq_series(list(c), prec=self.n)
        finally:
            ctx.cap = old

    def __len__(self) -> int:
        return self.n

    @property
    def c(self) -> list[fmpq]:
        cs = self.s.coeffs()
        return cs[: self.n] + [fmpq(0)] * (self.n - len(cs))

    def _run(self, o: Any, op: Callable[[Any, Any], Any]) -> QSeries:
        """op on the flint series, at the shorter operand's length (a scalar operand:
        this one's)."""
        n = self.n
        if type(o) is QSeries:
            if o.n < n:
                n = o.n
            o = o.s
        elif isinstance(o, (QSeries, Series)):
            o = o if isinstance(o, QSeries) else QSeries(o.c)
            n = min(n, o.n)
            o = o.s
        if n <= ctx.cap:  # flint keeps min(operands' precisions, cap) terms: n already
            out = object.__new__(QSeries)
            out.s, out.n = op(self.s, o), n
            return out
        old = ctx.cap
        ctx.cap = max(n, 1)
        try:
            out = object.__new__(QSeries)
            out.s, out.n = op(self.s, o), n
            return out
        finally:
            ctx.cap = old

    def __add__(self, o: Any) -> QSeries:
        return self._run(o, _add)

    __radd__ = __add__

    def __sub__(self, o: Any) -> QSeries:
        return self._run(o, _sub)

    def __rsub__(self, o: Any) -> QSeries:
        return self._run(o, lambda a, b: b - a)

    def __neg__(self) -> QSeries:
        return self._run(-1, _mul)

    def __mul__(self, o: Any) -> QSeries:
        return self._run(o, _mul)

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> QSeries:
        if not isinstance(o, (QSeries, Series)):
            o = fmpq(o)
            if o == 0:
                raise ZeroDivisionError("division of a series by zero")
            return self._run(1 / o, _mul)
        if o.c[0] == 0:  # flint would cancel powers of ε: Series raises here too
            raise ZeroDivisionError("division by a series without a constant term")
        return self._run(o, _truediv)

    def __rtruediv__(self, o: Any) -> QSeries:
        if self.c[0] == 0:
            raise ZeroDivisionError("division by a series without a constant term")
        return self._run(o, lambda a, b: b / a)

    def sqrt_with(self, s0: Any) -> QSeries:
        """The square root whose constant term is s0 (s0^2 = c_0, s0 nonzero):
        s0 sqrt(self/s0^2), whose constant term is 1."""
        s0 = fmpq(s0)
        return self._run(1 / (s0 * s0), lambda a, b: (a * b).sqrt() * s0)

    def valuation(self) -> int:
        """Index of the first nonzero coefficient; len(self) when all vanish."""
        for i, a in enumerate(self.c):
            if a != 0:
                return i
        return self.n


def _one_field(a: Sequence[Any], b: Sequence[Any], n: int) -> NumberField | None:
    """The field K when the first n terms of ``a`` and ``b`` are all elements of K (one
    ``NumberField``), else None (rationals, or a mix: the general path)."""
    if not n or type(a[0]) is not KElem:
        return None
    field = a[0].field
    for x in a[:n]:
        if type(x) is not KElem or x.field is not field:
            return None
    for x in b[:n]:
        if type(x) is not KElem or x.field is not field:
            return None
    return field


def _reduced(p: fmpq_poly, field: NumberField) -> fmpq_poly:
    """p's representative of degree below deg f (``KElem._wrap``'s)."""
    return p % field.f if p.degree() >= field.degree else p


def _k_dot(a: list[fmpq_poly], b: list[fmpq_poly], k: int, field: NumberField) -> fmpq_poly:
    """The representative of sum a_i b_(k-i) in K = Q[t]/(f): the products summed as
    polynomials and reduced once. An element of K has one representative of degree below
    deg f, so this is the very polynomial ``_dot`` gives on ``KElem``s, which reduces
    each product."""
    acc = a[0] * b[k]
    for i in range(1, k + 1):
        acc += a[i] * b[k - i]
    return _reduced(acc, field)


def _k_invert(a: list[fmpq_poly], b0: KElem, field: NumberField) -> list[KElem]:
    """``Series._invert``'s coefficients in K, each sum reduced once (``_k_dot``)."""
    h = b0.p
    b = [h]
    for k in range(1, len(a)):
        acc = a[1] * b[k - 1]
        for i in range(2, k + 1):
            acc += a[i] * b[k - i]
        b.append(-_reduced(_reduced(acc, field) * h, field))
    return [b0] + [KElem(p, field) for p in b[1:]]


def _k_sqrt(p: list[fmpq_poly], s0: KElem, half: KElem, field: NumberField) -> list[KElem]:
    """``Series.sqrt_with``'s coefficients in K, each sum reduced once (``_k_dot``)."""
    h = half.p
    s = [s0.p]
    for k in range(1, len(p)):
        acc = p[k]
        for i in range(1, k):
            acc = acc - s[i] * s[k - i]
        s.append(_reduced(_reduced(acc, field) * h, field))
    return [s0] + [KElem(q, field) for q in s[1:]]


def _dot(a: list[Scalar], b: list[Scalar], k: int) -> Scalar:
    acc = a[0] * b[k]
    for i in range(1, k + 1):
        acc = acc + a[i] * b[k - i]
    return acc


def _is_zero(a: Scalar) -> bool:
    return a.is_zero() if isinstance(a, KElem) else a == 0


def is_zero(a: Scalar) -> bool:
    """Exact zero test of a KElem or a rational (fmpq)."""
    return _is_zero(a)


def sign(a: Scalar) -> int:
    """Certified sign of a KElem, or the sign of a rational."""
    if isinstance(a, KElem):
        return a.sign()
    return (a > 0) - (a < 0)


def ball(a: Scalar) -> arb:
    """A KElem's value as a narrow ball (``NumberField.accurate``); a rational exactly
    (at 128 bits)."""
    if isinstance(a, KElem):
        return a.field.accurate(a.p)
    old = ctx.prec
    ctx.prec = 128
    try:
        return arb(a)
    finally:
        ctx.prec = old


def real(a: Scalar) -> float:
    """The double nearest a KElem or a rational (±inf beyond the double range; never
    raises, unlike ``float`` on a huge ``fmpq``)."""
    return float(a) if isinstance(a, KElem) else to_float(a)


def taylor(p: fmpq_poly, n: int) -> list[fmpq_poly]:
    """The first n Taylor coefficients of p about a symbolic point t: p^(k)(t)/k!."""
    out = []
    d = p
    fact = fmpq(1)
    for k in range(n):
        out.append(d / fact)
        d = d.derivative()
        fact *= k + 1
    return out

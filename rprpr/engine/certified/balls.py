"""Rigorous midpoint-radius balls over numpy float64 arrays.

A ``Ball(mid, rad)`` stands for the set {x : |x - mid| <= rad} of real numbers, one per
array element (numpy broadcasting applies). Every operation returns a ball that contains
every result of the exact operation applied to members of its operands (the inclusion
property), under IEEE-754 binary64 arithmetic with rounding to nearest, which is all
numpy uses. A ball whose bound cannot be proven finite (overflow, division by a ball
containing 0) is *unbounded*: its radius is not finite (+inf or NaN, ``bounded`` is
False; ``normal`` writes it as mid NaN, rad +inf); it contains everything. Operations
raise no numpy warnings when wrapped in ``quiet()`` (overflow is part of the design).

The bound (Rump, "Fast and parallel interval arithmetic", BIT 39(3), 1999, §2-3;
Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed., §2.1-2.2). Let
u = 2^-53 and η = 2^-1074 (the smallest subnormal). For floats a, b and ∘ in + - × ÷ √,
    fl(a ∘ b) = (a ∘ b)(1 + δ) + e,   |δ| <= u, |e| <= η/2, e = 0 for + and -,
and also |fl(z) - z| <= u |fl(z)| + η/2. Hence c = fl(a ∘ b) is within u|c| + η/2 of
a ∘ b, and each operation's radius is (the exact propagation of the operands' radii) +
u|c| + η/2. That sum of non-negative terms is itself evaluated in floating point: with
at most K <= 12 roundings along any path, each of relative error <= u, the computed
value R' satisfies R <= R'(1 + u)^K + n η/2 (n <= 8 underflows of a product or quotient,
never amplified: before every division the numerator is padded by TINY = 2^-1021, which
exceeds any underflow so far). ``_up`` returns fl(fl(R' (1 + 2^-48)) + 2^-1064), which is
>= R: if R' is normal, (1 + 2^-48)(1 - u) >= (1 + u)^K and n η/2 <= 8 u R'; if R' is
subnormal, all relative errors are below K η/2 and the addition of 2^-1064 = 1024 η is
exact. Overflow yields inf, never a wrong finite bound.

Constants: a Python or numpy float (and an int below 2^53) is taken as its exact binary
value; an ``fmpq`` becomes the ball of its rounding (``Ball.of_rational``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from flint import arb, fmpq, fmpq_poly

from ...model.numbers import to_float
from ..exact.equations import hypot as hypot  # its one home, read here by the layer
from .kernel import KERNEL

U = 2.0**-53  # unit roundoff of binary64, round to nearest
ETA = 2.0**-1074  # smallest positive subnormal
TINY = 2.0**-1021  # numerator pad before a division (absorbs earlier underflows)
_GROW = 1.0 + 2.0**-48  # covers (1 + u)^K for K <= 12 roundings, and the last rounding
_PAD = 2.0**-1064  # absolute pad: 1024 η
_DOWN = 1.0 - 2.0**-50  # shrink factor for lower bounds (covers 2 roundings)

Array = np.ndarray


def _const(x: float) -> Array:
    """x as a read-only 0-d array: the in-place steps below take it without converting a
    Python float on every call (the same double, so the same results), at ~60 % of the
    cost of such a step on short vectors."""
    a = np.array(x)
    a.flags.writeable = False
    return a


_AU, _AETA, _AGROW, _APAD, _ATINY = (_const(v) for v in (U, ETA, _GROW, _PAD, TINY))
_OPERANDS: tuple[type, ...] = (int, float, fmpq, np.ndarray, np.floating, np.integer)


def quiet() -> Any:
    """Silence numpy's floating-point warnings around ball arithmetic: overflow and 0/0
    only make balls unbounded (the operations themselves do not pay for a context)."""
    return np.errstate(all="ignore")


def _up(r: Any) -> Any:
    """An upper bound of the exact non-negative radius whose float evaluation is r."""
    return r * _GROW + _PAD


def round_up(r: Any) -> Any:
    """An upper bound of an exact non-negative quantity whose float evaluation (at most 12
    roundings along any path, sums and products of non-negative terms) is r: ``_up``."""
    return _up(r)


def stack(parts: list[Ball]) -> Ball:
    """One ball array from balls of equal (or broadcastable) shape, along a new first axis."""
    shapes = {np.shape(a) for b in parts for a in (b.mid, b.rad)}
    if len(shapes) == 1:  # the usual case: no broadcasting (np.broadcast_to is slow)
        return Ball._of(np.array([b.mid for b in parts]), np.array([b.rad for b in parts]))
    shape = np.broadcast_shapes(*shapes)
    return Ball._of(np.stack([full(b.mid, shape) for b in parts]),
                    np.stack([full(b.rad, shape) for b in parts]))  # fmt: skip


def full(a: Any, shape: tuple[int, ...]) -> Array:
    """A new float array of ``shape`` holding ``a`` broadcast (what
    ``np.array(np.broadcast_to(a, shape))`` gives, at a fraction of its cost)."""
    out = np.empty(shape)
    out[...] = a
    return out


class Ball:
    """A vector of real balls mid ± rad (see the module docstring for the bound)."""

    __slots__ = ("mid", "rad")
    __array_priority__ = 1000  # numpy scalars defer to Ball's reflected operators

    def __init__(self, mid: Any, rad: Any = 0.0) -> None:
        self.mid = np.asarray(mid, dtype=float)
        self.rad = np.asarray(rad, dtype=float)

    @classmethod
    def _of(cls, mid: Array, rad: Array) -> Ball:
        """A ball from float arrays as they are (the results of the operations: no
        conversion, which costs more than the arithmetic on short vectors)."""
        b = object.__new__(cls)
        b.mid = mid
        b.rad = rad
        return b

    # -- construction -------------------------------------------------------------
    @staticmethod
    def exact(x: Any) -> Ball:
        """Floats taken exactly (radius 0)."""
        return Ball(x, 0.0)

    @staticmethod
    def of_rational(q: fmpq | int) -> Ball:
        """The ball of the double nearest q: |q - RN(q)| <= u|RN(q)| + η/2."""
        return _rational(q if type(q) is fmpq else fmpq(q))

    @staticmethod
    def of_arb(a: arb) -> Ball:
        """A ball containing the arb ball ``a`` (its midpoint rounded to a double)."""
        if not a.is_finite():
            return Ball(np.nan, np.inf)
        m = float(a.mid())
        r = float((a - arb(m)).abs_upper())  # an arb upper bound, then float rounding
        if not (np.isfinite(m) and np.isfinite(r)):
            return Ball(np.nan, np.inf)
        return Ball(m, np.nextafter(r, np.inf))

    @staticmethod
    def hull(lo: Any, hi: Any) -> Ball:
        """A ball containing [lo, hi] (floats, lo <= hi), radius rounded outward."""
        lo = np.asarray(lo, dtype=float)
        hi = np.asarray(hi, dtype=float)
        mid = 0.5 * lo + 0.5 * hi  # within [lo, hi]
        rad = np.maximum(hi - mid, mid - lo)  # each difference rounded: _up covers it
        return _finish(mid, _up(rad))

    @staticmethod
    def coerce(o: Any) -> Ball:
        """A ball for an operand: a Ball, a float or int (exact), an fmpq (rounded)."""
        if isinstance(o, Ball):
            return o
        if isinstance(o, fmpq):
            return Ball.of_rational(o)
        if isinstance(o, int) and not isinstance(o, bool) and abs(o) > 2**53:
            return Ball.of_rational(fmpq(o))
        return Ball(o, 0.0)

    # -- arithmetic -----------------------------------------------------------------
    def __add__(self, o: Any) -> Ball:
        if type(o) is not Ball:
            if not isinstance(o, _OPERANDS):
                return NotImplemented
            o = Ball.coerce(o)
        c = self.mid + o.mid
        if c.ndim:  # in place where the shapes agree (``_sum_radius``)
            return _new(c, _sum_radius(self, o, c))  # fresh float arrays
        return _finish(c, _sum_radius(self, o, c))

    __radd__ = __add__

    def __sub__(self, o: Any) -> Ball:
        if type(o) is not Ball:
            if not isinstance(o, _OPERANDS):
                return NotImplemented
            o = Ball.coerce(o)
        c = self.mid - o.mid
        if c.ndim:
            return _new(c, _sum_radius(self, o, c))  # fresh float arrays
        return _finish(c, _sum_radius(self, o, c))

    def __rsub__(self, o: Any) -> Ball:
        return Ball.coerce(o) - self

    def __neg__(self) -> Ball:
        return Ball._of(-self.mid, self.rad)

    def __mul__(self, o: Any) -> Ball:
        if type(o) is not Ball:
            if not isinstance(o, _OPERANDS):
                return NotImplemented
            o = Ball.coerce(o)
        c = self.mid * o.mid
        am, ar, bm, br = self.mid, self.rad, o.mid, o.rad
        if am.shape == ar.shape == bm.shape == br.shape and am.ndim:  # in place: faster
            t = np.abs(am)
            t += ar
            t *= br
            u = np.abs(bm)
            u *= ar
            t += u
            np.abs(c, out=u)
            u *= _AU
            u += _AETA
            t += u
            t *= _AGROW
            t += _APAD
            return _new(c, t)  # the same operations, in the same order, as below
        prop = np.abs(am) + ar
        prop = prop * br  # as below, (|a| + r_a) r_b + r_a |b| in that order
        if c.ndim and prop.shape == c.shape:  # broadcast operands: the rest in place
            u = np.abs(bm)
            u = np.multiply(ar, u)
            prop += u
            if u.shape == c.shape:
                np.abs(c, out=u)
            else:
                u = np.abs(c)
            u *= _AU
            u += _AETA
            prop += u
            prop *= _AGROW
            prop += _APAD
            return _new(c, prop)
        prop = prop + ar * np.abs(bm)
        if c.ndim:  # an array: the last steps in place, no conversion
            u = np.abs(c)
            u *= _AU
            u += _AETA
            t = prop + u
            t *= _AGROW
            t += _APAD
            return _new(c, t)
        return _finish(c, _up(prop + (U * np.abs(c) + ETA)))

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> Ball:
        """x/y for x in self, y in o: |x/y - a/b| <= (r_a|b| + |a| r_b)/(|b|(|b| - r_b))."""
        if type(o) is not Ball:
            if not isinstance(o, _OPERANDS):
                return NotImplemented
            o = Ball.coerce(o)
        b = np.abs(o.mid)
        ok = b > o.rad
        c = self.mid / o.mid
        am, ar, br = self.mid, self.rad, o.rad
        if am.shape == ar.shape == b.shape == br.shape and am.ndim:  # in place: faster
            t = ar * b
            u = np.abs(am)
            u *= br
            t += u
            t += _ATINY
            t /= b
            t += _ATINY
            np.subtract(b, br, out=u)
            t /= u
            np.abs(c, out=u)
            u *= _AU
            u += _AETA
            t += u
            t *= _AGROW
            t += _APAD  # the same operations, in the same order, as below
            return _new(c, t) if ok.all() else _unbounded_where(_new(c, t), ~ok)
        num = ar * b + np.abs(am) * br
        if c.ndim and num.shape == c.shape:  # broadcast operands: the rest in place
            num += _ATINY
            num /= b
            num += _ATINY
            num /= b - br
            u = np.abs(c)
            u *= _AU
            u += _AETA
            num += u
            num *= _AGROW
            num += _APAD  # the same operations, in the same order, as below
            return _new(c, num) if ok.all() else _unbounded_where(_new(c, num), ~ok)
        num = num + TINY
        prop = ((num / b) + TINY) / (b - o.rad)
        out = _finish(c, _up(prop + (U * np.abs(c) + ETA)))
        return _unbounded_where(out, ~ok)

    def __rtruediv__(self, o: Any) -> Ball:
        return Ball.coerce(o) / self

    def __abs__(self) -> Ball:
        """|x|: mid |m|, same radius (|x| - |m| <= |x - m|)."""
        return Ball(np.abs(self.mid), self.rad)

    def sqrt(self) -> Ball:
        """√x over the non-negative members x of the ball (|√x - √m| <= min(r/√m, √r)).

        Unbounded where the ball holds no non-negative number."""
        m, r = self.mid, self.rad
        pos = m > 0
        c = np.sqrt(np.where(pos, m, 0.0))
        lip = np.where(pos, (r * (1 + 4 * U)) / np.where(pos, c, 1.0), np.inf)
        hold = np.sqrt(r)  # |√x - √m| <= √|x - m|
        prop = np.minimum(lip, hold)
        # m <= 0: the members lie in [0, m + r], √ of them in [0, √(m + r)]
        prop = np.where(pos, prop, np.sqrt(np.maximum(m + r, 0.0)))
        out = _finish(c, _up(prop + U * c))
        return _unbounded_where(out, m + r < 0)

    def square(self) -> Ball:
        return self * self

    # -- tests and bounds -------------------------------------------------------------
    def bounded(self) -> Array:
        """True where the ball is bounded (a finite radius, hence a finite midpoint)."""
        return np.isfinite(self.rad)

    def normal(self) -> Ball:
        """The same balls, each unbounded one written mid NaN, rad +inf."""
        ok = self.bounded()
        return Ball(np.where(ok, self.mid, np.nan), np.where(ok, self.rad, np.inf))

    def upper_abs(self) -> Array:
        """An upper bound of |x| over the ball (floats; +inf when unbounded)."""
        up = _up(np.abs(self.mid) + self.rad)
        return np.where(np.isfinite(up), up, np.inf)

    def lower_abs(self) -> Array:
        """A lower bound of |x| over the ball (0 when the ball contains 0)."""
        lo = (np.abs(self.mid) - self.rad) * _DOWN
        return np.where(np.isfinite(lo) & (lo > 0), lo, 0.0)

    def lower(self) -> Array:
        """A lower bound of the members (floats)."""
        lo = self.mid - self.rad
        lo = lo - np.abs(lo) * (4 * U) - _PAD
        return np.where(np.isfinite(lo), lo, -np.inf)

    def upper(self) -> Array:
        """An upper bound of the members (floats)."""
        hi = self.mid + self.rad
        hi = hi + np.abs(hi) * (4 * U) + _PAD
        return np.where(np.isfinite(hi), hi, np.inf)

    def contains_zero(self) -> Array:
        """True where 0 may be a member (always for an unbounded ball)."""
        return ~(np.abs(self.mid) > self.rad)

    def certified(self, tol: float) -> Array:
        """True where the mixed error of ``mid`` is proven below tol: rad <= tol (1 + |mid|)."""
        return self.rad <= tol * (1.0 + np.abs(self.mid))

    def __getitem__(self, index: Any) -> Ball:
        mid, rad = self.mid, self.rad
        if mid.shape != rad.shape:
            shape = np.broadcast_shapes(mid.shape, rad.shape)
            mid, rad = full(mid, shape), full(rad, shape)
        out = []
        for a in (mid, rad):
            v = np.asarray(a[index], dtype=float)
            if v.base is not None:  # a view: read-only, as the ball it came from may change
                v = v.view()
                v.flags.writeable = False
            out.append(v)
        return Ball._of(out[0], out[1])

    def __repr__(self) -> str:
        return f"Ball({self.mid!r}, {self.rad!r})"


_OPERANDS = (*_OPERANDS, Ball)  # the operand types a Ball operation accepts


def _new(mid: Array, rad: Array) -> Ball:
    """``Ball._of`` without the class method's call (the operations' results)."""
    b = _object_new(Ball)
    b.mid = mid
    b.rad = rad
    return b


_object_new = object.__new__


def _finish(mid: Array, rad: Array) -> Ball:
    """The ball mid ± rad. A non-finite midpoint always makes the radius non-finite
    (rad includes u|mid|), so ``rad`` alone tells a bounded ball (``bounded``)."""
    return Ball._of(np.asarray(mid, dtype=float), np.asarray(rad, dtype=float))


def _sum_radius(a: Ball, b: Ball, c: Array) -> Array:
    """The radius of c = a ± b: _up((r_a + r_b) + u|c|), in place where the shapes agree
    (the same operations in the same order)."""
    if c.ndim:  # an array: the result's own buffers
        t = a.rad + b.rad
        u = np.abs(c)
        u *= _AU
        if t.shape == c.shape:
            t += u
        else:  # radii of fewer dimensions than the midpoints
            t = t + u
        t *= _AGROW
        t += _APAD
        return t
    return _up((a.rad + b.rad) + U * np.abs(c))


def _unbounded_where(b: Ball, where: Array) -> Ball:
    if not where.any():
        return b
    return Ball._of(np.where(where, np.nan, b.mid), np.where(where, np.inf, b.rad))


def where(cond: Array, a: Ball, b: Ball) -> Ball:
    """Elementwise choice between two balls."""
    return Ball(np.where(cond, a.mid, b.mid), np.where(cond, a.rad, b.rad))


def two_sum(a: Array, b: Array) -> tuple[Array, Array]:
    """s = fl(a + b) and e with a + b = s + e exactly (Knuth's TwoSum, no overflow)."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


def poly_balls(p: fmpq_poly) -> list[Ball]:
    """The coefficients of the exact polynomial ``p`` (low to high) as balls."""
    return [_rational(c) for c in p.coeffs()] or [Ball.exact(0.0)]


def _rational(q: fmpq) -> Ball:
    """``Ball.of_rational`` for an fmpq (``rational_parts``)."""
    m, r = rational_parts(q)
    return Ball._of(np.array(m), np.array(r))


def rational_parts(q: fmpq) -> tuple[float, float]:
    """The midpoint and radius of ``Ball.of_rational(q)``, q an fmpq: a double m = RN(q)
    (correctly rounded), exact when m equals q, else of radius u|m| + η/2 rounded up;
    (NaN, inf) beyond the double range."""
    m = to_float(q)
    if m - m != 0.0:  # ±inf beyond the double range
        return math.nan, math.inf
    n, d = m.as_integer_ratio()
    exact = q.q == d and q.p == n
    return m, 0.0 if exact else _up(U * abs(m) + ETA)


def horner(c: list[Ball], x: Ball, flat: tuple[Array, ...] | None = None) -> Ball:
    """The polynomial with ball coefficients ``c`` (low to high) at ``x``, by Horner's rule
    (in one call of the compiled kernel where it is built and x is a vector of balls: the
    same doubles, ``kernel.py``). ``flat``: the coefficients as the kernel reads them
    (``flat``), made once by a caller that evaluates ``c`` often."""
    if KERNEL is not None and len(c) > 1 and type(x) is Ball and x.mid.ndim == 1:
        n = x.mid.shape[0]
        out = np.empty((2, n))
        cs = flat_coefficients(c) if flat is None else flat
        if type(c[0]) is Ball and KERNEL.horner(cs, x.mid, x.rad, out, n):
            return _new(out[0], out[1])
    return _horner(c, x)


def flat_coefficients(c: list[Ball]) -> tuple[Array, ...]:
    """Ball coefficients as the kernel's Horner call reads them: (mid, rad) of each."""
    return tuple(a for b in c for a in (b.mid, b.rad))


def _horner(c: list[Ball], x: Ball) -> Ball:
    """``horner`` by numpy's ball operations (the description the kernel is generated from)."""
    acc = c[-1]
    for ck in c[-2::-1]:
        acc = acc * x + ck
    return acc


def polyval(at: Array, c: list[float]) -> Array:
    """The polynomial with double coefficients ``c`` (low to high) at the times ``at``, in
    double precision: numpy.polynomial.polynomial.polyval's operations in its order (so
    the same doubles), without importing numpy.polynomial at start-up."""
    acc = c[-1] + at * 0
    for ck in c[-2::-1]:
        acc = ck + acc * at
    return acc


def intersect(a: Ball, b: Ball) -> Ball:
    """A ball containing the members common to ``a`` and ``b`` (both enclose the same
    quantity): the hull of [max of the lower bounds, min of the upper bounds]."""
    lo = np.maximum(a.lower(), b.lower())
    hi = np.minimum(a.upper(), b.upper())
    with quiet():
        return _finish(*_hull_parts(lo, np.maximum(lo, hi)))


def _hull_parts(lo: Array, hi: Array) -> tuple[Array, Array]:
    h = Ball.hull(lo, hi)
    return h.mid, h.rad


def centred(cs: list[list[Ball]], x: Ball) -> list[Ball]:
    """Enclosures of p, p', ..., p^(K) over the balls ``x`` from the ball coefficients
    ``cs[k]`` of p^(k), k = 0..K: the centred (mean-value) form
    p^(k)(x) ⊂ p^(k)(m) + p^(k+1)(x)·[-r, r] (m, r: the balls' midpoints and radii),
    from the highest derivative down, intersected with Horner's rule.

    Horner's rule over a ball of radius r widens by about r times the sum of the
    partial sums' sizes, which cancellation can make 10^4-10^5 times |p'| (a Chebyshev
    path y = T16(x - 3)/10 encloses y ∈ [0.1, 0.3] as ±260 on boxes of 4 ms); the
    centred form's excess over the true range shrinks like r^2."""
    m = Ball(x.mid, np.zeros_like(x.mid))
    e = Ball(np.zeros_like(x.mid), x.rad)
    out = [horner(cs[-1], x)]
    for c in reversed(cs[:-1]):
        out.append(intersect(horner(c, m) + out[-1] * e, horner(c, x)))
    return out[::-1]

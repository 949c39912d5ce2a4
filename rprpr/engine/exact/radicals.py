"""Exact numbers with two square roots adjoined: K(r1, r2), r_i = √D_i > 0, D_i in K.

At a Type II instant t_s of the 5R the elbows involve √D1(t_s) and √D2(t_s) (the legs'
discriminants), so every quantity of the analysis lives in K(r1, r2), K = Q or
Q[t]/(f) (``series.NumberField``). ``Rad`` is a0 + a1 r1 + a2 r2 + a3 r1 r2 with a_i in
K (``fmpq`` or ``series.KElem``), multiplied by the rules r_i² = D_i: a homomorphism onto
the real numbers whatever D1, D2 are (squares in K or not), so products and sums are
exact. Zero is decided exactly:

    X + r2 Y = 0 (X, Y in K(r1))  iff  Y = 0 and X = 0,
                                  or  Y != 0, X² - D2 Y² = 0 and sign X = -sign Y,

and likewise c + r1 d over K; the signs of nonzero numbers are certified by ball
evaluation (the ball narrows until it excludes zero, which it must). The inverse is the
product of the conjugates over the norm, which must not vanish (true of the divisors the
5R's formulas take: |E|², |E - B|², c × u = -e √D, and 1 + O(ε) series).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from flint import arb, ctx, fmpq

from .series import KElem

Scalar = Any  # fmpq or KElem


class Tower:
    """K(r1, r2): the discriminants D1, D2 (in K, positive) and a ball of each at a given
    precision (``value``)."""

    def __init__(self, D1: Scalar, D2: Scalar, value: Callable[[Scalar, int], arb]) -> None:
        self.D = (D1, D2)
        self.value = value  # (element of K, precision) -> ball
        self._inverse: list[Scalar | None] = [None, None]

    def inverse_D(self, i: int) -> Scalar:
        """1/D_i, made once (an inverse in K costs an extended gcd)."""
        v = self._inverse[i - 1]
        if v is None:
            v = self._inverse[i - 1] = 1 / self.D[i - 1]
        return v

    def roots(self, prec: int) -> tuple[arb, arb]:
        return self.value(self.D[0], prec).sqrt(), self.value(self.D[1], prec).sqrt()

    def of(self, a0: Scalar) -> Rad:
        z = a0 * 0
        return Rad(self, (a0, z, z, z))

    def root(self, i: int, k: Scalar) -> Rad:
        """k r_i (k in K)."""
        z = k * 0
        return Rad(self, (z, k, z, z) if i == 1 else (z, z, k, z))


def _zero(a: Scalar) -> bool:
    return a.is_zero() if isinstance(a, KElem) else a == 0


class Rad:
    """a0 + a1 r1 + a2 r2 + a3 r1 r2 in K(r1, r2) (module docstring)."""

    __slots__ = ("a", "tower")

    def __init__(self, tower: Tower, a: tuple[Scalar, Scalar, Scalar, Scalar]) -> None:
        self.tower = tower
        self.a = a

    def _lift(self, o: Any) -> tuple[Scalar, Scalar, Scalar, Scalar]:
        if isinstance(o, Rad):
            return o.a
        z = self.a[0] * 0
        return (o + z, z, z, z)

    def __add__(self, o: Any) -> Rad:
        b = self._lift(o)
        return Rad(self.tower, tuple(x + y for x, y in zip(self.a, b, strict=True)))

    __radd__ = __add__

    def __neg__(self) -> Rad:
        return Rad(self.tower, tuple(-x for x in self.a))

    def __sub__(self, o: Any) -> Rad:
        return self + (-Rad(self.tower, self._lift(o)))

    def __rsub__(self, o: Any) -> Rad:
        return Rad(self.tower, self._lift(o)) - self

    def __mul__(self, o: Any) -> Rad:
        if not isinstance(o, Rad):
            return Rad(self.tower, tuple(x * o for x in self.a))
        # r_i r_j by the basis index bits (bit 0: r1, bit 1: r2): r_i r_j = D^(i & j) r^(i ^ j)
        out: list[Any] = [None, None, None, None]
        for i, x in enumerate(self.a):
            if _zero(x):
                continue
            for j, y in enumerate(o.a):
                if _zero(y):
                    continue
                v = x * y
                both = i & j
                if both & 1:
                    v = v * self.tower.D[0]
                if both & 2:
                    v = v * self.tower.D[1]
                k = i ^ j
                out[k] = v if out[k] is None else out[k] + v
        z = self.a[0] * 0
        return Rad(self.tower, tuple(z if v is None else v for v in out))

    __rmul__ = __mul__

    def _conjugate(self, i: int) -> Rad:
        """r_i -> -r_i."""
        a0, a1, a2, a3 = self.a
        return Rad(self.tower, (a0, -a1, a2, -a3) if i == 1 else (a0, a1, -a2, -a3))

    def inverse(self) -> Rad:
        a0, a1, a2, a3 = self.a
        if _zero(a1) and _zero(a2) and _zero(a3):
            return self.tower.of(1 / a0)
        for i, k in ((1, a1), (2, a2)):  # k r_i: r_i/(k D_i)
            if _zero(a0) and _zero(a3) and _zero(a1 if i == 2 else a2):
                return self.tower.root(i, self.tower.inverse_D(i) * (1 / k))
        n2 = self * self._conjugate(2)  # in K(r1)
        n = n2 * n2._conjugate(1)  # in K
        return self._conjugate(2) * n2._conjugate(1) * (1 / n.a[0])

    def __truediv__(self, o: Any) -> Rad:
        if isinstance(o, Rad):
            return self * o.inverse()
        return Rad(self.tower, tuple(x / o for x in self.a))

    def __rtruediv__(self, o: Any) -> Rad:
        return self.inverse() * o

    def ball(self, prec: int = 128) -> arb:
        """The value as a ball computed at ``prec`` bits."""
        old = ctx.prec
        ctx.prec = prec
        try:
            r1, r2 = self.tower.roots(prec)
            v = [self.tower.value(x, prec) for x in self.a]
            return v[0] + v[1] * r1 + v[2] * r2 + v[3] * r1 * r2
        finally:
            ctx.prec = old

    def sign(self) -> int:
        """-1, 0 or 1, exactly (module docstring)."""
        if self.is_zero():
            return 0
        prec = 64
        while True:
            v = self.ball(prec)
            if v > 0:
                return 1
            if v < 0:
                return -1
            prec *= 2

    def is_zero(self) -> bool:
        a0, a1, a2, a3 = self.a
        X, Y = (a0, a1), (a2, a3)  # self = X + r2 Y, X and Y in K(r1)
        if self._zero1(Y):
            return self._zero1(X)
        D1, D2 = self.tower.D
        X2 = (X[0] * X[0] + X[1] * X[1] * D1, X[0] * X[1] * 2)
        Y2 = (Y[0] * Y[0] + Y[1] * Y[1] * D1, Y[0] * Y[1] * 2)
        if not self._zero1((X2[0] - Y2[0] * D2, X2[1] - Y2[1] * D2)):
            return False
        return self._sign1(X) == -self._sign1(Y)

    def _zero1(self, X: tuple[Scalar, Scalar]) -> bool:
        """c + r1 d = 0 (c, d in K): d = 0 and c = 0, or c² = D1 d² with opposite signs."""
        c, d = X
        if _zero(d):
            return _zero(c)
        if not _zero(c * c - d * d * self.tower.D[0]):
            return False
        return _sign(c) == -_sign(d)

    def _sign1(self, X: tuple[Scalar, Scalar]) -> int:
        """The sign of a nonzero X[0] + r1 X[1]."""
        z = X[0] * 0
        return Rad(self.tower, (X[0], X[1], z, z)).sign()

    def __eq__(self, o: object) -> bool:
        if isinstance(o, int | fmpq | KElem | Rad):
            return (self - o).is_zero()
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]

    def rational(self) -> fmpq | None:
        """The value as a rational when it visibly is one (K = Q, a1 = a2 = a3 = 0)."""
        a0, a1, a2, a3 = self.a
        if isinstance(a0, fmpq) and _zero(a1) and _zero(a2) and _zero(a3):
            return a0
        return None


def _sign(a: Scalar) -> int:
    """The sign of an element of K (certified for a KElem)."""
    if isinstance(a, KElem):
        return a.sign()
    return (a > 0) - (a < 0)

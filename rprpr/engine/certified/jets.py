"""First-order jets of balls: a function and its time derivative over a box of time,
both enclosed (the mean-value form of ``envelope`` reads T'(I) from them)."""

from __future__ import annotations

from typing import Any

from .balls import Ball


class Jet:
    """f and f' over a box of time, both balls: the arithmetic of first-order jets."""

    __slots__ = ("d", "v")

    def __init__(self, v: Ball, d: Ball) -> None:
        self.v = v
        self.d = d

    @staticmethod
    def _of(o: Any) -> Jet:
        if isinstance(o, Jet):
            return o
        return Jet(Ball.coerce(o), Ball.exact(0.0))

    def __add__(self, o: Any) -> Jet:
        o = Jet._of(o)
        return Jet(self.v + o.v, self.d + o.d)

    __radd__ = __add__

    def __sub__(self, o: Any) -> Jet:
        o = Jet._of(o)
        return Jet(self.v - o.v, self.d - o.d)

    def __rsub__(self, o: Any) -> Jet:
        return Jet._of(o) - self

    def __neg__(self) -> Jet:
        return Jet(-self.v, -self.d)

    def __mul__(self, o: Any) -> Jet:
        if not isinstance(o, Jet):
            o = Ball.coerce(o)
            return Jet(self.v * o, self.d * o)
        return Jet(self.v * o.v, self.d * o.v + self.v * o.d)

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> Jet:
        if not isinstance(o, Jet):
            o = Ball.coerce(o)
            return Jet(self.v / o, self.d / o)
        q = self.v / o.v
        return Jet(q, (self.d - q * o.d) / o.v)

    def __rtruediv__(self, o: Any) -> Jet:
        return Jet._of(o) / self

    def __getitem__(self, index: Any) -> Jet:
        return Jet(self.v[index], self.d[index])

    def sqrt(self) -> Jet:
        r = self.v.sqrt()
        return Jet(r, self.d / (r * 2.0))


def y_values(xd: Ball, xdd: Ball, q: Ball, qd: Ball, qdd: Ball) -> list[Ball]:
    """y' and y'' of y = q(x(t)) from x', x'' and q, q', q'' (q's derivatives in x):
    q' x' and q'' x' x' + q' x'' (``bounds.boxes``; the description the compiled kernel
    ``y_values`` is made from)."""
    return [qd * xd, qdd * xd * xd + qd * xdd]


def y_jets(xd: Ball, xdd: Ball, x3: Ball, q: Ball, qd: Ball, qdd: Ball, q3: Ball) -> list[Ball]:
    """Of y = q(x(t)), from x', x'', x3 = x''' and q, q', q'', q3 = q''' (q's derivatives
    in x): y's time derivative, then y' and y'' as jets, each its value then its
    derivative (``bounds.boxes``; the description the compiled kernel ``y_jets`` is made
    from)."""
    xj, xjj = Jet(xd, xdd), Jet(xdd, x3)
    q1 = Jet(qd, qdd * xd)
    q2 = Jet(qdd, q3 * xd)
    y = Jet(q, qd * xd)
    yd, ydd = q1 * xj, q2 * xj * xj + q1 * xjj
    return [y.d, yd.v, yd.d, ydd.v, ydd.d]

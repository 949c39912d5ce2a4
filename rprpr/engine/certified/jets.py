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

"""The planned motion as exact polynomials: x_E(t), y_E(t) = p(x_E(t)) and their derivatives
(the timing laws themselves are ``model.timing``)."""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

from flint import fmpq, fmpq_poly

from ..model.task import Task


@dataclass(frozen=True)
class Trajectory:
    """Exact end-point motion of a task: ``x``, ``y`` and their first two time derivatives
    (polynomials in t, SI units), ``a1`` and the time span [0, ``duration``]."""

    x: fmpq_poly
    y: fmpq_poly
    path: fmpq_poly  # y = path(x)
    a1: fmpq
    duration: fmpq

    @property
    def slope(self) -> fmpq_poly:
        """dy/dx along the motion, p'(x(t)) (polynomial in t)."""
        return self.path.derivative()(self.x)

    @cached_property
    def motion_coefficients(self) -> tuple[list[fmpq], ...]:
        """The coefficients of x, x', x'', y, y', y'' (computed once: a long polynomial's
        ``coeffs()`` costs milliseconds, and the ball-arithmetic samples read them often)."""
        polys = (self.x, self.xd, self.xdd, self.y, self.yd, self.ydd)
        return tuple(p.coeffs() for p in polys)

    @property
    def xd(self) -> fmpq_poly:
        return self.x.derivative()

    @property
    def yd(self) -> fmpq_poly:
        return self.y.derivative()

    @property
    def xdd(self) -> fmpq_poly:
        return self.x.derivative().derivative()

    @property
    def ydd(self) -> fmpq_poly:
        return self.y.derivative().derivative()


def trajectory(task: Task) -> Trajectory:
    """The exact trajectory of ``task``'s first piece: y(t) = p(x(t)) by composition."""
    piece = task.motion[0]
    assert piece.path is not None
    return Trajectory(x=piece.x, y=piece.y, path=piece.path, a1=task.robot.a1, duration=piece.end)

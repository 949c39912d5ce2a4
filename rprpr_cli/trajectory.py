"""The planned motion as exact polynomials: x_E(t), y_E(t) = p(x_E(t)) and their derivatives.

Timing laws (eq. 49): the rest-to-rest quintic x(t) = x0 + (x1 - x0)(10 τ^3 - 15 τ^4 + 6 τ^5),
τ = t / t_f, with zero velocity and acceleration at both ends; and the rest-to-rest cubic
x0 + (x1 - x0)(3 τ^2 - 2 τ^3), with zero velocity at both ends.
"""

from __future__ import annotations

from dataclasses import dataclass

from flint import fmpq, fmpq_poly

from .task import Task

LAWS = ("quintic", "cubic")


def timing_law(law: str, x0: fmpq, x1: fmpq, duration: fmpq) -> fmpq_poly:
    """x_E(t) of a rest-to-rest ``law`` from x0 to x1 in ``duration`` seconds (exact)."""
    tau = fmpq_poly([0, 1 / duration])
    if law == "quintic":
        shape = 10 * tau**3 - 15 * tau**4 + 6 * tau**5  # eq. (49) for x0=2, x1=4, t_f=5
    elif law == "cubic":
        shape = 3 * tau**2 - 2 * tau**3
    else:
        raise ValueError(f"unknown timing law {law!r}; expected one of {', '.join(LAWS)}")
    return x0 + (x1 - x0) * shape


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
    """The exact trajectory of ``task``: y(t) = p(x(t)) by composition."""
    return Trajectory(
        x=task.x_of_t,
        y=task.path(task.x_of_t),
        path=task.path,
        a1=task.robot.a1,
        duration=task.duration,
    )

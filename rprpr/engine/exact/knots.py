"""What happens at the knots of a piecewise motion: the jumps of velocity, acceleration
and torques across each interior break time t_k (pure, exact).

Each piece's polynomials are evaluated exactly at t_k (rationals); a velocity jump (a C0
knot) is an impulse of the torques; an acceleration jump (a C1 knot) makes the torques
jump, by T(t_k+) - T(t_k-), each side's value from the paper's formulas evaluated in
ball arithmetic (arb, 128 bits) at the exact one-sided motion, or each side's exact
limit when t_k is a singular instant (``torque_at_singularity`` of that side).
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from fractions import Fraction
from typing import Any, overload

from flint import arb, ctx, fmpq

from ...model.dataclass import dataclass
from ...model.numbers import to_float
from ...model.task import Piece, Robot
from . import equations as dyn
from .mechanism import of

PREC = 128  # bits of the one-sided torques


class _Exact:
    """``Knot.t_exact``: a Fraction, given as one or as an exact rational (``fmpq``, made
    into a Fraction where read: a long motion's knots hold no second copy of their
    times)."""

    @overload
    def __get__(self, obj: None, owner: Any = None) -> _Exact: ...
    @overload
    def __get__(self, obj: Knot, owner: Any = None) -> Fraction: ...
    def __get__(self, obj: Knot | None, owner: Any = None) -> Fraction | _Exact:
        if obj is None:
            raise AttributeError("t_exact")  # no default: the field is required
        t = getattr(obj, "_t_exact")  # noqa: B009
        return t if isinstance(t, Fraction) else Fraction(int(t.p), int(t.q))

    def __set__(self, obj: Knot, value: Fraction | fmpq) -> None:
        object.__setattr__(obj, "_t_exact", value)


@dataclass(frozen=True)
class Knot:
    """An interior break t_k between ``before`` (piece index) and before + 1.

    ``velocity_jump`` = (Δẋ, Δẏ) and ``acceleration_jump`` = (Δẍ, Δÿ) [SI], exactly
    rounded doubles of the exact jumps, None where continuous. ``torques`` = ((T1, T2)
    before, (T1, T2) after) [N m], certified doubles (None for a side where the torques
    are undefined or unbounded)."""

    t: float
    t_exact: Fraction  # ``_Exact``, set on the class below
    before: int
    velocity_jump: tuple[float, float] | None
    acceleration_jump: tuple[float, float] | None
    torques: tuple[tuple[float, float] | None, tuple[float, float] | None]
    line: int = 0  # where the piece before the knot ends: the task file's line, or
    file: str = ""  # the row of the waypoint CSV ``file``

    @property
    def torque_jump(self) -> tuple[float, float] | None:
        a, b = self.torques
        return None if a is None or b is None else (b[0] - a[0], b[1] - a[1])


setattr(Knot, "t_exact", _Exact())  # noqa: B010  (after the dataclass: a field with no default)


def _jump(p: Any, up: fmpq, q: Any, uq: fmpq) -> tuple[float, float] | None:
    """q(uq) - p(up) for the pairs p = (x, y) (before the knot, at its argument up) and
    q = (x, y) (after, at uq), as doubles; None when both vanish exactly."""
    dx, dy = q[0](uq) - p[0](up), q[1](uq) - p[1](up)
    return None if dx == 0 and dy == 0 else (to_float(dx), to_float(dy))


def _local(piece: Piece, t: fmpq) -> tuple[tuple[Any, Any], fmpq]:
    """The piece's (x, y) and the argument that gives their values at the absolute time
    t: its local form (a planner's segment, in u = t - start: the same values exactly,
    from far shorter rationals) at t - start where it has one, else x, y at t. Time
    derivatives are the same in u and in t."""
    if piece.local is not None:
        return piece.local, t - piece.start
    return (piece.x, piece.y), t


def path_at(piece: Piece, t: fmpq) -> list[fmpq]:
    """x, x', x'', y, y', y'' of the motion ``piece`` at the exact time t, exactly (each
    mechanism's ``torques_at`` starts from them)."""
    (x, y), u = _local(piece, t)
    return [p(u) for p in (x, x.derivative(), x.derivative().derivative(),
                           y, y.derivative(), y.derivative().derivative())]  # fmt: skip


def torques_at(piece: Piece, t: fmpq, robot: Robot) -> tuple[float, float] | None:
    """(T1, T2) of the motion ``piece`` at the exact time t (eq. 28 with λ = μ/δ,
    eqs. 30-31), in arb; None where δ or s1, s2 are not proven nonzero."""
    values = path_at(piece, t)
    old = ctx.prec
    ctx.prec = PREC
    try:
        X, Xd, Xdd, Y, Yd, Ydd = (arb(v) for v in values)
        a1 = arb(robot.a1)
        s1, s2 = dyn.hypot(X, Y), dyn.hypot(X - a1, Y)
        if not (s1 > 0 and s2 > 0):
            return None
        mech = of(robot)
        p = mech.params(robot, arb)
        leg1, leg2 = mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, dyn.hypot)
        d = mech.dynamics(leg1, leg2, p)
        delta = mech.delta(p, Y, leg1, leg2)
        if not (delta > 0 or delta < 0):
            return None
        T1, T2 = mech.efforts(d, d.mu1 / delta, d.mu2 / delta)
        return float(T1.mid()), float(T2.mid())
    finally:
        ctx.prec = old


def knots(
    pieces: tuple[Piece, ...],
    robot: Robot,
    torques: Callable[[Piece, fmpq, Robot], tuple[float, float] | None] | None = None,
) -> list[Knot]:
    """The interior knots of ``pieces`` with their jumps (module docstring); torques only
    where the acceleration jumps and the velocity does not. A jump a piece rules out by
    its construction (``Piece.smooth``) is not evaluated: it is zero exactly.
    ``torques``: the one-sided torques of the robot's mechanism (``torques_at``, the
    RPRPR's, by default)."""
    at = torques_at if torques is None else torques
    out = []
    none = (None, None)
    for i, (p, q) in enumerate(itertools.pairwise(pieces)):
        t = p.end  # also t_exact, as it is (``_Exact``)
        if q.smooth >= 2:  # continuous in velocity and acceleration by construction
            out.append(Knot(to_float(t), t, i, None, None, none, p.line, p.file))
            continue
        (px, py), up = _local(p, t)
        (qx, qy), uq = _local(q, t)
        dp = (px.derivative(), py.derivative())
        dq = (qx.derivative(), qy.derivative())
        v = None if q.smooth >= 1 else _jump(dp, up, dq, uq)
        a = _jump((dp[0].derivative(), dp[1].derivative()), up,
                  (dq[0].derivative(), dq[1].derivative()), uq)  # fmt: skip
        sides: tuple[Any, Any] = (None, None)
        if v is None and a is not None:
            sides = (at(p, t, robot), at(q, t, robot))
        out.append(Knot(to_float(t), t, i, v, a, sides, p.line, p.file))
    return out

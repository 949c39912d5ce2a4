"""Inverse kinematics and inverse dynamics of the RPRPR robot (the paper's Section 2-3).

The formulas are written once, for any number type with + - * / (numpy arrays for the
sample grid, ``series.Series`` for expansions about a singular instant), so that the
samples and the exact singularity analysis share one home for each equation.

Inverse kinematics (A at the origin, B at (a1, 0)): for leg 1 (u, v) = (x_E, y_E), for
leg 2 (u, v) = (x_E - a1, y_E); then s = |(u, v)|, cos θ = u/s, sin θ = v/s and, by
differentiating s^2 = u^2 + v^2 and s^2 θ' = u v' - v u' (derivation, eqs. 41-42):
    s'  = (u u' + v v') / s
    θ'  = (u v' - v u') / s^2
    s'' = (u'^2 + v'^2 + u u'' + v v'' - s'^2) / s
    θ'' = (u v'' - v u'' - 2 s s' θ') / s^2
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from ..model.task import Robot

Num = Any  # numpy array, float, or Series


@dataclass(frozen=True)
class Leg:
    """Joint values of one leg: s, cos θ, sin θ, s', θ', s'', θ''."""

    s: Num
    cos: Num
    sin: Num
    s_d: Num
    th_d: Num
    s_dd: Num
    th_dd: Num


def leg(
    u: Num, ud: Num, udd: Num, v: Num, vd: Num, vdd: Num, hypot: Callable[[Num, Num], Num]
) -> Leg:
    """Inverse kinematics of one leg from its end-point offset (u, v) and derivatives."""
    s = hypot(u, v)
    s2 = s * s
    s_d = (u * ud + v * vd) / s
    th_d = (u * vd - v * ud) / s2
    s_dd = (ud * ud + vd * vd + u * udd + v * vdd - s_d * s_d) / s
    th_dd = (u * vdd - v * udd - 2 * s * s_d * th_d) / s2
    return Leg(s, u / s, v / s, s_d, th_d, s_dd, th_dd)


@dataclass(frozen=True)
class Params:
    """The robot's mass data as numbers of the working type (fmpq or float)."""

    a1: Any
    g: Any
    m2: Any
    I2: Any
    r2: Any
    m3: Any
    I3: Any
    r3: Any
    m4: Any
    I4: Any
    r4: Any
    m5: Any
    I5: Any
    r5: Any

    @staticmethod
    def of(robot: Robot, convert: Callable[[Any], Any] = lambda v: v) -> Params:
        L = robot.links
        return Params(
            convert(robot.a1), convert(robot.gravity),
            convert(L[2].mass), convert(L[2].inertia), convert(L[2].r),
            convert(L[3].mass), convert(L[3].inertia), convert(L[3].r),
            convert(L[4].mass), convert(L[4].inertia), convert(L[4].r),
            convert(L[5].mass), convert(L[5].inertia), convert(L[5].r),
        )  # fmt: skip


@dataclass(frozen=True)
class Dynamics:
    """Terms of eqs. (7)-(14), (32)-(33) and (29) along a motion.

    F1 = M22 s1'' + N2 and F2 = M44 s2'' + N4 are the unactuated rows of eq. (18), so
    (F1, F2) = (J_u)^T λ; ``F1_abs``/``F2_abs``/``mu*_abs`` are the sums of the absolute
    values of their terms, the scale against which a cancellation is judged.
    """

    leg1: Leg
    leg2: Leg
    M11: Num
    M33: Num
    N1: Num
    N3: Num
    F1: Num
    F2: Num
    mu1: Num
    mu2: Num
    delta: Num


def dynamics(leg1: Leg, leg2: Leg, p: Params) -> Dynamics:
    """The equations of motion of the paper evaluated on the legs' joint values."""
    d1 = leg1.s - p.r3
    d2 = leg2.s - p.r5
    M11 = p.m2 * p.r2 * p.r2 + p.I2 + p.m3 * d1 * d1 + p.I3  # eq. (7)
    M33 = p.m4 * p.r4 * p.r4 + p.I4 + p.m5 * d2 * d2 + p.I5  # eq. (9)
    N1 = 2 * p.m3 * leg1.s_d * leg1.th_d * d1 + (p.m2 * p.r2 + p.m3 * d1) * p.g * leg1.cos  # (11)
    N2 = -p.m3 * d1 * leg1.th_d * leg1.th_d + p.m3 * p.g * leg1.sin  # eq. (12)
    N3 = 2 * p.m5 * leg2.s_d * leg2.th_d * d2 + (p.m4 * p.r4 + p.m5 * d2) * p.g * leg2.cos  # (13)
    N4 = -p.m5 * d2 * leg2.th_d * leg2.th_d + p.m5 * p.g * leg2.sin  # eq. (14)
    F1 = p.m3 * leg1.s_dd + N2  # M22 s1'' + N2, eq. (8)
    F2 = p.m5 * leg2.s_dd + N4  # M44 s2'' + N4, eq. (10)
    mu1 = -leg2.sin * F1 - leg1.sin * F2  # eq. (32)
    mu2 = leg2.cos * F1 + leg1.cos * F2  # eq. (33)
    delta = leg1.sin * leg2.cos - leg1.cos * leg2.sin  # sin(θ1 - θ2), eq. (29)
    return Dynamics(leg1, leg2, M11, M33, N1, N3, F1, F2, mu1, mu2, delta)


def torques(d: Dynamics, lambda1: Num, lambda2: Num) -> tuple[Num, Num]:
    """(T1, T2) of eq. (28): M_a q'' + N_a - (J_a)^T λ, with J_a of eq. (23)."""
    l1, l2 = d.leg1, d.leg2
    T1 = d.M11 * l1.th_dd + d.N1 - (-l1.s * l1.sin * lambda1 + l1.s * l1.cos * lambda2)
    T2 = d.M33 * l2.th_dd + d.N3 - (l2.s * l2.sin * lambda1 - l2.s * l2.cos * lambda2)
    return T1, T2

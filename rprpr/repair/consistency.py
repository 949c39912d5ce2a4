"""Eq. (34) at y = 0: the consistency a repaired crossing must meet (pure).

At a Type II instant of the paper's scheme E is on AB: y = 0, sin θ1 = sin θ2 = 0,
cos θ1 = c1 = sign(x), cos θ2 = c2 = sign(x - a1), s1 = |x|, s2 = |x - a1|. With v = 0 the
inverse kinematics (``equations``) give s_i' = c_i ẋ, θ_i' = c_i ẏ / s_i and
s_i'' = ẏ²/s_i + c_i ẍ, so eqs. (8), (12) (and (10), (14)) read, gravity dropping out
with sin θ_i,

    F1 = M22 s1'' + N2 = m3 c1 ẍ + m3 r3 ẏ²/s1²,   F2 = m5 c2 ẍ + m5 r5 ẏ²/s2².

μ1 = -sin θ2 F1 - sin θ1 F2 vanishes, and eq. (34) (μ2 = c2 F1 + c1 F2 = 0, eq. 33) is
linear in ẍ(t_s); multiplied by c1 c2 = ±1:

    (m3 + m5) ẍ(t_s) = -ẏ(t_s)² (c1 m3 r3 / s1² + c2 m5 r5 / s2²)

    case 1 (x > a1, c1 = c2 = 1):   (m3 + m5) ẍ = -ẏ² (m3 r3/s1² + m5 r5/s2²)
    case 2 (x < 0, c1 = c2 = -1):   (m3 + m5) ẍ = +ẏ² (m3 r3/s1² + m5 r5/s2²)
    case 3 (0 < x < a1, c2 = -1):   (m3 + m5) ẍ = ẏ² (m5 r5/s2² - m3 r3/s1²)

(``consistent_acceleration``). Only m3, m5, r3, r5 enter. The paper's path 2 (s1 = s2,
legs alike) needs ẍ(t_s) = 0, which the symmetric quintic has at its midpoint.
"""

from __future__ import annotations

from flint import fmpq

from ..engine import equations as dyn
from ..model.task import Robot


def consistent_acceleration(robot: Robot, x: fmpq, ydot: fmpq) -> fmpq | None:
    """ẍ(t_s) for which eq. (34) holds at the singular point (x, 0) with speed ẏ along the
    normal (the closed form above); None when m3 + m5 = 0 (then ẍ does not enter)."""
    m3, m5 = robot.links[3].mass, robot.links[5].mass
    if m3 + m5 == 0:
        return None
    return -(ydot**2) * leg_term(robot, x) / (m3 + m5)


def leg_term(robot: Robot, x: fmpq) -> fmpq:
    """c1 m3 r3 / s1² + c2 m5 r5 / s2² at (x, 0)."""
    a1, L = robot.a1, robot.links
    c1 = 1 if x > 0 else -1
    c2 = 1 if x > a1 else -1
    return c1 * L[3].mass * L[3].r / x**2 + c2 * L[5].mass * L[5].r / (x - a1) ** 2


def consistent_ydd(robot: Robot, x: fmpq, xdot: fmpq, ydot: fmpq) -> fmpq | None:
    """ÿ(t_s) for which the prismatic scheme's consistency holds at (x, 0) with velocity
    (ẋ, ẏ): μ1(t_s) = -(c2 U1/s1 + c1 U2/s2) = 0 (μ2 vanishes by itself), where
    U_i = M θ_i'' + N_i and θ_i'' = c_i ÿ/s_i - 2 s_i' θ_i'/s_i at y = 0 — affine in ÿ (and
    free of ẍ), so two exact evaluations of ``equations.dynamics`` give its root; None
    when ÿ does not enter (massless, inertia-free legs)."""
    params = dyn.Params.of(robot)

    def mu1(ydd: fmpq) -> fmpq:
        def exact_hypot(u: fmpq, v: fmpq) -> fmpq:
            return abs(u)  # v = y = 0 at a Type II instant

        legs = [dyn.leg(u, xdot, fmpq(0), fmpq(0), ydot, ydd, exact_hypot)
                for u in (x, x - robot.a1)]  # fmt: skip
        return fmpq(dyn.dynamics(legs[0], legs[1], params).mu1)

    r0, r1 = mu1(fmpq(0)), mu1(fmpq(1))
    return None if r0 == r1 else -r0 / (r1 - r0)

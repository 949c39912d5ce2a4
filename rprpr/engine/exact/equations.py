"""Inverse kinematics and inverse dynamics of the RPRPR robot (the paper's Section 2-3),
and its two actuation schemes as the two implementations of ``mechanism.Mechanism``.

The formulas are written once, for any number type with + - * / (numpy arrays for the
sample grid, ``series.Series`` for expansions about a singular instant, balls, arb), so
that the samples and the exact singularity analysis share one home for each equation.
``Rprpr`` holds what both schemes share (the parameters, the inverse kinematics, the
locus y = 0, δ, the terms of eqs. 7-14); ``Revolute`` and ``Prismatic`` add only what is
the scheme's own: μ, the efforts given λ, the consistency residual (the primitives of
``mechanism``'s contract). ``dynamics``, ``efforts``, ``consistency`` and ``Params.of`` are
the module's entry points, thin: each dispatches to the scheme its argument carries.

Inverse kinematics (A at the origin, B at (a1, 0)): for leg 1 (u, v) = (x_E, y_E), for
leg 2 (u, v) = (x_E - a1, y_E); then s = |(u, v)|, cos θ = u/s, sin θ = v/s and, by
differentiating s^2 = u^2 + v^2 and s^2 θ' = u v' - v u' (derivation, eqs. 41-42):
    s'  = (u u' + v v') / s
    θ'  = (u v' - v u') / s^2
    s'' = (u'^2 + v'^2 + u u'' + v v'' - s'^2) / s
    θ'' = (u v'' - v u'' - 2 s s' θ') / s^2
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import Any, ClassVar

from ...model.actuation import PRISMATIC, REVOLUTE, SCHEMES, Scheme
from ...model.dataclass import dataclass
from ...model.task import Robot

Num = Any  # numpy array, float, or Series


def hypot(u: Num, v: Num) -> Num:
    """√(u² + v²) for any number type with a ``sqrt`` method: numpy balls and their jets
    (every operation rounded outward, IEEE's correctly rounded square root), arb balls
    (arb's own enclosure), series. What ``leg`` takes; its one home."""
    return (u * u + v * v).sqrt()


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
    """The robot's physical parameters as numbers of the working type (fmpq, float, Ball,
    arb): a1 [m], g [m/s^2], m_i [kg], I_i [kg m^2], r_i [m], and the scheme they are
    driven by (``mechanism``: the ``mechanism.Mechanism`` that made them)."""

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
    mechanism: Any  # a ``mechanism.Mechanism`` (``Rprpr`` here)

    @property
    def actuation(self) -> str:
        """``Robot.actuation``: which rows of eq. (4) are actuated."""
        return self.mechanism.name

    @staticmethod
    def of(robot: Robot, convert: Callable[[Any], Any] = lambda v: v) -> Params:
        """The parameters of ``robot`` under its scheme (``mechanism.of``), converted."""
        return MECHANISMS[robot.actuation].params(robot, convert)


# The two actuation schemes (``Robot.actuation``). Eq. (4), M q'' + N = Q + J^T λ with
# q = (θ1, s1, θ2, s2), splits into the actuated rows (the efforts) and the unactuated
# rows (Q = 0 there), which fix λ:
#
# * revolute (the paper): Q = (T1, 0, T2, 0). Unactuated s1, s2: F1 = M22 s1'' + N2,
#   F2 = M44 s2'' + N4 and (J_u)^T λ = (F1, F2) with J_u of eq. (24), det (J_u)^T = δ;
#   λ = μ/δ with μ of eqs. (32)-(33); T = M_a q'' + N_a - (J_a)^T λ (eq. 28).
# * prismatic: Q = (0, F1, 0, F2). Unactuated θ1, θ2: U1 = M11 θ1'' + N1,
#   U2 = M33 θ2'' + N3 [N m] and (J_a)^T λ = (U1, U2) with J_a of eq. (23):
#       -s1 sin θ1 λ1 + s1 cos θ1 λ2 = U1,   s2 sin θ2 λ1 - s2 cos θ2 λ2 = U2,
#   det = s1 s2 sin(θ1 - θ2) = s1 s2 δ; by Cramer's rule λ = μ/δ with
#       μ1 = -(cos θ2 U1/s1 + cos θ1 U2/s2),  μ2 = -(sin θ1 U2/s2 + sin θ2 U1/s1),
#   the same δ, so the same singular instants and orders. The efforts are the s rows:
#       (F1, F2) = M_s q'' + N_s - (J_u)^T λ:
#       F1 = M22 s1'' + N2 - (cos θ1 λ1 + sin θ1 λ2),
#       F2 = M44 s2'' + N4 + (cos θ2 λ1 + sin θ2 λ2)   [N].
# At a Type II instant (sin θ1 = sin θ2 = 0) the automatic μ is μ1 for revolute (sin θ's
# multiply it, the paper's remark below eq. 35) and μ2 for prismatic; consistency is the
# other one: eq. (34) σ F1 + F2 = 0 (revolute), and U1/s1 + σ U2/s2 = 0 (prismatic:
# the legs' moments about A and B, as forces at E across AB). With sin θi = y/si:
# μ2 = -y (U1 + U2)/(s1 s2), so λ2 = (U1 + U2)/a1 is bounded for every prismatic motion.


@dataclass(frozen=True)
class Dynamics:
    """Terms of eqs. (7)-(14), (32)-(33) and (29) along a motion, for the robot's scheme.

    F1 = M22 s1'' + N2 and F2 = M44 s2'' + N4 are the s rows' inertial terms (the
    unactuated rows of eq. (18) under the paper's scheme, so (F1, F2) = (J_u)^T λ there);
    U1 = M11 θ1'' + N1 and U2 = M33 θ2'' + N3 are the θ rows' (the unactuated rows under
    the prismatic scheme). μ1, μ2 are the scheme's numerators of λ = μ/δ; ``mechanism``
    the scheme that made them.
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
    mechanism: Any  # a ``mechanism.Mechanism``
    U1: Num = None
    U2: Num = None

    @property
    def actuation(self) -> str:
        return self.mechanism.name


class Rprpr(ABC):
    """The RPRPR chain (A at the origin, B at (a1, 0)) under one actuation scheme: what
    the schemes share, written once; a scheme supplies ``_mu``, ``efforts``,
    ``consistency`` and its constants (``mechanism``'s contract)."""

    name: ClassVar[str]
    words: ClassVar[Scheme]
    automatic: ClassVar[int]

    def params(self, robot: Robot, convert: Callable[[Any], Any] = lambda v: v) -> Params:
        L = robot.links
        return Params(
            convert(robot.a1), convert(robot.gravity),
            convert(L[2].mass), convert(L[2].inertia), convert(L[2].r),
            convert(L[3].mass), convert(L[3].inertia), convert(L[3].r),
            convert(L[4].mass), convert(L[4].inertia), convert(L[4].r),
            convert(L[5].mass), convert(L[5].inertia), convert(L[5].r),
            self,
        )  # fmt: skip

    def locus(self, x: Any, y: Any) -> Any:
        """δ = -a1 y/(s1 s2) (eq. 29): the Type II instants are the roots of y(t)."""
        return y

    def legs(
        self, p: Params, x: Num, xd: Num, xdd: Num, y: Num, yd: Num, ydd: Num,
        hypot: Callable[[Num, Num], Num], hypot2: Callable[[Num, Num], Num] | None = None,
    ) -> tuple[Leg, Leg]:  # fmt: skip
        """Both legs (eqs. 41-42): (u, v) = (x, y) for leg 1, (x - a1, y) for leg 2."""
        u2 = x - p.a1
        return leg(x, xd, xdd, y, yd, ydd, hypot), leg(u2, xd, xdd, y, yd, ydd, hypot2 or hypot)

    def delta(self, p: Params, y: Num, leg1: Leg, leg2: Leg) -> Num:
        """δ = sin(θ1 - θ2) in its product form -a1 y/(s1 s2) (eq. 29)."""
        return -(p.a1 * y) / (leg1.s * leg2.s)

    def delta_rate(self, p: Params, y: Num, yd: Num, leg1: Leg, leg2: Leg) -> Num:
        """δ' = -a1/(s1 s2) (y' - y (s1'/s1 + s2'/s2)) [1/s], from eq. (29)."""
        return -(p.a1 / (leg1.s * leg2.s)) * (yd - y * (leg1.s_d / leg1.s + leg2.s_d / leg2.s))

    def dynamics(self, leg1: Leg, leg2: Leg, p: Params) -> Dynamics:
        """The equations of motion of the paper evaluated on the legs' joint values."""
        d1 = leg1.s - p.r3
        d2 = leg2.s - p.r5
        M11 = p.m2 * p.r2 * p.r2 + p.I2 + p.m3 * d1 * d1 + p.I3  # eq. (7)
        M33 = p.m4 * p.r4 * p.r4 + p.I4 + p.m5 * d2 * d2 + p.I5  # eq. (9)
        # eqs. (11) and (13): N1, N3
        N1 = 2 * p.m3 * leg1.s_d * leg1.th_d * d1 + (p.m2 * p.r2 + p.m3 * d1) * p.g * leg1.cos
        N2 = -p.m3 * d1 * leg1.th_d * leg1.th_d + p.m3 * p.g * leg1.sin  # eq. (12)
        N3 = 2 * p.m5 * leg2.s_d * leg2.th_d * d2 + (p.m4 * p.r4 + p.m5 * d2) * p.g * leg2.cos
        N4 = -p.m5 * d2 * leg2.th_d * leg2.th_d + p.m5 * p.g * leg2.sin  # eq. (14)
        F1 = p.m3 * leg1.s_dd + N2  # M22 s1'' + N2, eq. (8)
        F2 = p.m5 * leg2.s_dd + N4  # M44 s2'' + N4, eq. (10)
        delta = leg1.sin * leg2.cos - leg1.cos * leg2.sin  # sin(θ1 - θ2), eq. (29)
        mu1, mu2, U1, U2 = self._mu(leg1, leg2, M11, M33, N1, N3, F1, F2)
        return Dynamics(leg1, leg2, M11, M33, N1, N3, F1, F2, mu1, mu2, delta, self, U1, U2)

    @abstractmethod
    def _mu(
        self, l1: Leg, l2: Leg, M11: Num, M33: Num, N1: Num, N3: Num, F1: Num, F2: Num
    ) -> tuple[Num, Num, Num, Num]:
        """The scheme's μ1, μ2 from the shared terms, and U1, U2 (None when unused)."""

    @abstractmethod
    def efforts(self, d: Dynamics, lambda1: Num, lambda2: Num) -> tuple[Num, Num]:
        """The actuators' efforts given λ."""

    @abstractmethod
    def consistency(self, d: Dynamics, sigma: int, at: Callable[[Num], Any]) -> tuple[Any, Any]:
        """The consistency residual at a Type II instant [N]: (numerator, denominator or
        None), from the values ``at`` t_s of the series' terms; zero numerator: consistent."""


class Revolute(Rprpr):
    """The paper's scheme: torques T1, T2 [N m] at A and B; s1, s2 passive."""

    name = REVOLUTE
    words = SCHEMES[REVOLUTE]
    automatic = 0  # μ1 = -(sin θ2 F1 + sin θ1 F2) vanishes at every t_s

    def _mu(
        self, l1: Leg, l2: Leg, M11: Num, M33: Num, N1: Num, N3: Num, F1: Num, F2: Num
    ) -> tuple[Num, Num, Num, Num]:
        mu1 = -l2.sin * F1 - l1.sin * F2  # eq. (32)
        mu2 = l2.cos * F1 + l1.cos * F2  # eq. (33)
        return mu1, mu2, None, None

    def efforts(self, d: Dynamics, lambda1: Num, lambda2: Num) -> tuple[Num, Num]:
        """(T1, T2) of eq. (28): M_a q'' + N_a - (J_a)^T λ, with J_a of eq. (23)."""
        return torques(d, lambda1, lambda2)

    def consistency(self, d: Dynamics, sigma: int, at: Callable[[Num], Any]) -> tuple[Any, Any]:
        """Eq. (34): σ F1 + F2 (= cos θ1 μ2(t_s))."""
        return (sigma * at(d.F1) + at(d.F2), None)


class Prismatic(Rprpr):
    """Linear actuators in the legs: forces F1, F2 [N] on s1, s2; θ1, θ2 passive."""

    name = PRISMATIC
    words = SCHEMES[PRISMATIC]
    automatic = 1  # μ2 = -y (U1 + U2)/(s1 s2) vanishes at every t_s

    def _mu(
        self, l1: Leg, l2: Leg, M11: Num, M33: Num, N1: Num, N3: Num, F1: Num, F2: Num
    ) -> tuple[Num, Num, Num, Num]:
        U1 = M11 * l1.th_dd + N1  # the θ rows (module comment above)
        U2 = M33 * l2.th_dd + N3
        V1, V2 = U1 / l1.s, U2 / l2.s  # the legs' moments as forces at E [N]
        mu1 = -(l2.cos * V1 + l1.cos * V2)
        mu2 = -(l1.sin * V2 + l2.sin * V1)
        return mu1, mu2, U1, U2

    def efforts(self, d: Dynamics, lambda1: Num, lambda2: Num) -> tuple[Num, Num]:
        """(F1, F2) [N]: M_s q'' + N_s - (J_u)^T λ, with J_u of eq. (24)."""
        return prismatic_forces(d, lambda1, lambda2)

    def consistency(self, d: Dynamics, sigma: int, at: Callable[[Num], Any]) -> tuple[Any, Any]:
        """U1/s1 + σ U2/s2 = (s2 U1 + σ s1 U2)/(s1 s2) (= -cos θ2 μ1(t_s))."""
        s1, s2 = at(d.leg1.s), at(d.leg2.s)
        return (s2 * at(d.U1) + sigma * s1 * at(d.U2), s1 * s2)


# the implementations by ``Robot.actuation`` (``mechanism.of`` reads it; ``register`` adds)
MECHANISMS: dict[str, Any] = {REVOLUTE: Revolute(), PRISMATIC: Prismatic()}


def dynamics(leg1: Leg, leg2: Leg, p: Params) -> Dynamics:
    """The equations of motion on the legs' joint values, under ``p``'s scheme."""
    return p.mechanism.dynamics(leg1, leg2, p)


def efforts(d: Dynamics, lambda1: Num, lambda2: Num) -> tuple[Num, Num]:
    """The actuators' efforts given λ: (T1, T2) [N m] of eq. (28) for the revolute scheme,
    (F1, F2) [N] for the prismatic one (the module comment above)."""
    return d.mechanism.efforts(d, lambda1, lambda2)


def consistency(d: Dynamics, sigma: int, at: Callable[[Num], Any]) -> tuple[Any, Any]:
    """The consistency residual at a Type II instant [N] under ``d``'s scheme (eq. 34 for
    the revolute scheme, the legs' moment balance for the prismatic one)."""
    return d.mechanism.consistency(d, sigma, at)


def torques(d: Dynamics, lambda1: Num, lambda2: Num) -> tuple[Num, Num]:
    """(T1, T2) of eq. (28): M_a q'' + N_a - (J_a)^T λ, with J_a of eq. (23)."""
    l1, l2 = d.leg1, d.leg2
    T1 = d.M11 * l1.th_dd + d.N1 - (-l1.s * l1.sin * lambda1 + l1.s * l1.cos * lambda2)
    T2 = d.M33 * l2.th_dd + d.N3 - (l2.s * l2.sin * lambda1 - l2.s * l2.cos * lambda2)
    return T1, T2


def prismatic_forces(d: Dynamics, lambda1: Num, lambda2: Num) -> tuple[Num, Num]:
    """(F1, F2) [N]: M_s q'' + N_s - (J_u)^T λ, with J_u of eq. (24) (columns s1, s2)."""
    l1, l2 = d.leg1, d.leg2
    F1 = d.F1 - (l1.cos * lambda1 + l1.sin * lambda2)
    F2 = d.F2 + (l2.cos * lambda1 + l2.sin * lambda2)
    return F1, F2

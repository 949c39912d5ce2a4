"""The 5R five-bar (all-revolute): its geometry, Type II locus and inverse dynamics, for
any number type (docs/five-bar.md §1-6, the derivation this module implements).

A = (0, 0), B = (a, 0). Link 1 (A to the elbow C, length l1) and link 2 (B to the elbow D,
length l2) are driven by the torques T1, T2 at A and B; the distal links 3 (C to E, l3)
and 4 (D to E, l4) meet at the end point E = (x, y). Link i has mass m_i, centroidal
inertia I_i and its centre of mass at r_i from its inner joint (A, B, C, D). Gravity g
points along -y.

The formulas are written once, for any number type with + - * / (``fmpq``,
``series.Series``/``QSeries`` exact over Q, a number field or ``radicals.Rad``,
``flint.arb``, ``arb_series``, mpmath): a function returns numbers of the type it is
given, by the same operations in the same order, and never branches on a value. Where
the RPRPR's legs take a ``hypot`` (s = |E - base|), the 5R's take a ``root``: the
caller's square root of the leg's discriminant D_i (a polynomial in x, y), with the sign
of its own choosing for series (the working mode e_i multiplies it here).

Per leg (§2, §5; base b = A or B, u = E - b, R = |u|², proximal/distal lengths lp, ld):

    K = (lp² + R - ld²)/2,  D = lp² R - K²,  c = (K u + e √D u⊥)/R  (the elbow - b),
    d = u - c (the distal vector),  Δ = c × u = -e √D,
    θ' = d·E'/Δ,  φ' = -c·E'/Δ,  β = E'' + θ'² c + φ'² d,  θ'' = d·β/Δ,  φ'' = -c·β/Δ,
    h = (I_d + m_d r_d²) φ'' + (m_d r_d/ld)((c·d) θ'' + (c × d) θ'²) + m_d g r_d d_x/ld,
    Θ = (I_p + m_p r_p² + m_d lp²) θ'' + (m_d r_d/ld)((c·d) φ'' - (c × d) φ'²)
        + (m_p r_p + m_d lp) g c_x/lp.

Then δ = d1 × d2, ν = (d1·d2/l3) h1 + l3 h2, the multiplier (the force of leg 2 on leg 1
at E) λ = α d1/l3 + β1 d1⊥/l3 with α = ν/δ (the distal links' axial force: the only part
that can blow up) and β1 = h1/l3, and T1 = Θ1 - c1 × λ, T2 = Θ2 + c2 × λ.
The consistency residual at a Type II instant is w = h1/l3 + σ h2/l4 (§6, eq. C1).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

from flint import fmpq_mpoly_ctx

from ...model.dataclass import dataclass
from .mechanism import Root

Num = Any


class _Link(Protocol):
    @property
    def mass(self) -> Any: ...
    @property
    def inertia(self) -> Any: ...
    @property
    def r(self) -> Any: ...


class FiveBarRobot(Protocol):
    """What the engine reads of a 5R robot (``model.five_bar.FiveBar``): the base length
    ``a``, the link lengths (l1, l2, l3, l4), the working modes (e1, e2) at the start, and
    ``links`` keyed 1..4 (1 proximal at A, 2 proximal at B, 3 distal C to E, 4 distal D
    to E), each with mass, inertia and r (from the link's inner joint)."""

    @property
    def a(self) -> Any: ...
    @property
    def lengths(self) -> tuple[Any, Any, Any, Any]: ...
    @property
    def modes(self) -> tuple[int, int]: ...
    @property
    def links(self) -> dict[int, Any]: ...


@dataclass(frozen=True)
class FiveBarParams:
    """The 5R's parameters as numbers of the working type: a [m], l = (l1, l2, l3, l4)
    [m], m [kg], I [kg m^2], r [m] per link 1..4 (index 0..3), g [m/s^2]."""

    a: Any
    l: tuple[Any, Any, Any, Any]  # noqa: E741 - the links' lengths, as the paper's l_i
    m: tuple[Any, Any, Any, Any]
    I: tuple[Any, Any, Any, Any]  # noqa: E741 - the centroidal inertias I_i
    r: tuple[Any, Any, Any, Any]
    g: Any


def params(
    five_bar: FiveBarRobot, gravity: Any, convert: Callable[[Any], Any] = lambda v: v
) -> FiveBarParams:
    """The parameters of ``five_bar`` under ``gravity``, each exact value passed through
    ``convert`` (to a float, a ball, an arb; identity: exact)."""
    links = [five_bar.links[i] for i in (1, 2, 3, 4)]
    return FiveBarParams(
        convert(five_bar.a),
        tuple(convert(v) for v in five_bar.lengths),
        tuple(convert(k.mass) for k in links),
        tuple(convert(k.inertia) for k in links),
        tuple(convert(k.r) for k in links),
        convert(gravity),
    )


# -- the locus (§3) ----------------------------------------------------------------------------
@dataclass(frozen=True)
class Conjugates:
    """δ R1 R2 = P0 + e1 P1 √D1 + e2 P2 √D2 + e1 e2 P3 √(D1 D2), with R1 = |E|²,
    R2 = |E - B|², D1, D2 the legs' discriminants (Type I where one is zero)."""

    P0: Num
    P1: Num
    P2: Num
    P3: Num
    D1: Num
    D2: Num
    R1: Num
    R2: Num


def conjugates(p: FiveBarParams, x: Num, y: Num) -> Conjugates:
    """The radical-free parts of δ (§3) at (x, y): polynomials when x, y are."""
    l1, l2, l3, l4 = p.l
    R1 = x * x + y * y
    wx = x - p.a
    R2 = wx * wx + y * y
    K1 = (R1 + l1 * l1 - l3 * l3) / 2
    K2 = (R2 + l2 * l2 - l4 * l4) / 2
    EW = x * wx + y * y
    ay = y * p.a
    return Conjugates(
        (R1 - K1) * (R2 - K2) * ay, (R2 - K2) * EW, -((R1 - K1) * EW), ay,
        R1 * (l1 * l1) - K1 * K1, R2 * (l2 * l2) - K2 * K2, R1, R2,
    )  # fmt: skip


def _curve_parts(p: FiveBarParams, x: Num, y: Num) -> tuple[Num, Num, Num, Num, Num, Num]:
    """The parts ``curve`` and ``curve_gradient`` are made of: R1 = |E|², x - a,
    R2 = |E - B|², E·W (W = E - B), k1 = R1 + l3² - l1², k2 = R2 + l4² - l2²."""
    l1, l2, l3, l4 = p.l
    R1 = x * x + y * y
    wx = x - p.a
    R2 = wx * wx + y * y
    EW = x * wx + y * y
    return R1, wx, R2, EW, R1 + (l3 * l3 - l1 * l1), R2 + (l4 * l4 - l2 * l2)


def curve(p: FiveBarParams, sigma: int, x: Num, y: Num) -> Num:
    """S_σ(x, y) = l4² k1² R2 - 2σ l3 l4 k1 k2 (E·W) + l3² k2² R1 - 4 l3² l4² a² y², with
    k1 = R1 + l3² - l1², k2 = R2 + l4² - l2²: zero where the distal links can line up with
    E - D = σ (l4/l3)(E - C) (σ = -1: E between the elbows). 16 Π_e δ_e = S₊ S₋ R1⁻² R2⁻²
    (§3), so a path's Type II instants are roots of S_σ(x(t), y(t))."""
    l3, l4 = p.l[2], p.l[3]
    R1, _, R2, EW, k1, k2 = _curve_parts(p, x, y)
    return (
        k1 * k1 * R2 * (l4 * l4)
        - k1 * k2 * EW * (2 * sigma * l3 * l4)
        + k2 * k2 * R1 * (l3 * l3)
        - y * y * (4 * l3 * l3 * l4 * l4 * p.a * p.a)
    )


def curve_gradient(p: FiveBarParams, sigma: int, x: Num, y: Num) -> tuple[Num, Num]:
    """∇S_σ = (∂S_σ/∂x, ∂S_σ/∂y) at (x, y) (the derivative of ``curve`` term by term:
    ∂R1 = 2(x, y), ∂R2 = 2(x - a, y), ∂(E·W) = (2x - a, 2y), ∂k_i = ∂R_i)."""
    l3, l4 = p.l[2], p.l[3]
    R1, wx, R2, EW, k1, k2 = _curve_parts(p, x, y)
    A, S, C = l4 * l4, 2 * sigma * l3 * l4, l3 * l3
    out = []
    for dR1, dR2, dEW, extra in (
        (x * 2, wx * 2, x * 2 - p.a, 0),
        (y * 2, y * 2, y * 2, y * (8 * l3 * l3 * l4 * l4 * p.a * p.a)),
    ):
        out.append(
            (k1 * dR1 * R2 * 2 + k1 * k1 * dR2) * A
            - (dR1 * k2 * EW + k1 * dR2 * EW + k1 * k2 * dEW) * S
            + (k2 * dR2 * R1 * 2 + k2 * k2 * dR1) * C
            - extra
        )
    return out[0], out[1]


def reach(p: FiveBarParams, leg: int, x: Num, y: Num) -> tuple[Num, Num]:
    """The Type I factors of leg 1 or 2: (R - (lp + ld)², R - (lp - ld)²), zero where the
    leg is stretched or folded (D = -(R - (lp + ld)²)(R - (lp - ld)²)/4)."""
    lp, ld = p.l[leg - 1], p.l[leg + 1]
    u = x if leg == 1 else x - p.a
    R = u * u + y * y
    return R - (lp + ld) * (lp + ld), R - (lp - ld) * (lp - ld)


def polynomials(p: FiveBarParams) -> dict[str, Any]:
    """The locus and the Type I factors as exact polynomials in x, y (``fmpq_mpoly``):
    "S+", "S-" (``curve``), "D1", "D2" (the legs' discriminants), "R1", "R2" (|E|²,
    |E - B|²), for drawing the curves or composing them with a path."""
    x, y = fmpq_mpoly_ctx.get(("x", "y"), "lex").gens()
    c = conjugates(p, x, y)
    return {
        "S+": curve(p, 1, x, y), "S-": curve(p, -1, x, y),
        "D1": c.D1, "D2": c.D2, "R1": c.R1, "R2": c.R2,
    }  # fmt: skip


# -- inverse kinematics and dynamics (§2, §5) --------------------------------------------------
@dataclass(frozen=True)
class FiveBarLeg:
    """One leg at E: the elbow relative to the leg's base (c), the distal vector d = E - elbow,
    Δ = c × (E - base), the proximal and distal rates θ', φ' and accelerations θ'', φ''."""

    c: tuple[Num, Num]
    d: tuple[Num, Num]
    Delta: Num
    th_d: Num
    ph_d: Num
    th_dd: Num
    ph_dd: Num


def leg(
    p: FiveBarParams, i: int, e: int, x: Num, xd: Num, xdd: Num, y: Num, yd: Num, ydd: Num,
    root: Root,
) -> FiveBarLeg:  # fmt: skip
    """Leg i (1: links 1, 3 from A; 2: links 2, 4 from B) in working mode e = ±1."""
    lp, ld = p.l[i - 1], p.l[i + 1]
    u = x if i == 1 else x - p.a
    R = u * u + y * y
    K = (R + (lp * lp - ld * ld)) / 2
    s = root(R * (lp * lp) - K * K, i) * e
    c = ((K * u - s * y) / R, (K * y + s * u) / R)
    d = (u - c[0], y - c[1])
    Delta = c[0] * y - c[1] * u
    th_d = (d[0] * xd + d[1] * yd) / Delta
    ph_d = -(c[0] * xd + c[1] * yd) / Delta
    b = (
        xdd + th_d * th_d * c[0] + ph_d * ph_d * d[0],
        ydd + th_d * th_d * c[1] + ph_d * ph_d * d[1],
    )
    th_dd = (d[0] * b[0] + d[1] * b[1]) / Delta
    ph_dd = -(c[0] * b[0] + c[1] * b[1]) / Delta
    return FiveBarLeg(c, d, Delta, th_d, ph_d, th_dd, ph_dd)


def legs(
    p: FiveBarParams, modes: tuple[int, int], x: Num, xd: Num, xdd: Num, y: Num, yd: Num,
    ydd: Num, root: Root,
) -> tuple[FiveBarLeg, FiveBarLeg]:  # fmt: skip
    """Both legs from the end point E = (x, y) and its derivatives, in the working modes."""
    return (
        leg(p, 1, modes[0], x, xd, xdd, y, yd, ydd, root),
        leg(p, 2, modes[1], x, xd, xdd, y, yd, ydd, root),
    )


@dataclass(frozen=True)
class FiveBarDynamics:
    """The terms of §5 along a motion: the legs, the distal rows h1, h2 (moments about the
    elbows of the distal links' inertia and weight), the proximal rows Θ1, Θ2 (without
    the multiplier), δ = d1 × d2, ν (λ's axial part is ν/δ) and p."""

    leg1: FiveBarLeg
    leg2: FiveBarLeg
    h1: Num
    h2: Num
    Theta1: Num
    Theta2: Num
    delta: Num
    nu: Num
    p: FiveBarParams


def _rows(p: FiveBarParams, i: int, lg: FiveBarLeg) -> tuple[Num, Num]:
    """(h, Θ) of leg i (module docstring)."""
    lp, ld = p.l[i - 1], p.l[i + 1]
    mp_, md = p.m[i - 1], p.m[i + 1]
    Ip, Id = p.I[i - 1], p.I[i + 1]
    rp, rd = p.r[i - 1], p.r[i + 1]
    c, d = lg.c, lg.d
    dot = c[0] * d[0] + c[1] * d[1]
    cross = c[0] * d[1] - c[1] * d[0]
    k = md * rd / ld
    h = (
        lg.ph_dd * (Id + md * rd * rd)
        + (dot * lg.th_dd + cross * lg.th_d * lg.th_d) * k
        + d[0] * (md * p.g * rd / ld)
    )
    Theta = (
        lg.th_dd * (Ip + mp_ * rp * rp + md * lp * lp)
        + (dot * lg.ph_dd - cross * lg.ph_d * lg.ph_d) * k
        + c[0] * ((mp_ * rp + md * lp) * p.g / lp)
    )
    return h, Theta


def dynamics(leg1: FiveBarLeg, leg2: FiveBarLeg, p: FiveBarParams) -> FiveBarDynamics:
    """The equations of motion (§5) on the legs' joint values."""
    h1, Theta1 = _rows(p, 1, leg1)
    h2, Theta2 = _rows(p, 2, leg2)
    d1, d2 = leg1.d, leg2.d
    delta = d1[0] * d2[1] - d1[1] * d2[0]
    nu = (d1[0] * d2[0] + d1[1] * d2[1]) * h1 / p.l[2] + h2 * p.l[2]
    return FiveBarDynamics(leg1, leg2, h1, h2, Theta1, Theta2, delta, nu, p)


def efforts(d: FiveBarDynamics, alpha: Num) -> tuple[Num, Num]:
    """(T1, T2) [N m] given the distal links' axial force α (λ = α d1/l3 + (h1/l3) d1⊥/l3):
    T1 = Θ1 - c1 × λ, T2 = Θ2 + c2 × λ. Affine in α; α = ν/δ away from Type II."""
    l3 = d.p.l[2]
    u = d.leg1.d
    beta = d.h1 / l3
    lam = ((alpha * u[0] - beta * u[1]) / l3, (alpha * u[1] + beta * u[0]) / l3)
    c1, c2 = d.leg1.c, d.leg2.c
    T1 = d.Theta1 - (c1[0] * lam[1] - c1[1] * lam[0])
    T2 = d.Theta2 + (c2[0] * lam[1] - c2[1] * lam[0])
    return T1, T2


def torques(d: FiveBarDynamics) -> tuple[Num, Num]:
    """(T1, T2) [N m] away from a Type II singularity (δ != 0): α = ν/δ."""
    return efforts(d, d.nu / d.delta)


def consistency(d: FiveBarDynamics, sigma: int) -> Num:
    """The reciprocity residual w = h1/l3 + σ h2/l4 [N] (§6, eq. C1), σ frozen at its
    value at the Type II instant (+1: C and D on one side of E, -1: E between them)."""
    return d.h1 / d.p.l[2] + d.h2 * sigma / d.p.l[3]


def delta_rate(d: FiveBarDynamics) -> Num:
    """δ' = d1' × d2 + d1 × d2' [1/s], with d_i' = φ_i' d_i⊥ (the distal link turning)."""
    d1, d2 = d.leg1.d, d.leg2.d
    w1, w2 = d.leg1.ph_d, d.leg2.ph_d
    dot = d1[0] * d2[0] + d1[1] * d2[1]
    return (w2 - w1) * dot


class FiveBarMechanism:
    """The 5R behind the seam (``mechanism.py``'s contract, with ``root`` for ``hypot``):
    a namespace over this module's functions, so that layers reach the 5R through one
    object as they reach the RPRPR's schemes."""

    name = "5R"
    automatic = None  # one multiplier only: λ's axial part α = ν/δ carries any pole

    params = staticmethod(params)
    conjugates = staticmethod(conjugates)
    curve = staticmethod(curve)
    curve_gradient = staticmethod(curve_gradient)
    reach = staticmethod(reach)
    legs = staticmethod(legs)
    dynamics = staticmethod(dynamics)
    efforts = staticmethod(efforts)
    torques = staticmethod(torques)
    consistency = staticmethod(consistency)
    delta_rate = staticmethod(delta_rate)

    def robot_params(
        self, robot: Any, convert: Callable[[Any], Any] = lambda v: v
    ) -> FiveBarParams:
        """``params`` of a task's robot (``Robot.five_bar``, ``Robot.gravity``), as the
        seam's ``params(robot, convert)``."""
        return params(robot.five_bar, robot.gravity, convert)

    def locus(self, p: FiveBarParams, x: Any, y: Any) -> tuple[Any, Any]:
        """(S₊(x(t), y(t)), S₋(x(t), y(t))): polynomials in t whose real roots hold the
        Type II instants (``five_bar_instants`` decides which are the robot's)."""
        return curve(p, 1, x, y), curve(p, -1, x, y)


FIVE_BAR = FiveBarMechanism()

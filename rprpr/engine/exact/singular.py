"""Exact analysis of the Type II singular instants of a trajectory (Section 3 of the paper).

δ = sin(θ1 - θ2) = -a1 y_E / (s1 s2) (eq. 29), so while s1, s2 != 0 the Type II singular
instants are exactly the real roots of the polynomial y(t) = p(x(t)) in [0, t_f]. y(t) is
factored over Q into irreducible factors f^m; each real root t_s of f in [0, t_f] is
isolated and refined in rational arithmetic (``roots``: only the real roots in the span,
never all the complex ones, and no precision that escalates within one call) and m is
its multiplicity, the order of the singularity: δ, δ', ..., δ^(m-1) vanish at t_s and
δ^(m) does not. The expansions below are made once per factor (and sign pattern of the
legs) and moved to each of its roots.

About t_s every quantity of the paper is expanded as a power series in ε = t - t_s with
coefficients in K = Q[t]/(f) (``series``), so that "vanishes" is decided exactly:
 * consistency, eq. (34): σ (M22 s1'' + N2) + M44 s2'' + N4 = 0 at t_s, equivalently
   μ1(t_s) = μ2(t_s) = 0 (eq. 35);
 * boundedness: λ = μ/δ (eqs. 30-31) with δ of order m; λ is bounded exactly when μ1, μ2
   and their first m-1 derivatives vanish (the m conditions behind eqs. 36-38). The
   number k of these that hold, counted from the zeroth while they hold, leaves a pole of
   order m - k.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import field
from fractions import Fraction
from typing import Any

from flint import arb, fmpq, fmpq_poly

from ...model.cases import Case, case_of
from ...model.dataclass import dataclass
from ...model.numbers import exact_apart, exact_number, faithful, number
from ...model.task import Checks, Robot
from . import equations as dyn
from .kept import Kept, exact_key, robot_key
from .mechanism import Mechanism, of
from .roots import RootAt, real_roots_in
from .series import KElem, NumberField, QSeries, Series, ball, is_zero, real, sign, taylor
from .trajectory import Trajectory


@dataclass(frozen=True)
class Principle:
    """One design principle at one singular instant: passed, and why (or why not)."""

    passed: bool
    reason: str


@dataclass(frozen=True)
class SingularInstant:
    """A Type II singular instant t_s and everything the audit decides there.

    ``delta_derivatives[k]`` is d^k δ/dt^k at t_s for k = 0..order; ``conditions_met`` is k
    above; ``torque_at_singularity`` is the finite limit (T1, T2) [N m] when bounded.
    Every float is the double nearest the exact value (±inf beyond the double range);
    ``beyond_double_range`` = ((name, exact value as text), ...) for each quantity whose
    double is not faithful (``numbers.faithful``): ``("speed", "1.41421e+400")``,
    ``("delta_derivatives[1]", ...)``, ``("torque_at_singularity[0]", ...)``.
    ``t_exact`` is t_s as a ``fractions.Fraction`` when it is rational (``t_exact ==
    2.5``, ``str(t_exact) == "5/2"``), None when it is irrational (an algebraic number:
    ``t`` is then the double nearest it, and the engine keeps it exactly as a root of
    y(t) isolated in a ball). What only the sampler needs (the number field of t_s, the
    orders of μ, the sign of y) is kept apart, private to the engine, in
    ``SingularAnalysis``.
    """

    t: float
    x: float
    t_exact: Fraction | None  # t_s exactly when rational (see ``t_rational``), else None
    case: Case
    order: int
    delta_m: float  # d^m δ/dt^m at t_s, m = ``order`` (the lower derivatives vanish)
    slope: float
    speed: float
    slope_principle: Principle
    velocity_principle: Principle
    consistency_residual: float
    consistent: bool
    conditions_met: int  # k of the ``order`` conditions (eqs. 34-38) that hold
    torque_at_singularity: tuple[float, float] | None
    beyond_double_range: tuple[tuple[str, str], ...] = ()
    knot: bool = False  # t_s is a break of a piecewise motion (0 and t_f included)
    sides: tuple[tuple[str, SingularInstant], ...] = ()  # ("before", s), ("after", s)

    def side(self, name: str) -> SingularInstant | None:
        """The one-sided analysis ``name`` ("before" or "after") at a knot, else None."""
        return dict(self.sides).get(name)

    @property
    def t_rational(self) -> fmpq | None:
        """``t_exact`` as the engine's exact rational (``flint.fmpq``), None when t_s is
        irrational (a root of an irreducible factor of y(t) of degree 2 or more)."""
        e = self.t_exact
        return None if e is None else fmpq(e.numerator, e.denominator)

    def number(self, name: str) -> str:
        """The quantity ``name`` (``x``, ``slope``, ...) as text: ``numbers.number`` of its
        double, or its exact value where that double is not faithful."""
        return dict(self.beyond_double_range).get(name) or number(getattr(self, name))

    @property
    def y(self) -> float:
        """E is on the line AB: y(t_s) = 0."""
        return 0.0

    @property
    def delta_derivatives(self) -> list[float]:
        """d^k δ/dt^k at t_s for k = 0..order: zero but the last, ``delta_m``."""
        return [0.0] * self.order + [self.delta_m]

    @property
    def conditions_required(self) -> int:
        """The conditions for bounded torques at an instant of order m: m (eqs. 34-38)."""
        return self.order

    @property
    def kind(self) -> str:
        return "crossing" if self.order % 2 else "touch"

    @property
    def high_order(self) -> bool:
        """δ' = 0 at t_s (eq. 39): a high-order singularity."""
        return self.order >= 2

    @property
    def torque_bounded(self) -> bool:
        return self.conditions_met >= self.conditions_required

    @property
    def pole_order(self) -> int:
        return self.conditions_required - self.conditions_met


@dataclass(frozen=True)
class KinematicSingularity:
    """E at A (leg 1, s1 = 0) or at B (leg 2, s2 = 0) at time t: the inverse kinematics fail."""

    t: float
    x: float
    y: float
    leg: int
    order: int = 1  # multiplicity of the root of y(t) there
    beyond_double_range: tuple[tuple[str, str], ...] = ()  # as in SingularInstant: ("t", ...)


@dataclass(frozen=True)
class _SamplerHints:
    """What the float sampler needs at a singular instant beyond what the audit reports
    (private to the engine): the number field K = Q[t]/(f) of t_s, the orders of the first
    nonzero terms of μ1 and μ2 (at most order + 1), and the sign of the first nonzero
    Taylor coefficient of y at t_s."""

    field: NumberField
    mu_valuations: tuple[int, int]
    y_leading_sign: int


@dataclass(frozen=True)
class SingularAnalysis:
    """The singular instants of a motion, in time order.

    ``_hints[i]`` (private to the engine: the sampler reads it) belongs to ``instants[i]``;
    ``_kinematic_signs[j]`` is the sign of the first nonzero Taylor coefficient of y at
    ``kinematic[j]`` (1 where it does not matter: E at B, or a motion on y = 0).
    """

    instants: list[SingularInstant]
    kinematic: list[KinematicSingularity]
    on_singular_line: bool  # y(t) is identically zero: the whole motion is singular
    _hints: tuple[_SamplerHints, ...] = field(repr=False, compare=False)
    _kinematic_signs: tuple[int, ...] = field(repr=False, compare=False)
    # a motion of several pieces: for each instant, the pieces' own (index, local instant)
    # it was joined from (two at a knot); empty for one piece: the instants are its own
    _sources: tuple[tuple[tuple[int, SingularInstant], ...], ...] = field(
        default=(), repr=False, compare=False
    )

    def hints(self, s: SingularInstant) -> _SamplerHints:
        """The engine's private record of the instant ``s`` (one of ``instants``)."""
        return next(h for i, h in zip(self.instants, self._hints, strict=True) if i is s)

    def kinematic_sign(self, k: KinematicSingularity) -> int:
        """The sign of y's first nonzero Taylor coefficient at ``k`` (one of ``kinematic``)."""
        return next(g for i, g in zip(self.kinematic, self._kinematic_signs, strict=True) if i is k)

    def __post_init__(self) -> None:
        if len(self._hints) != len(self.instants):
            raise ValueError("one sampler record is needed per singular instant")
        if len(self._kinematic_signs) != len(self.kinematic):
            raise ValueError("one sign is needed per kinematic singularity")


OnStage = Callable[[str], None]  # told the name of each stage of the analysis as it begins

# the stages of the exact analysis, named for "exceeded its budget at ..." (``audit.STAGES``)
FACTORING = "the factorisation of y(t)"
ISOLATING = "the isolation of the real roots of y(t)"
EXPANDING = "the series about the singular instants"


def _quiet(stage: str) -> None:
    """An ``OnStage`` that listens to nothing."""


def _passage(
    exact: fmpq | None, at: RootAt, x: float, leg: int, order: int = 1
) -> KinematicSingularity:
    """E at A (leg 1) or B (leg 2) at the root ``exact`` (or ball ``at``) of y(t)."""
    beyond: list[tuple[str, str]] = []
    t = _double("t", exact if exact is not None else at(128), beyond)
    return KinematicSingularity(t, x, 0.0, leg, order, tuple(beyond))


def analyse(
    traj: Trajectory, robot: Robot, checks: Checks, on_stage: OnStage = _quiet
) -> SingularAnalysis:
    """Every Type II and inverse-kinematic singular instant of ``traj`` in [0, t_f];
    ``on_stage`` is told each stage (FACTORING, ISOLATING, EXPANDING) as it begins."""
    y = of(robot).locus(traj.x, traj.y)
    if y.is_zero():
        on_line = _kinematic_on_line(traj)
        return SingularAnalysis([], on_line, True, (), (1,) * len(on_line))
    instants: list[tuple[SingularInstant, _SamplerHints]] = []
    kinematic: list[tuple[KinematicSingularity, int]] = []
    on_stage(FACTORING)
    _, factors = y.factor()
    for f, m in factors:
        if f.degree() < 1:
            continue
        done: Expansions = {}
        on_stage(ISOLATING)
        roots = real_roots_in(f, traj.duration, simple=True)
        on_stage(EXPANDING)
        for exact, at in roots:
            if (traj.x % f).is_zero():
                # E at A lies on leg 2's branch cut: its sign change keeps θ2 continuous
                lead = taylor(traj.y, int(m) + 1)[int(m)]
                ys = sign(lead(exact)) if exact is not None else NumberField(f, at).sign(lead % f)
                kinematic.append((_passage(exact, at, 0.0, 1, int(m)), ys))
                continue
            if ((traj.x - traj.a1) % f).is_zero():
                kinematic.append((_passage(exact, at, float(arb(traj.a1)), 2), 1))
                continue
            instants.append(_instant(traj, robot, checks, f, int(m), exact, at, done))
    instants.sort(key=lambda pair: pair[0].t)
    kinematic.sort(key=lambda pair: pair[0].t)
    return SingularAnalysis(
        [s for s, _ in instants],
        [k for k, _ in kinematic],
        False,
        tuple(h for _, h in instants),
        tuple(ys for _, ys in kinematic),
    )


def _kinematic_on_line(traj: Trajectory) -> list[KinematicSingularity]:
    """For a motion on y = 0: the instants at which E passes A or B."""
    out = []
    for poly, leg, xv in ((traj.x, 1, 0.0), (traj.x - traj.a1, 2, float(arb(traj.a1)))):
        if poly.is_zero():
            out.append(KinematicSingularity(0.0, xv, 0.0, leg))
            continue
        for exact, at in real_roots_in(poly, traj.duration):
            out.append(_passage(exact, at, xv, leg))
    return sorted(out, key=lambda k: k.t)


def expansion(
    traj: Trajectory, field: NumberField, n: int, exact: fmpq | None = None
) -> tuple[Series, Series, Series, Series, Series, Series]:
    """Exact series (n terms) of x, x', x'', y, y', y'' about t_s: in Q when the rational
    t_s = ``exact`` is given, else in K = Q[t]/(f)."""
    at: Any = (lambda c: c(exact)) if exact is not None else field.elem
    return _series([[at(c) for c in taylor(p, n + 2)] for p in (traj.x, traj.y)], n)


def _series(es: list[list[Any]], n: int) -> tuple[Series, Series, Series, Series, Series, Series]:
    """``expansion`` from the n + 2 Taylor coefficients at t_s of x and of y (``es``)."""
    kind: Any = Series if type(es[0][0]) is KElem else QSeries
    out = []
    for e in es:
        out.append(kind(e[:n]))
        out.append(kind([(k + 1) * e[k + 1] for k in range(n)]))
        out.append(kind([(k + 1) * (k + 2) * e[k + 2] for k in range(n)]))
    return out[0], out[1], out[2], out[3], out[4], out[5]


def legs(
    mech: Mechanism, p: dyn.Params, X: Series, Xd: Series, Xdd: Series, Y: Series,
    Yd: Series, Ydd: Series, sx: int, sxa: int,
) -> tuple[dyn.Leg, dyn.Leg]:  # fmt: skip
    """Both legs' series; s1(t_s) = |x(t_s)| and s2(t_s) = |x(t_s) - a1| since y(t_s) = 0."""

    def hyp(sign: int) -> Callable[[Series, Series], Series]:
        return lambda u, v: (u * u + v * v).sqrt_with(u.c[0] * sign)

    return mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, hyp(sx), hyp(sxa))


@dataclass(frozen=True)
class _Expanded:
    """What the audit reads of the exact expansions about a root t_s of f^m, for one
    choice of the legs' signs s1 = sx x(t_s), s2 = sxa (x(t_s) - a1): as elements of
    K = Q[t]/(f) these are the same at every root of f with those signs (only their
    values differ), so they are computed once per factor and signs (``on`` moves them to
    another root's field); plain rationals when t_s is rational."""

    delta_m: Any  # the coefficient of ε^m of δ (eq. 29)
    mu_valuations: tuple[int, int]  # orders of the first nonzero terms of μ1, μ2
    residual: tuple[Any, Any]  # the consistency residual at t_s (``dyn.consistency``)
    limit: tuple[Any, Any] | None  # (T1, T2) at t_s when λ bounded; in K (num, den) each
    speed2: Any  # x'(t_s)^2 + y'(t_s)^2
    y_m: Any  # the coefficient of ε^m of y

    def on(self, field: NumberField) -> _Expanded:
        """The same elements at another root of the same f."""

        def move(v: Any) -> Any:
            if isinstance(v, tuple):
                return tuple(move(x) for x in v)
            return KElem(v.p, field) if isinstance(v, KElem) else v

        limit = None if self.limit is None else move(self.limit)
        return _Expanded(
            move(self.delta_m), self.mu_valuations,
            (move(self.residual[0]), move(self.residual[1])), limit,
            move(self.speed2), move(self.y_m),
        )  # fmt: skip


def _expanded(
    traj: Trajectory, robot: Robot, K: NumberField, m: int, exact: fmpq | None,
    sx: int, sxa: int, case: Case,
) -> _Expanded:  # fmt: skip
    """The exact expansions about t_s (orders 0..m: the m conditions and the limit) and
    what the audit reads of them; at a rational t_s, made once per exact data (Taylor
    coefficients of x and y there, order, legs' signs, robot: ``_MADE``), so that a motion
    that repeats itself (a zig-zag, a repair's candidates) expands each instant once."""
    if exact is None:
        return _expand(expansion(traj, K, m + 1), robot, m, sx, sxa, case)
    es = [[c(exact) for c in taylor(q, m + 3)] for q in (traj.x, traj.y)]
    key = (exact_key(es), robot_key(robot), m, sx, sxa)
    return _MADE.get(key, lambda: _expand(_series(es, m + 1), robot, m, sx, sxa, case))


def _expand(
    series: tuple[Any, ...], robot: Robot, m: int, sx: int, sxa: int, case: Case
) -> _Expanded:
    """``_expanded`` from the series of x and y (with derivatives) about t_s."""
    X, Xd, Xdd, Y, Yd, Ydd = series
    mech = of(robot)
    p = mech.params(robot)
    assert all(is_zero(c) for c in Y.c[:m]) and not is_zero(Y.c[m])
    leg1, leg2 = legs(mech, p, X, Xd, Xdd, Y, Yd, Ydd, sx, sxa)
    d = mech.dynamics(leg1, leg2, p)
    if d.delta.valuation() != m:  # δ = -a1 y/(s1 s2): same order as y
        raise AssertionError("order of δ differs from the multiplicity of y")
    valuations = (d.mu1.valuation(), d.mu2.valuation())
    return _Expanded(
        delta_m=d.delta.c[m],
        mu_valuations=valuations,
        residual=mech.consistency(d, case.sigma, lambda v: v.c[0]),  # exact
        limit=_limit_torque(mech, d, m) if min(*valuations, m) >= m else None,
        speed2=Xd.c[0] * Xd.c[0] + Yd.c[0] * Yd.c[0],
        y_m=Y.c[m],
    )


# the expansions about rational instants, by the exact data they are made from
# (``_expanded``; ``exact.kept``): rationals and tuples of them, never changed
MADE_KEPT = 512
_MADE: Kept[_Expanded] = Kept(MADE_KEPT)


Expansions = dict[tuple[int, int], _Expanded]  # (sx, sxa) -> expansions, for one factor


def _instant(
    traj: Trajectory,
    robot: Robot,
    checks: Checks,
    f: fmpq_poly,
    m: int,
    exact: fmpq | None,
    at: RootAt,
    done: Expansions,
) -> tuple[SingularInstant, _SamplerHints]:
    """The singular instant at the root ``exact`` (or ball ``at``) of f^m; ``done`` holds
    the expansions already made at other roots of f (and gains this root's)."""
    K = NumberField(f, at)
    x0 = traj.x(exact) if exact is not None else K.elem(traj.x)
    sx, sxa = sign(x0), sign(x0 - traj.a1)
    case = case_of(sx, sxa)
    if (sx, sxa) in done:
        e = done[sx, sxa].on(K)
    else:
        e = done[sx, sxa] = _expanded(traj, robot, K, m, exact, sx, sxa, case)
    k = min(*e.mu_valuations, m)
    # the design principles: path slope dy/dx and end-point speed at t_s
    if traj.path is not None:
        slope: Any = traj.slope(exact) if exact is not None else K.elem(traj.slope)
        slope_principle = _slope_principle(slope, checks.min_slope)
    else:
        slope, slope_principle = _tangent_slope(traj, K, exact, checks.min_slope)
    speed = _speed(e.speed2)
    beyond: list[tuple[str, str]] = []  # filled in the order of the fields
    t = _double("t", exact if exact is not None else at(128), beyond)
    x = _double("x", x0, beyond)
    delta_m = _double(f"delta_derivatives[{m}]", e.delta_m * math.factorial(m), beyond)
    slope_f = _double("slope", slope, beyond)
    speed_f = _double("speed", speed, beyond)
    residual_f = _double("consistency_residual", _residual(*e.residual), beyond)
    torque = None
    if e.limit is not None:  # in K, the quotient at this root (``_limit_torque``)
        t1, t2 = (_quotient(*v) if isinstance(v, tuple) else v for v in e.limit)
        torque = (
            _double("torque_at_singularity[0]", t1, beyond),
            _double("torque_at_singularity[1]", t2, beyond),
        )
    instant = SingularInstant(
        t=t,
        x=x,
        t_exact=None if exact is None else Fraction(int(exact.p), int(exact.q)),
        case=case,
        order=m,
        delta_m=delta_m,
        slope=slope_f,
        speed=speed_f,
        slope_principle=slope_principle,
        velocity_principle=_velocity_principle(e.speed2, speed, checks.min_speed),
        consistency_residual=residual_f,
        consistent=is_zero(e.residual[0]),
        conditions_met=k,
        torque_at_singularity=torque,
        beyond_double_range=tuple(beyond),
    )
    return instant, _SamplerHints(K, e.mu_valuations, sign(e.y_m))


def _residual(numerator: Any, denominator: Any) -> Any:
    """The residual's value: exact when rational, a ball in K (no inverse taken there)."""
    if denominator is None:
        return numerator
    if isinstance(numerator, KElem):
        return _quotient(numerator, denominator)
    return numerator / denominator


def _limit_torque(mech: Mechanism, d: dyn.Dynamics, m: int) -> tuple[Any, Any]:
    """(T1, T2) at t_s when λ is bounded there: λ = μ^(m)/δ^(m) (eqs. 30-31), exactly when
    t_s is rational. In K the torque is only reported, so no inverse is taken there (an
    inverse in K can cost seconds: its numbers grow like a resultant's): eq. (28) is
    affine in λ, T = A + B1 λ1 + B2 λ2, so T = (A δ^(m) + B1 μ1^(m) + B2 μ2^(m)) / δ^(m)
    with an exact numerator, and that one division is made in ball arithmetic at each
    root of f (``_instant``): here, in K, (numerator, δ^(m)) for each torque."""
    D, N1, N2 = d.delta.c[m], d.mu1.c[m], d.mu2.c[m]
    if not isinstance(D, KElem):
        T1, T2 = mech.efforts(d, QSeries([N1 / D]), QSeries([N2 / D]))
        return T1.c[0], T2.c[0]
    zero, one = D * 0, D * 0 + 1
    A = mech.efforts(d, Series([zero]), Series([zero]))
    B1 = mech.efforts(d, Series([one]), Series([zero]))
    B2 = mech.efforts(d, Series([zero]), Series([one]))
    out = []
    for a, b1, b2 in zip(A, B1, B2, strict=True):
        a0 = a.c[0]
        numerator = a0 * D + (b1.c[0] - a0) * N1 + (b2.c[0] - a0) * N2
        out.append((numerator, D))
    return out[0], out[1]


def _quotient(numerator: KElem, denominator: KElem) -> arb:
    """numerator/denominator as a ball of about 80 bits or more (0 exactly when the
    numerator is)."""
    if numerator.is_zero():
        return arb(0)
    return numerator.field.accurate(numerator.p, 80) / denominator.field.accurate(denominator.p, 80)


def _double(name: str, value: Any, beyond: list[tuple[str, str]]) -> float:
    """The double nearest ``value`` (a rational, a KElem, a ball, or a double already);
    where it is not faithful (beyond the double range), ``(name, exact value as text)``
    joins ``beyond``."""
    if isinstance(value, float):
        return value
    if isinstance(value, arb):
        f, zero = float(value.mid()), value.is_zero()
    else:
        f, zero = real(value), is_zero(value)
    if not faithful(f, zero):
        beyond.append((name, exact_number(value if isinstance(value, arb | fmpq) else ball(value))))
    return f


def _shown(value: Any) -> arb | fmpq:
    """What a message prints of an exact value (a rational, a KElem or a ball): its double
    when faithful (so that the message reads as ``numbers.number`` of the reported
    double), else the exact value."""
    if isinstance(value, arb):
        f, zero = float(value.mid()), value.is_zero()
        return arb(f) if faithful(f, zero) else value
    f = real(value)
    if faithful(f, is_zero(value)):
        return arb(f)
    return value if isinstance(value, fmpq) else ball(value)


def _speed(speed2: Any) -> arb | float:
    """The speed from its square: the square root of the double of speed^2 when that is
    faithful, else of its exact value (a ball)."""
    f = real(speed2)
    if faithful(f, is_zero(speed2)):
        return math.sqrt(max(f, 0.0))
    return ball(speed2).sqrt()


def _slope_principle(slope: Any, min_slope: fmpq) -> Principle:
    """|dy/dx| > min_slope, decided exactly (slope: KElem or fmpq)."""
    if min_slope == 0:
        if is_zero(slope):
            return Principle(
                False, "the path is horizontal here (dy/dx = 0, eq. 48): a high-order singularity"
            )
        return Principle(True, f"dy/dx = {exact_number(_shown(slope))} is nonzero")
    diff = slope * slope - min_slope * min_slope
    if sign(diff) > 0:
        return Principle(
            True,
            "|dy/dx| = {} exceeds checks.min_slope = {}".format(
                *exact_apart(abs(_shown(slope)), min_slope)
            ),
        )
    if is_zero(slope):
        return Principle(
            False, "the path is horizontal here (dy/dx = 0, eq. 48): a high-order singularity"
        )
    return Principle(
        False,
        "|dy/dx| = {} does not exceed the margin checks.min_slope = {}".format(
            *exact_apart(abs(_shown(slope)), min_slope)
        ),
    )


def _tangent_slope(
    traj: Trajectory, K: NumberField, exact: fmpq | None, min_slope: fmpq
) -> tuple[Any, Principle]:
    """dy/dx at t_s for a motion given as x(t), y(t) (no path): the slope of the tangent,
    ẏ/ẋ, or where the end point is at rest the limit direction y^(k)/x^(k) of the lowest
    derivatives k >= 1 that do not both vanish. A vertical tangent (x^(k) = 0) has an
    infinite slope (``inf``: JSON null) and passes; no direction at all (x, y constant)
    is slope 0. The principle |dy/dx| > min_slope is decided exactly as
    |y^(k)| > min_slope |x^(k)|."""
    dx: Any = 0
    dy: Any = 0
    px, py = traj.x, traj.y
    for _ in range(max(px.degree(), py.degree(), 0)):
        px, py = px.derivative(), py.derivative()
        dx = px(exact) if exact is not None else K.elem(px)
        dy = py(exact) if exact is not None else K.elem(py)
        if not (is_zero(dx) and is_zero(dy)):
            break
    if is_zero(dx) and not is_zero(dy):
        return math.inf, Principle(
            True, "the tangent is vertical here (dx/dt = 0): |dy/dx| is infinite"
        )
    slope = dy / dx if not is_zero(dx) else fmpq(0)
    return slope, _slope_principle(slope, min_slope)


def _velocity_principle(speed2: Any, speed: arb | float, min_speed: fmpq) -> Principle:
    """speed > min_speed, decided exactly on speed^2 (KElem or fmpq); ``speed`` is only
    printed (``_speed``)."""
    if is_zero(speed2):
        return Principle(
            False, "the end point is at rest here (speed 0, eq. 47): a high-order singularity"
        )
    shown = _shown(speed if isinstance(speed, arb) else arb(speed))
    if min_speed == 0:
        return Principle(True, f"speed {exact_number(shown)} m/s is nonzero")
    if sign(speed2 - min_speed * min_speed) > 0:
        return Principle(
            True,
            "speed {} m/s exceeds checks.min_speed = {} m/s".format(*exact_apart(shown, min_speed)),
        )
    return Principle(
        False,
        "speed {} m/s does not exceed the margin checks.min_speed = {} m/s".format(
            *exact_apart(shown, min_speed)
        ),
    )

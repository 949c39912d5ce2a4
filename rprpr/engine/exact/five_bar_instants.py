"""The 5R's Type II instants along a motion, exactly (docs/five-bar.md §3-6).

For a motion E(t) = (x(t), y(t)) with rational polynomial coordinates on [t0, t1]:

* **Type I first.** The legs' working modes e1, e2 (given at t0) are followed
  continuously: they cannot change while the discriminants D1, D2 stay positive, which
  fails exactly where a leg is stretched or folded, at a root of R_i - (lp ± ld)²
  (``five_bar.reach``). A path that reaches one is refused from there on: the analysis
  lists the first such instant (``TypeOne``, leg and kind; both legs when they meet it at
  once), as the RPRPR reports E at A or B, and the Type II instants strictly before it
  (the working modes are known up to it); a start out of a leg's reach is an error.
* **The candidates.** S₊(E(t)) and S₋(E(t)) (``five_bar.curve``) are factored over Q and
  their real roots in the span isolated exactly (``roots.real_roots_in``): rational, or
  irrational in a rational interval refined on demand. A root common to both is one
  candidate.
* **The mode.** At a candidate the product of the four modes' δ vanishes; the robot's is
  decided by ball evaluation of the four conjugates (its ball excludes 0: another mode's
  instant; the other three exclude 0: the robot's, alone), else exactly in K(√D1, √D2)
  (``radicals``).
* **The order.** Alone, the robot's δ vanishes to the order of t_s in S₊ S₋(E(t)), the
  root's multiplicity (§4); where another mode is singular too (the node of equal-link
  robots, S₊ ∩ S₋), it is read from δ's own exact series.
* **The principles** (§4): transversality ∇S_σ·E' != 0, with the margin tan α =
  |∇S_σ·E'|/|∇S_σ × E'| (α the crossing angle; at rest, along the first nonzero
  derivative of E), against ``min_slope``; speed |E'| against ``min_speed``.
* **Consistency and the high-order conditions** (§6): w^(j)(t_s) = 0 for j < k (σ
  frozen), the limit torques when all k hold (``five_bar_expansion``).
"""

from __future__ import annotations

import math
from typing import Any

from flint import arb, ctx, fmpq, fmpq_poly

from ...model.dataclass import dataclass
from ...model.numbers import exact_apart, exact_number
from . import five_bar as fb
from . import five_bar_expansion as xp
from .roots import RootAt, real_roots_in
from .series import is_zero, sign
from .singular import Principle

ZERO = fmpq(0)


class FiveBarError(ValueError):
    """A 5R motion the analysis cannot take (the message says why and where)."""


@dataclass(frozen=True)
class TypeOne:
    """A Type I (serial) singularity on the path: leg 1 or 2 stretched (|E - base| =
    lp + ld) or folded (|lp - ld|) at t (``t_exact`` when rational)."""

    leg: int
    kind: str  # "stretched" or "folded"
    t: float
    t_exact: fmpq | None
    piece: int = 0  # the piece of the motion it lies on (0-based)


@dataclass(frozen=True)
class FiveBarInstant:
    """A Type II instant of the robot in its working modes, and what is decided there.

    Exact values are ``fmpq`` where t_s and the elbows are rational, else certified
    ``arb`` balls (zero decided exactly all the same: ``consistent``, ``conditions_met``).
    At a break of a piecewise motion (``knot``) the fields are the conservative
    combination of the one-sided analyses in ``sides`` (``five_bar_audit.at_knot``).
    """

    t: float
    t_exact: fmpq | None
    t_ball: arb
    x: float
    y: float
    modes: tuple[int, int]
    sigma: int  # -1: E between the elbows, +1: C and D on one side of E
    order: int  # of δ at t_s
    multiplicity: int  # of t_s in S₊ S₋(E(t))
    degenerate: bool  # another working mode is singular at t_s too
    delta_k: Any  # d^k δ/dt^k at t_s, k = order, δ = (E - C) × (E - D) [m²/s^k]
    normal_rate: Any  # ∇S_σ·E' at t_s (zero: tangent or at rest)
    slope: Any  # tan α (``math.inf``: the path crosses along the normal)
    speed2: Any  # |E'(t_s)|²
    slope_principle: Principle
    velocity_principle: Principle
    residuals: tuple[Any, ...]  # w^(j)(t_s) [N/s^j], j = 0..order - 1
    conditions_met: int
    torque_at_singularity: tuple[Any, Any] | None  # (T1, T2) [N m] when bounded
    knot: bool = False  # t_s is a break of a piecewise motion (0 and t_f included)
    sides: tuple[tuple[str, FiveBarInstant], ...] = ()  # then its one-sided analyses

    @property
    def consistency_residual(self) -> Any:
        return self.residuals[0]

    @property
    def consistent(self) -> bool:
        return self.conditions_met >= 1

    @property
    def bounded(self) -> bool:
        return self.conditions_met == self.order


@dataclass(frozen=True)
class FiveBarAnalysis:
    """The Type II instants of a 5R motion in time order and (``type_one`` non-empty) the
    first Type I instant, which stops the analysis: the instants are those before it;
    ``locus``: S₊(E(t)), S₋(E(t)) in absolute time; ``on_curve``: S₊ or S₋ vanishes all
    along the motion (every instant is a Type II singularity: no instant is listed)."""

    instants: tuple[FiveBarInstant, ...]
    type_one: tuple[TypeOne, ...]
    locus: tuple[fmpq_poly, fmpq_poly]
    on_curve: bool = False

    @property
    def refused(self) -> bool:
        return bool(self.type_one)


def analyse(
    five_bar: fb.FiveBarRobot, gravity: fmpq, x: fmpq_poly, y: fmpq_poly, t0: fmpq, t1: fmpq,
    min_slope: fmpq = ZERO, min_speed: fmpq = ZERO,
    local: tuple[fmpq_poly, fmpq_poly] | None = None,
) -> FiveBarAnalysis:  # fmt: skip
    """Every Type II instant of the motion (x(t), y(t)), t0 <= t <= t1, of ``five_bar``
    in its working modes (those at t0), exactly (module docstring). ``local``, when given,
    is the same motion in the local time u = t - t0 (a planner's segment: shorter
    rationals); the instants' times are absolute all the same."""
    p = fb.params(five_bar, gravity)
    modes = (int(five_bar.modes[0]), int(five_bar.modes[1]))
    if local is None:
        shift = fmpq_poly([t0, 1])
        X, Y = x(shift), y(shift)  # local time u = t - t0
    else:
        X, Y = local
    duration = t1 - t0
    locus = (fb.curve(p, 1, x, y), fb.curve(p, -1, x, y))
    _start(p, X, Y)
    type_one, first = _type_one(p, X, Y, duration, t0)
    curves = {sigma: fb.curve(p, sigma, X, Y) for sigma in (1, -1)}  # S±(E(u))
    if any(S.is_zero() for S in curves.values()):
        return FiveBarAnalysis((), type_one, locus, on_curve=True)
    found = []
    for cand in _candidates(curves, duration):
        if first is not None and not _before(cand, first):
            continue  # at or after the first Type I instant: the working modes are lost
        instant = _instant(p, modes, X, Y, t0, cand, min_slope, min_speed)
        if instant is not None:
            found.append(instant)
    found.sort(key=lambda i: (i.t, float(i.t_ball.mid())))
    return FiveBarAnalysis(tuple(found), type_one, locus)


def analyse_robot(
    robot: Any, x: fmpq_poly, y: fmpq_poly, t0: fmpq, t1: fmpq,
    min_slope: fmpq = ZERO, min_speed: fmpq = ZERO,
    local: tuple[fmpq_poly, fmpq_poly] | None = None,
) -> FiveBarAnalysis:  # fmt: skip
    """``analyse`` for a task's robot (``Robot.five_bar`` and ``Robot.gravity``)."""
    return analyse(robot.five_bar, robot.gravity, x, y, t0, t1, min_slope, min_speed, local)


def _start(p: fb.FiveBarParams, X: fmpq_poly, Y: fmpq_poly) -> None:
    c = fb.conjugates(p, X, Y)
    for i, D in ((1, c.D1), (2, c.D2)):
        if D(0) < 0:
            raise FiveBarError(
                f"the start point ({exact_number(X(0))}, {exact_number(Y(0))}) is out of "
                f"leg {i}'s reach: |E - {'AB'[i - 1]}| must lie between "
                f"|l{i} - l{i + 2}| and l{i} + l{i + 2}"
            )


@dataclass(frozen=True)
class _Root:
    """A real root in the local span: exact when rational, else the ``index``-th root of
    the monic irreducible ``f`` (roots of one factor in increasing order) and its balls."""

    exact: fmpq | None
    f: fmpq_poly
    index: int
    at: RootAt

    @property
    def key(self) -> Any:
        return self.exact if self.exact is not None else (str(self.f), self.index)


def _roots(g: fmpq_poly, duration: fmpq) -> list[_Root]:
    out = []
    for f, _ in g.factor()[1]:
        if f.degree() < 1:
            continue
        monic = f / f[f.degree()]
        for index, (exact, at) in enumerate(real_roots_in(monic, duration, simple=True)):
            out.append(_Root(exact, monic, index, at))
    return out


def _type_one(
    p: fb.FiveBarParams, X: fmpq_poly, Y: fmpq_poly, duration: fmpq, t0: fmpq
) -> tuple[tuple[TypeOne, ...], _Root | None]:
    """The first Type I instant in the span (each leg and kind met there), and its root."""
    found: list[tuple[TypeOne, _Root]] = []
    for leg in (1, 2):
        for kind, g in zip(("stretched", "folded"), fb.reach(p, leg, X, Y), strict=True):
            if g.is_zero():
                root = _Root(ZERO, fmpq_poly([0, 1]), 0, _zero_ball)
                found.append((TypeOne(leg, kind, float(t0), t0), root))
                continue
            for r in _roots(g, duration):
                t = t0 + r.exact if r.exact is not None else None
                found.append((TypeOne(leg, kind, _float(t0, r.exact, r.at), t), r))
    if not found:
        return (), None
    first = found[0][1]
    for _, r in found[1:]:
        if _earlier(r, first):
            first = r
    return tuple(k for k, r in found if r.key == first.key), first


def _zero_ball(prec: int) -> arb:
    return arb(0)


def _earlier(a: Any, b: _Root) -> bool:
    """Whether the root ``a`` (a ``_Root`` or a candidate) lies strictly before ``b``,
    decided exactly: rationals compared, roots of one irreducible factor by their order,
    roots of distinct irreducible factors (never equal) by balls narrowed until apart."""
    if a.exact is not None and b.exact is not None:
        return bool(a.exact < b.exact)
    if a.exact is None and b.exact is None and a.f == b.f:
        return bool(a.index < b.index)
    prec = 64
    while True:
        lo, hi = a.at(prec), b.at(prec)
        if lo < hi:
            return True
        if lo > hi:
            return False
        prec *= 2


def _before(cand: _Candidate, first: _Root) -> bool:
    """Whether the candidate lies strictly before the first Type I instant."""
    return _earlier(cand, first)


def _float(t0: fmpq, exact: fmpq | None, at: RootAt) -> float:
    if exact is not None:
        return float(t0 + exact)
    return float(_ball(t0, at).mid())


def _ball(t0: fmpq, at: RootAt) -> arb:
    """t0 + the root, as a ball of about 128 bits."""
    old = ctx.prec
    ctx.prec = 136
    try:
        return at(128) + arb(t0)
    finally:
        ctx.prec = old


@dataclass(frozen=True)
class _Candidate:
    """A real root of S₊ S₋(E(u)) in the local span: its factor f, the root (exact or
    ball) and its multiplicity in S₊(E(u)) and S₋(E(u))."""

    f: fmpq_poly
    exact: fmpq | None
    at: RootAt
    multiplicity: dict[int, int]
    index: int = 0  # among the real roots of f in the span, in increasing order


def _candidates(curves: dict[int, fmpq_poly], duration: fmpq) -> list[_Candidate]:
    """The real roots of S₊(E(u)) S₋(E(u)) in [0, duration] (neither is zero)."""
    found: dict[Any, _Candidate] = {}
    for sigma, S in curves.items():
        for f, m in S.factor()[1]:
            if f.degree() < 1:
                continue
            monic = f / f[f.degree()]
            for index, (exact, at) in enumerate(real_roots_in(monic, duration, simple=True)):
                key = exact if exact is not None else (str(monic), index)
                cand = found.setdefault(key, _Candidate(monic, exact, at, {1: 0, -1: 0}, index))
                cand.multiplicity[sigma] = int(m)
    return list(found.values())


def _instant(
    p: fb.FiveBarParams, modes: tuple[int, int], X: fmpq_poly, Y: fmpq_poly, t0: fmpq,
    cand: _Candidate, min_slope: fmpq, min_speed: fmpq,
) -> FiveBarInstant | None:  # fmt: skip
    """The instant at a candidate root, or None when the robot is not singular there."""
    point = xp.Point(cand.f, cand.exact, cand.at)
    conj = fb.conjugates(p, X, Y)
    tw = xp.tower(point, conj)
    singular, degenerate = xp.singular_modes(xp.deltas(point, conj, tw), modes)
    if not singular:
        return None
    m = cand.multiplicity[1] + cand.multiplicity[-1]
    e = xp.expansion(p, point, X, Y, modes, m + 1, tw)
    k = xp.valuation(e.d.delta)
    if k != m and not degenerate:
        raise AssertionError("the order of δ differs from the multiplicity of S₊ S₋")
    dyn = xp.read(e, k)
    slope, slope_principle, rate = _slope(p, dyn.sigma, point, X, Y, min_slope)
    vx, vy = point.val(X.derivative()), point.val(Y.derivative())
    speed2 = vx * vx + vy * vy
    tb = _ball(t0, point.at) if cand.exact is None else arb(t0 + cand.exact)
    return FiveBarInstant(
        t=float(t0 + cand.exact) if cand.exact is not None else float(tb.mid()),
        t_exact=None if cand.exact is None else t0 + cand.exact,
        t_ball=tb,
        x=_real(point, X), y=_real(point, Y),
        modes=modes, sigma=dyn.sigma, order=k, multiplicity=m, degenerate=degenerate,
        delta_k=dyn.delta_k, normal_rate=_exact(point, rate), slope=slope,
        speed2=_exact(point, speed2),
        slope_principle=slope_principle,
        velocity_principle=_velocity(point, speed2, min_speed),
        residuals=dyn.residuals, conditions_met=dyn.conditions_met,
        torque_at_singularity=dyn.limit,
    )  # fmt: skip


def _real(point: xp.Point, p: fmpq_poly) -> float:
    return float(_exact(point, point.val(p)).mid()) if point.field else float(p(point.exact))


def _exact(point: xp.Point, v: Any) -> fmpq | arb:
    """A scalar of the point as a rational, or a ball of 64 bits or more (K)."""
    if point.field is None:
        return fmpq(v)
    return point.field.accurate(v.p, 64)


def _quotient(point: xp.Point, a: Any, b: Any) -> fmpq | arb:
    """a/b exactly at a rational point, else a ball (no inverse taken in K)."""
    if point.field is None:
        return fmpq(a) / fmpq(b)
    old = ctx.prec
    ctx.prec = 128
    try:
        return _exact(point, a) / _exact(point, b)
    finally:
        ctx.prec = old


def _slope(
    p: fb.FiveBarParams, sigma: int, point: xp.Point, X: fmpq_poly, Y: fmpq_poly,
    min_slope: fmpq,
) -> tuple[Any, Principle, Any]:  # fmt: skip
    """(tan α, the transversality principle, ∇S_σ·E'): the crossing angle α between the
    path (its velocity, or at rest the first nonzero derivative of E) and the curve."""
    gx, gy = (point.val(g) for g in fb.curve_gradient(p, sigma, X, Y))
    rate = gx * point.val(X.derivative()) + gy * point.val(Y.derivative())
    if is_zero(gx) and is_zero(gy):
        return ZERO, Principle(False, SINGULAR_POINT), rate
    dx, dy = _direction(point, X, Y)
    dot, cross = gx * dx + gy * dy, gx * dy - gy * dx
    if is_zero(dot):
        return ZERO, Principle(False, TANGENT), rate
    if is_zero(cross):
        return math.inf, Principle(True, NORMAL), rate
    shown = abs(_quotient(point, dot, cross))
    if min_slope == 0:
        return shown, Principle(True, f"tan α = {exact_number(shown)} is nonzero"), rate
    a, b = exact_apart(shown, min_slope)
    if sign(dot * dot - cross * cross * min_slope * min_slope) > 0:
        return shown, Principle(True, f"tan α = {a} exceeds checks.min_slope = {b}"), rate
    return shown, Principle(False, f"tan α = {a} does not exceed checks.min_slope = {b}"), rate


SINGULAR_POINT = "the path passes a singular point of the Type II curve (∇S = 0): high order"
TANGENT = "the path is tangent to the Type II curve here (∇S·E' = 0): a high-order singularity"
NORMAL = "the path crosses the Type II curve along its normal (tan α infinite)"


def _direction(point: xp.Point, X: fmpq_poly, Y: fmpq_poly) -> tuple[Any, Any]:
    """The path's direction at the point: E', or at rest the first nonzero derivative."""
    px, py = X.derivative(), Y.derivative()
    dx, dy = point.val(px), point.val(py)
    while is_zero(dx) and is_zero(dy) and not (px.is_zero() and py.is_zero()):
        px, py = px.derivative(), py.derivative()
        dx, dy = point.val(px), point.val(py)
    return dx, dy


def _velocity(point: xp.Point, speed2: Any, min_speed: fmpq) -> Principle:
    """|E'| > min_speed, decided exactly on |E'|²."""
    if is_zero(speed2):
        return Principle(False, "the end point is at rest here (speed 0): a high-order singularity")
    speed = _exact(point, speed2)
    shown = (arb(speed) if isinstance(speed, fmpq) else speed).sqrt()
    if min_speed == 0:
        return Principle(True, f"speed {exact_number(shown)} m/s is nonzero")
    a, b = exact_apart(shown, min_speed)
    if sign(speed2 - min_speed * min_speed) > 0:
        return Principle(True, f"speed {a} m/s exceeds checks.min_speed = {b} m/s")
    return Principle(False, f"speed {a} m/s does not exceed the margin checks.min_speed = {b} m/s")

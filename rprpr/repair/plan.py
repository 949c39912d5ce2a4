"""The plan at each failing instant: where, how wide, and the bumps' coefficients that
give it a speed, a slope across AB and the scheme's consistency (exactly)."""

from __future__ import annotations

from dataclasses import field

from flint import fmpq, fmpq_poly, fmpz

from ..engine.audit import AuditResult
from ..engine.exact.singular import SingularInstant
from ..model.actuation import PRISMATIC
from ..model.dataclass import dataclass
from ..model.task import Piece, Robot, Task
from .consistency import consistent_acceleration, consistent_ydd, leg_term
from .middle import middle
from .records import Change, NoRepair
from .windows import short, window_about


@dataclass(frozen=True)
class Plan:
    """One failing instant: where, and the bumps' coefficients (Δx: b1, a; Δy: b or lift h)."""

    t: fmpq
    w: fmpq
    b1: fmpq
    a: fmpq
    b: fmpq
    h: fmpq
    change: Change
    ay: fmpq = field(default_factory=fmpq)  # Δy += ay (t - t_s)² W: ÿ(t_s) changed by 2 ay
    x0: fmpq = field(default_factory=fmpq)  # Δx += x0 W: x(t_s) moved by x0 (a snap)


def plan_at(
    task: Task,
    before: AuditResult,
    s: SingularInstant,
    keep: str | None,
    window: fmpq | None,
    fraction: fmpq,
    target: fmpq,
    clearance: fmpq | None,
    timing: bool = True,
) -> Plan:
    """The plan at the failing instant ``s``: its window (``window``, or the largest that
    fits times ``fraction``), a touch lifted clear (``_lift``), else the speed, the slope
    (``target``, ``_slope``) and the scheme's consistency."""
    t = s.t_rational
    if t is None:
        raise NoRepair(
            f"the singular instant t ≈ {s.t:.6g} s is irrational (a root of an irreducible"
            " factor of y(t)): a rational window cannot be centred on it"
        )
    piece, w = window_about(task, before, t, window, fraction)
    x, y = piece.x, piece.y
    dx, ddx = x.derivative(), x.derivative().derivative()
    x_s, v0, acc0 = x(t), dx(t), ddx(t)
    ydot0 = y.derivative()(t)
    order = multiplicity(y, t)
    xs = f"(x, y) = ({x_s}, 0) at t = {t} s"
    if order % 2 == 0:  # a touch: lift it clear of AB
        return _lift(y, t, order, x_s, w, v0, acc0, ydot0, keep, target, clearance, xs)
    actions: list[str] = []
    v = speed_for(task, x, t, w, v0, ydot0, fraction, keep, xs)
    if v != v0:
        actions.append("speed")
    slope_now = task.path.derivative()(x_s) if task.path is not None and piece.path else None
    base = slope_now * v if slope_now is not None else ydot0  # ẏ(t_s) before a path change
    ydot, b = _slope(task, y, t, order, v, base, target, keep, xs, actions)
    if task.robot.actuation == PRISMATIC:
        route = "path" if keep == "path" or timing else None  # None: by the path bump
        return prismatic_plan(task, piece, t, w, b, v0, v, acc0, ydot0, ydot, actions, keep,
                              xs, route)  # fmt: skip
    c = consistent_acceleration(task.robot, x_s, ydot)
    if c is None:
        if leg_term(task.robot, x_s) != 0:
            raise NoRepair(f"m3 + m5 = 0: ẍ(t_s) does not enter eq. (34) at {xs}")
        c = acc0
    elif keep != "timing":  # with uncertainty: the box's middle (ẏ's route stays nominal)
        c = middle(task, x_s, v, ydot, c, y.derivative().derivative()(t), "x")
    if c != acc0:
        if keep == "timing":
            b = slope_for(task.robot, x_s, acc0, ydot, b, xs)
            ydot = base + b
            c = acc0
        actions.append("consistency")
    change = Change(t, x_s, w, tuple(actions), (v0, v), (acc0, c), (ydot0, ydot))
    return Plan(t, w, v - v0, (c - acc0) / 2, b, fmpq(0), change)


def _lift(y: fmpq_poly, t: fmpq, order: int, x_s: fmpq, w: fmpq, v0: fmpq, acc0: fmpq,
          ydot0: fmpq, keep: str | None, target: fmpq, clearance: fmpq | None,
          xs: str) -> Plan:  # fmt: skip
    """A touch of AB (even ``order``) lifted clear of it by Δy = h W, on the side y leaves
    to: h = ``clearance``, by default w |ẋ(t_s)| ``target`` / 2, at least 1/100 m."""
    if keep == "path":
        raise NoRepair(
            f"a touch of the singular line at {xs} (order {order}): the path itself meets"
            " AB tangentially, and no change of the timing removes that; allow a path"
            " change (drop --keep path)"
        )
    side = 1 if leading(y, t, order) > 0 else -1
    lift = clearance if clearance is not None else max(fmpq(1, 100), w * abs(v0) * target / 2)
    change = Change(t, x_s, w, ("lift",), (v0, v0), (acc0, acc0), (ydot0, ydot0))
    return Plan(t, w, fmpq(0), fmpq(0), fmpq(0), side * lift, change)


def _slope(task: Task, y: fmpq_poly, t: fmpq, order: int, v: fmpq, base: fmpq, target: fmpq,
           keep: str | None, xs: str, actions: list[str]) -> tuple[fmpq, fmpq]:  # fmt: skip
    """(ẏ(t_s), Δẏ): ``base`` (ẏ(t_s) before a path change) where |dy/dx| exceeds
    checks.min_slope, else ``target`` |ẋ| on the crossing's side (``actions`` told
    "slope")."""
    ydot, b = base, fmpq(0)
    margin = task.checks.min_slope
    if ydot == 0 or (v != 0 and abs(ydot) <= margin * abs(v)):  # |dy/dx| <= the margin
        if keep == "path":
            what = "= 0" if ydot == 0 else f"= {ydot / v}, not above checks.min_slope = {margin},"
            raise NoRepair(
                f"the path has slope dy/dx {what} at {xs}: the crossing is of order {order},"
                " and no change of the timing changes the path's slope; allow a path change"
                " (drop --keep path)"
            )
        sign = (1 if ydot > 0 else -1) if ydot != 0 else leading_sign(y, t, order)
        ydot = sign * target * abs(v)
        b = ydot - base
        actions.append("slope")
    return ydot, b


def prismatic_plan(task: Task, piece: Piece, t: fmpq, w: fmpq, b: fmpq, v0: fmpq, v: fmpq,
                    acc0: fmpq, ydot0: fmpq, ydot: fmpq, actions: list[str],
                    keep: str | None, xs: str, route: str | None) -> Plan:  # fmt: skip
    """The plan at a prismatic crossing: the scheme's consistency fixes ÿ(t_s)
    (``consistent_ydd``). With the path given and its slope nonzero, ÿ = p'' ẋ² + p' ẍ, so
    a timing bump sets ẍ (path kept; ``route`` "path"); otherwise a path bump
    Δy = ay (t - t_s)² W adds 2 ay to ÿ (timing kept)."""
    x_s = piece.x(t)
    want = consistent_ydd(task.robot, x_s, v, ydot)
    if want is not None:  # with uncertainty: the box's middle
        want = middle(task, x_s, v, ydot, want, acc0, "y")
    path = task.path if task.path is not None and piece.path is not None else None
    if path is not None:
        p1, p2 = path.derivative()(x_s), path.derivative().derivative()(x_s)
        now = p2 * v * v + p1 * acc0
    else:
        p1, p2 = fmpq(0), fmpq(0)
        now = piece.y.derivative().derivative()(t)
    c, ay = acc0, fmpq(0)
    if want is not None and want != now:
        if path is not None and p1 != 0 and keep != "timing" and route == "path":
            c = (want - p2 * v * v) / p1
        elif keep != "path":
            ay = (want - now) / 2
        else:
            raise NoRepair(
                f"the prismatic consistency at {xs} needs ÿ(t_s) = {want} (now {now}); with"
                " the path kept only ẍ can change, which moves ÿ only along a sloped path"
                " given as y(x); allow a path change (drop --keep path)"
            )
        actions.append("consistency")
    change = Change(t, x_s, w, tuple(actions), (v0, v), (acc0, c), (ydot0, ydot),
                    (now, want if want is not None else now))  # fmt: skip
    return Plan(t, w, v - v0, (c - acc0) / 2, b, fmpq(0), change, ay)


def speed_for(task: Task, x: fmpq_poly, t: fmpq, w: fmpq, v0: fmpq, ydot0: fmpq,
               fraction: fmpq, keep: str | None, xs: str) -> fmpq:  # fmt: skip
    """ẋ(t_s) to reach: v0 when the speed already exceeds checks.min_speed; else, from a
    zero speed, the window's mean speed (times ``fraction``), and at least 11/10 of the
    margin (|ẋ| > min_speed makes the speed exceed it)."""
    margin = task.checks.min_speed
    if v0 != 0 and v0 * v0 + ydot0 * ydot0 > margin * margin:
        return v0
    if keep == "timing":
        what = "zero speed" if v0 == 0 and ydot0 == 0 else f"speed not above {margin} m/s"
        raise NoRepair(
            f"{what} at {xs}: only a change of the timing gives the end point a"
            " speed there; allow it (drop --keep timing)"
        )
    span = x(t + w) - x(t - w)
    if v0 == 0 and span == 0:
        raise NoRepair(f"the end point dwells at {xs} over the whole window: no speed")
    sign = (1 if v0 > 0 else -1) if v0 != 0 else (1 if span > 0 else -1)
    mean = abs(span) / (2 * w) * fraction if v0 == 0 else abs(v0)
    return sign * max(mean, short(margin * fmpq(11, 10), up=True))


def slope_for(robot: Robot, x_s: fmpq, acc: fmpq, ydot: fmpq, b: fmpq, xs: str) -> fmpq:
    """With the timing kept (ẍ fixed), the Δẏ that makes eq. (34) hold: ẏ² = -(m3 + m5)
    ẍ / K must be the square of a rational of the crossing's sign."""
    k = leg_term(robot, x_s)
    m = robot.links[3].mass + robot.links[5].mass
    if k == 0:
        raise NoRepair(f"with the timing kept, eq. (34) at {xs} needs ẍ(t_s) = 0, not {acc}")
    q = -m * acc / k
    if q <= 0:
        raise NoRepair(
            f"with the timing kept (ẍ(t_s) = {acc}), eq. (34) at {xs} needs ẏ(t_s)² = {q}:"
            " no nonzero speed across AB satisfies it; allow a timing change (drop --keep"
            " timing)"
        )
    root = rational_sqrt(q)
    if root is None:
        raise NoRepair(
            f"with the timing kept (ẍ(t_s) = {acc}), eq. (34) at {xs} needs ẏ(t_s)² = {q},"
            " which is not the square of a nonzero rational: no exact path change gives it;"
            " allow a timing change (drop --keep timing)"
        )
    sign = 1 if ydot > 0 else -1
    return sign * root - (ydot - b)


def rational_sqrt(q: fmpq) -> fmpq | None:
    p, d = fmpz(q.p), fmpz(q.q)
    rp, rd = p.isqrt(), d.isqrt()
    return fmpq(rp, rd) if rp * rp == p and rd * rd == d else None


def multiplicity(y: fmpq_poly, t: fmpq) -> int:
    m, d = 0, y
    while d != 0 and d(t) == 0:
        m, d = m + 1, d.derivative()
    return m


def leading(y: fmpq_poly, t: fmpq, order: int) -> fmpq:
    d = y
    for _ in range(order):
        d = d.derivative()
    return d(t)


def leading_sign(y: fmpq_poly, t: fmpq, order: int) -> int:
    return 1 if leading(y, t, order) > 0 else -1

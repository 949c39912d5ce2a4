"""Repair of a failing motion: the smallest local, exact change that makes it pass (pure).

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

At a first-order crossing (ẏ(t_s) != 0) eq. (34) is the only condition for bounded
torques (one condition for order 1). So a failing instant is repaired by local bumps of
half-width w about t_s, u = (t - t_s)/w, W = (1 - u²)³ on |u| <= 1 (zero outside; W and
its first two derivatives vanish at u = ±1, so the motion stays C2 and its torques
continuous):

* timing, Δx = (t - t_s)(b1 + a (t - t_s)) W: keeps x(t_s), changes ẋ(t_s) by b1 (a zero
  speed made nonzero) and ẍ(t_s) by 2a (to the consistent value);
* path, Δy = b (t - t_s) W: keeps the crossing point, changes ẏ(t_s) by b (a zero slope
  made b/ẋ); a touch (even order) is lifted clear of AB instead, Δy = h W.

A knot where the velocity or the acceleration jumps (RPR203, RPR204: impulsive or
jumping torques) is smoothed by blending the two pieces over [t_k - w, t_k + w]:
x_B = x_L + (x_R - x_L) S(σ), σ = (t - t_k + w)/(2w), S = 10σ³ - 15σ⁴ + 6σ⁵ (the
quintic smoothstep: S and its first two derivatives are 0 at σ = 0 and match 1, 0, 0 at
σ = 1), so x_B continues x_L and x_R with two derivatives at the window's ends; y alike
(or y = p(x_B) when the task gives its path). At a C1 knot x_R - x_L = O((t - t_k)²),
so the change is of order Δẍ w².

Every bump is a polynomial with rational coefficients in rational windows, so the
repaired motion is exact and its audit is exact; every candidate is audited (strict)
and only a passing one is returned.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable
from dataclasses import dataclass, field, replace

from flint import fmpq, fmpq_poly, fmpz

from ..model.actuation import PRISMATIC
from ..model.task import Piece, Robot, Task
from . import equations as dyn
from .audit import AuditResult, audit
from .roots import isolate, max_abs
from .singular import SingularInstant

KEEPS = ("path", "timing")
FRACTIONS = tuple(fmpq(1, 2**k) for k in range(8))  # of the largest window, tried in turn


class NoRepair(Exception):
    """No repair exists within the constraints; the message says exactly why."""


@dataclass(frozen=True)
class Change:
    """What was done at one singular instant: ``kind`` ("consistency", "speed", "slope",
    "lift"), the window [t_s - w, t_s + w] and the values before and after."""

    t: fmpq
    x: fmpq
    window: fmpq
    actions: tuple[str, ...]
    speed: tuple[fmpq, fmpq]  # ẋ(t_s) before, after
    acceleration: tuple[fmpq, fmpq]  # ẍ(t_s) before, after
    ydot: tuple[fmpq, fmpq]  # ẏ(t_s) before, after
    yddot: tuple[fmpq, fmpq] | None = None  # ÿ(t_s) before, after (the prismatic scheme)


@dataclass(frozen=True)
class Repair:
    """The repaired task and an honest account of the change.

    ``task`` is the new task (``before.task`` the old one); ``changes`` one per repaired
    instant; ``path_deviation`` = (max |Δy| at equal x [m], the x where) or None when the
    path is kept; ``timing_change`` = (max |Δx(t)| [m], the t where) or None; both are
    exact maxima of the polynomial differences (upper bounds within about 1e-15).
    ``before``/``after``: the strict audits.
    ``changed`` is False for a task that already passes (then ``task is before.task``).
    """

    task: Task
    before: AuditResult
    after: AuditResult
    changes: tuple[Change, ...] = ()
    path_deviation: tuple[float, float] | None = None
    timing_change: tuple[float, float] | None = None
    path_kept: bool = True
    notes: tuple[str, ...] = field(default=())

    @property
    def changed(self) -> bool:
        return self.task is not self.before.task


def consistent_acceleration(robot: Robot, x: fmpq, ydot: fmpq) -> fmpq | None:
    """ẍ(t_s) for which eq. (34) holds at the singular point (x, 0) with speed ẏ along the
    normal (the closed form above); None when m3 + m5 = 0 (then ẍ does not enter)."""
    m3, m5 = robot.links[3].mass, robot.links[5].mass
    if m3 + m5 == 0:
        return None
    return -(ydot**2) * _k(robot, x) / (m3 + m5)


def _k(robot: Robot, x: fmpq) -> fmpq:
    """c1 m3 r3 / s1² + c2 m5 r5 / s2² at (x, 0)."""
    a1, L = robot.a1, robot.links
    c1 = 1 if x > 0 else -1
    c2 = 1 if x > a1 else -1
    return c1 * L[3].mass * L[3].r / x**2 + c2 * L[5].mass * L[5].r / (x - a1) ** 2


def bump(t_s: fmpq, w: fmpq) -> fmpq_poly:
    """W(t) = (1 - ((t - t_s)/w)²)³, the window of every local change."""
    u = fmpq_poly([-t_s / w, 1 / w])
    return (1 - u * u) ** 3


@dataclass(frozen=True)
class _Plan:
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


def repair(
    task: Task,
    *,
    keep: str | None = None,
    window: fmpq | None = None,
    slope: fmpq | None = None,
    clearance: fmpq | None = None,
    blend: bool = True,
    snap: bool = True,
) -> Repair:
    """The nearest passing motion: local bumps at each failing singular instant, each
    candidate window tried (``window``, or the largest that fits, then halves) and
    audited strictly; the first that passes is returned. ``keep`` = "path" (timing
    changes only) or "timing" (path changes only); ``slope`` the |dy/dx| to give a
    zero-slope crossing (default max(1/5, 2 min_slope)); ``clearance`` the lift of a
    touch [m] (default w ẋ(t_s) slope / 2, at least 1/100); ``blend``: first smooth the
    knots whose velocity or acceleration jump fails (``_smooth_knots``); ``snap``: move
    failing instants at irrational times to rational ones (``_snap_instants``). Raises
    ``NoRepair``."""
    if keep not in (None, *KEEPS):
        raise ValueError(f"keep is 'path', 'timing' or None, not {keep!r}")
    before = audit(task, strict=True, peak=True)
    if before.passed:
        return Repair(task, before, before)
    jumps = [f.t for f in before.findings if f.rule in JUMP_RULES and f.fails(True)]
    if jumps and blend:
        return _smooth_knots(task, before, jumps, keep, window, slope, clearance)
    failing = [s for s in before.singularities if before.status_of(s) == "fail"]
    other = [f for f in before.findings if f.fails(True) and f.t not in {s.t for s in failing}]
    if not failing:
        raise NoRepair(_no_local_repair(before, other))
    if before.on_singular_line:
        raise NoRepair("the path lies on the singular line y = 0: no local change helps")
    irrational = [s for s in failing if s.t_rational is None]
    if irrational and snap:
        return _snap_instants(task, before, irrational, keep, window, slope, clearance)
    target = slope if slope is not None else max(fmpq(1, 5), 2 * task.checks.min_slope)
    last = "no candidate window"
    # the candidates: each window (the largest that fits, then halves) and, where the
    # prismatic scheme can set ÿ(t_s) by the timing or by the path, the timing first
    routes = (True, False) if task.robot.actuation == PRISMATIC and keep is None else (True,)
    for fraction, timing in itertools.product(FRACTIONS, routes):
        plans = [
            _plan(task, before, s, keep, window, fraction, target, clearance, timing)
            for s in failing
        ]
        new = _apply(task, plans)
        if new is None:
            last = "the changed timing law is not monotone in x"
            continue
        after = audit(new, strict=True, peak=True)
        if after.passed:
            return _account(task, new, before, after, plans)
        last = "; ".join(f.message for f in after.findings if f.fails(True))[:400]
        if window is not None:
            break
    raise NoRepair(f"no candidate passes the strict check (last: {last})")


JUMP_RULES = ("RPR203", "RPR204")  # a velocity or acceleration jump at a knot


def _smooth_knots(
    task: Task,
    before: AuditResult,
    jumps: list[float | None],
    keep: str | None,
    window: fmpq | None,
    slope: fmpq | None,
    clearance: fmpq | None,
) -> Repair:
    """Blend the pieces at each knot whose jump fails (``jumps``: the findings' times),
    then repair what still fails at the singular instants (``repair`` on the blended
    motion); the account is against the task as given."""
    if keep == "timing" or (keep == "path" and task.path is None):
        raise NoRepair(
            "a knot's velocity or acceleration jump is smoothed by blending the pieces"
            " about it, which changes the timing (and, without a path, the path); allow"
            " it (drop --keep)"
        )
    knots = [i for i, p in enumerate(task.motion[:-1]) if float(p.end) in set(jumps)]
    last = ""
    for fraction in FRACTIONS:
        widths = [_blend_width(task, before, i, window, fraction) for i in knots]
        new = _blended(task, dict(zip(knots, widths, strict=True)))
        if new is None:
            last = "the blended timing law is not monotone in x"
            continue
        try:
            inner = repair(new, keep=keep, window=window, slope=slope, clearance=clearance,
                           blend=False)  # fmt: skip
        except NoRepair as why:
            last = str(why)
            if window is not None:
                break
            continue
        blends = tuple(
            f"knot t = {task.motion[i].end} s: the pieces blended over ±{w} s (C2)"
            for i, w in zip(knots, widths, strict=True)
        )
        path_changed = task.path is None or not inner.path_kept
        r = _account(task, inner.task, before, inner.after, [], path_changed)
        return replace(r, changes=inner.changes, notes=blends + inner.notes)
    raise NoRepair(f"no blend of the knots passes the strict check (last: {last})")


def _blend_width(task: Task, before: AuditResult, i: int, window: fmpq | None,
                 fraction: fmpq) -> fmpq:  # fmt: skip
    """The half-width of the blend at the knot after piece i: ``window``, or the largest
    that keeps to a quarter of each neighbouring piece and half-way to any singular
    instant, times ``fraction``."""
    left, right = task.motion[i], task.motion[i + 1]
    t = left.end
    gap = _half_way(before, t, min(left.end - left.start, right.end - right.start) / 4)
    w = window if window is not None else _short(min(gap * fraction, task.duration / 5))
    if w > gap:
        raise NoRepair(
            f"the blend ±{w} s about the knot t = {t} s reaches past a quarter of a"
            f" neighbouring piece or half-way to a singular instant (at most ±{gap} s fits)"
        )
    return w


def smoothstep(lo: fmpq, hi: fmpq) -> fmpq_poly:
    """S(σ) = 10σ³ - 15σ⁴ + 6σ⁵, σ = (t - lo)/(hi - lo): 0 at lo and 1 at hi, with zero
    first and second derivatives at both."""
    sig = fmpq_poly([-lo / (hi - lo), 1 / (hi - lo)])
    return sig**3 * (10 - 15 * sig + 6 * sig * sig)


def _blended(task: Task, widths: dict[int, fmpq]) -> Task | None:
    """The task with the pieces blended at the knots after pieces ``widths`` (index ->
    half-width); None when a blend makes x non-monotone where the path is kept."""
    out: list[Piece] = []
    motion = task.motion
    for j, p in enumerate(motion):
        start = p.start + widths.get(j - 1, fmpq(0))
        end = p.end - widths.get(j, fmpq(0))
        out.append(replace(p, start=start, end=end, line=0, file=""))
        if j in widths:
            r, w = motion[j + 1], widths[j]
            lo, hi = p.end - w, p.end + w
            S = smoothstep(lo, hi)
            x = p.x + (r.x - p.x) * S
            if task.path is not None and p.path is not None:
                if not _monotone(x, lo, hi):
                    return None
                y = task.path(x)
            else:
                y = p.y + (r.y - p.y) * S
            out.append(Piece(lo, hi, x, y, p.path))
    name = _renamed(task.name)
    if task.path is not None and all(q.path is not None for q in out):
        return replace(task, name=name, x_of_t=None, pieces=tuple(out), law="pieces", lines={})
    pieces = tuple(replace(q, path=None) for q in out)
    return replace(task, name=name, path=None, x_of_t=None, pieces=pieces, law="motion", lines={})


def _no_local_repair(before: AuditResult, other: Iterable[object]) -> str:
    rules = sorted({getattr(f, "rule", "") for f in other})
    peak = before.torque_peak
    where = ""
    if peak is not None:
        t1, t2 = peak
        where = (
            f"; peak |T1| {t1.value:.6g} N m at t = {t1.t:.4g} s,"
            f" |T2| {t2.value:.6g} N m at t = {t2.t:.4g} s"
        )
    return (
        f"every singular instant passes; what fails ({', '.join(rules)}) is not at a"
        " singular instant, and rprpr repair changes the motion only locally around"
        " singular instants and its knots (a torque limit exceeded away from them needs a"
        f" slower or longer motion){where}"
    )


def _snap_instants(
    task: Task,
    before: AuditResult,
    instants: list[SingularInstant],
    keep: str | None,
    window: fmpq | None,
    slope: fmpq | None,
    clearance: fmpq | None,
) -> Repair:
    """Failing instants at irrational times (roots of an irreducible factor of y(t) of
    degree >= 2, as a quintic law's crossing of a rational point usually is) moved to a
    short decimal t_r within 10^-4 t_f of t_s, so that the exact bumps can be centred on
    them: with the path given and the crossing point x_s rational, the timing is moved,
    Δx = (x_s - x(t_r)) W (W = (1 - ((t - t_r)/w)²)³: x(t_r) = x_s, x' and the rest of
    the motion kept, a change of order |x'| |t_r - t_s|); otherwise the path, Δy =
    -y(t_r) W. Then the moved instants are repaired as rational ones (``repair``), and
    the account is against the task as given."""
    plans = []
    for s in instants:
        t_r, piece = _rational_near(task, s.t)
        w = _snap_width(task, before, s, t_r, piece, window)
        x0 = h = fmpq(0)
        x_s = _rational_crossing(task, piece, t_r) if keep != "timing" else None
        if x_s is not None:
            x0 = x_s - piece.x(t_r)
        elif keep != "path":
            h = -piece.y(t_r)
        else:
            raise NoRepair(
                f"the singular instant t ≈ {s.t:.6g} s is irrational and its crossing point"
                " too: no exact change of the timing alone moves it to a rational time;"
                " allow a path change (drop --keep path)"
            )
        x_r = piece.x(t_r)
        change = Change(t_r, x_r, w, ("snap",), (fmpq(0), fmpq(0)), (fmpq(0), fmpq(0)),
                        (fmpq(0), fmpq(0)))  # fmt: skip
        plans.append(_Plan(t_r, w, fmpq(0), fmpq(0), fmpq(0), h, change, fmpq(0), x0))
    new = _apply(task, plans)
    if new is None:
        raise NoRepair("moving the irrational singular instants to rational times makes x(t)"
                       " non-monotone")  # fmt: skip
    inner = repair(new, keep=keep, window=window, slope=slope, clearance=clearance, blend=False,
                   snap=False)  # fmt: skip
    path_changed = any(p.h != 0 for p in plans) or not inner.path_kept
    r = _account(task, inner.task, before, inner.after, [], path_changed)
    moved = tuple(
        f"t ≈ {s.t:.12g} s (irrational) moved to t = {p.t} s" for s, p in zip(instants, plans,
                                                                            strict=True)
    )  # fmt: skip
    return replace(r, changes=inner.changes, notes=moved + inner.notes)


def _rational_near(task: Task, t: float) -> tuple[fmpq, Piece]:
    """A short decimal t_r within 10^-4 t_f of ``t`` (the fewest digits, so that the
    repaired task's numbers stay short) and the piece holding it."""
    tol = 1e-4 * float(task.duration)
    den = 10
    while abs(round(t * den) / den - t) > tol:
        den *= 10
    t_r = fmpq(round(t * den), den)
    for p in task.motion:
        if p.start < t_r < p.end:
            return t_r, p
    raise NoRepair(f"the singular instant t ≈ {t:.6g} s is too near a knot to be moved")


def _snap_width(task: Task, before: AuditResult, s: SingularInstant, t_r: fmpq, piece: Piece,
                window: fmpq | None) -> fmpq:  # fmt: skip
    """The snap's half-width: the window the repair will use about t_r (``window``, or
    the largest inside the piece and half-way to the other instants)."""
    gap = _half_way(before, t_r, min(t_r - piece.start, piece.end - t_r), skip=s)
    w = window if window is not None else _short(min(gap, task.duration / 5))
    if not 0 < w <= gap:
        raise NoRepair(f"no room about t ≈ {s.t:.6g} s to move the instant (at most ±{gap} s)")
    return w


def _rational_crossing(task: Task, piece: Piece, t_r: fmpq) -> fmpq | None:
    """The rational root of the path y = p(x) nearest x(t_r) (within 1e-3 m), or None
    (no path, or the crossing point is irrational)."""
    if task.path is None or piece.path is None:
        return None
    x = piece.x(t_r)
    roots = [-f[0] / f[1] for f, _ in task.path.factor()[1] if f.degree() == 1]
    near = [r for r in roots if abs(r - x) < fmpq(1, 10**3)]  # |ẋ| |t_r - t_s| is far less
    return min(near, key=lambda r: abs(r - x)) if near else None


def _piece_at(task: Task, t: fmpq) -> Piece:
    for p in task.motion:
        if p.start < t < p.end:
            return p
    raise NoRepair(f"the singular instant t = {t} s is at a knot of the motion: not repaired")


def _neighbours(task: Task, before: AuditResult, t: fmpq) -> fmpq:
    """The largest half-width that keeps the window inside the piece holding t (so off
    every knot, 0 and t_f) and clear of the other singular instants' windows."""
    p = _piece_at(task, t)
    return _half_way(before, t, min(t - p.start, p.end - t))


def _half_way(before: AuditResult, t: fmpq, gap: fmpq, skip: object = None) -> fmpq:
    """``gap``, or less: half-way from t to every singular instant but ``skip`` (and
    one at t itself), exactly to a rational instant, rounded down to an irrational one."""
    for s in before.singularities:
        q = s.t_rational
        d = abs(q - t) / 2 if q is not None else fmpq(int(abs(s.t - float(t)) * 512), 1024)
        if s is not skip and d > 0:
            gap = min(gap, d)
    return gap


def _plan(
    task: Task,
    before: AuditResult,
    s: SingularInstant,
    keep: str | None,
    window: fmpq | None,
    fraction: fmpq,
    target: fmpq,
    clearance: fmpq | None,
    timing: bool = True,
) -> _Plan:
    t = s.t_rational
    if t is None:
        raise NoRepair(
            f"the singular instant t ≈ {s.t:.6g} s is irrational (a root of an irreducible"
            " factor of y(t)): a rational window cannot be centred on it"
        )
    piece = _piece_at(task, t)
    gap = _neighbours(task, before, t)
    w = window if window is not None else _short(min(gap * fraction, task.duration / 5))
    if w > gap:
        raise NoRepair(
            f"the window ±{w} s about t = {t} s reaches past a knot, an end of the motion"
            f" or another singular instant's window (at most ±{gap} s fits)"
        )
    x, y = piece.x, piece.y
    dx, ddx = x.derivative(), x.derivative().derivative()
    x_s, v0, acc0 = x(t), dx(t), ddx(t)
    ydot0 = y.derivative()(t)
    order = _multiplicity(y, t)
    xs = f"(x, y) = ({x_s}, 0) at t = {t} s"
    if order % 2 == 0:  # a touch: lift it clear of AB
        if keep == "path":
            raise NoRepair(
                f"a touch of the singular line at {xs} (order {order}): the path itself meets"
                " AB tangentially, and no change of the timing removes that; allow a path"
                " change (drop --keep path)"
            )
        side = 1 if _leading(y, t, order) > 0 else -1
        lift = clearance if clearance is not None else max(fmpq(1, 100), w * abs(v0) * target / 2)
        change = Change(t, x_s, w, ("lift",), (v0, v0), (acc0, acc0), (ydot0, ydot0))
        return _Plan(t, w, fmpq(0), fmpq(0), fmpq(0), side * lift, change)
    actions: list[str] = []
    v = _speed_for(task, x, t, w, v0, ydot0, fraction, keep, xs)
    if v != v0:
        actions.append("speed")
    slope_now = task.path.derivative()(x_s) if task.path is not None and piece.path else None
    base = slope_now * v if slope_now is not None else ydot0  # ẏ(t_s) before a path change
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
        sign = (1 if ydot > 0 else -1) if ydot != 0 else _leading_sign(y, t, order)
        ydot = sign * target * abs(v)
        b = ydot - base
        actions.append("slope")
    if task.robot.actuation == PRISMATIC:
        route = "path" if keep == "path" or timing else None  # None: by the path bump
        return _prismatic_plan(task, piece, t, w, b, v0, v, acc0, ydot0, ydot, actions, keep,
                               xs, route)  # fmt: skip
    c = consistent_acceleration(task.robot, x_s, ydot)
    if c is None:
        if _k(task.robot, x_s) != 0:
            raise NoRepair(f"m3 + m5 = 0: ẍ(t_s) does not enter eq. (34) at {xs}")
        c = acc0
    if c != acc0:
        if keep == "timing":
            b = _slope_for(task.robot, x_s, acc0, ydot, b, xs)
            ydot = base + b
            c = acc0
        actions.append("consistency")
    change = Change(t, x_s, w, tuple(actions), (v0, v), (acc0, c), (ydot0, ydot))
    return _Plan(t, w, v - v0, (c - acc0) / 2, b, fmpq(0), change)


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


def _prismatic_plan(task: Task, piece: Piece, t: fmpq, w: fmpq, b: fmpq, v0: fmpq, v: fmpq,
                    acc0: fmpq, ydot0: fmpq, ydot: fmpq, actions: list[str],
                    keep: str | None, xs: str, route: str | None) -> _Plan:  # fmt: skip
    """The plan at a prismatic crossing: the scheme's consistency fixes ÿ(t_s)
    (``consistent_ydd``). With the path given and its slope nonzero, ÿ = p'' ẋ² + p' ẍ, so
    a timing bump sets ẍ (path kept; ``route`` "path"); otherwise a path bump
    Δy = ay (t - t_s)² W adds 2 ay to ÿ (timing kept)."""
    x_s = piece.x(t)
    want = consistent_ydd(task.robot, x_s, v, ydot)
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
    return _Plan(t, w, v - v0, (c - acc0) / 2, b, fmpq(0), change, ay)


def _speed_for(task: Task, x: fmpq_poly, t: fmpq, w: fmpq, v0: fmpq, ydot0: fmpq,
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
    return sign * max(mean, _short(margin * fmpq(11, 10), up=True))


def _slope_for(robot: Robot, x_s: fmpq, acc: fmpq, ydot: fmpq, b: fmpq, xs: str) -> fmpq:
    """With the timing kept (ẍ fixed), the Δẏ that makes eq. (34) hold: ẏ² = -(m3 + m5)
    ẍ / K must be the square of a rational of the crossing's sign."""
    k = _k(robot, x_s)
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
    root = _rational_sqrt(q)
    if root is None:
        raise NoRepair(
            f"with the timing kept (ẍ(t_s) = {acc}), eq. (34) at {xs} needs ẏ(t_s)² = {q},"
            " which is not the square of a nonzero rational: no exact path change gives it;"
            " allow a timing change (drop --keep timing)"
        )
    sign = 1 if ydot > 0 else -1
    return sign * root - (ydot - b)


def _rational_sqrt(q: fmpq) -> fmpq | None:
    p, d = fmpz(q.p), fmpz(q.q)
    rp, rd = p.isqrt(), d.isqrt()
    return fmpq(rp, rd) if rp * rp == p and rd * rd == d else None


_DENOMINATORS = (1, 2, 4, 5, 8, 10, 16, 20, 40, 80, 160, 320, 640, 1280)


def _short(value: fmpq, up: bool = False) -> fmpq:
    """A short rational (a denominator of a power of two times 1, 5 or 10) near
    ``value`` >= 0: at most it and at least 3/4 of it, or (``up``) at least it and at
    most 5/4 of it; ``value`` itself when none is found."""
    for den in _DENOMINATORS:
        n = -((-value.p * den) // value.q) if up else (value.p * den) // value.q
        r = fmpq(int(n), den)
        if (r <= value * fmpq(5, 4)) if up else (r > 0 and r >= value * fmpq(3, 4)):
            return r
    return value


def _multiplicity(y: fmpq_poly, t: fmpq) -> int:
    m, d = 0, y
    while d != 0 and d(t) == 0:
        m, d = m + 1, d.derivative()
    return m


def _leading(y: fmpq_poly, t: fmpq, order: int) -> fmpq:
    d = y
    for _ in range(order):
        d = d.derivative()
    return d(t)


def _leading_sign(y: fmpq_poly, t: fmpq, order: int) -> int:
    return 1 if _leading(y, t, order) > 0 else -1


def _apply(task: Task, plans: list[_Plan]) -> Task | None:
    """The task with every plan's bumps; None when a timing change makes x non-monotone."""
    pieces = list(task.motion)
    path = task.path
    path_changed = any(p.b != 0 or p.h != 0 or p.ay != 0 for p in plans)
    out: list[Piece] = []
    for piece in pieces:
        cuts = sorted(
            {piece.start, piece.end}
            | {e for p in plans for e in (p.t - p.w, p.t + p.w) if piece.start < e < piece.end}
        )
        for lo, hi in itertools.pairwise(cuts):
            x, dy = piece.x, fmpq_poly([0])
            for p in plans:
                if p.t - p.w <= lo and hi <= p.t + p.w:
                    tau, W = fmpq_poly([-p.t, 1]), bump(p.t, p.w)
                    x = x + (tau * (p.b1 + p.a * tau) + p.x0) * W
                    dy = dy + (p.b * tau + p.h + p.ay * tau * tau) * W
                    if x != piece.x and not _monotone(x, lo, hi):
                        return None
            y = (path(x) if path is not None else piece.y) + dy
            keep_path = path is not None and not path_changed
            out.append(Piece(lo, hi, x, y, path if keep_path else None))
    if path is not None and not path_changed:
        return replace(task, name=_renamed(task.name), x_of_t=None, pieces=tuple(out),
                       law="pieces", lines={})  # fmt: skip
    return replace(task, name=_renamed(task.name), path=None, x_of_t=None, pieces=tuple(out),
                   law="motion", lines={})  # fmt: skip


def _renamed(name: str) -> str:
    """The repaired task's name: the old one marked, so that reports and overlays tell
    the two apart."""
    return name if name.endswith(" (repaired)") else f"{name} (repaired)"


def _monotone(x: fmpq_poly, lo: fmpq, hi: fmpq) -> bool:
    """ẋ keeps one sign on (lo, hi) (exactly: no root of odd multiplicity inside)."""
    d = x.derivative()
    if d == 0:
        return False
    mid = (lo + hi) / 2
    for f, e in d.factor()[1]:
        if e % 2 == 0:
            continue
        if f.degree() == 1:
            r = -f[0] / f[1]
            if lo < r < hi:
                return False
            continue
        g = f(fmpq_poly([lo, 1]))
        if isolate(g, hi - lo):
            return False
    return bool(d(mid) != 0) or _monotone_far(d, lo, hi)


def _monotone_far(d: fmpq_poly, lo: fmpq, hi: fmpq) -> bool:
    return any(d(lo + (hi - lo) * fmpq(k, 7)) != 0 for k in range(1, 7))


def _account(task: Task, new: Task, before: AuditResult, after: AuditResult,
             plans: list[_Plan], path_changed: bool | None = None) -> Repair:  # fmt: skip
    """The change's metrics, exact maxima (``roots.max_abs``, an upper bound within
    about 1e-15): max |Δx(t)| over the motion, and max |Δy| at equal x — the new y(t)
    against the old path at the new x(t) (or, without a path, the old y(t))."""
    dxm: tuple[float, float] | None = None
    dym: tuple[float, float] | None = None
    if path_changed is None:
        path_changed = any(p.b != 0 or p.h != 0 or p.ay != 0 for p in plans)
    for q, o, lo, hi in _overlaps(new.motion, task.motion):
        m, t = max_abs(q.x - o.x, lo, hi)
        if m > 0 and (dxm is None or m > dxm[0]):
            dxm = (m, t)
        if path_changed:
            old_y = task.path(q.x) if task.path is not None else o.y
            m, t = max_abs(q.y - old_y, lo, hi)
            if dym is None or m > dym[0]:
                dym = (m, float(q.x(fmpq(*t.as_integer_ratio()))))
    return Repair(new, before, after, tuple(p.change for p in plans), dym, dxm, not path_changed)


Overlap = tuple[Piece, Piece, fmpq, fmpq]


def _overlaps(new: tuple[Piece, ...], old: tuple[Piece, ...]) -> list[Overlap]:
    """(new piece, old piece, lo, hi) for every interval [lo, hi] of positive length on
    which one new and one old piece both hold."""
    out = []
    i = j = 0
    while i < len(new) and j < len(old):  # both consecutive from t = 0: one merge pass
        q, o = new[i], old[j]
        lo, hi = max(q.start, o.start), min(q.end, o.end)
        if lo < hi:
            out.append((q, o, lo, hi))
        if q.end <= o.end:
            i += 1
        else:
            j += 1
    return out

"""A piecewise motion audited piece by piece, and the results put back together (pure).

Each piece is analysed, certified and enveloped alone in its local time (``trajectory``:
u = t - origin, exact); what it finds is moved back to absolute time here: exact instants
stay exact (origin + u), float ends of windows are rounded outward. A singular instant
exactly at a knot is found by both pieces that meet there, each with its own one-sided
analysis (its own order, slope, speed, eq. 34 residual, conditions and limit torque):
the two are combined conservatively (``at_knot``).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from fractions import Fraction
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from flint import arb, ctx, fmpq, fmpq_poly

from ..model.numbers import to_float
from ..model.task import Checks, Piece, Robot, Task
from .bounds.verdicts import CROSSING_REL, Approach, LimitCheck, Peak, Window
from .exact.singular import (
    KinematicSingularity,
    OnStage,
    Principle,
    SingularAnalysis,
    SingularInstant,
    analyse,
)
from .exact.trajectory import Trajectory, origin_of, piece_trajectory

if TYPE_CHECKING:  # the ball machinery is imported when a piece needs a pass (below)
    from .bounds.batch import Batch
    from .bounds.envelope import Envelope
    from .certified.motion import CertifiedMotion
    from .certified.sampling import Samples


class Part:
    """One piece [start, end] (absolute, exact) audited in its local time. Its exact
    trajectory, certified motion and envelope are made when first read: a plain piece of
    a batch (``batch``) needs none of them unless it is sampled."""

    def __init__(
        self, piece: Piece, robot: Robot, analysis: SingularAnalysis, apart: bool = False
    ) -> None:
        self.piece = piece
        self.robot = robot
        self.analysis = analysis  # local times, instants before the piece's start dropped
        self.apart = apart  # proven never to meet y = 0 (``Batch.apart``)
        self.start: fmpq = piece.start
        self.end: fmpq = piece.end
        self.theta_offset: tuple[float, float] = (0.0, 0.0)  # 2πk per leg
        self.offsets_known = False  # (on the first part) ``theta_offsets`` made

    @cached_property
    def origin(self) -> fmpq:
        """Where the piece's local time starts (``trajectory.origin_of``)."""
        return origin_of(self.start, self.end)

    @cached_property
    def traj(self) -> Trajectory:
        return piece_trajectory(self.piece, self.robot.a1)

    @cached_property
    def motion(self) -> CertifiedMotion:
        from .certified.motion import CertifiedMotion

        return CertifiedMotion(self.traj, self.robot, self.analysis)

    @cached_property
    def envelope(self) -> Envelope:
        from .bounds.envelope import Envelope

        return Envelope(self.motion)

    @property
    def duration(self) -> fmpq:
        """The local span's length (``trajectory``: end - origin)."""
        return self.end - self.origin

    @property
    def plain(self) -> bool:
        """Whether the batch can enclose the piece (``batch.plain``)."""
        if self.apart:
            return True
        from .bounds.batch import plain

        return plain(self.motion)


NOTHING = SingularAnalysis([], [], False, (), ())  # of every piece proven apart (read only)


def part(piece: Piece, robot: Robot, checks: Checks, tell: OnStage) -> Part:
    """One piece with its exact singular analysis (in its local time, trimmed)."""
    traj = piece_trajectory(piece, robot.a1)
    p = Part(piece, robot, _trimmed(analyse(traj, robot, checks, tell), traj.lead))
    p.__dict__["traj"] = traj  # made already: the cached property, set
    return p


def parts(task: Task, tell: OnStage) -> tuple[list[Part], Batch | None]:
    """The parts of ``task``'s motion, and the batch of all its pieces when there are
    several of one form: a piece the batch proves apart from y = 0 gets the empty
    analysis (exact: y has no root on it) without the exact root finding."""
    motion = list(task.motion)
    batch = None
    if len(motion) > 1 and len({p.path is None for p in motion}) == 1:
        from .bounds.batch import Batch

        batch = Batch(motion, task.robot)
    apart = batch.apart() if batch is not None else np.zeros(len(motion), dtype=bool)
    out = []
    for piece, free in zip(motion, apart.tolist(), strict=True):
        if free:
            out.append(Part(piece, task.robot, NOTHING, True))
        else:
            out.append(part(piece, task.robot, task.checks, tell))
    return out, batch


def _root_ball(a: SingularAnalysis, s: SingularInstant, prec: int) -> arb:
    return a.hints(s).field.evaluate(fmpq_poly([0, 1]), prec)


def _before(a: SingularAnalysis, s: SingularInstant, lead: fmpq) -> bool:
    """t_s < lead, decided exactly (an irrational t_s is never equal to it)."""
    if lead == 0:
        return False
    if s.t_rational is not None:
        return s.t_rational < lead
    prec = 64
    while prec <= 1 << 16:
        b = _root_ball(a, s, prec)
        if b < arb(lead):
            return True
        if b > arb(lead):
            return False
        prec *= 2
    return False


def _trimmed(a: SingularAnalysis, lead: fmpq) -> SingularAnalysis:
    """``a`` without what lies in the sliver before the piece's start (``trajectory``)."""
    if lead == 0:
        return a
    keep = [(s, h) for s, h in zip(a.instants, a._hints, strict=True) if not _before(a, s, lead)]
    lead_f = to_float(lead)
    kin = [(k, g) for k, g in zip(a.kinematic, a._kinematic_signs, strict=True) if k.t >= lead_f]
    return SingularAnalysis(
        [s for s, _ in keep], [k for k, _ in kin], a.on_singular_line,
        tuple(h for _, h in keep), tuple(g for _, g in kin),
    )  # fmt: skip


# -- back to absolute time --------------------------------------------------------------


def shift(origin: fmpq, u: float, up: bool | None = None) -> float:
    """origin + u as a double: nearest (``up`` None), or rounded up / down."""
    if origin == 0 or not math.isfinite(u):
        return u
    v = origin + fmpq(*u.as_integer_ratio())
    f = to_float(v)
    g = fmpq(*f.as_integer_ratio())
    if up is True and g < v:
        f = math.nextafter(f, math.inf)
    elif up is False and g > v:
        f = math.nextafter(f, -math.inf)
    return f


def absolute(p: Part, s: SingularInstant) -> SingularInstant:
    """The instant ``s`` of the piece ``p`` at its absolute time."""
    o = p.origin
    if o == 0:
        return s
    if s.t_rational is not None:
        t = o + s.t_rational
        return replace(s, t=to_float(t), t_exact=Fraction(int(t.p), int(t.q)))
    old = ctx.prec
    ctx.prec = 128
    try:
        return replace(s, t=float((arb(o) + _root_ball(p.analysis, s, 128)).mid()))
    finally:
        ctx.prec = old


def absolute_kinematic(p: Part, k: KinematicSingularity) -> KinematicSingularity:
    return k if p.origin == 0 else replace(k, t=shift(p.origin, k.t))


def _window(o: fmpq, w: Window) -> Window:
    return Window(
        shift(o, w.start_lo, False), shift(o, w.start_hi, True),
        shift(o, w.end_lo, False), shift(o, w.end_hi, True), w.pole,
    )  # fmt: skip


# -- one-sided instants at knots ------------------------------------------------------


def _side(name: str, principle: Principle, two: bool) -> Principle:
    return replace(principle, reason=f"{name} the knot: {principle.reason}") if two else principle


def at_knot(before: SingularInstant | None, after: SingularInstant | None) -> SingularInstant:
    """One instant at a knot from its one-sided analyses (either may be absent: t = 0,
    t = t_f): ``order`` the larger; a principle fails if it fails on either side; the
    eq. (34) residual of an inconsistent side; ``torque_bounded`` only if both are (the
    pole of the higher order); ``torque_at_singularity`` the common limit, else None."""
    sides = tuple((n, s) for n, s in (("before", before), ("after", after)) if s is not None)
    ss = [s for _, s in sides]
    two = len(ss) == 2
    base = max(ss, key=lambda s: s.order)
    order = base.order
    slope_n, slope_s = min(sides, key=lambda p: (p[1].slope_principle.passed, abs(p[1].slope)))
    speed_n, speed_s = min(sides, key=lambda p: (p[1].velocity_principle.passed, p[1].speed))
    _, resid_s = max(sides, key=lambda p: (not p[1].consistent, abs(p[1].consistency_residual)))
    pole = max(s.pole_order for s in ss)
    limits = {s.torque_at_singularity for s in ss}
    torque = limits.pop() if len(limits) == 1 else None
    beyond = tuple(dict.fromkeys(b for s in ss for b in s.beyond_double_range))
    return replace(
        base,
        order=order,
        slope=slope_s.slope,
        slope_principle=_side(slope_n, slope_s.slope_principle, two),
        speed=speed_s.speed,
        velocity_principle=_side(speed_n, speed_s.velocity_principle, two),
        consistency_residual=resid_s.consistency_residual,
        consistent=all(s.consistent for s in ss),
        conditions_met=order - pole,
        torque_at_singularity=torque,
        beyond_double_range=beyond,
        knot=True,
        sides=sides,
    )


# -- the envelopes put together ---------------------------------------------------------


def batches(parts: list[Part], batch: Batch | None) -> list[tuple[Batch, list[int]]]:
    """The plain pieces (``Part.plain``) of a motion of several, as one ``Batch`` (taken
    from ``batch``, that of all the pieces); the others keep an envelope each."""
    if len(parts) < 2 or batch is None:
        return []
    ids = [j for j, p in enumerate(parts) if p.plain]
    return [(batch.take(ids), ids)] if len(ids) > 1 else []


Verdicts = tuple[
    tuple[Peak, Peak] | None, bool, tuple[LimitCheck, LimitCheck] | None, Approach | None
]


def envelopes(
    parts: list[Part],
    limit: tuple[float, float] | None,
    batch: Batch | None = None,
    peak: bool = True,
) -> Verdicts:
    """The torque peak, whether it was computed, the limit check (``limit`` given) and
    the closest approach of the whole motion: the plain pieces enclosed together
    (``batch``, of all the pieces), each other piece by its own envelope.

    ``peak`` False: the certified peak is computed only where it costs no pass (None
    where undefined, infinite at a pole; ``known_peak``), else it is not computed (None,
    and False for ``computed``); the limit check then decides without it."""
    groups = batches(parts, batch)
    grouped = {j for _, ids in groups for j in ids}
    alone = [j for j in range(len(parts)) if j not in grouped]
    checks: dict[int, tuple[LimitCheck, LimitCheck]] = {}
    if peak:
        got = {j: parts[j].envelope.torque_peak() for j in alone}
        together = [(b, ids, b.torque_peak()) for b, ids in groups]
        extra = [tuple((parts[ids[j]].start, pk) for pk, j in both) for _, ids, both in together]
        top = peaks([parts[j].origin for j in alone], [got[j] for j in alone], extra)  # type: ignore[arg-type]
        computed = True
        if limit is not None:
            for _, ids, both in together:
                if all(pk.certified and pk.upper <= lim
                       for (pk, _), lim in zip(both, limit, strict=True)):  # fmt: skip
                    for j in ids:  # the peak of all of them decides the limit at once
                        checks[j] = _kept(parts[j], limit)
    else:
        top, computed = known_peak(parts, alone)
        if limit is not None:
            for b, ids in groups:
                if b.below(limit):  # proven below both limits over every piece at once
                    for j in ids:
                        checks[j] = _kept(parts[j], limit)
    checked = None
    if limit is not None:
        for j, p in enumerate(parts):
            if j not in checks:
                checks[j] = p.envelope.limit_violations(limit)
        checked = limits(parts, [checks[j] for j in range(len(parts))])
    near = {j: None if _meets(parts[j]) else parts[j].envelope.closest_approach() for j in alone}
    pairs: list[tuple[fmpq, fmpq, Approach | None]] = [
        (parts[j].origin, parts[j].origin, near[j]) for j in alone
    ]
    for b, ids in groups if all(a is not None for a in near.values()) else ():
        a, jy, jd = b.closest_approach()
        pairs.append((parts[ids[jy]].start, parts[ids[jd]].start, a))
    return top, computed, checked, approach(pairs)


def _kept(p: Part, limit: tuple[float, float]) -> tuple[LimitCheck, LimitCheck]:
    """The limit check of a piece proven below both limits everywhere."""
    res = CROSSING_REL * to_float(p.duration)
    return LimitCheck(limit[0], True, (), res), LimitCheck(limit[1], True, (), res)


def _undefined(p: Part) -> bool:
    """``Envelope.peak_undefined`` of the piece, its envelope made only where E is at A
    or B (the one case that needs it)."""
    if p.analysis.on_singular_line:
        return True
    return bool(p.analysis.kinematic) and p.envelope.peak_undefined


def _poles(p: Part) -> list[SingularInstant]:
    """The piece's instants with unbounded torques (``Envelope.poles``)."""
    return [s for s in p.analysis.instants if not s.torque_bounded]


def _meets(p: Part) -> bool:
    """Whether the piece meets y = 0 or E reaches A or B: then it has no closest
    approach (``Envelope.closest_approach`` is None) and needs no envelope for it."""
    a = p.analysis
    return bool(a.instants or a.kinematic or a.on_singular_line)


def known_peak(parts: list[Part], alone: list[int]) -> tuple[tuple[Peak, Peak] | None, bool]:
    """The peak where it needs no pass, and whether it is known: None (known) where it is
    undefined on a piece (the path on y = 0, E through A or B along AB), infinite at the
    first pole (known), else not computed (None, False). The pieces of a batch are plain:
    neither undefined nor unbounded."""
    if any(_undefined(parts[j]) for j in alone):
        return None, True
    poles = [shift(parts[j].origin, _poles(parts[j])[0].t) for j in alone if _poles(parts[j])]
    if poles:
        t = min(poles)
        return (Peak(math.inf, t, math.inf, True), Peak(math.inf, t, math.inf, True)), True
    return None, False


def peaks(
    origins: list[fmpq],
    got: list[tuple[Peak, Peak] | None],
    extra: list[tuple[tuple[fmpq, Peak], tuple[fmpq, Peak]]] = (),  # type: ignore[assignment]
) -> tuple[Peak, Peak] | None:
    """max |T1|, max |T2| over all pieces (None where undefined on one; the first pole),
    each piece's times local to its ``origins``; ``extra``: the peaks of batches, each
    torque's with the origin of the times of the piece where it is reached."""
    if any(g is None for g in got):
        return None
    each = [[(o, g[i]) for o, g in zip(origins, got, strict=True) if g is not None]
            + [e[i] for e in extra] for i in (0, 1)]  # fmt: skip
    poles = [shift(o, g.t) for o, g in each[0] if math.isinf(g.value)]
    if poles:
        t = min(poles)
        return Peak(math.inf, t, math.inf, True), Peak(math.inf, t, math.inf, True)
    out = []
    for i in (0, 1):
        o, g = max(each[i], key=lambda pg: pg[1].value)
        out.append(
            Peak(
                g.value, shift(o, g.t), max(h.upper for _, h in each[i]),
                all(h.certified for _, h in each[i]),
            )
        )  # fmt: skip
    return out[0], out[1]


def limits(
    parts: list[Part], got: list[tuple[LimitCheck, LimitCheck]]
) -> tuple[LimitCheck, LimitCheck]:
    """The limit checks of all pieces as one: failed if one fails, undecided if one is;
    windows in absolute time, joined where they meet across a knot."""
    out = []
    for i in (0, 1):
        checks = [g[i] for g in got]
        passed: bool | None = True
        if any(c.passed is False for c in checks):
            passed = False
        elif any(c.passed is None for c in checks):
            passed = None
        windows: list[Window] = []
        for p, c in zip(parts, checks, strict=True):
            for w in c.windows:
                w = _window(p.origin, w)
                if windows and windows[-1].end_hi >= w.start_lo:
                    last = windows.pop()
                    w = Window(last.start_lo, last.start_hi, w.end_lo, w.end_hi,
                               last.pole or w.pole)  # fmt: skip
                windows.append(w)
        resolution = max(c.resolution for c in checks)
        out.append(LimitCheck(checks[0].limit, passed, tuple(windows), resolution))
    return out[0], out[1]


def approach(pairs: list[tuple[fmpq, fmpq, Approach | None]]) -> Approach | None:
    """The closest approach over all pieces (None when one of them meets the line); each
    approach with the origins of the times of its ``t_y`` and its ``t_delta``."""
    if any(a is None for _, _, a in pairs):
        return None
    got = [(py, pd, a) for py, pd, a in pairs if a is not None]
    py, _, ay = min(got, key=lambda g: g[2].distance)
    _, pd, ad = min(got, key=lambda g: g[2].delta_hi)
    low = min(a.delta_lo for _, _, a in got)
    return Approach(ay.distance, shift(py, ay.t_y), low, ad.delta_hi,
                    shift(pd, ad.t_delta))  # fmt: skip


# -- samples ----------------------------------------------------------------------------


def which(parts: list[Part], t: np.ndarray) -> np.ndarray:
    """The piece holding each float time (the later one exactly at a knot)."""
    starts = [p.start for p in parts[1:]]
    floats = np.array([to_float(s) for s in starts])
    idx = np.searchsorted(floats, t, side="right")
    for j in np.nonzero(idx > 0)[0]:
        k = int(idx[j]) - 1
        if t[j] == floats[k] and fmpq(*float(t[j]).as_integer_ratio()) < starts[k]:
            idx[j] = k  # the double of a knot that is no double, below it
    return idx


def _theta_at(p: Part, t: float) -> tuple[float, float]:
    u = float(t - to_float(p.origin))
    c = p.motion.sample(np.array([u]), refine=False)
    return float(c.value["theta1"][0]), float(c.value["theta2"][0])


def theta_offsets(
    parts: Sequence[Any], theta_at: Callable[[Any, float], tuple[float, float]] | None = None
) -> None:
    """Each piece's 2πk per leg, so that θ is continuous across every knot: the angle
    just after the knot (a double above it) is moved by the multiple of 2π nearest its
    difference from the angle just before (a double below it). ``theta_at(part, t)`` is
    (θ1, θ2) of a part at the absolute time t (the RPRPR's parts' by default; the 5R's
    parts give theirs, ``five_bar_pieces``)."""
    angle = theta_at or _theta_at
    offset = [0.0, 0.0]
    for prev, p in itertools.pairwise(parts):
        lo, hi = just_about(p.start)
        before, after = angle(prev, lo), angle(p, hi)
        for leg in (0, 1):
            jump = before[leg] + prev.theta_offset[leg] - after[leg]
            if math.isfinite(jump):
                offset[leg] = 2 * math.pi * round(jump / (2 * math.pi))
        p.theta_offset = (offset[0], offset[1])


def just_about(t: fmpq) -> tuple[float, float]:
    """The doubles just below and just above the exact time t (t itself where it is a
    double below or above t)."""
    f = to_float(t)
    q = fmpq(*f.as_integer_ratio())
    lo = f if q < t else math.nextafter(f, -math.inf)
    hi = f if q > t else math.nextafter(f, math.inf)
    return lo, hi


def sample(parts: list[Part], t: np.ndarray) -> Samples:
    """Certified samples at the absolute times ``t``, each from its own piece."""
    from .certified.motion import FIELDS
    from .certified.sampling import Samples

    t = np.asarray(t, dtype=float)
    if len(parts) == 1:
        c = parts[0].motion.sample(t)
        return Samples(t=c.t, reason=c.reason, **c.value)
    if not parts[0].offsets_known:  # made when first sampled, not by the audit
        theta_offsets(parts)
        parts[0].offsets_known = True
    idx = which(parts, t)
    value = {n: np.full(len(t), np.nan) for n in FIELDS}
    reason = np.zeros(len(t), dtype=np.int8)
    for i in np.unique(idx):
        p = parts[int(i)]
        sel = np.nonzero(idx == i)[0]
        c = p.motion.sample(t[sel] - to_float(p.origin))  # exact (``trajectory``)
        for n in FIELDS:
            value[n][sel] = c.value[n]
        value["theta1"][sel] += p.theta_offset[0]
        value["theta2"][sel] += p.theta_offset[1]
        reason[sel] = c.reason
    return Samples(t=t, reason=reason, **value)

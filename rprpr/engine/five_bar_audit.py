"""The audit of a 5R task: its exact verdicts (pure; docs/five-bar.md).

    task -> each piece's E(t) (exact polynomials) -> its Type II instants up to the first
         Type I instant (``exact.five_bar_instants``) -> joined (instants at knots from
         both sides) + the knots' jumps (``exact.knots``) -> findings -> FiveBarAuditResult

The rules are the RPRPR's where the meaning is the same: the transversality principle is
RPR101 (the slope principle: the path crosses the Type II curve at an angle), the speed
principle RPR102, a leg stretched or folded RPR103 (the inverse kinematics fail, as at A
or B for the RPRPR), the path along the Type II curve RPR104, unbounded torques RPR201
(the reciprocity condition and the high-order conditions, §6), and at the knots of a
piecewise motion RPR203 (velocity jump) and RPR204 (acceleration and torque jump).

What this build audits of a 5R: a motion of one piece or of several (y = p(x) with a
timing law or ``timing.x`` pieces, ``motion.pieces``, waypoints inline or from a CSV
file), without declared uncertainty; its certified layers (``five_bar_certified`` for a
motion of one piece, ``five_bar_pieces`` each piece's joined for several, loaded only for
a task that asks for them): the torque peak, the torque limit check and its windows, the
samples. What it does not audit of a 5R (declared uncertainty, repair) ``refuse`` and
``refuse_command`` refuse in one located line (a ``TaskFileError``: exit status 2).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import field, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from flint import arb, ctx, fmpq

from ..model.dataclass import dataclass
from ..model.defaults import DEFAULT_SAMPLES
from ..model.errors import TaskFileError
from ..model.five_bar import FIVE_BAR
from ..model.numbers import exact_number, labels, number, to_float
from ..model.options import AuditOptions
from ..model.rules import Finding, Judged, with_levels
from ..model.task import Piece, Robot, Task
from .bounds.verdicts import LimitCheck, Peak, Window
from .exact import five_bar as fb
from .exact import knots as K
from .exact.five_bar_instants import (
    FiveBarAnalysis,
    FiveBarError,
    FiveBarInstant,
    TypeOne,
    analyse_robot,
)
from .exact.singular import FACTORING, OnStage, Principle
from .findings import exact_text, knot

if TYPE_CHECKING:  # the ball machinery is imported only by a task that needs it
    from .certified.five_bar import FiveBarMotion
    from .certified.five_bar_samples import FiveBarSamples
    from .five_bar_pieces import FiveBarPart

YET = "not available for a 5R yet"
FINDINGS = "the findings"
ENVELOPE = "the torque envelope"


@dataclass(frozen=True)
class FiveBarAuditResult(Judged):
    """What ``rprpr check`` reports for a 5R task: its Type II instants (``analysis``:
    times, working modes, line-up σ, order, principles, residuals, limit torques) up to
    the first Type I instant, which stops its inverse kinematics; for a piecewise motion
    each piece's analysis (``parts``, up to the piece that stops) and its knots
    (``knot_jumps``: velocity, acceleration and torque jumps); the findings and the
    verdict; and the certified layers as the RPRPR's
    ``AuditResult`` has them: ``torque_peak`` (inf at a pole; None when not asked for,
    then ``peak_computed`` is False, or undefined: a Type I instant or the path on the
    curve), ``torque_limit`` (None without a limit), ``saturation`` and ``samples``
    (certified values on ``grid_size`` times, made when first read; ``resample`` at any
    times)."""

    task: Task
    strict: bool
    analysis: FiveBarAnalysis = field(repr=False, compare=False)
    findings: list[Finding]
    on_singular_curve: bool = False  # the path runs along a Type II curve all along
    peak_computed: bool = False
    grid_size: int = field(default=DEFAULT_SAMPLES, repr=False)  # the sheet's samples
    parts: tuple[FiveBarAnalysis, ...] = field(default=(), repr=False, compare=False)
    knot_jumps: tuple[K.Knot, ...] = field(default=(), repr=False, compare=False)
    torque_peak: tuple[Peak, Peak] | None = None
    torque_limit: tuple[LimitCheck, LimitCheck] | None = None
    closest_approach: None = None  # the RPRPR's distance to the line AB: no 5R meaning

    @cached_property
    def motion(self) -> FiveBarMotion:
        """The motion in balls (``certified.five_bar``), made when first read (of a
        motion of one piece; of several: ``pieces``)."""
        return certified_motion(self.task, self.analysis)

    @cached_property
    def pieces(self) -> list[FiveBarPart]:
        """Each piece in its local time with its own instants (``five_bar_pieces``), the
        motors' angles continuous across the knots; a piece after the one a Type I
        instant stops has no instant found."""
        from .five_bar_pieces import five_bar_parts, theta_offsets

        parts = _analyses(self.task, list(self.parts))
        out = five_bar_parts(self.task.motion, self.task.robot, parts)
        theta_offsets(out)
        return out

    @cached_property
    def samples(self) -> FiveBarSamples:
        """Certified samples at ``grid_size`` evenly spaced times, t = 0 .. t_f."""
        from .certified.sampling import grid

        return self.resample(grid(self.task.duration, self.grid_size))

    def resample(self, t: np.ndarray) -> FiveBarSamples:
        """The motion, joints, δ, the axial force and the torques at the times ``t`` [s],
        certified (``certified.five_bar_samples``); from the first Type I instant on the
        working modes are lost: the joints, δ, α and the torques there are NaN with the
        Type I reason code (only the path is known)."""
        times = np.asarray(t, dtype=float)
        if len(self.task.motion) > 1:
            from .five_bar_pieces import sample_pieces

            got = sample_pieces(self.pieces, times)
        else:
            from .certified.five_bar_samples import sample

            got = sample(self.motion, times)
        if self.analysis.type_one:
            _past_type_one(got, self.analysis.type_one[0])
        return got

    @cached_property
    def saturation(self) -> list[tuple[FiveBarInstant, Window | None, Window | None]]:
        """For each unbounded instant, the windows around it in which |T1|, |T2| exceed
        their limits (empty without a limit)."""
        if self.torque_limit is None:
            return []
        out = []
        for s in self.singularities:
            if s.bounded:
                continue
            pair = [
                next((w for w in c.windows if w.pole and w.start_lo <= s.t <= w.end_hi), None)
                for c in self.torque_limit
            ]
            out.append((s, pair[0], pair[1]))
        return out

    @property
    def knots(self) -> tuple[float, ...]:
        """The break times of a piecewise motion [s] (``knot_jumps``' times)."""
        return tuple(k.t for k in self.knot_jumps)

    @property
    def singularities(self) -> tuple[FiveBarInstant, ...]:
        """The Type II instants, in time order."""
        return self.analysis.instants

    @property
    def type_one(self) -> tuple[TypeOne, ...]:
        """The Type I instants (a leg stretched or folded), in time order."""
        return self.analysis.type_one

    def findings_at(self, s: FiveBarInstant) -> list[Finding]:
        """The findings made at the Type II instant ``s`` (one of ``singularities``)."""
        i = next(i for i, x in enumerate(self.singularities) if x is s)
        return [f for f in self.findings if f.instant == i]

    def __repr__(self) -> str:
        n = len(self.singularities)
        rules = ", ".join(dict.fromkeys(f.rule for f in self.findings)) or "none"
        return (
            f"<FiveBarAuditResult {self.task.name!r}: {self.verdict}, {n} Type II"
            f" instant{'s' if n != 1 else ''}, findings {rules}>"
        )


def audit_five_bar(task: Task, o: AuditOptions, tell: OnStage) -> FiveBarAuditResult:
    """The exact audit of the 5R ``task`` under the options ``o`` (``engine.audit``
    resolved them); what this build cannot audit of a 5R is refused first (``refuse``).

    A motion of several pieces (``timing.x``, ``motion.pieces``, waypoints) is analysed
    piece by piece in time order, each on its closed span [t_k, t_k+1]: the working modes
    at the start of a piece are those at the end of the one before (positions are
    continuous at the knots and the modes can change only where a leg is stretched or
    folded), an instant at a knot is judged from each side (``at_knot``), and the first
    Type I instant stops the analysis: the pieces after it are not analysed."""
    strict = task.checks.strict if o.strict is None else o.strict
    asked = task.checks.peak if o.peak is None else o.peak
    refuse(task, options=o)
    tell(FACTORING)
    r = task.robot
    assert r.five_bar is not None  # a 5R task's robot (``model.five_bar``)
    parts: list[FiveBarAnalysis] = []
    for j, piece in enumerate(task.motion):
        try:
            a = analyse_robot(
                r, piece.x, piece.y, piece.start, piece.end,
                task.checks.min_slope, task.checks.min_speed, piece.local,
            )  # fmt: skip
        except FiveBarError as e:
            raise _error(task, str(e), _motion_key(task)) from None
        parts.append(replace(a, type_one=tuple(replace(k, piece=j) for k in a.type_one)))
        if a.refused:
            break  # the working modes are lost at a Type I instant
    tell(FINDINGS)
    several = len(task.motion) > 1
    analysis = joined(task, parts) if several else parts[0]
    knots = K.knots(task.motion[: len(parts)], r, torques_at) if several else []
    whole = all(a.on_curve for a in parts) and len(parts) == len(task.motion)
    found = findings(task, analysis, knots, _on_curve(task, parts, whole))
    peak, computed, checked = _certified(task, analysis, asked, whole, tell, parts)
    text = labels([k.t for k in analysis.type_one] + [s.t for s in analysis.instants])
    if checked is not None:
        from .five_bar_certified import limit_findings

        found += limit_findings(
            task, analysis.instants, peak, checked, lambda t: f"t = {text[t]} s"
        )
    elif task.checks.torque_limit is not None and analysis.refused and not whole:
        found.append(unchecked(analysis.type_one[0], text[analysis.type_one[0].t]))
    return FiveBarAuditResult(
        task=task,
        strict=strict,
        analysis=analysis,
        findings=[
            replace(f, strict=strict) for f in with_levels(found, o.levels(task.checks.rules))
        ],
        on_singular_curve=whole,
        parts=tuple(parts),
        knot_jumps=tuple(knots),
        peak_computed=computed,
        torque_peak=peak,
        torque_limit=checked,
        grid_size=o.samples,
    )


def _certified(
    task: Task, analysis: FiveBarAnalysis, asked: bool, on_curve: bool, tell: OnStage,
    parts: Sequence[FiveBarAnalysis] = (),
) -> tuple[tuple[Peak, Peak] | None, bool, tuple[LimitCheck, LimitCheck] | None]:  # fmt: skip
    """The torque peak (when asked for, or free: infinite at a pole), whether it was
    computed, and the limit check (with ``checks.torque_limit``); none of them where
    the torques are undefined (a Type I instant, the path on a Type II curve or a piece
    along one). A motion of several pieces: each piece's (``parts``: their analyses)
    joined (``five_bar_pieces``)."""
    limit = task.checks.torque_limit
    if on_curve or analysis.refused or any(a.on_curve for a in parts):
        return None, asked or limit is not None, None
    poles = [s for s in analysis.instants if not s.bounded]
    peak: tuple[Peak, Peak] | None = None
    if poles:
        t = poles[0].t
        peak = (Peak(math.inf, t, math.inf, True), Peak(math.inf, t, math.inf, True))
    if not asked and limit is None:
        return peak, peak is not None, None
    tell(ENVELOPE)
    lim = None if limit is None else (to_float(limit[0]), to_float(limit[1]))
    if len(task.motion) > 1:
        from .five_bar_pieces import five_bar_parts, limit_check_pieces, torque_peak_pieces

        each = five_bar_parts(task.motion, task.robot, parts)
        if peak is None and asked:
            peak = torque_peak_pieces(each)
        return peak, peak is not None, None if lim is None else limit_check_pieces(each, lim, peak)
    from .five_bar_certified import limit_check, torque_peak

    motion = certified_motion(task, analysis)
    if peak is None and asked:
        peak = torque_peak(motion)
    checked = None
    if limit is not None:
        checked = limit_check(motion, (to_float(limit[0]), to_float(limit[1])), peak)
    return peak, peak is not None, checked


def _past_type_one(samples: FiveBarSamples, k: TypeOne) -> None:
    """The samples at or after the Type I instant ``k`` (exactly when it is rational):
    NaN but for the path, with the Type I reason code (in place)."""
    from .certified.five_bar_samples import FIELDS, PATH, TYPE_ONE

    if k.t_exact is not None:
        past = np.array([fmpq(*v.as_integer_ratio()) >= k.t_exact for v in samples.t.tolist()])
    else:
        past = samples.t >= k.t
    if not past.any():
        return
    for name in FIELDS:
        if name not in PATH:
            samples.column(name)[past] = math.nan
    samples.reason[past] = TYPE_ONE


def certified_motion(task: Task, analysis: FiveBarAnalysis) -> FiveBarMotion:
    """The 5R task's motion (of one piece) in balls, with its Type II instants."""
    from .certified.five_bar import FiveBarMotion

    piece = task.motion[0]
    r = task.robot
    return FiveBarMotion(r.five_bar, r.gravity, piece.x, piece.y, task.duration, analysis.instants)


def _analyses(task: Task, parts: list[FiveBarAnalysis]) -> list[FiveBarAnalysis]:
    """The analyses of every piece: those after the last analysed (the first Type I
    instant stops the analysis) with no instant."""
    empty = FiveBarAnalysis((), (), parts[0].locus, False)
    return parts + [empty] * (len(task.motion) - len(parts))


def _on_curve(task: Task, parts: list[FiveBarAnalysis], whole: bool) -> list[Finding]:
    """RPR104: the motion (of one piece) or each of its pieces runs along a Type II curve."""
    if whole and len(task.motion) == 1:
        return [Finding("RPR104", ON_CURVE)]
    out = []
    for j, a in enumerate(parts):
        if a.on_curve:
            piece = task.motion[j]
            start, end = exact_text(piece.start), exact_text(piece.end)
            message = (
                f"piece {j + 1}, t = {start} s to {end} s, runs along a Type II curve of the"
                " robot (S₊ or S₋ vanishes all along it): every instant of that piece is a"
                " Type II singularity"
            )
            out.append(Finding("RPR104", message, to_float(piece.start)))
    return out


def joined(task: Task, parts: list[FiveBarAnalysis]) -> FiveBarAnalysis:
    """The analyses of the pieces as one, in time order: an instant at a break of the
    motion (0 and t_f included) found by the pieces on either side becomes one instant
    with its sides (``at_knot``); the Type I instants are those of the last piece
    analysed (the first Type I instant stops the analysis); the locus is the first
    piece's (each piece's is in ``FiveBarAuditResult.parts``)."""
    breaks = {task.motion[0].start} | {p.end for p in task.motion}
    plain: list[FiveBarInstant] = []
    sides: dict[fmpq, dict[str, FiveBarInstant]] = {}
    for j, a in enumerate(parts):
        piece = task.motion[j]
        for s in a.instants:
            if s.t_exact is not None and s.t_exact in breaks:
                side = "after" if s.t_exact == piece.start else "before"
                sides.setdefault(s.t_exact, {})[side] = s
            else:
                plain.append(s)
    plain += [at_knot(pair.get("before"), pair.get("after")) for pair in sides.values()]
    plain.sort(key=lambda s: (s.t, float(s.t_ball.mid())))
    return FiveBarAnalysis(
        tuple(plain), parts[-1].type_one, parts[0].locus, all(a.on_curve for a in parts)
    )


def _side(name: str, principle: Principle, two: bool) -> Principle:
    return replace(principle, reason=f"{name} the knot: {principle.reason}") if two else principle


def _float(v: Any) -> float:
    """An exact value (rational, ball, float) as a double for ordering."""
    if isinstance(v, fmpq):
        return to_float(v)
    if isinstance(v, arb):
        return float(v.mid())
    return float(v)


def at_knot(before: FiveBarInstant | None, after: FiveBarInstant | None) -> FiveBarInstant:
    """One instant at a knot from its one-sided analyses (either may be absent: t = 0,
    t = t_f), as the RPRPR's (``pieces.at_knot``): the order the larger; a principle
    fails if it fails on either side (the side's name in its reason); the residuals of an
    inconsistent side; bounded only if both sides are (the pole of the higher order);
    the limit torques the common limit, else None."""
    sides = tuple((n, s) for n, s in (("before", before), ("after", after)) if s is not None)
    ss = [s for _, s in sides]
    two = len(ss) == 2
    base = max(ss, key=lambda s: s.order)
    slope_n, slope_s = min(
        sides, key=lambda p: (p[1].slope_principle.passed, _float(abs(p[1].slope)))
    )
    speed_n, speed_s = min(
        sides, key=lambda p: (p[1].velocity_principle.passed, _float(p[1].speed2))
    )
    _, resid_s = max(
        sides, key=lambda p: (not p[1].consistent, _float(abs(p[1].consistency_residual)))
    )
    pole = max(s.order - s.conditions_met for s in ss)
    limits = [s.torque_at_singularity for s in ss]
    torque = limits[0] if all(_same(lim, limits[0]) for lim in limits) else None
    return replace(
        base,
        order=base.order,
        slope=slope_s.slope,
        normal_rate=slope_s.normal_rate,
        slope_principle=_side(slope_n, slope_s.slope_principle, two),
        speed2=speed_s.speed2,
        velocity_principle=_side(speed_n, speed_s.velocity_principle, two),
        residuals=resid_s.residuals,
        conditions_met=base.order - pole,
        torque_at_singularity=torque,
        knot=True,
        sides=sides,
    )


def _same(a: tuple[Any, Any] | None, b: tuple[Any, Any] | None) -> bool:
    """Two limit torques known equal (exactly, or as the same ball)."""
    if a is None or b is None:
        return a is b
    return all(
        (u == v) if isinstance(u, fmpq) and isinstance(v, fmpq) else (u is v)
        for u, v in zip(a, b, strict=True)
    )


def torques_at(piece: Piece, t: fmpq, robot: Robot) -> tuple[float, float] | None:
    """(T1, T2) of the 5R ``robot`` on the motion ``piece`` at the exact time t in its
    working modes (``knots.knots``' one-sided torques at a knot), in arb; None where a
    leg's discriminant or δ is not proven nonzero."""
    assert robot.five_bar is not None
    values = K.path_at(piece, t)
    with ctx.workprec(K.PREC):
        X, Xd, Xdd, Y, Yd, Ydd = (arb(v) for v in values)
        p = fb.params(robot.five_bar, robot.gravity, arb)
        modes = (int(robot.five_bar.modes[0]), int(robot.five_bar.modes[1]))
        proven = [True]

        def root(D: arb, i: int) -> arb:
            proven[0] = proven[0] and bool(D > 0)
            return D.sqrt() if D > 0 else arb(1)

        d = fb.dynamics(*fb.legs(p, modes, X, Xd, Xdd, Y, Yd, Ydd, root), p)
        if not proven[0] or not (d.delta > 0 or d.delta < 0):
            return None
        T1, T2 = fb.torques(d)
        if not (T1.is_finite() and T2.is_finite()):
            return None
        return float(T1.mid()), float(T2.mid())


ON_CURVE = (
    "the path runs along a Type II curve of the robot (S₊ or S₋ vanishes all along it):"
    " every instant is a Type II singularity"
)


def refuse(task: Task, *, options: AuditOptions | None = None) -> None:
    """A 5R task asks for what this build cannot audit of a 5R: a ``TaskFileError``
    located at the key that asks for it: declared uncertainty. (The certified layers of
    a motion of one piece: ``five_bar_certified``; of several: ``five_bar_pieces``.)"""
    if task.robot.mechanism != FIVE_BAR:
        return
    u = task.uncertainty or (options.uncertainty if options is not None else None)
    if u is not None:
        whose = f" (declared by the configuration {u.origin})" if u.origin else ""
        raise _error(task, f"uncertainty is {YET}{whose} (its audit is the RPRPR's)", "uncertainty")


def refuse_command(task: Task, command: str) -> None:
    """``command`` (repair) is not available for a 5R task yet: a ``TaskFileError`` at
    ``robot.mechanism`` (nothing for an RPRPR)."""
    if task.robot.mechanism != FIVE_BAR:
        return
    raise _error(task, f"rprpr {command} is {YET} (rprpr check audits it)", "robot.mechanism")


def _motion_key(task: Task) -> str:
    for key in ("motion", "timing", "path"):
        if key in task.lines:
            return key
    return "motion"


def _error(task: Task, message: str, key: str) -> TaskFileError:
    """A ``TaskFileError`` at ``key``'s line, else its section's, else (a key the task
    file does not hold: an option or the configuration asked for it) at the motion's
    top-level key (column 1)."""
    line = task.lines.get(key) or task.lines.get(key.split(".")[0], 0)
    if line:
        return TaskFileError(message, file=task.source, line=line, key=key)
    line = task.lines.get(_motion_key(task), 0)
    return TaskFileError(message, file=task.source, line=line, column=1 if line else 0, key=key)


# -- the findings -------------------------------------------------------------------------


def findings(
    task: Task, a: FiveBarAnalysis, knots: Sequence[K.Knot] = (), on_curve: Sequence[Finding] = ()
) -> list[Finding]:
    """What the audit found wrong, in report order: the path (``on_curve``) or pieces
    along a Type II curve (RPR104), the knots' velocity and acceleration jumps (RPR203,
    RPR204, as for the RPRPR), the Type I instant that stops the analysis (RPR103), then
    at each Type II instant the broken principles (RPR101, RPR102) and unbounded torques
    (RPR201, a warning under ``checks.unbounded_torque: warn``)."""
    text = labels([k.t for k in a.type_one] + [s.t for s in a.instants])
    out = list(on_curve) + [f for k in knots for f in knot(k)]
    out += [type_one(k, text[k.t], len(a.instants), len(task.motion) > 1) for k in a.type_one]
    accepted = task.checks.unbounded_torque == "warn"
    for i, s in enumerate(a.instants):
        where = where_text(s, text[s.t])
        hits = []
        if not s.slope_principle.passed:
            hits.append(
                Finding("RPR101", f"{where}: transversality (slope) principle fails:"
                        f" {s.slope_principle.reason}", s.t)
            )  # fmt: skip
        if not s.velocity_principle.passed:
            hits.append(
                Finding("RPR102", f"{where}: velocity principle fails:"
                        f" {s.velocity_principle.reason}", s.t)
            )  # fmt: skip
        if not s.bounded:
            hits.append(Finding("RPR201", unbounded_text(s, where), s.t, downgraded=accepted))
        out += [replace(f, instant=i) for f in hits]
    return out


def type_one(k: TypeOne, t: str, before: int = 0, several: bool = False) -> Finding:
    """RPR103: leg k.leg stretched or folded at k.t (the inverse kinematics fail); the
    analysis stops there (``before``: the Type II instants found before it)."""
    joint = "A" if k.leg == 1 else "B"
    bound = "l{0} + l{1}" if k.kind == "stretched" else "|l{0} - l{1}|"
    bound = bound.format(k.leg, k.leg + 2)
    where = f" (piece {k.piece + 1})" if several else ""
    found = f"{before} Type II instant{'s' if before != 1 else ''}"
    message = (
        f"t = {t} s{where}: leg {k.leg} is {k.kind} (|E - {joint}| = {bound}): Type I"
        " singularity, the inverse kinematics fail and the working mode is lost; the"
        f" analysis stops here ({found} before it)"
    )
    return Finding("RPR103", message, k.t)


def unchecked(k: TypeOne, t: str) -> Finding:
    """RPR202: ``checks.torque_limit`` is not checked, because the first Type I instant
    (``k``, at ``t``) stops the analysis: the torques are undefined past it (the working
    mode is lost), so the limit is not decided over [0, t_f] (``torque_limit`` None)."""
    joint = "A" if k.leg == 1 else "B"
    message = (
        f"t = {t} s: the torque limit is not checked: leg {k.leg} is {k.kind} (Type I"
        f" singularity, |E - {joint}| at its bound), where the analysis stops; the torques"
        " past it are undefined (the working mode is lost)"
    )
    return Finding("RPR202", message, k.t)


def where_text(s: FiveBarInstant, t: str) -> str:
    """``t = 0.5 s, (x, y) = (0.969, 0.754), modes (+1, -1), σ = -1, order 1`` (and
    ``, at a knot`` for an instant at a break of a piecewise motion)."""
    e1, e2 = s.modes
    return (
        f"t = {t} s, (x, y) = ({number(s.x)}, {number(s.y)}), modes ({e1:+d}, {e2:+d}),"
        f" σ = {s.sigma:+d}, order {s.order}{', at a knot' if s.knot else ''}"
    )


def unbounded_text(s: FiveBarInstant, where: str) -> str:
    """RPR201's message: the reciprocity condition fails (with its residual), or it holds
    but only k of the order's conditions do."""
    pole = s.order - s.conditions_met
    why = (
        f"consistent (the reciprocity condition holds), but only {s.conditions_met} of"
        f" {s.order} boundedness conditions hold"
        if s.consistent
        else f"inconsistent: reciprocity residual {exact_number(s.consistency_residual)} N ≠ 0"
    )
    return f"{where}: torques unbounded (pole of order {pole}): {why}"

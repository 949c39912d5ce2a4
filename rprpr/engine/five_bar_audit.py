"""The audit of a 5R task: its exact verdicts (pure; docs/five-bar.md).

    task -> E(t) (exact polynomials) -> Type I instants, else Type II instants
         (``exact.five_bar_instants``) -> findings -> FiveBarAuditResult

The rules are the RPRPR's where the meaning is the same: the transversality principle is
RPR101 (the slope principle: the path crosses the Type II curve at an angle), the speed
principle RPR102, a leg stretched or folded RPR103 (the inverse kinematics fail, as at A
or B for the RPRPR), the path along the Type II curve RPR104 and unbounded torques RPR201
(the reciprocity condition and the high-order conditions, §6).

What this build audits of a 5R: a motion of one piece (y = p(x) with a timing law, or the
end point's x(t), y(t) as one piece), without declared uncertainty; with its certified
layers (``five_bar_certified``, loaded only for a task that asks for them): the torque
peak, the torque limit check and its windows, the samples. What it does not audit of a 5R
(the sheet, repair) ``refuse`` refuses in one located line (a ``TaskFileError``: exit
status 2).
"""

from __future__ import annotations

import math
from dataclasses import field, replace
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
from flint import fmpq_poly

from ..model.dataclass import dataclass
from ..model.errors import TaskFileError
from ..model.five_bar import FIVE_BAR
from ..model.numbers import exact_number, labels, number, to_float
from ..model.options import AuditOptions
from ..model.rules import Finding, Judged, with_levels
from ..model.task import Task
from .bounds.verdicts import LimitCheck, Peak, Window
from .exact import five_bar as fb
from .exact.five_bar_instants import (
    FiveBarAnalysis,
    FiveBarError,
    FiveBarInstant,
    TypeOne,
    analyse_robot,
)
from .exact.singular import FACTORING, OnStage

if TYPE_CHECKING:  # the ball machinery is imported only by a task that needs it
    from .certified.five_bar import FiveBarMotion
    from .certified.five_bar_samples import FiveBarSamples

YET = "not available for a 5R yet"
FINDINGS = "the findings"
ENVELOPE = "the torque envelope"
GRID = 101  # ``samples``' default grid (``AuditOptions.samples``)


@dataclass(frozen=True)
class FiveBarAuditResult(Judged):
    """What ``rprpr check`` reports for a 5R task: its Type II instants (``analysis``:
    times, working modes, line-up σ, order, principles, residuals, limit torques), or the
    Type I instants that stop its inverse kinematics; the findings and the verdict; and
    the certified layers as the RPRPR's ``AuditResult`` has them: ``torque_peak`` (inf at
    a pole; None when not asked for, then ``peak_computed`` is False, or undefined: a
    Type I instant or the path on the curve), ``torque_limit`` (None without a limit),
    ``saturation`` and ``samples`` (certified values on ``grid_size`` times, made when
    first read; ``resample`` at any times)."""

    task: Task
    strict: bool
    analysis: FiveBarAnalysis = field(repr=False, compare=False)
    findings: list[Finding]
    on_singular_curve: bool = False  # the path runs along a Type II curve all along
    peak_computed: bool = False
    torque_peak: tuple[Peak, Peak] | None = None
    torque_limit: tuple[LimitCheck, LimitCheck] | None = None
    grid_size: int = field(default=GRID, repr=False)
    closest_approach: None = None  # the RPRPR's distance to the line AB: no 5R meaning

    @cached_property
    def motion(self) -> FiveBarMotion:
        """The motion in balls (``certified.five_bar``), made when first read."""
        return certified_motion(self.task, self.analysis)

    @cached_property
    def samples(self) -> FiveBarSamples:
        """Certified samples at ``grid_size`` evenly spaced times, t = 0 .. t_f."""
        from .certified.sampling import grid

        return self.resample(grid(self.task.duration, self.grid_size))

    def resample(self, t: np.ndarray) -> FiveBarSamples:
        """The motion, joints, δ, the axial force and the torques at the times ``t`` [s],
        certified (``certified.five_bar_samples``)."""
        from .certified.five_bar_samples import sample

        return sample(self.motion, np.asarray(t, dtype=float))

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
    resolved them); what this build cannot audit of a 5R is refused first (``refuse``)."""
    strict = task.checks.strict if o.strict is None else o.strict
    refuse(task, peak=task.checks.peak if o.peak is None else o.peak, options=o)
    piece = task.motion[0]
    x, y = piece.x, piece.y
    asked = task.checks.peak if o.peak is None else o.peak
    tell(FACTORING)
    r = task.robot
    assert r.five_bar is not None  # a 5R task's robot (``model.five_bar``)
    p = fb.params(r.five_bar, r.gravity)
    if any(fb.curve(p, s, x, y).is_zero() for s in (1, -1)):
        analysis = FiveBarAnalysis((), (), (fmpq_poly(), fmpq_poly()))
        found = [Finding("RPR104", ON_CURVE)]
        on_curve = True
    else:
        try:
            analysis = analyse_robot(
                r, x, y, piece.start, piece.end, task.checks.min_slope, task.checks.min_speed
            )
        except FiveBarError as e:
            raise _error(task, str(e), _motion_key(task)) from None
        tell(FINDINGS)
        found = findings(task, analysis, x, y)
        on_curve = False
    peak, computed, checked = _certified(task, analysis, asked, on_curve, tell)
    if checked is not None:
        from .five_bar_certified import limit_findings

        text = labels([k.t for k in analysis.type_one] + [s.t for s in analysis.instants])
        found += limit_findings(
            task, analysis.instants, peak, checked, lambda t: f"t = {text[t]} s"
        )
    return FiveBarAuditResult(
        task=task,
        strict=strict,
        analysis=analysis,
        findings=[
            replace(f, strict=strict) for f in with_levels(found, o.levels(task.checks.rules))
        ],
        on_singular_curve=on_curve,
        peak_computed=computed,
        torque_peak=peak,
        torque_limit=checked,
        grid_size=o.samples,
    )


def _certified(
    task: Task, analysis: FiveBarAnalysis, asked: bool, on_curve: bool, tell: OnStage
) -> tuple[tuple[Peak, Peak] | None, bool, tuple[LimitCheck, LimitCheck] | None]:
    """The torque peak (when asked for, or free: infinite at a pole), whether it was
    computed, and the limit check (with ``checks.torque_limit``); none of them where
    the torques are undefined (a Type I instant, the path on a Type II curve)."""
    limit = task.checks.torque_limit
    if on_curve or analysis.refused:
        return None, asked or limit is not None, None
    poles = [s for s in analysis.instants if not s.bounded]
    peak: tuple[Peak, Peak] | None = None
    if poles:
        t = poles[0].t
        peak = (Peak(math.inf, t, math.inf, True), Peak(math.inf, t, math.inf, True))
    if not asked and limit is None:
        return peak, peak is not None, None
    from .five_bar_certified import limit_check, torque_peak

    tell(ENVELOPE)
    motion = certified_motion(task, analysis)
    if peak is None and asked:
        peak = torque_peak(motion)
    checked = None
    if limit is not None:
        checked = limit_check(motion, (to_float(limit[0]), to_float(limit[1])), peak)
    return peak, peak is not None, checked


def certified_motion(task: Task, analysis: FiveBarAnalysis) -> FiveBarMotion:
    """The 5R task's motion in balls, with its Type II instants."""
    from .certified.five_bar import FiveBarMotion

    piece = task.motion[0]
    r = task.robot
    return FiveBarMotion(r.five_bar, r.gravity, piece.x, piece.y, task.duration, analysis.instants)


ON_CURVE = (
    "the path runs along a Type II curve of the robot (S₊ or S₋ vanishes all along it):"
    " every instant is a Type II singularity"
)


def refuse(task: Task, *, peak: bool = False, options: AuditOptions | None = None) -> None:
    """A 5R task asks for what this build cannot audit of a 5R: a ``TaskFileError``
    located at the key that asks for it (the first met): a motion of several pieces
    (``timing``, ``motion``), declared uncertainty."""
    if task.robot.mechanism != FIVE_BAR:
        return
    if len(task.motion) != 1 or task.law == "waypoints":
        raise _error(
            task,
            f"a piecewise motion ({task.law}) is {YET}: give one polynomial piece (y = p(x)"
            " with a rest-to-rest or explicit timing law, or one piece of motion.pieces)",
            _motion_key(task),
        )
    if task.uncertainty is not None or (options is not None and options.uncertainty):
        raise _error(task, f"uncertainty is {YET} (its audit is the RPRPR's)", "uncertainty")


def refuse_command(task: Task, command: str) -> None:
    """``command`` (plot, export, repair) needs the certified layers, which a 5R task does
    not have yet: a ``TaskFileError`` at ``robot.mechanism`` (nothing for an RPRPR)."""
    if task.robot.mechanism == FIVE_BAR:
        raise _error(task, f"rprpr {command} is {YET} (rprpr check audits it)", "robot.mechanism")


def _motion_key(task: Task) -> str:
    for key in ("motion", "timing", "path"):
        if key in task.lines:
            return key
    return "motion"


def _error(task: Task, message: str, key: str) -> TaskFileError:
    line = task.lines.get(key) or task.lines.get(key.split(".")[0], 0)
    return TaskFileError(message, file=task.source, line=line, key=key)


# -- the findings -------------------------------------------------------------------------


def findings(task: Task, a: FiveBarAnalysis, x: fmpq_poly, y: fmpq_poly) -> list[Finding]:
    """What the audit found wrong, in report order: the Type I instants (RPR103), then at
    each Type II instant the broken principles (RPR101, RPR102) and unbounded torques
    (RPR201, a warning under ``checks.unbounded_torque: warn``)."""
    text = labels([k.t for k in a.type_one] + [s.t for s in a.instants])
    out = [type_one(k, text[k.t], x, y) for k in a.type_one]
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


def type_one(k: TypeOne, t: str, x: fmpq_poly, y: fmpq_poly) -> Finding:
    """RPR103: leg k.leg stretched or folded at k.t (the inverse kinematics fail)."""
    joint = "A" if k.leg == 1 else "B"
    bound = "l{0} + l{1}" if k.kind == "stretched" else "|l{0} - l{1}|"
    bound = bound.format(k.leg, k.leg + 2)
    message = (
        f"t = {t} s: leg {k.leg} is {k.kind} (|E - {joint}| = {bound}): Type I singularity,"
        " the inverse kinematics fail and the working mode is lost"
    )
    return Finding("RPR103", message, k.t)


def where_text(s: FiveBarInstant, t: str) -> str:
    """``t = 0.5 s, (x, y) = (0.969, 0.754), modes (+1, -1), σ = -1, order 1``."""
    e1, e2 = s.modes
    return (
        f"t = {t} s, (x, y) = ({number(s.x)}, {number(s.y)}), modes ({e1:+d}, {e2:+d}),"
        f" σ = {s.sigma:+d}, order {s.order}"
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

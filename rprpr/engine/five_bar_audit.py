"""The audit of a 5R task: its exact verdicts (pure; docs/five-bar.md).

    task -> E(t) (exact polynomials) -> Type I instants, else Type II instants
         (``exact.five_bar_instants``) -> findings -> FiveBarAuditResult

The rules are the RPRPR's where the meaning is the same: the transversality principle is
RPR101 (the slope principle: the path crosses the Type II curve at an angle), the speed
principle RPR102, a leg stretched or folded RPR103 (the inverse kinematics fail, as at A
or B for the RPRPR), the path along the Type II curve RPR104 and unbounded torques RPR201
(the reciprocity condition and the high-order conditions, §6).

What this build audits of a 5R: a motion of one piece (y = p(x) with a timing law, or the
end point's x(t), y(t) as one piece), without declared uncertainty. The certified layers
(torque peak, torque limit, samples, the sheet, export, repair) are not available for a
5R yet: ``refuse`` says so in one located line (a ``TaskFileError``: exit status 2).
"""

from __future__ import annotations

from dataclasses import field, replace

from flint import fmpq_poly

from ..model.dataclass import dataclass
from ..model.defaults import DEFAULT_SAMPLES
from ..model.errors import TaskFileError
from ..model.five_bar import FIVE_BAR
from ..model.numbers import exact_number, labels, number
from ..model.options import AuditOptions
from ..model.rules import Finding, Judged, with_levels
from ..model.task import Task
from .exact import five_bar as fb
from .exact.five_bar_instants import (
    FiveBarAnalysis,
    FiveBarError,
    FiveBarInstant,
    TypeOne,
    analyse_robot,
)
from .exact.singular import FACTORING, OnStage

YET = "not available for a 5R yet"
FINDINGS = "the findings"


@dataclass(frozen=True)
class FiveBarAuditResult(Judged):
    """What ``rprpr check`` reports for a 5R task: its Type II instants (``analysis``:
    times, working modes, line-up σ, order, principles, residuals, limit torques), or the
    Type I instants that stop its inverse kinematics; the findings and the verdict. The
    certified layers of the RPRPR's ``AuditResult`` are absent: no torque peak, no torque
    limit, no samples (``peak_computed`` is False)."""

    task: Task
    strict: bool
    analysis: FiveBarAnalysis = field(repr=False, compare=False)
    findings: list[Finding]
    on_singular_curve: bool = False  # the path runs along a Type II curve all along
    peak_computed: bool = False
    grid_size: int = field(default=DEFAULT_SAMPLES, repr=False)  # the sheet's samples

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
    return FiveBarAuditResult(
        task=task,
        strict=strict,
        analysis=analysis,
        findings=[
            replace(f, strict=strict) for f in with_levels(found, o.levels(task.checks.rules))
        ],
        on_singular_curve=on_curve,
        grid_size=o.samples,
    )


ON_CURVE = (
    "the path runs along a Type II curve of the robot (S₊ or S₋ vanishes all along it):"
    " every instant is a Type II singularity"
)


def refuse(task: Task, *, peak: bool = False, options: AuditOptions | None = None) -> None:
    """A 5R task asks for what this build cannot audit of a 5R: a ``TaskFileError``
    located at the key that asks for it (the first met): a motion of several pieces
    (``timing``, ``motion``), declared uncertainty, a torque limit, the torque peak."""
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
    if task.checks.torque_limit is not None:
        raise _error(
            task,
            f"the certified torque limit check is {YET} (remove checks.torque_limit)",
            "checks.torque_limit",
        )
    if peak:
        raise _error(
            task, f"the certified torque peak (--peak, checks.peak) is {YET}", "checks.peak"
        )


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

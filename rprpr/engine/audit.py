"""The audit of a task: singular instants, torque verdicts, findings and the verdict (pure).

    task -> trajectory (exact polynomials) -> singular analysis (exact)
         -> certified motion -> torque envelope (grid-free) -> findings -> AuditResult

Nothing the audit decides depends on a sampling grid: the singular instants are exact,
the torque peak, the limit check, the saturation windows and the closest approach are
certified over the whole interval [0, t_f] (``envelope``). The samples that ``export``
writes and ``plot`` draws are certified values at the grid's times, made on demand
(``AuditResult.samples``). ``audit`` returns a plain result object; rendering it is the
command line's business.
"""

from __future__ import annotations

from dataclasses import field, replace
from fractions import Fraction
from functools import cached_property
from typing import TYPE_CHECKING, Any, Unpack

import numpy as np
from flint import fmpq

from ..model.dataclass import dataclass
from ..model.errors import TaskFileError
from ..model.five_bar import FIVE_BAR, RPRPR
from ..model.numbers import to_float
from ..model.options import AuditKeywords, AuditOptions
from ..model.rules import Finding, Judged, with_levels
from ..model.task import Task
from . import pieces as P
from .bounds.verdicts import Approach, LimitCheck, Peak, Window, around_poles
from .exact import knots as K
from .exact.singular import (
    EXPANDING,
    FACTORING,
    ISOLATING,
    KinematicSingularity,
    OnStage,
    SingularAnalysis,
    SingularInstant,
)
from .exact.trajectory import Trajectory
from .findings import findings

if TYPE_CHECKING:  # the ball machinery is imported only by a task that needs a pass
    from .certified.motion import CertifiedMotion
    from .certified.sampling import Samples
    from .robust.windows import Robust

ENVELOPE = "the torque envelope"
FINDINGS = "the findings"
STAGES = (FACTORING, ISOLATING, EXPANDING, ENVELOPE, FINDINGS)  # in the order they begin

DEFAULT = AuditOptions()  # the task's own choices

Saturation = tuple[SingularInstant, Window | None, Window | None]


@dataclass(frozen=True)
class AuditResult(Judged):
    """Everything ``rprpr check`` reports for one task.

    ``torque_peak`` = (max |T1|, max |T2|) over [0, t_f], certified (``envelope.Peak``:
    the value, where it is reached, a proven upper bound); inf where a singular instant
    has unbounded torques; None when the path lies on y = 0, or when it was not asked
    for (``audit``'s ``peak``: then ``peak_computed`` is False). ``torque_limit``: the
    certified check of ``checks.torque_limit`` for every t (None without a limit);
    ``saturation``: for each unbounded instant, the windows around it in which |T1|, |T2|
    exceed their limits (empty without a limit); ``closest_approach``: for a motion that
    never meets the line AB, how close it comes (None otherwise). ``verdict`` is "pass"
    or "fail". ``samples`` are certified values on the grid of ``grid_size`` points, made
    when first read. Only what the audit decided is stored; what follows from it (the
    instants of ``analysis``, ``saturation``, ``knots``, ``trajectory``) is a property.
    """

    task: Task
    strict: bool
    torque_peak: tuple[Peak, Peak] | None
    torque_limit: tuple[LimitCheck, LimitCheck] | None
    closest_approach: Approach | None
    findings: list[Finding]
    grid_size: int = field(repr=False)
    analysis: SingularAnalysis = field(repr=False, compare=False)
    parts: tuple[P.Part, ...] = field(default=(), repr=False, compare=False)  # ``resample``
    knot_jumps: tuple[K.Knot, ...] = field(default=(), repr=False)  # what jumps at the knots
    peak_computed: bool = True  # False: the peak was not asked for (``torque_peak`` None)
    # with ``task.uncertainty``: each singular instant's robust analysis (docs/robust.md)
    robust: tuple[Robust, ...] = ()
    # with ``task.uncertainty`` and the peak asked for: ((lower, upper) of sup |E1|, of
    # sup |E2|) over the box and the times outside the proven windows (``worst_peak``)
    robust_peak: tuple[tuple[float, float], tuple[float, float]] | None = None

    @property
    def singularities(self) -> list[SingularInstant]:
        """The Type II singular instants, in time order (``analysis.instants``)."""
        return self.analysis.instants

    @property
    def kinematic_singularities(self) -> list[KinematicSingularity]:
        """E at A or at B (``analysis.kinematic``)."""
        return self.analysis.kinematic

    @property
    def on_singular_line(self) -> bool:
        """The path lies on y = 0 all along (``analysis.on_singular_line``)."""
        return self.analysis.on_singular_line

    @cached_property
    def saturation(self) -> list[Saturation]:
        """For each unbounded instant, the windows around it in which |T1|, |T2| exceed
        their limits (empty without a limit)."""
        checked = self.torque_limit
        return [] if checked is None else _saturation(self.analysis, checked)

    @property
    def trajectory(self) -> Trajectory:
        """The first piece's exact trajectory."""
        return self.parts[0].traj

    @property
    def knots(self) -> tuple[float, ...]:
        """The break times of a piecewise motion [s] (``knot_jumps``' times)."""
        return tuple(k.t for k in self.knot_jumps)

    @property
    def motion(self) -> CertifiedMotion:
        """The first piece's certified motion (made when first read)."""
        return self.parts[0].motion

    @cached_property
    def samples(self) -> Samples:
        """Certified samples at ``grid_size`` evenly spaced times, t = 0 .. t_f."""
        from .certified.sampling import grid

        return self.resample(grid(self.task.duration, self.grid_size))

    def resample(self, t: np.ndarray) -> Samples:
        """The motion, joints, δ, λ and torques at the times ``t`` [s], certified, from
        the exact analysis already made (no new analysis)."""
        return P.sample(list(self.parts), np.asarray(t, dtype=float))

    def findings_at(self, s: SingularInstant) -> list[Finding]:
        """The findings the audit made at the singular instant ``s`` (one of
        ``singularities``), tied to it by its index: two instants whose times round to one
        double never share them."""
        i = next((i for i, x in enumerate(self.singularities) if x is s), None)
        if i is None:
            i = self.singularities.index(s)
        return [f for f in self.findings if f.instant == i]

    def status_of(self, s: SingularInstant) -> str:
        """ "fail" when a finding at ``s`` fails the task, "warn" when one only warns,
        else "ok" (decided here once; renderers only read it)."""
        hits = self.findings_at(s)
        if any(f.fails(self.strict) for f in hits):
            return "fail"
        return "warn" if hits else "ok"

    def __repr__(self) -> str:
        """One short line: ``<AuditResult 'paper_path1': fail, 1 singular instant (1
        high-order), findings RPR101, RPR201>`` (the fields themselves hold the rest)."""
        n = len(self.singularities)
        high = sum(s.high_order for s in self.singularities)
        rules = ", ".join(dict.fromkeys(f.rule for f in self.findings)) or "none"
        return (
            f"<AuditResult {self.task.name!r}: {self.verdict}, {n} singular"
            f" instant{'s' if n != 1 else ''} ({high} high-order), findings {rules}>"
        )


def audit(
    task: Task,
    options: AuditOptions | None = None,
    *,
    on_stage: OnStage | None = None,
    **keywords: Unpack[AuditKeywords],
) -> AuditResult:
    """Audit ``task`` as ``options`` say (``model.options.AuditOptions``: the grid of
    ``AuditResult.samples``, the strict mode, the peak, RPR201's level; by default the
    task's own choices); ``keywords`` are its fields, over ``options``:
    ``audit(task, strict=True)`` is ``audit(task, AuditOptions(strict=True))``.
    ``on_stage``, when given, is told the name of each stage (``STAGES``) as it begins (a
    caller that stops a long audit can say where it was). No verdict needs the certified
    peak, so unless asked for it is computed only where it costs nothing (infinite at a
    pole, undefined on y = 0 or through A or B), else ``AuditResult.peak_computed`` is
    False and ``torque_peak`` None. ``uncertainty`` (an option) replaces the task's own
    (``docs/robust.md``): each instant then has its robust analysis (``robust``).

    A piecewise motion is audited piece by piece (``pieces``): between knots as one
    polynomial, at each knot from both sides. A task of another mechanism than the
    RPRPR's is audited by its own module (``five_bar_audit``: a 5R task's exact
    verdicts, a ``FiveBarAuditResult``)."""
    o = options or DEFAULT
    if keywords:
        o = replace(o, **keywords)
    if task.robot.mechanism != RPRPR:
        return _other(task, o, on_stage or _quiet)
    strict = task.checks.strict if o.strict is None else o.strict
    asked = task.checks.peak if o.peak is None else o.peak
    task = _uncertain(task, o)
    tell = on_stage or _quiet
    parts, batch = P.parts(task, tell)
    tell(ENVELOPE)
    limit = task.checks.torque_limit
    pair = None if limit is None else (to_float(limit[0]), to_float(limit[1]))
    top, computed, checked, approach = P.envelopes(parts, pair, batch, asked)
    analysis = _joined(task, parts)
    knots = K.knots(task.motion, task.robot)
    on_line = [(p.start, p.end) for p in parts if p.analysis.on_singular_line]
    whole = len(on_line) == len(parts) and not task.pieces
    robust = _robust(task, parts, analysis)
    tell(FINDINGS)
    found = findings(task, analysis, top, checked, knots, [] if whole else on_line, robust)
    return AuditResult(
        task=task,
        strict=strict,
        torque_peak=top,
        peak_computed=computed,
        torque_limit=checked,
        closest_approach=approach,
        findings=[
            replace(f, strict=strict) for f in with_levels(found, o.levels(task.checks.rules))
        ],
        grid_size=o.samples,
        analysis=analysis,
        parts=tuple(parts),
        knot_jumps=tuple(knots),
        robust=tuple(robust),
        robust_peak=_robust_peak(task, parts, robust) if asked else None,
    )


def _other(task: Task, o: AuditOptions, tell: OnStage) -> Any:
    """The audit of a task of another mechanism than the RPRPR's: the 5R's
    (``five_bar_audit``, loaded only for such a task); any other is refused here, the
    audit's one door, rather than audited as an RPRPR: a ``TaskFileError`` at
    ``robot.mechanism`` (the command line: a bad input, exit 2)."""
    if task.robot.mechanism == FIVE_BAR:
        from .five_bar_audit import audit_five_bar

        return audit_five_bar(task, o, tell)
    raise TaskFileError(
        f"the {task.robot.mechanism} audit is not available in this build",
        file=task.source,
        line=task.lines.get("robot.mechanism", 0),
        key="robot.mechanism",
    )


def _robust_peak(
    task: Task, parts: list[P.Part], robust: list[Robust]
) -> tuple[tuple[float, float], tuple[float, float]] | None:
    """The worst-case peak over the box between the instants (with uncertainty only)."""
    if task.uncertainty is None:
        return None
    from .robust.worst_peak import worst_peak

    return worst_peak(task, parts, robust)


def _robust(task: Task, parts: list[P.Part], analysis: SingularAnalysis) -> list[Robust]:
    """The robust analysis of each instant when the task declares uncertainty."""
    if task.uncertainty is None or not analysis.instants:
        return []
    from .robust.instants import robust

    sources = analysis._sources or tuple(((0, s),) for s in analysis.instants)
    return robust(task, parts, analysis.instants, sources)


def _uncertain(task: Task, o: AuditOptions) -> Task:
    """The task with the options' uncertainty in place of its own (when given); a
    ValueError when an uncertainty is declared without a torque limit to measure it by."""
    if o.uncertainty is not None:
        task = replace(task, uncertainty=o.uncertainty.exact())
    if task.uncertainty is not None and task.checks.torque_limit is None:
        raise ValueError(
            "uncertainty needs checks.torque_limit: the saturation window around each"
            " singular instant is measured against the actuators' limits"
        )
    return task


def _joined(task: Task, parts: list[P.Part]) -> SingularAnalysis:
    """The singular analyses of all pieces as one, in absolute time: an instant at a
    break of a piecewise motion (0 and t_f included) becomes one knot instant with its
    sides (``pieces.at_knot``); ``on_singular_line`` when every piece lies on y = 0."""
    if len(parts) == 1 and not task.pieces:
        return parts[0].analysis
    sides: dict[Fraction, dict[str, SingularInstant]] = {}
    hints: dict[Fraction, object] = {}
    origins: dict[Fraction, list[tuple[int, SingularInstant]]] = {}
    plain: list[tuple[SingularInstant, object, tuple[tuple[int, SingularInstant], ...]]] = []
    kinematic: dict[tuple[float, int], tuple[KinematicSingularity, int]] = {}
    for j, p in enumerate(parts):
        a = p.analysis
        for local, h in zip(a.instants, a._hints, strict=True):
            s = P.absolute(p, local)
            e = s.t_exact
            if e is not None and e in (_fraction(p.start), _fraction(p.end)):
                sides.setdefault(e, {})["after" if e == _fraction(p.start) else "before"] = s
                hints.setdefault(e, h)
                origins.setdefault(e, []).append((j, local))
            else:
                plain.append((s, h, ((j, local),)))
        for k, g in zip(a.kinematic, a._kinematic_signs, strict=True):
            k = P.absolute_kinematic(p, k)
            kinematic.setdefault((k.t, k.leg), (k, g))
    for e, pair in sides.items():
        knot = P.at_knot(pair.get("before"), pair.get("after"))
        plain.append((knot, hints[e], tuple(origins[e])))
    plain.sort(key=lambda sh: sh[0].t)
    kin = sorted(kinematic.values(), key=lambda kg: kg[0].t)
    return SingularAnalysis(
        [s for s, _, _ in plain], [k for k, _ in kin],
        all(p.analysis.on_singular_line for p in parts),
        tuple(h for _, h, _ in plain),  # type: ignore[misc]
        tuple(g for _, g in kin),
        tuple(o for _, _, o in plain),
    )  # fmt: skip


def _fraction(q: fmpq) -> Fraction:
    return Fraction(int(q.p), int(q.q))


def _saturation(a: SingularAnalysis, checks: tuple[LimitCheck, LimitCheck]) -> list[Saturation]:
    """For each unbounded instant, the windows around it in which |T1|, |T2| exceed
    their limits (the limit checks' windows that hold it)."""
    return around_poles(a.instants, checks)


def _quiet(stage: str) -> None:
    """An ``OnStage`` that listens to nothing."""

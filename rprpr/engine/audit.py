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

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..model.defaults import DEFAULT_SAMPLES
from ..model.numbers import to_float
from ..model.rules import Finding, with_levels
from ..model.task import Task
from .certified import CertifiedMotion
from .envelope import Approach, Envelope, LimitCheck, Peak, Window
from .findings import findings
from .sampling import Samples, grid, sample
from .singular import (
    EXPANDING,
    FACTORING,
    ISOLATING,
    KinematicSingularity,
    OnStage,
    SingularAnalysis,
    SingularInstant,
    analyse,
)
from .trajectory import Trajectory, trajectory

ENVELOPE = "the torque envelope"
FINDINGS = "the findings"
STAGES = (FACTORING, ISOLATING, EXPANDING, ENVELOPE, FINDINGS)  # in the order they begin

Saturation = tuple[SingularInstant, Window | None, Window | None]


@dataclass(frozen=True)
class AuditResult:
    """Everything ``rprpr check`` reports for one task.

    ``torque_peak`` = (max |T1|, max |T2|) over [0, t_f], certified (``envelope.Peak``:
    the value, where it is reached, a proven upper bound); inf where a singular instant
    has unbounded torques; None when the path lies on y = 0. ``torque_limit``: the
    certified check of ``checks.torque_limit`` for every t (None without a limit);
    ``saturation``: for each unbounded instant, the windows around it in which |T1|, |T2|
    exceed their limits (empty without a limit); ``closest_approach``: for a motion that
    never meets the line AB, how close it comes (None otherwise). ``verdict`` is "pass"
    or "fail". ``samples`` are certified values on the grid of ``grid_size`` points, made
    when first read.
    """

    task: Task
    strict: bool
    singularities: list[SingularInstant]
    kinematic_singularities: list[KinematicSingularity]
    on_singular_line: bool
    torque_peak: tuple[Peak, Peak] | None
    torque_limit: tuple[LimitCheck, LimitCheck] | None
    saturation: list[Saturation]
    closest_approach: Approach | None
    findings: list[Finding]
    grid_size: int = field(repr=False)
    trajectory: Trajectory = field(repr=False)
    analysis: SingularAnalysis = field(repr=False, compare=False)
    motion: CertifiedMotion = field(repr=False, compare=False)  # what ``resample`` reads

    @cached_property
    def samples(self) -> Samples:
        """Certified samples at ``grid_size`` evenly spaced times, t = 0 .. t_f."""
        return self.resample(grid(self.task.duration, self.grid_size))

    def resample(self, t: np.ndarray) -> Samples:
        """The motion, joints, δ, λ and torques at the times ``t`` [s], certified, from
        the exact analysis already made (no new analysis)."""
        return sample(self.motion, np.asarray(t, dtype=float))

    def findings_at(self, s: SingularInstant) -> list[Finding]:
        """The findings the audit made at the singular instant ``s``."""
        return [f for f in self.findings if f.t is not None and f.t == s.t]

    def status_of(self, s: SingularInstant) -> str:
        """ "fail" when a finding at ``s`` fails the task, "warn" when one only warns,
        else "ok" (decided here once; renderers only read it)."""
        hits = self.findings_at(s)
        if any(f.fails(self.strict) for f in hits):
            return "fail"
        return "warn" if hits else "ok"

    @property
    def verdict(self) -> str:
        return "fail" if any(f.fails(self.strict) for f in self.findings) else "pass"

    @property
    def passed(self) -> bool:
        return self.verdict == "pass"

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
    *,
    samples: int = DEFAULT_SAMPLES,
    strict: bool | None = None,
    on_stage: OnStage | None = None,
) -> AuditResult:
    """Audit ``task``; ``samples`` is the size of the grid of ``AuditResult.samples``
    (nothing the audit decides depends on it); ``strict`` overrides
    ``task.checks.strict``. ``on_stage``, when given, is told the name of each stage
    (``STAGES``) as it begins (a caller that stops a long audit can say where it was)."""
    if samples < 2:
        raise ValueError("at least 2 samples are needed")
    strict = task.checks.strict if strict is None else strict
    tell = on_stage or _quiet
    traj = trajectory(task)
    analysis = analyse(traj, task.robot, task.checks, tell)
    tell(ENVELOPE)
    motion = CertifiedMotion(traj, task.robot, analysis)
    envelope = Envelope(motion)
    peak = envelope.torque_peak()
    limit = task.checks.torque_limit
    checked = saturation = None
    if limit is not None:
        pair = (to_float(limit[0]), to_float(limit[1]))
        checked = envelope.limit_violations(pair)
        saturation = envelope.saturation_windows(pair)
    approach = envelope.closest_approach()
    tell(FINDINGS)
    found = with_levels(findings(task, analysis, peak, checked), task.checks.rules)
    return AuditResult(
        task=task,
        strict=strict,
        singularities=analysis.instants,
        kinematic_singularities=analysis.kinematic,
        on_singular_line=analysis.on_singular_line,
        torque_peak=peak,
        torque_limit=checked,
        saturation=saturation or [],
        closest_approach=approach,
        findings=found,
        grid_size=samples,
        trajectory=traj,
        analysis=analysis,
        motion=motion,
    )


def _quiet(stage: str) -> None:
    """An ``OnStage`` that listens to nothing."""

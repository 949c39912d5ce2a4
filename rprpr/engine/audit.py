"""The audit of a task: singular instants, samples, findings and the verdict (pure).

    task -> trajectory (exact polynomials) -> singular analysis (exact) -> samples (float)
         -> findings -> AuditResult

``audit`` returns a plain result object; rendering it is the command line's business.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..model.defaults import DEFAULT_SAMPLES
from ..model.rules import Finding
from ..model.task import Task
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

SAMPLING = "the sampling of the motion"
FINDINGS = "the findings"
STAGES = (FACTORING, ISOLATING, EXPANDING, SAMPLING, FINDINGS)  # in the order they begin


@dataclass(frozen=True)
class AuditResult:
    """Everything ``rprpr check`` reports for one task.

    ``torque_peak`` = (max |T1|, max |T2|) [N m] over the samples at which the torques are
    finite and the limits at bounded singular instants (None when there is none);
    ``verdict`` is "pass" or "fail".
    """

    task: Task
    strict: bool
    singularities: list[SingularInstant]
    kinematic_singularities: list[KinematicSingularity]
    on_singular_line: bool
    torque_peak: tuple[float, float] | None
    findings: list[Finding]
    samples: Samples = field(repr=False)
    trajectory: Trajectory = field(repr=False)
    analysis: SingularAnalysis = field(repr=False, compare=False)  # what ``resample`` reads

    def resample(self, t: np.ndarray) -> Samples:
        """The motion, joints, δ, λ and torques at the times ``t`` [s], from the exact
        analysis already made (no new analysis)."""
        return sample(self.trajectory, self.task.robot, self.analysis, np.asarray(t, dtype=float))

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


def audit(
    task: Task,
    *,
    samples: int = DEFAULT_SAMPLES,
    strict: bool | None = None,
    on_stage: OnStage | None = None,
) -> AuditResult:
    """Audit ``task`` on ``samples`` grid points; ``strict`` overrides ``task.checks.strict``.
    ``on_stage``, when given, is told the name of each stage (``STAGES``) as it begins (a
    caller that stops a long audit can say where it was)."""
    strict = task.checks.strict if strict is None else strict
    tell = on_stage or _quiet
    traj = trajectory(task)
    analysis = analyse(traj, task.robot, task.checks, tell)
    tell(SAMPLING)
    s = sample(traj, task.robot, analysis, grid(task.duration, samples))
    peak = _torque_peak(s, analysis.instants)
    tell(FINDINGS)
    found = findings(task, analysis, peak)
    return AuditResult(
        task=task,
        strict=strict,
        singularities=analysis.instants,
        kinematic_singularities=analysis.kinematic,
        on_singular_line=analysis.on_singular_line,
        torque_peak=peak,
        findings=found,
        samples=s,
        trajectory=traj,
        analysis=analysis,
    )


def _quiet(stage: str) -> None:
    """An ``OnStage`` that listens to nothing."""


def _torque_peak(s: Samples, instants: list[SingularInstant]) -> tuple[float, float] | None:
    """max |T1|, max |T2| over the samples with finite torques and the finite limits at
    the bounded singular instants (which the grid may miss)."""
    ok = np.isfinite(s.T1) & np.isfinite(s.T2)
    t1 = [float(v) for v in np.abs(s.T1[ok])]
    t2 = [float(v) for v in np.abs(s.T2[ok])]
    for i in instants:
        if i.torque_at_singularity is not None:
            t1.append(abs(i.torque_at_singularity[0]))
            t2.append(abs(i.torque_at_singularity[1]))
    if not t1:
        return None
    return max(t1), max(t2)

"""The audit of a task: singular instants, samples, findings and the verdict (pure).

    task -> trajectory (exact polynomials) -> singular analysis (exact) -> samples (float)
         -> findings -> AuditResult

``audit`` returns a plain result object; rendering it is the command line's business.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..model.numbers import distinct as distinct_times
from ..model.rules import Finding
from ..model.task import Task
from .sampling import Samples, grid, sample
from .singular import KinematicSingularity, SingularAnalysis, SingularInstant, analyse
from .trajectory import Trajectory, trajectory

DEFAULT_SAMPLES = 1001


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
        analysis already made (no new analysis; the value at a time never depends on
        the other times asked for)."""
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


def audit(task: Task, *, samples: int = DEFAULT_SAMPLES, strict: bool | None = None) -> AuditResult:
    """Audit ``task`` on ``samples`` grid points; ``strict`` overrides ``task.checks.strict``."""
    strict = task.checks.strict if strict is None else strict
    traj = trajectory(task)
    analysis = analyse(traj, task.robot, task.checks)
    s = sample(traj, task.robot, analysis, grid(task.duration, samples))
    peak = _torque_peak(s, analysis.instants)
    findings = _findings(task, analysis, peak)
    return AuditResult(
        task=task,
        strict=strict,
        singularities=analysis.instants,
        kinematic_singularities=analysis.kinematic,
        on_singular_line=analysis.on_singular_line,
        torque_peak=peak,
        findings=findings,
        samples=s,
        trajectory=traj,
        analysis=analysis,
    )


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


def _findings(task: Task, a: SingularAnalysis, peak: tuple[float, float] | None) -> list[Finding]:
    out: list[Finding] = []
    times = [k.t for k in a.kinematic] + [s.t for s in a.instants]
    label = dict(zip(times, distinct_times(times), strict=True))

    def _at(t: float) -> str:
        return f"t = {label[t]} s"

    if a.on_singular_line:
        out.append(
            Finding(
                "RPR104",
                "the path lies on the singular line y = 0 (δ ≡ 0):"
                " every instant is a Type II singularity",
                None,
                "path.y",
            )
        )
    for k in a.kinematic:
        joint = "A" if k.leg == 1 else "B"
        out.append(
            Finding(
                "RPR103",
                f"{_at(k.t)}: the end point is at {joint} (s{k.leg} = 0):"
                " inverse-kinematic singularity",
                k.t,
                "path.y",
            )
        )
    for s in a.instants:
        where = f"{_at(s.t)}, (x, y) = ({s.x:.6g}, 0), case {s.case.number}, order {s.order}"
        if not s.slope_principle.passed:
            out.append(
                Finding(
                    "RPR101",
                    f"{where}: slope principle fails: {s.slope_principle.reason}",
                    s.t,
                    "path.y",
                )
            )
        if not s.velocity_principle.passed:
            out.append(
                Finding(
                    "RPR102",
                    f"{where}: velocity principle fails: {s.velocity_principle.reason}",
                    s.t,
                    "timing",
                )
            )
        if not s.torque_bounded:
            why = (
                f"inconsistent (eq. 34 residual {s.consistency_residual:.6g} N)"
                if not s.consistent
                else f"consistent, but only {s.conditions_met} of {s.conditions_required}"
                " boundedness conditions hold"
            )
            out.append(
                Finding(
                    "RPR201",
                    f"{where}: {why}: torques unbounded (pole of order {s.pole_order})",
                    s.t,
                    "robot.links",
                )
            )
    limit = task.checks.torque_limit
    unbounded = [s for s in a.instants if not s.torque_bounded]
    if limit is not None and unbounded:
        # near a pole the sampled peak only says where the grid fell: report the pole
        for s in unbounded:
            out.append(
                Finding(
                    "RPR202",
                    f"{_at(s.t)}: the torques are unbounded (pole of order {s.pole_order}):"
                    " beyond any limit",
                    s.t,
                    "checks.torque_limit",
                )
            )
    elif limit is not None and peak is not None:
        for j in (0, 1):
            lim = float(limit[j])
            if peak[j] > lim:
                out.append(
                    Finding(
                        "RPR202",
                        f"|T{j + 1}| reaches {peak[j]:.6g} N m, beyond the limit {lim:g} N m",
                        None,
                        "checks.torque_limit",
                    )
                )
    return out

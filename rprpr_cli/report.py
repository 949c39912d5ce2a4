"""An audit as plain data: the JSON-ready report every renderer (text, JSON, JUnit,
GitHub) works from, so that a worker process can hand it back and all formats agree.

Floats that are not finite become None (JSON null).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from . import __version__
from .audit import AuditResult
from .errors import ExitCode, TaskFileError
from .rules import RULES


def _f(v: float | None) -> float | None:
    return None if v is None or not math.isfinite(v) else float(v)


def task_report(result: AuditResult, task_path: str) -> dict[str, Any]:
    """The report of one audited task (the ``reports[]`` entries of ``--format json``)."""
    task = result.task
    sings = []
    for s in result.singularities:
        sings.append(
            {
                "t": s.t,
                "x": s.x,
                "y": s.y,
                "case": s.case.number,
                "sigma": s.case.sigma,
                "psi": s.case.psi,
                "order": s.order,
                "kind": s.kind,
                "high_order": s.order >= 2,
                "delta_derivatives": [_f(v) for v in s.delta_derivatives],
                "slope": _f(s.slope),
                "speed": _f(s.speed),
                "slope_principle": "pass" if s.slope_principle.passed else "fail",
                "slope_reason": s.slope_principle.reason,
                "velocity_principle": "pass" if s.velocity_principle.passed else "fail",
                "velocity_reason": s.velocity_principle.reason,
                "consistency_residual": _f(s.consistency_residual),
                "consistent": s.consistent,
                "conditions_required": s.conditions_required,
                "conditions_met": s.conditions_met,
                "torque_bounded": s.torque_bounded,
                "pole_order": s.pole_order,
                "torque_at_singularity": (
                    [_f(s.torque_at_singularity[0]), _f(s.torque_at_singularity[1])]
                    if s.torque_at_singularity
                    else None
                ),
            }
        )
    findings = []
    for f in result.findings:
        rule = RULES[f.rule]
        findings.append(
            {
                "rule": f.rule,
                "name": rule.name,
                "severity": "error" if f.fails(result.strict) else "warning",
                "message": f.message,
                "t": _f(f.t),
                "key": f.key,
                "line": task.lines.get(f.key, task.lines.get(f.key.split(".")[0], 1)),
            }
        )
    return {
        "task": task_path,
        "name": task.name,
        "verdict": result.verdict,
        "strict": result.strict,
        "singularities": sings,
        "kinematic_singularities": [
            {"t": k.t, "x": k.x, "y": k.y, "leg": k.leg} for k in result.kinematic_singularities
        ],
        "on_singular_line": result.on_singular_line,
        "torque_peak": [_f(v) for v in result.torque_peak] if result.torque_peak else None,
        "findings": findings,
    }


def input_error(e: TaskFileError, task_path: str) -> dict[str, Any]:
    """An input error as data (``input_errors[]`` of ``--format json``)."""
    return {
        "task": task_path,
        "line": e.line,
        "column": e.column,
        "key": e.key,
        "message": e.message,
        "rule": "RPR001",
        "text": str(e.with_file(task_path)),
    }


@dataclass
class Run:
    """The outcome of one ``rprpr check`` run: reports, input errors, internal errors."""

    reports: list[dict[str, Any]] = field(default_factory=list)
    input_errors: list[dict[str, Any]] = field(default_factory=list)
    internal_errors: list[dict[str, Any]] = field(default_factory=list)
    order: list[tuple[str, int]] = field(default_factory=list)  # (kind, index) in task order

    def summary(self) -> dict[str, int]:
        passed = sum(r["verdict"] == "pass" for r in self.reports)
        return {
            "tasks": len(self.reports) + len(self.input_errors) + len(self.internal_errors),
            "passed": passed,
            "failed": len(self.reports) - passed,
            "errors": len(self.input_errors) + len(self.internal_errors),
        }

    def exit_code(self, exit_zero: bool = False) -> ExitCode:
        """The highest status that applies: 3 internal > 2 input > 1 failed > 0 passed.
        ``exit_zero`` turns a failed audit into 0 but never hides an error."""
        if self.internal_errors:
            return ExitCode.INTERNAL
        if self.input_errors:
            return ExitCode.INPUT
        if not exit_zero and any(r["verdict"] == "fail" for r in self.reports):
            return ExitCode.FAILED
        return ExitCode.PASSED

    def document(self) -> dict[str, Any]:
        """The ``--format json`` document."""
        return {
            "rprpr": __version__,
            "reports": self.reports,
            "summary": self.summary(),
            "input_errors": self.input_errors,
            "internal_errors": self.internal_errors,
        }

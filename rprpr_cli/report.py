"""An audit as plain data: the JSON-ready report every renderer (text, JSON, JUnit,
GitHub) works from, so that a worker process can hand it back and all formats agree.

Floats that are not finite become None (JSON null).
"""

from __future__ import annotations

import math
import traceback
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from . import __version__
from .auditing import AuditResult
from .errors import ExitCode, TaskFileError
from .rules import RULES
from .singular import SingularInstant

INVALID_TASK = "RPR001"  # the rule of every input error


def _f(v: float | None) -> float | None:
    return None if v is None or not math.isfinite(v) else float(v)


def singularity_record(s: SingularInstant) -> dict[str, Any]:
    """One singular instant as JSON-ready data (``singularities[]`` of a report)."""
    return {
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


def task_report(result: AuditResult, task_path: str) -> dict[str, Any]:
    """The report of one audited task (the ``reports[]`` entries of ``--format json``)."""
    task = result.task
    sings = [singularity_record(s) for s in result.singularities]
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
    """An input error as data (``input_errors[]`` of ``--format json``).

    ``line``/``column`` are 1-based, None when unknown; ``key`` is the dotted key path,
    None for the whole file. ``text`` is the one-line message of the command line.
    """
    return {
        "task": task_path,
        "line": e.line or None,
        "column": e.column or None,
        "key": e.key or None,
        "message": e.message,
        "rule": INVALID_TASK,
        "text": f"{e.with_file(task_path)} [{INVALID_TASK}]",
    }


def internal_error(e: BaseException, task_path: str) -> dict[str, Any]:
    """A bug met while auditing one task, as data (``internal_errors[]``)."""
    return {
        "task": task_path,
        "message": f"{type(e).__name__}: {e}",
        "text": f"{task_path}: internal error ({type(e).__name__}: {e}); please report it to"
        " the rprpr maintainers with this task file",
        "traceback": "".join(traceback.format_exception(e)),
    }


REPORT, INPUT, INTERNAL = "report", "input", "internal"  # the kinds of a task's outcome


@dataclass
class Run:
    """The outcome of one ``rprpr check`` run, in task order: a report per audited task,
    an input error per task file that could not be read, an internal error per bug met.

    ``order[i]`` = (kind, index into that kind's list) of the i-th task; ``times[i]`` its
    load-and-audit time in seconds (JUnit reports it; the JSON document leaves it out so
    that the same tasks always give the same bytes).
    """

    reports: list[dict[str, Any]] = field(default_factory=list)
    input_errors: list[dict[str, Any]] = field(default_factory=list)
    internal_errors: list[dict[str, Any]] = field(default_factory=list)
    order: list[tuple[str, int]] = field(default_factory=list)
    times: list[float] = field(default_factory=list)

    def add(self, kind: str, item: dict[str, Any], seconds: float = 0.0) -> None:
        """Append the next task's outcome; ``kind`` is REPORT, INPUT or INTERNAL."""
        target = {REPORT: self.reports, INPUT: self.input_errors, INTERNAL: self.internal_errors}[
            kind
        ]
        self.order.append((kind, len(target)))
        target.append(item)
        self.times.append(seconds)

    def entries(self) -> Iterator[tuple[str, dict[str, Any], float]]:
        """(kind, item, seconds) for every task, in task order."""
        lists = {REPORT: self.reports, INPUT: self.input_errors, INTERNAL: self.internal_errors}
        for (kind, i), seconds in zip(self.order, self.times, strict=True):
            yield kind, lists[kind][i], seconds

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

    def document(self, quiet: bool = False) -> dict[str, Any]:
        """The ``--format json`` document; ``quiet`` leaves passing reports out (the
        summary still counts every task)."""
        reports = [r for r in self.reports if r["verdict"] != "pass"] if quiet else self.reports
        return {
            "rprpr": __version__,
            "reports": reports,
            "summary": self.summary(),
            "input_errors": self.input_errors,
            "internal_errors": self.internal_errors,
        }

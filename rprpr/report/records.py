"""An audit as plain data: the JSON-ready records every renderer (text, JSON, JUnit,
GitHub) works from, so that a worker process can hand them back and all formats agree.

Floats that are not finite become None (JSON null).
"""

from __future__ import annotations

import math
import traceback
from typing import Any

from ..engine.audit import AuditResult
from ..engine.singular import SingularInstant
from ..model.errors import TaskFileError
from ..model.numbers import labels, number
from ..model.rules import RULES

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
        "high_order": s.high_order,
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
        "torque_peak": [_f(p.value) for p in result.torque_peak] if result.torque_peak else None,
        "torque_peak_t": [_f(p.t) for p in result.torque_peak] if result.torque_peak else None,
        "findings": findings,
        "beyond_double_range": beyond_double_range(result),
    }


def beyond_double_range(result: AuditResult) -> list[dict[str, str]]:
    """Each reported quantity whose double is not faithful to its exact value (beyond the
    double range: JSON null where the double is infinite, else the nearest double, 0 or a
    subnormal), with that exact value as text: ``{"quantity": "singularities[0].speed",
    "value": "1.41421e+400"}``."""
    out = []
    for i, k in enumerate(result.kinematic_singularities):
        for name, value in k.beyond_double_range:
            out.append({"quantity": f"kinematic_singularities[{i}].{name}", "value": value})
    for i, s in enumerate(result.singularities):
        for name, value in s.beyond_double_range:
            out.append({"quantity": f"singularities[{i}].{name}", "value": value})
    return out


def instant_times(rep: dict[str, Any]) -> dict[float, str]:
    """The time of each instant of a task report (inverse-kinematic and singular) as text,
    all told apart together as in the findings' messages, so that every renderer names an
    instant the same way and two close instants never alike."""
    kinematic = [k["t"] for k in rep["kinematic_singularities"]]
    return labels(kinematic + [s["t"] for s in rep["singularities"]])


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


def budget_error(task_path: str, budget: float, stage: str) -> dict[str, Any]:
    """A task whose audit exceeded its work budget of ``budget`` seconds during ``stage``
    (``budget_errors[]``): it was stopped there, and the run went on."""
    message = f"the exact analysis exceeded its budget of {number(budget)} s at {stage}"
    return {
        "task": task_path,
        "budget": budget,
        "stage": stage,
        "message": message,
        "text": f"{task_path}: {message} (check --budget SECONDS allows more)",
    }

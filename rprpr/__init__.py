"""rprpr: an exact trajectory auditor for the RPRPR planar parallel robot.

Python API::

    from rprpr import AuditOptions, audit, load_task
    result = audit(load_task("configs/paper_path2.rprpr.yaml"))
    result.verdict, result.singularities[0].order
    result.singularities[0].t_exact  # Fraction(5, 2), or None where irrational
    result.to_dict()  # the entry of ``rprpr check --format json``'s reports[]
    audit(result.task, AuditOptions(peak=True)).torque_peak  # the certified max |T1|, |T2|
    audit(result.task, strict=True)  # AuditOptions' fields also as keywords

    # a planner's spline (scipy's PPoly layout), on the robot and checks of a task file
    from rprpr import Motion, with_motion
    motion = Motion.from_ppoly(CubicSpline(t, xy))  # or from_pieces(breaks, cx, cy)
    result = audit(with_motion(load_task("configs/paper_path2.rprpr.yaml"), motion))

    # a failing motion made executable (raises NoRepair, saying why, where none exists)
    from rprpr import repair
    fixed = repair(load_task("configs/paper_path1.rprpr.yaml"))  # fixed.task, .changes

Importing the package costs nothing: ``audit`` and the engine (numpy, python-flint) load
when first used, the YAML loader when ``load_task`` or ``parse_task`` is, so that
``rprpr --version`` stays light and the core stays free of YAML, click and rich.

The stages, in the order the data flows (see CONTRIBUTING.md)::

    io (task file -> Task) -> model (Task, the paper's tables, rules, AuditOptions)
       -> engine (exact trajectory, singular instants, samples, findings, audit)
       -> report (records, the run, the exit policy) -> render (text, JSON, JUnit, GitHub,
          export, sheet, animation) -> cli (one module per command)

    repair (the second use case: task -> audit -> exact changes -> task), beside the
    report: it uses the engine, and ``rprpr repair`` uses it
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from ._version import __version__

if TYPE_CHECKING:
    from .api import AuditResult, audit
    from .io.loader import load_task, parse_task
    from .model.errors import RprprError, TaskFileError
    from .model.motion import Motion, with_motion
    from .model.options import AuditOptions
    from .model.task import Uncertainty
    from .repair import NoRepair, Repair, repair

_LAZY = {
    "AuditOptions": ".model.options",
    "AuditResult": ".api",
    "audit": ".api",
    "load_task": ".io.loader",
    "Motion": ".model.motion",
    "with_motion": ".model.motion",
    "repair": ".repair",
    "Repair": ".repair",
    "NoRepair": ".repair",
    "parse_task": ".io.loader",
    "RprprError": ".model.errors",
    "TaskFileError": ".model.errors",
    "Uncertainty": ".model.task",
}

__all__ = [
    "AuditOptions",
    "AuditResult",
    "Motion",
    "NoRepair",
    "Repair",
    "RprprError",
    "TaskFileError",
    "Uncertainty",
    "__version__",
    "audit",
    "load_task",
    "parse_task",
    "repair",
    "with_motion",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'rprpr' has no attribute {name!r}")

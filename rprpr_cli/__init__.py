"""rprpr: an exact trajectory auditor for the RPRPR planar parallel robot.

Python API::

    from rprpr_cli import load_task, audit
    result = audit(load_task("configs/paper_path2.yaml"))
    result.verdict, result.singularities[0].order

The numerical core (``auditing`` and what it uses) is imported with the package; the YAML
loader only when ``load_task`` or ``parse_task`` is first used, so that the core stays
free of YAML, click and rich.
"""

from __future__ import annotations

from typing import Any

__version__ = "0.1.0"

from .auditing import AuditResult, audit
from .errors import RprprError, TaskFileError

_LAZY = {"load_task": "loader", "parse_task": "loader"}

__all__ = [
    "AuditResult",
    "RprprError",
    "TaskFileError",
    "__version__",
    "audit",
    "load_task",
    "parse_task",
]


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'rprpr_cli' has no attribute {name!r}")

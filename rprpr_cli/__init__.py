"""rprpr: an exact trajectory auditor for the RPRPR planar parallel robot.

Python API::

    from rprpr_cli import load_task, audit
    result = audit(load_task("configs/paper_path2.yaml"))
    result.verdict, result.singularities[0].order

The names are imported lazily, so that importing the numerical core (``rprpr_cli.audit``
and below) never pulls in the YAML loader or the command line.
"""

from __future__ import annotations

from typing import Any

__version__ = "0.1.0"

_API = {
    "audit": "audit",
    "AuditResult": "audit",
    "load_task": "loader",
    "parse_task": "loader",
    "RprprError": "errors",
    "TaskFileError": "errors",
}

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
    if name in _API:
        import importlib

        return getattr(importlib.import_module(f".{_API[name]}", __name__), name)
    raise AttributeError(f"module 'rprpr_cli' has no attribute {name!r}")

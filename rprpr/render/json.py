"""The ``--format json`` report of ``rprpr check``: one document for the whole run.

The document holds no measured time, so that the same tasks always give the same bytes.
It is strict JSON: a value that is not finite is ``null`` (never ``NaN`` or ``Infinity``).
"""

from __future__ import annotations

import json
import math
from typing import Any

from .._version import __version__
from ..report.run import Run
from .escape import inert_json


def document(run: Run, quiet: bool = False) -> dict[str, Any]:
    """The JSON document of ``run``: the version, the reports, the summary, the input,
    internal and budget errors; ``quiet`` leaves passing reports out (the summary still
    counts every task)."""
    reports = [r for r in run.reports if r["verdict"] != "pass"] if quiet else run.reports
    return {
        "rprpr": __version__,
        "reports": reports,
        "summary": run.summary(),
        "input_errors": run.input_errors,
        "internal_errors": run.internal_errors,
        "budget_errors": run.budget_errors,
    }


def finite(value: Any) -> Any:
    """``value`` with every float that is not finite, at any depth, replaced by None."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [finite(v) for v in value]
    return value


def render(run: Run, quiet: bool = False) -> str:
    """The document of ``run`` as text: indented by 2, ending with a newline."""
    text = json.dumps(finite(document(run, quiet=quiet)), indent=2, allow_nan=False)
    return inert_json(text) + "\n"

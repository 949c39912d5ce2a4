"""The Python API's audit result: ``engine.audit.AuditResult`` with what a notebook or a
script wants from it as data (``to_dict``, the JSON report's entry) and as a table
(``_repr_html_``).

This module stands outside the stages (as the package root does): the engine's result
cannot import the report or the renderers (dependencies point one way, cli -> render ->
report -> engine -> model), so ``rprpr.audit`` hands back this thin subclass, which can.
A 5R task's result is ``FiveBarAuditResult``, the 5R's engine result with the same two.
"""

from __future__ import annotations

from dataclasses import fields
from typing import Any, Unpack

from .engine import audit as _engine
from .engine import five_bar_audit as _five_bar
from .engine.exact.singular import OnStage
from .model.options import AuditKeywords, AuditOptions
from .model.task import Task
from .render.html import report_html
from .render.json import finite
from .report.records import task_report


class _Report:
    """``to_dict`` and ``_repr_html_`` of an audit result (the RPRPR's or a 5R's)."""

    task: Task

    def to_dict(self, task_path: str | None = None) -> dict[str, Any]:
        """The report of this task exactly as ``rprpr check --format json`` writes it
        (an entry of ``reports[]``): ``task`` is ``task_path``, by default the file the
        task was loaded from (``Task.source``)."""
        report = task_report(self, task_path or self.task.source or self.task.name)  # type: ignore[arg-type]
        return finite(report)

    def _repr_html_(self) -> str:
        return report_html(self.to_dict())


class AuditResult(_Report, _engine.AuditResult):
    """An ``engine.audit.AuditResult`` that also gives its report (``to_dict``) and an
    HTML table for notebooks (``_repr_html_``)."""


class FiveBarAuditResult(_Report, _five_bar.FiveBarAuditResult):
    """A 5R task's ``engine.five_bar_audit.FiveBarAuditResult`` with ``to_dict`` and
    ``_repr_html_`` (its samples: ``samples``, ``resample``)."""


def audit(
    task: Task,
    options: AuditOptions | None = None,
    *,
    on_stage: OnStage | None = None,
    **keywords: Unpack[AuditKeywords],
) -> AuditResult:
    """``engine.audit.audit(task, options, on_stage=..., **keywords)`` as an
    ``AuditResult`` of this module: ``options`` an ``AuditOptions`` (``samples``,
    ``strict``, ``peak``, ``warn_unbounded``), its fields also taken as keywords
    (``audit(task, peak=True)``)."""
    result = _engine.audit(task, options, on_stage=on_stage, **keywords)
    if isinstance(result, _five_bar.FiveBarAuditResult):  # a 5R task: its own result
        return FiveBarAuditResult(**{f.name: getattr(result, f.name) for f in fields(result)})
    return AuditResult(**{f.name: getattr(result, f.name) for f in fields(result)})

"""One audited task ready to draw: the audit and its dense samples (no new analysis)."""

from __future__ import annotations

from typing import cast

import numpy as np

from ...engine.audit import AuditResult, audit
from ...engine.certified.sampling import Samples, grid
from ...engine.five_bar_audit import FiveBarAuditResult
from ...model.dataclass import dataclass
from ...model.names import file_name
from ...model.task import Task
from .five_bar import motion as five_bar_motion


@dataclass(frozen=True)
class Motion:
    """One audited task, ready to draw: the audit and dense samples that include every
    singular instant exactly; ``label``, when given, names it in the legends instead of
    its name (e.g. "before" and "after" on a repair's sheet)."""

    source: str
    result: AuditResult
    s: Samples
    label: str = ""

    @property
    def task(self) -> Task:
        return self.result.task

    @property
    def name(self) -> str:
        return self.result.task.name

    @property
    def duration(self) -> float:
        return float(self.s.t[-1])


def motion(result: AuditResult | FiveBarAuditResult | Task, source: str = "") -> Motion:
    """The audited task ``result`` (``audit(task)``; a ``Task`` is audited here first),
    ready to draw: its samples with its singular instants added to the grid and, about an
    unbounded one, the times t_s ± 10^-k t_f (k = 3..8), so that the curves visibly
    diverge however fine or coarse the grid. ``source`` (the task file) is held as
    ``model.names.file_name`` writes it: any name can be drawn. A 5R's audit is read for
    drawing by ``five_bar`` (its ``Drawn`` answers what the sheet reads of an
    ``AuditResult``)."""
    if isinstance(result, Task):
        result = audit(result)
    source = file_name(source)
    if isinstance(result, FiveBarAuditResult):
        drawn, s = five_bar_motion(result, source, result.grid_size)
        return Motion(source, cast(AuditResult, drawn), s)
    t = grid(result.task.duration, result.grid_size)
    tf = float(t[-1])
    tol = 1e-12 * max(1.0, tf)
    missing = [i.t for i in result.singularities if not np.any(np.abs(t - i.t) <= tol)]
    for i in result.singularities:
        if not i.torque_bounded:
            near = i.t + tf * np.outer([-1, 1], 10.0 ** -np.arange(3, 9)).ravel()
            missing += [float(v) for v in near if 0 < v < tf]
    if not missing:
        return Motion(source, result, result.samples)
    return Motion(source, result, result.resample(np.union1d(t, missing)))


def at(m: Motion, t: float) -> int:
    """The index of the sample of ``m`` nearest the time ``t``."""
    return int(np.argmin(np.abs(m.s.t - t)))


def finite(v: np.ndarray) -> np.ndarray:
    """``v`` with ±inf as NaN (a gap in a drawn curve, not a line to the edge)."""
    return np.where(np.isfinite(v), v, np.nan)

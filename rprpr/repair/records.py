"""What a repair returns: the repaired task and its account (``Repair``), one ``Change``
per repaired instant; ``NoRepair`` when none exists within the constraints."""

from __future__ import annotations

from dataclasses import field

from flint import fmpq

from ..engine.audit import AuditResult
from ..model.dataclass import dataclass
from ..model.task import Task


class NoRepair(Exception):
    """No repair exists within the constraints; the message says exactly why."""


@dataclass(frozen=True)
class Change:
    """What was done at one singular instant: ``kind`` ("consistency", "speed", "slope",
    "lift"), the window [t_s - w, t_s + w] and the values before and after."""

    t: fmpq
    x: fmpq
    window: fmpq
    actions: tuple[str, ...]
    speed: tuple[fmpq, fmpq]  # ẋ(t_s) before, after
    acceleration: tuple[fmpq, fmpq]  # ẍ(t_s) before, after
    ydot: tuple[fmpq, fmpq]  # ẏ(t_s) before, after
    yddot: tuple[fmpq, fmpq] | None = None  # ÿ(t_s) before, after (the prismatic scheme)


@dataclass(frozen=True)
class Repair:
    """The repaired task and an honest account of the change.

    ``task`` is the new task (``before.task`` the old one); ``changes`` one per repaired
    instant; ``path_deviation`` = (max |Δy| at equal x [m], the x where) or None when the
    path is kept; ``timing_change`` = (max |Δx(t)| [m], the t where) or None; both are
    exact maxima of the polynomial differences (upper bounds within about 1e-15).
    ``before``/``after``: the strict audits (with uncertainty, ``after.robust`` is the
    repaired motion's residual over the box and proven window at each instant).
    ``changed`` is False for a task that already passes (then ``task is before.task``).
    """

    task: Task
    before: AuditResult
    after: AuditResult
    changes: tuple[Change, ...] = ()
    path_deviation: tuple[float, float] | None = None
    timing_change: tuple[float, float] | None = None
    path_kept: bool = True
    notes: tuple[str, ...] = field(default=())
    # what the user must weigh before running it (``effort.effort_warning``)
    warnings: tuple[str, ...] = field(default=())

    @property
    def changed(self) -> bool:
        return self.task is not self.before.task

"""What changes an audit's verdict or report, in one value (black's ``Mode``).

``AuditOptions`` is what ``audit(task, options)`` takes; the command line builds one from
its flags (``cli.options.CheckOptions.audit``), beside its own plumbing (formats, jobs,
colours, budgets), which never changes a verdict. Plain Python: the command line reads
it without numpy or flint.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, TypedDict

from .dataclass import dataclass
from .defaults import DEFAULT_SAMPLES

if TYPE_CHECKING:
    from .task import Uncertainty


@dataclass(frozen=True)
class AuditOptions:
    """How a task is audited (the defaults are the task's own choices).

    ``samples``: the size of the grid of ``AuditResult.samples`` (what ``export`` writes
    and ``plot`` draws; nothing the audit decides depends on it), at least 2.
    ``strict``: the strict mode over the task's ``checks.strict`` (None: the task's).
    ``peak``: the certified torque peak asked for (None: the task's ``checks.peak``); no
    verdict needs it, but the reports show it. ``warn_unbounded``: unbounded torques
    (RPR201) a warning, over the task's own level of the rule. ``uncertainty``: what the
    real robot may differ by from the model (``docs/robust.md``), over the task's own
    (None: the task's); each singular instant then has its robust analysis.
    """

    samples: int = DEFAULT_SAMPLES
    strict: bool | None = None
    peak: bool | None = None
    warn_unbounded: bool = False
    uncertainty: Uncertainty | None = None

    def __post_init__(self) -> None:
        if self.samples < 2:
            raise ValueError("at least 2 samples are needed")

    def levels(self, task_levels: dict[str, str]) -> dict[str, str]:
        """The rule levels an audit applies: the task's (``checks.rules``), with RPR201
        a warning under ``warn_unbounded``."""
        return {**task_levels, "RPR201": "warn"} if self.warn_unbounded else task_levels


class AuditKeywords(TypedDict, total=False):
    """``AuditOptions``' fields as keywords: ``audit(task, strict=True)`` is
    ``audit(task, AuditOptions(strict=True))``."""

    samples: int
    strict: bool | None
    peak: bool | None
    warn_unbounded: bool
    uncertainty: Uncertainty | None

"""The outcome of one ``rprpr check`` run: the records of every task, in task order, and
the summary (its exit status is decided by ``report.exit.run_status``; its JSON document
is ``render.json``)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import field
from typing import Any

from ..model.dataclass import dataclass

# the kinds of a task's outcome: audited, a bad task file, a bug, over its work budget
REPORT, INPUT, INTERNAL, BUDGET = "report", "input", "internal", "budget"


@dataclass(frozen=True)
class Attachment:
    """What the HTML report shows of a task beyond its records, asked for by that format
    alone (the others never pay for it): ``source`` the task file's own lines (None when
    it could not be read again, or is larger than a task file may be), split where YAML
    splits lines so that a finding's line number is its index + 1; ``sheet`` the task's
    audit sheet as SVG text (drawn in the worker from the audit it just made: records
    carry no figures); ``note`` why there is no sheet, in one line (None when there is
    one, or none was asked for)."""

    source: tuple[str, ...] | None = None
    sheet: str | None = None
    note: str | None = None


@dataclass
class Run:
    """The outcome of one ``rprpr check`` run, in task order: a report per audited task,
    an input error per task file that could not be read, an internal error per bug met,
    a budget error per task whose audit exceeded its work budget.

    ``order[i]`` = (kind, index into that kind's list) of the i-th task; ``times[i]`` its
    load-and-audit time in seconds (JUnit reports it; the JSON document leaves it out so
    that the same tasks always give the same bytes); ``attachments[i]`` its
    ``Attachment`` (``--format html`` only); ``notes``: what a report says of itself in
    one line each (the HTML report without sheets on the light install).
    """

    reports: list[dict[str, Any]] = field(default_factory=list)
    input_errors: list[dict[str, Any]] = field(default_factory=list)
    internal_errors: list[dict[str, Any]] = field(default_factory=list)
    budget_errors: list[dict[str, Any]] = field(default_factory=list)
    order: list[tuple[str, int]] = field(default_factory=list)
    times: list[float] = field(default_factory=list)
    attachments: dict[int, Attachment] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)

    def add(
        self,
        kind: str,
        item: dict[str, Any],
        seconds: float = 0.0,
        attachment: Attachment | None = None,
    ) -> None:
        """Append the next task's outcome; ``kind`` is REPORT, INPUT, INTERNAL or BUDGET;
        ``attachment``: what the HTML report shows of it beyond its records."""
        target = self._lists()[kind]
        if attachment is not None:
            self.attachments[len(self.order)] = attachment
        self.order.append((kind, len(target)))
        target.append(item)
        self.times.append(seconds)

    def entries(self) -> Iterator[tuple[str, dict[str, Any], float]]:
        """(kind, item, seconds) for every task, in task order."""
        lists = self._lists()
        for (kind, i), seconds in zip(self.order, self.times, strict=True):
            yield kind, lists[kind][i], seconds

    def _lists(self) -> dict[str, list[dict[str, Any]]]:
        return {
            REPORT: self.reports,
            INPUT: self.input_errors,
            INTERNAL: self.internal_errors,
            BUDGET: self.budget_errors,
        }

    def summary(self) -> dict[str, int]:
        """The counts of the run: tasks, passed, failed and errors (input, internal and
        budget)."""
        passed = sum(r["verdict"] == "pass" for r in self.reports)
        errors = len(self.input_errors) + len(self.internal_errors) + len(self.budget_errors)
        return {
            "tasks": len(self.reports) + errors,
            "passed": passed,
            "failed": len(self.reports) - passed,
            "errors": errors,
        }

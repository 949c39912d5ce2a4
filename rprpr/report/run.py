"""The outcome of one ``rprpr check`` run: the records of every task, in task order, and
the summary (its exit status is decided by ``report.exit.run_status``; its JSON document
is ``render.json``)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

REPORT, INPUT, INTERNAL = "report", "input", "internal"  # the kinds of a task's outcome


@dataclass
class Run:
    """The outcome of one ``rprpr check`` run, in task order: a report per audited task,
    an input error per task file that could not be read, an internal error per bug met.

    ``order[i]`` = (kind, index into that kind's list) of the i-th task; ``times[i]`` its
    load-and-audit time in seconds (JUnit reports it; the JSON document leaves it out so
    that the same tasks always give the same bytes).
    """

    reports: list[dict[str, Any]] = field(default_factory=list)
    input_errors: list[dict[str, Any]] = field(default_factory=list)
    internal_errors: list[dict[str, Any]] = field(default_factory=list)
    order: list[tuple[str, int]] = field(default_factory=list)
    times: list[float] = field(default_factory=list)

    def add(self, kind: str, item: dict[str, Any], seconds: float = 0.0) -> None:
        """Append the next task's outcome; ``kind`` is REPORT, INPUT or INTERNAL."""
        target = {REPORT: self.reports, INPUT: self.input_errors, INTERNAL: self.internal_errors}[
            kind
        ]
        self.order.append((kind, len(target)))
        target.append(item)
        self.times.append(seconds)

    def entries(self) -> Iterator[tuple[str, dict[str, Any], float]]:
        """(kind, item, seconds) for every task, in task order."""
        lists = {REPORT: self.reports, INPUT: self.input_errors, INTERNAL: self.internal_errors}
        for (kind, i), seconds in zip(self.order, self.times, strict=True):
            yield kind, lists[kind][i], seconds

    def summary(self) -> dict[str, int]:
        """The counts of the run: tasks, passed, failed and errors (input and internal)."""
        passed = sum(r["verdict"] == "pass" for r in self.reports)
        return {
            "tasks": len(self.reports) + len(self.input_errors) + len(self.internal_errors),
            "passed": passed,
            "failed": len(self.reports) - passed,
            "errors": len(self.input_errors) + len(self.internal_errors),
        }

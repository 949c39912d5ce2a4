"""The outcome of one ``rprpr check`` run: the records of every task, in task order, the
summary, the exit status (by the policy of ``report.exit``) and the JSON document."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any

from .._version import __version__
from .exit import ExitCode

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
        passed = sum(r["verdict"] == "pass" for r in self.reports)
        return {
            "tasks": len(self.reports) + len(self.input_errors) + len(self.internal_errors),
            "passed": passed,
            "failed": len(self.reports) - passed,
            "errors": len(self.input_errors) + len(self.internal_errors),
        }

    def exit_code(self, exit_zero: bool = False) -> ExitCode:
        """The highest status that applies: 3 internal > 2 input > 1 failed > 0 passed.
        ``exit_zero`` turns a failed audit into 0 but never hides an error."""
        if self.internal_errors:
            return ExitCode.INTERNAL
        if self.input_errors:
            return ExitCode.INPUT
        if not exit_zero and any(r["verdict"] == "fail" for r in self.reports):
            return ExitCode.FAILED
        return ExitCode.PASSED

    def document(self, quiet: bool = False) -> dict[str, Any]:
        """The ``--format json`` document; ``quiet`` leaves passing reports out (the
        summary still counts every task)."""
        reports = [r for r in self.reports if r["verdict"] != "pass"] if quiet else self.reports
        return {
            "rprpr": __version__,
            "reports": reports,
            "summary": self.summary(),
            "input_errors": self.input_errors,
            "internal_errors": self.internal_errors,
        }

"""The exit-code policy of ``rprpr``: the one place that says which status a run ends with."""

from __future__ import annotations

from enum import IntEnum


class ExitCode(IntEnum):
    """Process exit status of ``rprpr``; when several apply, the highest wins."""

    PASSED = 0  # every task passed
    FAILED = 1  # at least one task failed its audit
    INPUT = 2  # bad invocation or a bad task file
    INTERNAL = 3  # a bug in rprpr: please report

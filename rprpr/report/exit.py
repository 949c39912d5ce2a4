"""The exit-code policy of ``rprpr``: the one place that says which status a command ends
with. The command line only prints one line about what stopped it and exits with the
status decided here.

======  ============  =====================================================================
status  ``ExitCode``  when
======  ============  =====================================================================
0       PASSED        ``check``: every task passed (or a task failed under ``--exit-zero``);
                      ``plot``, ``export``, ``schema``: the output is written, whatever
                      the verdict (``check`` is the gate); ``--help``, ``--version``
1       FAILED        ``check``: a task failed its audit
2       INPUT         a bad invocation (usage error), a bad task file, an output that
                      cannot be written (no permission, a full disk: the environment)
3       INTERNAL      a bug in rprpr, met while auditing a task or anywhere else
4       BUDGET        ``check``: the audit of a task exceeded its work budget
                      (``--budget``, 10 s by default); it was stopped, the other tasks
                      were audited (a valid task that is too hard to decide in time)
130     INTERRUPTED   interrupted before the command could handle it (128 + SIGINT)
======  ============  =====================================================================

When several apply, the highest wins (a bad task file among failing tasks exits 2; a task
over its budget exits 4 whatever else happened).
A reader that closes the pipe early (``rprpr check ... | head``) fails nothing: the
status the command had reached stands.
"""

from __future__ import annotations

from enum import IntEnum
from typing import TYPE_CHECKING

import click

if TYPE_CHECKING:  # annotations only: run.py never imports this module (no circle)
    from .run import Run


class ExitCode(IntEnum):
    """Process exit status of ``rprpr``; when several apply, the highest wins."""

    PASSED = 0  # every task passed; or the output is written
    FAILED = 1  # at least one task failed its audit
    INPUT = 2  # bad invocation, a bad task file, an output that cannot be written
    INTERNAL = 3  # a bug in rprpr: please report
    BUDGET = 4  # a task's audit exceeded its work budget
    INTERRUPTED = 130  # Ctrl-C outside click's own handling (128 + SIGINT)


class InputError(click.ClickException):
    """A bad task file or an output that cannot be written: one line, exit 2."""

    exit_code = int(ExitCode.INPUT)


class InternalError(click.ClickException):
    """A bug met while working on a named task file: one line, exit 3."""

    exit_code = int(ExitCode.INTERNAL)


def run_status(run: Run, *, exit_zero: bool = False) -> ExitCode:
    """The status of a ``check`` run, the highest that applies: 4 over budget > 3 internal
    > 2 input > 1 failed > 0 passed. ``exit_zero`` turns a failed audit into 0 but never
    hides an error."""
    if run.budget_errors:
        return ExitCode.BUDGET
    if run.internal_errors:
        return ExitCode.INTERNAL
    if run.input_errors:
        return ExitCode.INPUT
    if not exit_zero and any(r["verdict"] == "fail" for r in run.reports):
        return ExitCode.FAILED
    return ExitCode.PASSED


def returned_status(value: object) -> ExitCode:
    """The status of a command that returned ``value``: the ExitCode it returned (click
    returns 0 for ``--help`` and ``--version``), PASSED when it returned nothing."""
    return ExitCode(value) if isinstance(value, int) else ExitCode.PASSED


def error_status(error: BaseException) -> ExitCode:
    """The status of a command stopped by ``error``."""
    if isinstance(error, KeyboardInterrupt):
        return ExitCode.INTERRUPTED
    if isinstance(error, BrokenPipeError):  # the reader went away; nothing else failed
        return ExitCode.PASSED
    if isinstance(error, click.exceptions.Exit):
        return returned_status(error.exit_code)
    if isinstance(error, InternalError):
        return ExitCode.INTERNAL
    if isinstance(error, click.ClickException | click.exceptions.Abort):
        return ExitCode.INPUT  # usage errors, bad input, unwritable outputs; click's own 1 never
    return ExitCode.INTERNAL  # any other exception is a bug

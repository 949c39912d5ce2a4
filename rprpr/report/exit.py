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
2       INPUT         a bad invocation (usage error), a bad task file (``check``: that
                      task's; the others are still audited), an output that cannot be
                      written (no permission, a full disk, a closed stream: the
                      environment), an output that would overwrite an input of the run
3       INTERNAL      a bug in rprpr, met while auditing a task or anywhere else
4       BUDGET        ``check``: the audit of a task exceeded its work budget
                      (``--budget``, 10 s by default); it was stopped, the other tasks
                      were audited (a valid task that is too hard to decide in time)
128+N   INTERRUPTED   stopped by signal N: SIGINT (Ctrl-C, 130), SIGTERM (143), SIGHUP
                      (129). rprpr first stops its worker processes and removes its
                      temporary files (any previous output file stays as it was), then
                      dies of that same signal, as git does: a shell reports 128 + N, and
                      a calling script (or a shell loop) sees the interruption.
                      Python's ``subprocess`` reports it as ``-N``.
======  ============  =====================================================================

When several apply, the highest wins (a bad task file among failing tasks exits 2; a task
over its budget exits 4 whatever else happened).
A reader that closes the pipe early (``rprpr check ... | head``) fails nothing: the
status the command had reached stands.
"""

from __future__ import annotations

import errno
from enum import IntEnum
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # annotations only: run.py never imports this module (no circle)
    from .run import Run


class ExitCode(IntEnum):
    """Process exit status of ``rprpr``; when several apply, the highest wins."""

    PASSED = 0  # every task passed; or the output is written
    FAILED = 1  # at least one task failed its audit
    INPUT = 2  # bad invocation, a bad task file, an output that cannot be written
    INTERNAL = 3  # a bug in rprpr: please report
    BUDGET = 4  # a task's audit exceeded its work budget
    INTERRUPTED = 130  # Ctrl-C (128 + SIGINT); 128 + N for signal N (``Interrupted``)


class Interrupted(BaseException):
    """A signal that stops rprpr (SIGINT, SIGTERM, SIGHUP), raised where the main thread
    was, so that every ``finally`` runs: workers are stopped, temporary files removed.
    A ``BaseException``, like ``KeyboardInterrupt``, so that nothing catching
    ``Exception`` swallows it (and not one, so that click does not turn it into its
    ``Abort``). ``delivered``: a real signal came (then rprpr dies of it once cleaned
    up)."""

    def __init__(self, signum: int, *, delivered: bool = True) -> None:
        super().__init__(signum)
        self.signum = signum
        self.delivered = delivered

    @property
    def status(self) -> int:
        """The status a shell reports for a process killed by the signal: 128 + N."""
        return 128 + self.signum


# the errors of a disk (or quota) that cannot take what is written: never rprpr's bug
OUT_OF_SPACE = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG})


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


def exception_status(error: BaseException) -> int:
    """The status of a command stopped by ``error``, any exception but the command line's
    own (``cli.errors.error_status`` maps click's): an ``ExitCode``, or 128 + N for a
    command stopped by signal N."""
    if isinstance(error, Interrupted):
        return error.status
    if isinstance(error, KeyboardInterrupt):
        return ExitCode.INTERRUPTED
    if isinstance(error, BrokenPipeError):  # the reader went away; nothing else failed
        return ExitCode.PASSED
    if isinstance(error, OSError) and error.errno in OUT_OF_SPACE:
        return ExitCode.INPUT  # a full disk met outside a guarded write (--help > /dev/full)
    return ExitCode.INTERNAL  # any other exception is a bug

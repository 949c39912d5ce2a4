"""The command line's own errors (click's exceptions) and the status each ends a command
with; the policy itself (``ExitCode``, what wins) is ``report.exit``'s.

``InputError`` and ``InternalError`` carry one line and their status: a bad task file or
an output that cannot be written (2), a bug met while working on a named task file (3).
``error_status`` maps click's exceptions (usage errors, ``Abort``, ``Exit``) and these two
onto ``ExitCode``, and leaves every other exception to ``report.exit.exception_status``.
"""

from __future__ import annotations

import click

from ..report.exit import ExitCode, exception_status, returned_status


class InputError(click.ClickException):
    """A bad task file or an output that cannot be written: one line, exit 2."""

    exit_code = int(ExitCode.INPUT)


class InternalError(click.ClickException):
    """A bug met while working on a named task file: one line, exit 3."""

    exit_code = int(ExitCode.INTERNAL)


def error_status(error: BaseException) -> int:
    """The status of a command stopped by ``error`` (an ``ExitCode``, or 128 + N for a
    command stopped by signal N): click's exceptions here, any other by
    ``report.exit.exception_status``."""
    if _interrupted_abort(error):
        return ExitCode.INTERRUPTED
    if isinstance(error, click.exceptions.Exit):
        return returned_status(error.exit_code)
    if isinstance(error, InternalError):
        return ExitCode.INTERNAL
    if isinstance(error, click.ClickException | click.exceptions.Abort):
        return ExitCode.INPUT  # usage errors, bad input, unwritable outputs; click's own 1 never
    return exception_status(error)


def _interrupted_abort(error: BaseException) -> bool:
    """click's ``Abort`` standing for a KeyboardInterrupt it caught (Ctrl-C)."""
    return isinstance(error, click.exceptions.Abort) and isinstance(
        error.__context__, KeyboardInterrupt
    )

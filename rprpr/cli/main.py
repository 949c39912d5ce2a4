"""The ``rprpr`` command line: the group of commands and ``main``, the entry point.

Each command lives in its own module (``check``, ``plot``, ``export``, ``schema``),
imported only when named (or listed by ``--help``), so that ``rprpr --version`` and
``rprpr --help`` load neither numpy, flint, YAML nor the engine. ``main`` prints one line
about whatever stopped a command and exits with the status ``report.exit`` decides
(0 passed, 1 a task failed, 2 bad invocation or input, 3 internal error), never click's
own 1.
"""

from __future__ import annotations

import importlib
import os
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

import click

from .._version import __version__
from ..report.exit import OUT_OF_SPACE, Interrupted, returned_status
from .errors import error_status

# each command in the module of its name, with the line ``rprpr --help`` lists it with (so
# that the list imports none of them; tests/cli/test_main.py keeps the lines true)
COMMANDS = {
    "check": "Audit every Type II singular instant of each TASK",
    "export": "Write the sampled motion of TASK",
    "init": "Write a commented task file to start from",
    "plot": "Draw the audit sheet of TASK",
    "repair": "Write the nearest passing motion of a failing TASK",
    "rule": "Explain the rule ID",
    "schema": "Print the JSON Schema (draft 2020-12) of the task file",
}


# the libraries each command needs beyond click (import name: distribution name)
NEEDS = {"flint": "python-flint", "numpy": "numpy", "yaml": "pyyaml", "rich": "rich"}
ENGINE_COMMANDS = {"check", "export", "plot", "repair"}


def _missing_libraries() -> list[str]:
    """The distributions of ``NEEDS`` this Python cannot import (found without importing)."""
    from importlib.util import find_spec

    return [dist for name, dist in NEEDS.items() if find_spec(name) is None]


class _LazyGroup(click.Group):
    """A group whose commands are imported only when used: ``rprpr check`` pays nothing
    for ``plot`` at start-up."""

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted(COMMANDS)

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name not in COMMANDS:
            return None
        missing = _missing_libraries() if name in ENGINE_COMMANDS else []
        if missing:  # an installation without its dependencies: say so, not "internal error"
            raise click.ClickException(
                f"{', '.join(missing)} not installed for {sys.executable}: install rprpr with"
                " pip (pip install .), or run the rprpr of the environment it was installed in"
            )
        command: click.Command = getattr(importlib.import_module(f".{name}", __package__), name)
        if name != "check":  # check releases it itself, once the audit is imported
            from . import collector

            collector.release()
        return command

    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        """The list of commands, from ``COMMANDS`` (no command module imported)."""
        with formatter.section("Commands"):
            formatter.write_dl(sorted(COMMANDS.items()))


@click.group(cls=_LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, "-V", "--version", prog_name="rprpr")
def main_group() -> None:
    """rprpr: audit planned motions of an RPRPR planar parallel robot for Type II and
    high-order singularities (exact), consistency and bounded torques."""


# click >= 8.2 raises this for a bare ``rprpr``; on 8.1 the name does not exist, and an
# ``isinstance`` against it must then match nothing
_NO_ARGS_IS_HELP: Any = getattr(click.exceptions, "NoArgsIsHelpError", ())


def main(argv: Sequence[str] | None = None) -> NoReturn:
    """Entry point: run the command and exit with rprpr's status (``report.exit``).

    SIGINT, SIGTERM and SIGHUP stop the command cleanly (``signals``): rprpr then dies
    of the signal. Text that standard output or error cannot encode gets ASCII
    fallbacks, and a closed standard output is a failed write (``output.standard_streams``)."""
    from . import signals
    from .output import standard_streams

    with signals.handled(), standard_streams():
        try:
            returned = main_group.main(args=list(argv) if argv is not None else None,
                                       prog_name="rprpr", standalone_mode=False)  # fmt: skip
        except (Exception, KeyboardInterrupt, Interrupted) as error:
            _say(error)
            if isinstance(error, Interrupted) and error.delivered:
                signals.die_of(error.signum)
            sys.exit(error_status(error))
    sys.exit(returned_status(returned))


# the variables by which OpenBLAS (numpy's linear algebra) takes its number of threads
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")


def _one_blas_thread() -> None:
    """One OpenBLAS thread, unless the user's environment chooses: rprpr does no linear
    algebra (its balls are elementwise), and importing numpy starts a pool of OpenBLAS
    threads that costs ~60-110 ms of CPU per run (measured on two cores: more than ten
    audits of a task). Set before numpy is imported (by a command, or in a worker: the
    variable is inherited); a process that has imported numpy already is not changed."""
    if not any(os.environ.get(v) for v in BLAS_THREADS):
        os.environ["OPENBLAS_NUM_THREADS"] = "1"


def run() -> NoReturn:
    """The ``rprpr`` program (its console script, ``python -m rprpr``): ``main``, then the
    end of the process as soon as its output is out. With the standard streams flushed
    nothing is left to do but free memory, and the interpreter's teardown (every object
    of numpy, flint and the engine freed one by one) costs more CPU than the audit of a
    task: ``os._exit`` skips it (files are written in ``with`` blocks, workers are reaped
    in theirs). Where the flush fails (a closed pipe, a full disk) the ordinary exit
    reports it as before; ``main`` itself, called in a process that goes on, never ends
    it this way."""
    from . import collector

    _one_blas_thread()
    collector.hold()  # until the command's imports are done
    try:
        main()
    except SystemExit as done:
        code = done.code
        if code is not None and not isinstance(code, int):
            raise
        try:
            for stream in (sys.stdout, sys.stderr):
                if stream is not None:
                    stream.flush()
        except Exception:
            raise done from None
        if "multiprocessing" in sys.modules:  # its workers' shared memory (off Linux)
            raise done from None  # lives in a folder its exit handler removes
        os._exit(code or 0)


def _say(error: BaseException) -> None:
    """The one line on standard error about what stopped the command (control characters
    escaped: a file name or a value quoted in it may hold any)."""
    from .output import say

    if isinstance(error, _NO_ARGS_IS_HELP):  # a bare ``rprpr``: the help itself
        say(error.format_message(), keep="\n")
    elif isinstance(error, click.UsageError):
        say(f"rprpr: usage error: {error.format_message()}")
    elif isinstance(error, click.ClickException):  # a bad input, or a bug in a named task
        say(f"rprpr: {error.format_message()}")
    elif isinstance(error, click.exceptions.Abort):
        interrupted = isinstance(error.__context__, KeyboardInterrupt)
        say("rprpr: interrupted" if interrupted else "rprpr: aborted")
    elif isinstance(error, Interrupted):
        from .signals import signal_name

        say(f"rprpr: interrupted ({signal_name(error.signum)})")
    elif isinstance(error, KeyboardInterrupt):
        say("rprpr: interrupted")
    elif isinstance(error, BrokenPipeError):  # the reader went away: nothing to say, nowhere
        from .output import silence_stdout

        silence_stdout()
    elif isinstance(error, OSError) and error.errno in OUT_OF_SPACE:  # the environment
        from .output import silence_stdout

        silence_stdout()
        say(f"rprpr: cannot write the output: {error.strerror or error}")
    elif isinstance(error, Exception) and not isinstance(error, click.exceptions.Exit):
        say(f"rprpr: internal error ({type(error).__name__}: {error}); please report it")
        if os.environ.get("RPRPR_DEBUG"):
            import traceback

            traceback.print_exception(error)

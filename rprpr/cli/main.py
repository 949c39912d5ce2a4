"""The ``rprpr`` command line: parses arguments, runs the audits, renders, exits.

Exit status (``errors.ExitCode``, the one policy): 0 every task passed, 1 a task failed,
2 bad invocation or bad task file, 3 internal error. click and Python would exit 1 on
their own; ``main`` routes both.
"""

from __future__ import annotations

import contextlib
import json
import os
import sys
import time
import traceback
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

import click

from .._version import __version__
from ..model.errors import TaskFileError
from ..report.exit import ExitCode

if TYPE_CHECKING:  # the report (and with it numpy and flint) is imported only to check
    from ..report.run import Run

FORMATS = ("text", "json", "junit", "github")
PROGRESS_MIN_TASKS = 8  # a progress bar only for runs longer than a handful of tasks
TASK_SUFFIXES = (".yaml", ".yml")
NON_TTY_WIDTH = 160  # text report width when not writing to a terminal (COLUMNS overrides)


def collect_tasks(paths: Sequence[str]) -> list[str]:
    """The task files to check, in order: each file as given; each directory searched
    recursively for *.yaml and *.yml, sorted by path, skipping hidden files and
    directories (.git, .venv, .github, .pre-commit-config.yaml ...). A file named twice
    is checked once, at its first place."""
    out: list[str] = []
    for p in paths:
        if os.path.isdir(p):
            found: list[tuple[tuple[str, ...], str]] = []
            for top, dirs, files in os.walk(p):
                dirs[:] = [d for d in dirs if not d.startswith(".")]
                for f in files:
                    if f.endswith(TASK_SUFFIXES) and not f.startswith("."):
                        full = os.path.join(top, f)
                        found.append((Path(os.path.relpath(full, p)).parts, full))
            out.extend(full for _, full in sorted(found))
        else:
            out.append(p)
    seen: set[str] = set()
    unique = []
    for f in out:
        key = os.path.normcase(os.path.abspath(f))
        if key not in seen:
            seen.add(key)
            unique.append(f)
    return unique


def check_one(path: str, samples: int, strict: bool | None) -> tuple[str, dict[str, Any], float]:
    """Load and audit one task file: (kind, item, seconds), kind "report" (item: the
    report), "input" (a bad task file) or "internal" (a bug; the item names the file)."""
    from ..engine.audit import audit
    from ..io.loader import load_task
    from ..report.records import input_error, internal_error, task_report
    from ..report.run import INPUT, INTERNAL, REPORT

    start = time.perf_counter()
    try:
        task = load_task(path)
    except TaskFileError as e:
        return INPUT, input_error(e, path), time.perf_counter() - start
    except Exception as e:  # a bug while reading: still name the file
        return INTERNAL, internal_error(e, path), time.perf_counter() - start
    try:
        report = task_report(audit(task, samples=samples, strict=strict), path)
    except Exception as e:
        return INTERNAL, internal_error(e, path), time.perf_counter() - start
    return REPORT, report, time.perf_counter() - start


def _check_star(args: tuple[str, int, bool | None]) -> tuple[str, dict[str, Any], float]:
    return check_one(*args)


def run_checks(
    files: Sequence[str], samples: int, strict: bool | None, jobs: int, progress: Any = None
) -> Run:
    """Audit ``files`` in ``jobs`` worker processes (1: in this process); the outcomes come
    back in task order, so the report does not depend on ``jobs``. ``progress`` is a
    rich Console to draw a progress bar on, or None."""
    from ..engine import audit as auditing  # noqa: F401  (imported before forking: workers inherit them)
    from ..io import loader  # noqa: F401  (imported before forking: workers inherit them)
    from ..report.run import Run

    run = Run()
    args = [(f, samples, strict) for f in files]
    results: Iterable[tuple[str, dict[str, Any], float]]
    pool = None
    jobs = min(jobs, len(files))
    if jobs > 1:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        # fork: workers start in milliseconds with the modules above already imported
        ctx = multiprocessing.get_context("fork" if sys.platform.startswith("linux") else "spawn")
        pool = ProcessPoolExecutor(max_workers=jobs, mp_context=ctx)
        chunk = max(1, min(16, len(files) // (8 * jobs)))
        results = pool.map(_check_star, args, chunksize=chunk)  # submits (and forks) now
    else:
        results = map(_check_star, args)
    try:
        if progress is not None:
            from rich.progress import Progress

            with Progress(console=progress, transient=True) as bar:
                job = bar.add_task("checking", total=len(files))
                for result in results:
                    run.add(*result)
                    bar.advance(job)
        else:
            for result in results:
                run.add(*result)
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
    return run


def color_enabled(color: str, stream: Any, environ: Mapping[str, str] = os.environ) -> bool:
    """Whether to colour output on ``stream``: ``--color always``/``never`` win; else
    NO_COLOR (set and not empty) turns colour off, then FORCE_COLOR (set and not empty)
    turns it on; else colour only on a terminal (TERM not ``dumb``)."""
    if color != "auto":
        return color == "always"
    if environ.get("NO_COLOR"):
        return False
    if environ.get("FORCE_COLOR"):
        return True
    try:
        tty = bool(stream.isatty())
    except (AttributeError, ValueError):
        tty = False
    return tty and environ.get("TERM", "") not in ("dumb", "unknown")


def make_console(stream: Any, colored: bool, environ: Mapping[str, str] = os.environ) -> Any:
    """A rich Console on ``stream``: ANSI styles only when ``colored``; no markup, emoji or
    highlighting (task names and messages are printed as they are)."""
    from rich.console import Console

    try:
        tty = bool(stream.isatty())
    except (AttributeError, ValueError):
        tty = False
    kw: dict[str, Any] = {"file": stream, "highlight": False, "markup": False, "emoji": False}
    if colored:
        kw.update(force_terminal=True, no_color=False, color_system="auto")
    else:
        kw.update(force_terminal=tty, no_color=True, color_system=None)
    if not tty:
        cols = environ.get("COLUMNS", "")
        kw["width"] = int(cols) if cols.isdigit() and int(cols) > 0 else NON_TTY_WIDTH
    console = Console(**kw)
    if colored and console.color_system is None:  # colour forced on a dumb terminal
        console = Console(**{**kw, "color_system": "standard"})
    console.on_broken_pipe = _broken_pipe  # type: ignore[method-assign]  # rich: exit 1
    return console


def _broken_pipe() -> None:
    raise BrokenPipeError("the report's reader closed the pipe")


def want_progress(n_tasks: int, stream: Any, quiet: bool) -> bool:
    """A progress bar only on a terminal, for more than a handful of tasks, unless -q."""
    try:
        tty = bool(stream.isatty())
    except (AttributeError, ValueError):
        tty = False
    return tty and n_tasks > PROGRESS_MIN_TASKS and not quiet


class _LazyGroup(click.Group):
    """A group whose ``plot`` and ``export`` commands are imported only when used, so that
    ``rprpr check`` pays nothing for them at start-up."""

    LAZY = ("export", "plot")

    def list_commands(self, ctx: click.Context) -> list[str]:
        return sorted([*super().list_commands(ctx), *self.LAZY])

    def get_command(self, ctx: click.Context, name: str) -> click.Command | None:
        if name in self.LAZY:
            from . import plot_export as cli_plot

            return getattr(cli_plot, name)
        return super().get_command(ctx, name)


@click.group(cls=_LazyGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="rprpr")
def main_group() -> None:
    """rprpr: audit planned motions of an RPRPR planar parallel robot for Type II and
    high-order singularities (exact), consistency and bounded torques."""


@main_group.command()
@click.argument("tasks", nargs=-1, required=True, type=click.Path())
@click.option(
    "--format",
    "fmt",
    type=click.Choice(FORMATS),
    default="text",
    show_default=True,
    help="Report format: text (rich), json, junit (JUnit XML) or github "
    "(GitHub Actions annotations).",
)
@click.option(
    "-o",
    "--output-file",
    type=click.Path(dir_okay=False),
    help="Write the report to this file instead of standard output.",
)
@click.option(
    "--strict",
    is_flag=True,
    default=None,
    help="Also fail on inconsistent/unbounded singular instants and torque limits.",
)
@click.option(
    "--samples",
    type=click.IntRange(2, 1_000_000),
    default=1001,
    show_default=True,
    help="Sample points t = 0 .. t_f for the torques.",
)
@click.option(
    "-j",
    "--jobs",
    type=click.IntRange(0, 256),
    default=1,
    show_default=True,
    help="Worker processes (0: one per CPU). The report is the same for any N.",
)
@click.option(
    "-q",
    "--quiet",
    is_flag=True,
    help="Report only failures and errors (text, json, github; JUnit lists every task).",
)
@click.option(
    "--exit-zero",
    is_flag=True,
    help="Exit 0 even when a task fails (bad input and internal errors still count).",
)
@click.option(
    "--color",
    type=click.Choice(["auto", "always", "never"]),
    default="auto",
    show_default=True,
    help="Colour in the text report; auto honours NO_COLOR, FORCE_COLOR and a non-terminal output.",
)
def check(
    tasks: tuple[str, ...], fmt: str, output_file: str | None, strict: bool | None,
    samples: int, jobs: int, quiet: bool, exit_zero: bool, color: str,
) -> None:  # fmt: skip
    """Audit every Type II singular instant of each TASK (task files, or directories
    searched recursively for *.yaml and *.yml).

    Exit status: 0 every task passed, 1 a task failed, 2 bad invocation or bad task
    file, 3 internal error (the highest that applies)."""
    files = collect_tasks(tasks)
    if not files:
        raise click.UsageError(f"no task files (*.yaml, *.yml) found in {', '.join(tasks)}")
    if output_file == "-":
        output_file = None  # the usual spelling of standard output
    if output_file and os.path.exists(output_file):
        for f in files:
            if os.path.exists(f) and os.path.samefile(output_file, f):
                raise click.UsageError(
                    f"the output file {output_file} is also a task file: it would be overwritten"
                )
    out = _open_output(output_file)
    try:
        show = want_progress(len(files), sys.stderr, quiet)
        progress = make_console(sys.stderr, color_enabled(color, sys.stderr)) if show else None
        run = run_checks(files, samples, strict or None, jobs or _cpus(), progress)
        try:
            _write_report(run, fmt, out, output_file, quiet, color)
        except BrokenPipeError:  # the reader went away (| head): the verdict still stands
            _silence_stdout()
            raise SystemExit(int(run.exit_code(exit_zero))) from None
        except OSError as err:  # disk full and the like: the environment, not rprpr
            where = output_file or "standard output"
            raise click.ClickException(
                f"cannot write the report to {where}: {err.strerror or err}"
            ) from None
    finally:
        if output_file:
            with contextlib.suppress(OSError):
                out.close()
    if fmt != "text" or output_file:  # the one-line errors also go to stderr for the log
        for e in run.input_errors + run.internal_errors:
            click.echo(e["text"], err=True)
    if os.environ.get("RPRPR_DEBUG"):  # the tracebacks of bugs met in a task, for a report
        for e in run.internal_errors:
            click.echo(e["traceback"], err=True)
    if output_file and not quiet:  # the log still says what the report file holds
        s = run.summary()
        click.echo(
            f"rprpr: {s['tasks']} task{'s' if s['tasks'] != 1 else ''}: {s['passed']} passed,"
            f" {s['failed']} failed, {s['errors']} error{'s' if s['errors'] != 1 else ''};"
            f" {fmt} report written to {output_file}",
            err=True,
        )
    raise SystemExit(int(run.exit_code(exit_zero)))


def _silence_stdout() -> None:
    """Point standard output at /dev/null, so that the interpreter's last flush into a
    closed pipe raises nothing more."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def _cpus() -> int:
    """The CPUs this process may run on (``-j 0``)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _open_output(output_file: str | None) -> TextIO:
    """The report's stream; a file that cannot be written is a usage error, found before
    any task is audited."""
    if not output_file:
        return sys.stdout
    try:
        return open(output_file, "w", encoding="utf-8", newline="\n")
    except OSError as e:
        raise click.UsageError(
            f"cannot write the output file {output_file}: {e.strerror or e}"
        ) from None


def _write_report(
    run: Run, fmt: str, out: TextIO, output_file: str | None, quiet: bool, color: str
) -> None:
    if fmt == "text":
        from ..render.text import render

        # colour in a file only when asked for (--color always), never from the environment
        colored = color == "always" if output_file else color_enabled(color, out)
        err = make_console(sys.stderr, color_enabled(color, sys.stderr))
        # bad task files: on stderr, and in the report too when it goes to a file
        render(run, make_console(out, colored), err, quiet=quiet, errors_inline=bool(output_file))
        return
    if fmt == "json":
        text = json.dumps(run.document(quiet=quiet), indent=2) + "\n"
    elif fmt == "junit":
        from ..render.junit import render as junit

        text = junit(run)
    else:
        from ..render.github import render as github

        text = github(run, quiet=quiet)
    out.write(text)
    out.flush()


@main_group.command()
def schema() -> None:
    """Print the JSON Schema (draft 2020-12) of the task file."""
    from ..io.schema import json_schema

    try:
        click.echo(json.dumps(json_schema(), indent=2))
        sys.stdout.flush()
    except BrokenPipeError:  # | head: click would exit 1 by itself
        _silence_stdout()


# click >= 8.2 raises this for a bare ``rprpr``; on 8.1 the name does not exist, and an
# ``except`` naming it would itself fail while handling any other error
_NO_ARGS_IS_HELP: Any = getattr(click.exceptions, "NoArgsIsHelpError", ())


def main(argv: Sequence[str] | None = None) -> None:
    """Entry point: run the command and exit with rprpr's status (never click's own 1)."""
    try:
        main_group.main(args=list(argv) if argv is not None else None, prog_name="rprpr",
                        standalone_mode=False)  # fmt: skip
    except _NO_ARGS_IS_HELP as e:
        click.echo(e.format_message() if hasattr(e, "format_message") else str(e), err=True)
        sys.exit(ExitCode.INPUT)
    except click.UsageError as e:
        click.echo(f"rprpr: usage error: {e.format_message()}", err=True)
        sys.exit(ExitCode.INPUT)
    except click.ClickException as e:  # a bad input (2), or a bug met in a named task (3)
        click.echo(f"rprpr: {e.format_message()}", err=True)
        sys.exit(ExitCode.INTERNAL if e.exit_code == ExitCode.INTERNAL else ExitCode.INPUT)
    except click.exceptions.Abort:
        click.echo("rprpr: aborted", err=True)
        sys.exit(ExitCode.INPUT)
    except click.exceptions.Exit as e:
        sys.exit(e.exit_code)
    except SystemExit:
        raise
    except KeyboardInterrupt:
        sys.exit(130)
    except BrokenPipeError:  # e.g. rprpr schema | head: nothing failed but the reader
        _silence_stdout()
        sys.exit(ExitCode.PASSED)
    except Exception as e:
        click.echo(f"rprpr: internal error ({type(e).__name__}: {e}); please report it", err=True)
        if os.environ.get("RPRPR_DEBUG"):
            traceback.print_exc()
        sys.exit(ExitCode.INTERNAL)
    sys.exit(ExitCode.PASSED)

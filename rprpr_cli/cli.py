"""The ``rprpr`` command line: parses arguments, runs the audits, renders, exits.

Exit status (``errors.ExitCode``, the one policy): 0 every task passed, 1 a task failed,
2 bad invocation or bad task file, 3 internal error. click and Python would exit 1 on
their own; ``main`` routes both.
"""

from __future__ import annotations

import json
import os
import sys
import traceback
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import click

from . import __version__
from .errors import ExitCode, TaskFileError

FORMATS = ("text", "json", "junit", "github")
PROGRESS_MIN_TASKS = 8  # a progress bar only for runs longer than a handful of tasks


def collect_tasks(paths: Sequence[str]) -> list[str]:
    """Files as given; directories searched recursively for *.yaml and *.yml, sorted."""
    out: list[str] = []
    for p in paths:
        if os.path.isdir(p):
            found = [
                str(f) for f in Path(p).rglob("*") if f.suffix in (".yaml", ".yml") and f.is_file()
            ]
            out.extend(sorted(found))
        else:
            out.append(p)
    return out


def check_one(path: str, samples: int, strict: bool | None) -> tuple[str, dict[str, Any]]:
    """Audit one task file: ("report", report) | ("input", error) | ("internal", error)."""
    from .audit import audit
    from .loader import load_task
    from .report import input_error, task_report

    try:
        task = load_task(path)
    except TaskFileError as e:
        return "input", input_error(e, path)
    except Exception as e:  # a bug while reading: still name the file
        return "internal", _internal(path, e)
    try:
        return "report", task_report(audit(task, samples=samples, strict=strict), path)
    except Exception as e:
        return "internal", _internal(path, e)


def _internal(path: str, e: BaseException) -> dict[str, Any]:
    return {
        "task": path,
        "message": f"{type(e).__name__}: {e}",
        "text": f"{path}: internal error ({type(e).__name__}: {e}); please report it to the"
        " rprpr maintainers with this task file",
        "traceback": "".join(traceback.format_exception(e)),
    }


def _check_star(args: tuple[str, int, bool | None]) -> tuple[str, dict[str, Any]]:
    return check_one(*args)


def run_checks(
    files: Sequence[str], samples: int, strict: bool | None, jobs: int, progress: bool
) -> Any:
    from .report import Run

    run = Run()
    args = [(f, samples, strict) for f in files]
    results: Iterable[tuple[str, dict[str, Any]]]
    pool = None
    if jobs > 1 and len(files) > 1:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        ctx = multiprocessing.get_context("fork" if sys.platform.startswith("linux") else "spawn")
        pool = ProcessPoolExecutor(max_workers=jobs, mp_context=ctx)
        chunk = max(1, min(32, len(files) // (4 * jobs)))
        results = pool.map(_check_star, args, chunksize=chunk)
    else:
        results = map(_check_star, args)
    try:
        if progress:
            from rich.progress import Progress

            with Progress(console=_console(sys.stderr, "auto"), transient=True) as bar:
                job = bar.add_task("checking", total=len(files))
                for kind, item in results:
                    _add(run, kind, item)
                    bar.advance(job)
        else:
            for kind, item in results:
                _add(run, kind, item)
    finally:
        if pool is not None:
            pool.shutdown()
    return run


def _add(run: Any, kind: str, item: dict[str, Any]) -> None:
    target = {"report": run.reports, "input": run.input_errors, "internal": run.internal_errors}[kind]
    run.order.append((kind, len(target)))
    target.append(item)


def _console(stream: Any, color: str, width: int | None = None) -> Any:
    from rich.console import Console

    kw: dict[str, Any] = {"file": stream, "highlight": False}
    if color == "always":
        kw["force_terminal"] = True
    elif color == "never":
        kw["no_color"] = True
        kw["color_system"] = None
    if not stream.isatty():
        kw["width"] = width or 160
    return Console(**kw)


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="rprpr")
def main_group() -> None:
    """rprpr: audit planned motions of an RPRPR planar parallel robot for Type II and
    high-order singularities (exact), consistency and bounded torques."""


@main_group.command()
@click.argument("tasks", nargs=-1, required=True, type=click.Path())
@click.option("--format", "fmt", type=click.Choice(FORMATS), default="text", show_default=True,
              help="Report format.")
@click.option("-o", "--output-file", type=click.Path(dir_okay=False, writable=True),
              help="Write the report here instead of standard output.")
@click.option("--strict", is_flag=True, default=None,
              help="Also fail on inconsistent/unbounded singular instants and torque limits.")
@click.option("--samples", type=click.IntRange(2, 1_000_000), default=1001, show_default=True,
              help="Sample points t = 0 .. t_f for the torques.")
@click.option("-j", "--jobs", type=click.IntRange(1, 256), default=1, show_default=True,
              help="Worker processes.")
@click.option("-q", "--quiet", is_flag=True, help="Report only failures and errors.")
@click.option("--exit-zero", is_flag=True,
              help="Exit 0 even when a task fails (bad input and internal errors still count).")
@click.option("--color", type=click.Choice(["auto", "always", "never"]), default="auto",
              show_default=True, help="Colour in the text report (NO_COLOR and FORCE_COLOR are honoured).")
def check(
    tasks: tuple[str, ...], fmt: str, output_file: str | None, strict: bool | None,
    samples: int, jobs: int, quiet: bool, exit_zero: bool, color: str,
) -> None:  # fmt: skip
    """Audit every Type II singular instant of each TASK (files or directories)."""
    files = collect_tasks(tasks)
    if not files:
        raise click.UsageError(f"no task files (*.yaml, *.yml) found in {', '.join(tasks)}")
    progress = sys.stderr.isatty() and len(files) > PROGRESS_MIN_TASKS and fmt == "text"
    run = run_checks(files, samples, strict or None, jobs, progress)
    out = open(output_file, "w", encoding="utf-8") if output_file else sys.stdout  # noqa: SIM115
    try:
        if fmt == "text":
            from .render_text import render

            render(run, _console(out, color), _console(sys.stderr, color), quiet=quiet)
        elif fmt == "json":
            doc = run.document()
            if quiet:
                doc["reports"] = [r for r in doc["reports"] if r["verdict"] != "pass"]
            out.write(json.dumps(doc, indent=2) + "\n")
        elif fmt == "junit":
            from .render_junit import render as junit

            out.write(junit(run))
        else:
            from .render_github import render as github

            out.write(github(run))
    finally:
        if output_file:
            out.close()
    if fmt != "text":
        for e in run.input_errors + run.internal_errors:
            click.echo(e["text"], err=True)
    raise SystemExit(int(run.exit_code(exit_zero)))


@main_group.command()
def schema() -> None:
    """Print the JSON Schema (draft 2020-12) of the task file."""
    from .schema import json_schema

    click.echo(json.dumps(json_schema(), indent=2))


def _register_plot_commands() -> None:
    from .cli_plot import export, plot

    main_group.add_command(plot)
    main_group.add_command(export)


_register_plot_commands()


def main(argv: Sequence[str] | None = None) -> None:
    """Entry point: run the command and exit with rprpr's status (never click's own 1)."""
    try:
        main_group.main(args=list(argv) if argv is not None else None, prog_name="rprpr",
                        standalone_mode=False)  # fmt: skip
    except click.exceptions.NoArgsIsHelpError as e:  # type: ignore[attr-defined]
        click.echo(e.format_message() if hasattr(e, "format_message") else str(e), err=True)
        sys.exit(ExitCode.INPUT)
    except click.UsageError as e:
        click.echo(f"rprpr: usage error: {e.format_message()}", err=True)
        sys.exit(ExitCode.INPUT)
    except click.ClickException as e:
        click.echo(f"rprpr: {e.format_message()}", err=True)
        sys.exit(ExitCode.INPUT)
    except click.exceptions.Abort:
        click.echo("rprpr: aborted", err=True)
        sys.exit(ExitCode.INPUT)
    except click.exceptions.Exit as e:
        sys.exit(e.exit_code)
    except SystemExit:
        raise
    except KeyboardInterrupt:
        sys.exit(130)
    except BrokenPipeError:
        sys.exit(ExitCode.PASSED)
    except Exception as e:
        click.echo(f"rprpr: internal error ({type(e).__name__}: {e}); please report it", err=True)
        if os.environ.get("RPRPR_DEBUG"):
            traceback.print_exc()
        sys.exit(ExitCode.INTERNAL)
    sys.exit(ExitCode.PASSED)

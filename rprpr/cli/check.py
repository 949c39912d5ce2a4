"""``rprpr check``: audit task files in worker processes, each under a work budget
(``budget``), render the run in one format, exit with the run's status
(``report.exit.run_status``)."""

from __future__ import annotations

import contextlib
import functools
import importlib.util
import os
import re
import signal
import stat
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import replace
from typing import TYPE_CHECKING, Any, TextIO

import click

from ..model.defaults import DEFAULT_SAMPLES
from ..model.errors import TaskFileError
from ..model.options import AuditOptions
from ..report.exit import ExitCode, run_status
from .config import DEFAULT_BUDGET, Settings, configure, load_settings, show, with_rules
from .options import CHECK_FORMATS, PLOT_EXTRA, CheckOptions, color_option, output_file_option
from .output import (
    Lossy,
    color_enabled,
    echo,
    is_tty,
    make_console,
    refuse_overwriting_inputs,
    report_stream,
    say,
    utf8,
    writing,
)
from .tasks import STDIN, read_task, run_inputs, tasks_or_usage_error

if TYPE_CHECKING:  # the report (and with it numpy and flint) is imported only to check
    from ..engine.audit import AuditResult
    from ..report.run import Attachment, Run
    from . import workers

PROGRESS_MIN_TASKS = 8  # a progress bar only for runs longer than a handful of tasks

# (kind, item, seconds, attachment) of one task; the attachment: --format html only
Outcome = tuple[str, dict[str, Any], float, "Attachment | None"]

# the stages of a task around those of the audit (``engine.audit.STAGES``)
LOADING = "the loading of the task file"
REPORTING = "the report"
SHEET = "the audit sheet"  # --format html: drawn after the report, within what is left
SHEET_MARGIN = 0.5  # seconds of the budget kept back for sending the outcome home


@click.command()
@click.argument("tasks", nargs=-1, type=click.Path(readable=False))
@click.option(
    "--output-format",
    "--format",
    "fmt",
    type=click.Choice(CHECK_FORMATS),
    default=None,
    help="Report format: text (rich), concise (the findings alone, one line each: "
    "FILE:LINE:COL: RPRnnn [severity] message), json, junit (JUnit XML), github (GitHub Actions "
    "annotations), sarif (SARIF 2.1.0, for code scanning) or gitlab (GitLab Code "
    "Quality) or html (one self-contained page: verdicts, findings with their lines, the "
    "instants and each task's audit sheet).  [default: text]",
)
@output_file_option(
    "Write the report to this file instead of standard output.", dash_is_stdout=True
)
@click.option(
    "--strict",
    is_flag=True,
    default=None,
    help="Fail on every finding: also on torque limits (RPR202) and on accepted unbounded torques.",
)
@click.option(
    "--peak",
    is_flag=True,
    default=None,
    help="Compute the certified torque peak (max |T1|, max |T2| over [0, t_f]) of every "
    "task for the report; no verdict needs it (else: each task's checks.peak).",
)
@click.option(
    "--warn-unbounded",
    is_flag=True,
    help="Accept unbounded torques at singular instants (RPR201): a warning instead of a "
    "failure, for every task, whatever its checks.unbounded_torque says.",
)
@click.option(
    "--samples",
    type=click.IntRange(2, 1_000_000),
    default=None,
    help=f"Grid size of the sampled motion; no verdict depends on it (grid-free).  "
    f"[default: {DEFAULT_SAMPLES}]",
)
@click.option(
    "-j",
    "--jobs",
    type=click.IntRange(0, 256),
    default=None,
    help="Worker processes (0: one per CPU). The report is the same for any N.  [default: 1]",
)
@click.option(
    "-q",
    "--quiet",
    is_flag=True,
    help="Report only failures and errors (text, json, github; JUnit lists every task).",
)
@click.option(
    "--layout",
    type=click.Choice(["auto", "table", "rows"]),
    default="auto",
    show_default=True,
    help="Text report: each task's singular instants as a table (table), as key/value rows"
    " per instant (rows), or as a table where the terminal is wide enough (auto).",
)
@click.option(
    "--exit-zero",
    is_flag=True,
    help="Exit 0 even when a task fails (bad input and internal errors still count).",
)
@click.option(
    "--budget",
    type=click.FloatRange(0, 1e6),
    default=None,
    metavar="SECONDS",
    help="Work budget per task: a task still being audited after SECONDS is stopped and "
    f"reported (exit status 4); the others go on. 0: no limit.  [default: {DEFAULT_BUDGET:g}]",
)
@color_option()
@click.option(
    "--config",
    type=click.Path(dir_okay=False, readable=False),
    help="Read this configuration file (rprpr.toml, or a pyproject.toml's [tool.rprpr]) "
    "instead of the one found from the working directory upward.",
)
@click.option("--isolated", is_flag=True, help="Ignore every configuration file.")
@click.option(
    "--show-settings",
    is_flag=True,
    help="Print the resolved settings, and where each comes from, then exit.",
)
@click.option(
    "--select",
    multiple=True,
    metavar="RULES",
    help="Run only these rules (comma-separated ids, names or the start of ids: RPR2, "
    "unbounded-torque); replaces the configuration's select and ignore.",
)
@click.option(
    "--extend-select",
    multiple=True,
    metavar="RULES",
    help="Rules to run besides those selected (comma-separated).",
)
@click.option(
    "--ignore",
    multiple=True,
    metavar="RULES",
    help="Rules to silence (comma-separated), besides the configuration's ignore.",
)
@click.option("--statistics", is_flag=True, help="Print the count of findings per rule.")
@click.option(
    "--force-exclude",
    is_flag=True,
    help="Apply include and exclude to the files named on the command line too (for "
    "pre-commit and editors): a file that is not a task file is skipped.",
)
@click.option(
    "--sheets/--no-sheets",
    default=True,
    show_default=True,
    help="HTML report: each task's audit sheet as inline SVG (needs matplotlib: "
    "pip install 'rprpr[plot]'; without it the report says so and has none).",
)
@click.option(
    "--stdin-filename",
    metavar="NAME",
    help="The name of the task file read from standard input (TASK -) in the report.",
)
def check(tasks: tuple[str, ...], **params: Any) -> ExitCode:
    """Audit every Type II singular instant of each TASK (task files, or directories
    searched recursively for task files: *.rprpr.yaml and *.rprpr.yml unless the
    configuration's include says otherwise; - reads a task from standard input). With no
    TASK, the configuration's paths (default: the working directory).

    Exit status: 0 every task passed, 1 a task failed, 2 bad invocation, bad task file
    or bad configuration, 3 internal error, 4 a task exceeded its work budget (the
    highest that applies); 128 + N stopped by signal N."""
    settings, options = resolve(params)
    if params["show_settings"]:
        for line in show(settings):
            echo(line)
        return ExitCode.PASSED
    selection = settings.selection(force=params["force_exclude"])
    files = tasks_or_usage_error(tasks or settings["paths"], selection)
    if not files:  # every file named was left out (--force-exclude): nothing to do
        return ExitCode.PASSED
    if STDIN in files:
        options = _read_stdin(options)
    if options.output_file:  # every file the run reads, known before any is loaded
        inputs = run_inputs(files, options.stdin, settings.file)
        refuse_overwriting_inputs([options.output_file], inputs)
    options, note = _sheets(options)
    with report_stream(options.output_file, "the report") as out:
        show_bar = want_progress(len(files), sys.stderr, options.quiet)
        progress = (
            make_console(Lossy(sys.stderr), color_enabled(options.color, sys.stderr))
            if show_bar
            else None
        )
        run = run_checks(files, options, progress)
        if note:
            run.notes.append(note)
        status = run_status(run, exit_zero=options.exit_zero)
        with writing("the report", options.output_file, status):
            write_report(run, options, out)
    _log(run, options)
    return status


def resolve(params: dict[str, Any]) -> tuple[Settings, CheckOptions]:
    """The settings of the run (the configuration under the options given) and the
    options of ``check`` they make."""
    given = {
        "format": params["fmt"],
        "strict": params["strict"] or None,
        "peak": params["peak"] or None,
        "samples": params["samples"],
        "jobs": params["jobs"],
        "budget": params["budget"],
    }
    settings = with_rules(
        load_settings(params["config"], params["isolated"], given),
        select=_selectors(params["select"]),
        extend_select=_selectors(params["extend_select"]),
        ignore=_selectors(params["ignore"]),
    )
    output_file = params["output_file"]
    verdicts = AuditOptions(
        samples=settings["samples"],
        strict=params["strict"] or None,  # the command line's: over every task's own
        peak=params["peak"] or None,
        warn_unbounded=params["warn_unbounded"],
    )
    options = CheckOptions(
        audit=verdicts,
        format=settings["format"],
        output_file=output_file,
        jobs=settings["jobs"] or _cpus(),
        quiet=params["quiet"],
        layout=params["layout"],
        exit_zero=params["exit_zero"],
        budget=settings["budget"] or None,  # 0: no limit
        color=params["color"],
        defaults=settings.task_defaults(),
        statistics=params["statistics"],
        stdin_filename=params["stdin_filename"] or STDIN,
        sheets=params["sheets"],
    )
    return settings, options


def _sheets(options: CheckOptions) -> tuple[CheckOptions, str | None]:
    """The options with ``sheets`` only where they are drawn (an HTML report, matplotlib
    installed), and the report's one-line note when they were asked for and cannot be."""
    if options.format != "html" or options.statistics or not options.sheets:
        return replace(options, sheets=False), None
    if importlib.util.find_spec("matplotlib") is None:  # the light install: found, not imported
        note = f"The audit sheets are left out: they need matplotlib ({PLOT_EXTRA})."
        return replace(options, sheets=False), note
    return options, None


def _selectors(given: Sequence[str]) -> tuple[str, ...]:
    """The rule selectors of a repeatable, comma-separated option (``--select A,B``)."""
    return tuple(p.strip() for value in given for p in value.split(",") if p.strip())


def _read_stdin(options: CheckOptions) -> CheckOptions:
    """``options`` with standard input read (here: the workers have none), through the
    capped reader: a stream past the cap is stopped there and is that task's error."""
    from ..io.loader import read_stdin

    try:
        return replace(options, stdin=read_stdin(options.stdin_filename))
    except TaskFileError as e:
        return replace(options, stdin=b"", stdin_error=e.message)


def check_one(
    path: str, options: CheckOptions, on_stage: Callable[[str], None] | None = None
) -> Outcome:
    """Load and audit one task file, in this process: (kind, item, seconds, attachment),
    kind "report" (item: the report), "input" (a bad task file) or "internal" (a bug; the
    item names the file). ``on_stage`` is told each stage as it begins (LOADING is where
    it starts). The attachment is None but for ``--format html``: the task file's lines
    and, with ``options.sheets``, the audit sheet (``_attach``)."""
    from ..engine.audit import audit
    from ..report.records import input_error, internal_error, task_report
    from ..report.run import INPUT, INTERNAL, REPORT

    start = time.perf_counter()
    if path == STDIN:
        path = options.stdin_filename
        name = STDIN
    else:
        name = path
    html = options.format == "html"
    try:
        if name == STDIN and options.stdin_error:
            raise TaskFileError(options.stdin_error, file=path)
        task = read_task(name, options.stdin, path)
        task = configure(task, options.defaults)  # the configuration's defaults and levels
    except TaskFileError as e:
        attached = _attach(name, options, None, path, start) if html else None
        return INPUT, input_error(e, path), time.perf_counter() - start, attached
    except Exception as e:  # a bug while reading: still name the file
        return INTERNAL, internal_error(e, path), time.perf_counter() - start, None
    try:
        result = audit(task, options=options.audit, on_stage=on_stage)
        if on_stage is not None:
            on_stage(REPORTING)
        report = task_report(result, path)
    except TaskFileError as e:  # a task the audit refuses (a mechanism it cannot audit)
        return INPUT, input_error(e.naming(path), path), time.perf_counter() - start, None
    except Exception as e:
        return INTERNAL, internal_error(e, path), time.perf_counter() - start, None
    if html and on_stage is not None and options.sheets:
        on_stage(SHEET)
    attached = _attach(name, options, result, path, start) if html else None
    return REPORT, report, time.perf_counter() - start, attached


def _attach(
    name: str, options: CheckOptions, result: AuditResult | None, path: str, start: float
) -> Attachment:
    """What the HTML report shows of a task beyond its records: the task file's own
    lines (read again: standard input's bytes are at hand), and with ``options.sheets``
    the sheet of ``result`` as SVG, drawn within what is left of the task's budget (a
    report format never turns a verdict into a budget error: out of time, or failing to
    draw, the task has a one-line note instead of its sheet)."""
    from ..report.run import Attachment

    source = _source_lines(options.stdin if name == STDIN else None, name)
    if result is None or not options.sheets:
        return Attachment(source)
    left = None if options.budget is None else options.budget - (time.perf_counter() - start)
    if left is not None and left <= SHEET_MARGIN:
        return Attachment(source, note=_NO_TIME)
    try:
        with _time_limit(None if left is None else left - SHEET_MARGIN):
            from ..render import sheet
            from ..render.escape import printable

            drawn = sheet.svg([sheet.motion(result, printable(path))])
    except _OutOfTime:
        return Attachment(source, note=_NO_TIME)
    except Exception as e:  # a bug in drawing: the report stands, the sheet says why not
        return Attachment(source, note=f"The audit sheet could not be drawn ({type(e).__name__}).")
    return Attachment(source, sheet=drawn)


_NO_TIME = "The audit sheet was left out: the task's work budget ran out (check --budget)."


class _OutOfTime(Exception):
    """The sheet's time ran out (``_time_limit``)."""


def _ring(signum: int, frame: object) -> None:
    raise _OutOfTime


@contextlib.contextmanager
def _time_limit(seconds: float | None) -> Iterator[None]:
    """Raise ``_OutOfTime`` in the block after ``seconds``, and every 50 ms after until it
    stops (a ring in a weakref callback is swallowed there); a real-time alarm, none where
    none can be set: no limit, not the main thread, not POSIX."""
    main = threading.current_thread() is threading.main_thread()
    if seconds is None or not hasattr(signal, "setitimer") or not main:
        yield
        return
    previous = signal.getsignal(signal.SIGALRM)
    try:  # armed within the try: a ring before the block still switches the timer off
        signal.signal(signal.SIGALRM, _ring)
        signal.setitimer(signal.ITIMER_REAL, max(seconds, 1e-3), 0.05)
        yield
    finally:
        while True:  # a ring may still land here, before the timer is off, or just after
            try:
                signal.setitimer(signal.ITIMER_REAL, 0)
                break
            except _OutOfTime:
                continue
        signal.signal(signal.SIGALRM, previous)


# where YAML (PyYAML's marks) starts a new line: the line numbers of the findings
_LINE_BREAK = re.compile("\r\n|[\n\r\x85\u2028\u2029]")


def _source_lines(stdin: bytes | None, path: str) -> tuple[str, ...] | None:
    """The lines of the task file ``path`` (or of ``stdin``, the task read from standard
    input) as the loader numbered them, bytes that are not UTF-8 kept as surrogates
    (escaped when shown); None for what is not a regular file, cannot be read, or is
    larger than a task file may be (the loader's cap)."""
    from ..io.loader import MAX_BYTES

    data = stdin
    if data is None:
        try:
            if not stat.S_ISREG(os.stat(path).st_mode):  # never wait on a FIFO twice
                return None
            with open(path, "rb") as fh:
                data = fh.read(MAX_BYTES + 1)
        except OSError:
            return None
    if len(data) > MAX_BYTES:
        return None
    text = data.decode("utf-8", "surrogateescape").removeprefix("\ufeff")
    lines = _LINE_BREAK.split(text)
    if lines and lines[-1] == "":  # the break that ends the last line starts none
        lines.pop()
    return tuple(lines)


def _check_in_worker(options: CheckOptions, path: str, on_stage: Callable[[str], None]) -> Outcome:
    return check_one(path, options, on_stage)


def run_checks(files: Sequence[str], options: CheckOptions, progress: Any = None) -> Run:
    """Audit ``files`` in ``options.jobs`` worker processes (at least one: the audit never
    runs in this process), each task under ``options.budget`` (``budget``); the outcomes
    come back in task order, so the report does not depend on the number of workers.
    ``progress`` is a rich Console to draw a progress bar on, or None."""
    from ..engine import audit as auditing  # imported before forking: workers inherit it
    from ..io import loader  # noqa: F401  (imported before forking: workers inherit them)
    from ..report import records  # noqa: F401
    from ..report.run import Run
    from . import collector, workers

    run = Run()
    if not files:
        return run
    if min(options.jobs, len(files)) > 1:  # the ball machinery once, not in every worker
        from ..engine.bounds import envelope  # noqa: F401  (one task loads it only if it needs it)
    work = functools.partial(_check_in_worker, options)
    if options.format == "html" and options.sheets:  # drawn in the workers: imported once
        with contextlib.suppress(Exception):  # a broken matplotlib: each task's note says so
            from ..render import sheet  # noqa: F401
    stages = (LOADING, *auditing.STAGES, REPORTING, SHEET)
    collector.release(freeze=True)  # the start-up is over (``collector``)
    with workers.Workers(work, min(options.jobs, len(files)), stages) as pool:
        results = pool.run(files, options.budget)
        _collect(run, _outcomes(results, options), len(files), progress)
    return run


def _outcomes(
    results: Iterable[tuple[str, workers.Result[Outcome]]], options: CheckOptions
) -> Iterator[Outcome]:
    """Each task's outcome: its own, or a budget error (stopped at its budget), or an
    internal error (its worker died)."""
    from ..report.records import budget_error, internal_error
    from ..report.run import BUDGET, INTERNAL
    from . import workers

    for path, result in results:
        if isinstance(result, workers.Done):
            yield result.value
        elif isinstance(result, workers.OverBudget):
            assert options.budget is not None
            error = budget_error(path, options.budget, result.stage)
            yield BUDGET, error, result.seconds, None
        else:
            died = RuntimeError(
                f"the worker process auditing it died (exit code {result.exitcode})"
            )
            yield INTERNAL, internal_error(died, path), result.seconds, None


def _collect(run: Run, results: Iterable[Outcome], total: int, progress: Any) -> None:
    """Add each outcome to ``run`` as it comes, advancing a progress bar on ``progress``
    (a rich Console) when one is given."""
    if progress is None:
        for result in results:
            run.add(*result)
        return
    from rich.progress import Progress

    with Progress(console=progress, transient=True) as bar:
        job = bar.add_task("checking", total=total)
        for result in results:
            run.add(*result)
            bar.advance(job)


def want_progress(n_tasks: int, stream: Any, quiet: bool) -> bool:
    """A progress bar only on a terminal, for more than a handful of tasks, unless -q."""
    return is_tty(stream) and n_tasks > PROGRESS_MIN_TASKS and not quiet


def write_report(run: Run, options: CheckOptions, out: TextIO) -> None:
    """Render ``run`` on ``out`` in ``options.format`` (``--statistics``: the counts per
    rule, as JSON for ``json``, else as text)."""
    if options.statistics:
        from ..render.statistics import render as statistics

        text = statistics(run, as_json=options.format == "json")
    elif options.format == "text":
        _write_text(run, options, out)
        return
    elif options.format == "concise":
        from ..render.concise import render as concise

        text = concise(run, quiet=options.quiet)
    elif options.format == "json":
        from ..render.json import render as json_report

        text = json_report(run, quiet=options.quiet)
    elif options.format == "junit":
        from ..render.junit import render as junit

        text = junit(run)
        if not utf8(out):  # the document says UTF-8: keep it true on any stream
            text = text.encode("ascii", "xmlcharrefreplace").decode("ascii")
    elif options.format == "sarif":
        from ..render.sarif import render as sarif

        text = sarif(run)
    elif options.format == "gitlab":
        from ..render.gitlab import render as gitlab

        text = gitlab(run)
    elif options.format == "html":
        from ..render.html import render as html

        text = html(run, quiet=options.quiet)
        if not utf8(out):  # the page says UTF-8: keep it true on any stream
            text = text.encode("ascii", "xmlcharrefreplace").decode("ascii")
    else:
        from ..render.github import render as github

        text = github(run, quiet=options.quiet)
    out.write(text)
    out.flush()


def _write_text(run: Run, options: CheckOptions, out: TextIO) -> None:
    from ..render.text import render

    color = options.color
    # colour in a file only when asked for (--color always), never from the environment
    colored = color == "always" if options.output_file else color_enabled(color, out)
    err = make_console(Lossy(sys.stderr), color_enabled(color, sys.stderr))
    # bad task files: on stderr, and in the report too when it goes to a file
    render(
        run,
        make_console(out, colored),
        err,
        quiet=options.quiet,
        errors_inline=bool(options.output_file),
        layout=options.layout,
    )


def _log(run: Run, options: CheckOptions) -> None:
    """What standard error says after the report: the one-line errors (when the report is
    not the text on the terminal), the tracebacks of bugs (RPRPR_DEBUG), and a summary
    line when the report went to a file."""
    if options.format != "text" or options.output_file:  # the one-line errors, for the log
        for e in run.input_errors + run.internal_errors + run.budget_errors:
            for line in e.get("errors", [e]):  # a bad task file: each of its errors
                say(line["text"])
    if os.environ.get("RPRPR_DEBUG"):  # the tracebacks of bugs met in a task, for a report
        for e in run.internal_errors:
            say(e["traceback"], keep="\n")
    if options.output_file and not options.quiet:  # the log still says what the file holds
        s = run.summary()
        say(
            f"rprpr: {s['tasks']} task{'s' if s['tasks'] != 1 else ''}: {s['passed']} passed,"
            f" {s['failed']} failed, {s['errors']} error{'s' if s['errors'] != 1 else ''};"
            f" {options.format} report written to {options.output_file}"
        )


def _cpus() -> int:
    """The CPUs this process may run on (``-j 0``)."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1

"""Shared test helpers: the repository's paths, task files written from text, ``rprpr``
run in this process, a plain terminal for every test, and hypothesis's profiles."""

from __future__ import annotations

import gc
import io
import json
import math
import os
import sys
import warnings
from collections.abc import Iterator
from contextlib import contextmanager, redirect_stderr, redirect_stdout
from dataclasses import replace
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = ROOT / "configs"

# -- byte code: cached even where the environment says not to (PYTHONDONTWRITEBYTECODE) ----
# The suite starts many Python processes (xdist's workers, rprpr as a real process where
# the process is what a test is about); without caches each compiles rprpr, and pytest
# rewrites every test module, again (collection alone: ~7 CPU-s a process against ~3.5).
# The caches go to __pycache__ folders, which git ignores. hypothesis is imported after
# the switch: pytest rewrites the asserts of its ~75 modules (a pytest plugin's package),
# and without the cache it rewrites them again in every process (~1 CPU-s each).
sys.dont_write_bytecode = False
os.environ.pop("PYTHONDONTWRITEBYTECODE", None)

from hypothesis import settings  # noqa: E402 (after the byte-code switch above)

# -- the garbage collector: young collections less often, full ones rarely ---------------
# A test process holds ~1 M objects that live to its end (matplotlib, sympy, hypothesis,
# the shared audits and sheets), and Python's defaults (700, 10, 10) ran a full
# collection, which walks them all, every few hundred thousand new objects: ~10 % of the
# suite's CPU time. With a young generation of 10,000 objects, fewer short-lived ones
# reach the old generations, and a full collection waits for 100 middle ones (and, as
# always, for the old generation to have grown by a quarter): the collector's share falls
# to ~3 % for ~5 % more memory. Only when collections run changes, not what they collect
# (gc.freeze, which left the shared objects out of every collection, made two
# derandomized properties fail as "Unreliable assumption" under hypothesis 6.100; this
# does not, .ci/lowest.txt). Collections that tests ask for (gc.collect) run as before.
gc.set_threshold(10_000, 10, 100)

# -- hypothesis: random locally, derandomized in CI ---------------------------------------
# CI (which sets CI=true) draws the same examples on every run and keeps no example database,
# so a red build is never luck; developers keep hypothesis's random search and its database.
# Neither has a deadline: an example's wall time says how busy the machine is, not whether
# rprpr is right (a bound on work is asserted in CPU seconds where it matters).
# Choose one by hand with --hypothesis-profile=ci (or dev).
settings.register_profile("ci", derandomize=True, database=None, print_blob=True, deadline=None)
settings.register_profile("dev", deadline=None)
settings.load_profile("ci" if os.environ.get("CI") else "dev")
# CI draws the same examples on every run: it re-checks a fixed set, and developers' random
# runs do the exploring. There each property runs CI_SHARE of the examples its test asks
# for, at least CI_MIN_EXAMPLES (``pytest_collection_modifyitems``); a developer's run
# (and --hypothesis-profile=dev) runs them all.
CI_SHARE, CI_MIN_EXAMPLES = 0.5, 25


def _fewer_examples_under_ci(items: list[pytest.Item]) -> None:
    """Each hypothesis test's examples cut to CI_SHARE under the derandomized CI profile."""
    if not settings.default.derandomize:
        return
    for item in items:
        test = getattr(item, "obj", None)
        own = getattr(test, "_hypothesis_internal_use_settings", None)
        if own is None or getattr(test, "_rprpr_ci_examples", False):
            continue
        n = own.max_examples
        fewer = min(n, max(CI_MIN_EXAMPLES, math.ceil(n * CI_SHARE)))
        test._hypothesis_internal_use_settings = settings(own, max_examples=fewer)  # type: ignore[union-attr]
        test._rprpr_ci_examples = True  # type: ignore[union-attr]


# -- task files ------------------------------------------------------------------------------
LINKS_ALIKE = """\
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
"""
QUINTIC = "timing:\n  duration: 5\n  law: quintic\n"  # the paper's quintic timing, t_f = 5 s
# the paper's paths (eqs. 50 and 51) as the YAML of a task's path block: y, from, to
PATH1_YAML = "x^3 - 9*x^2 + 27*x - 27\n  from: [2, -1]\n  to: [4, 1]"
PATH2_YAML = "0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2\n  from: [2, -1]\n  to: [4, 1]"
PATH1_FILE = str(CONFIGS / "paper_path1.rprpr.yaml")  # the shipped task files of the two paths
PATH2_FILE = str(CONFIGS / "paper_path2.rprpr.yaml")
FAST = ["--samples", "101"]  # enough samples for tests that do not look at the torques


def task_text(
    y: str, timing: str, *, a1: str = "6", links: str = LINKS_ALIKE, extra: str = ""
) -> str:
    """A task file's text with the given path, timing block and links."""
    return f"name: test\nrobot:\n  a1: {a1}\n{links}path:\n  y: {y}\n{timing}{extra}"


BAD_A1 = task_text(PATH2_YAML, QUINTIC, a1="-1")  # robot.a1 on line 3, column 7
# two first-order crossings a microsecond apart: t = 1 and t = 1.000001 (x = 3, x = 3.000001)
CLOSE_INSTANTS = task_text("(x-3)*(x-3.000001)", "timing:\n  duration: 2\n  x: 2 + t\n")


@pytest.fixture
def write_task(tmp_path: Path):  # type: ignore[no-untyped-def]
    """Write a task file and return its path."""
    count = [0]

    def write(text: str, name: str | None = None) -> Path:
        count[0] += 1
        p = tmp_path / (name or f"task{count[0]}.yaml")
        p.write_text(text, encoding="utf-8")
        return p

    return write


# -- the command line, in this process ---------------------------------------------------
# Variables of the runner's own terminal that change what rprpr prints (colour, width,
# tracebacks). pytest-xdist's workers, for one, set COLUMNS=80.
TERMINAL_VARIABLES = (
    "NO_COLOR", "FORCE_COLOR", "COLUMNS", "TTY_COMPATIBLE", "TTY_INTERACTIVE", "RPRPR_DEBUG",
)  # fmt: skip


@contextmanager
def _plain_terminal() -> Iterator[None]:
    """Every test sees the same terminal: none of the runner's TERMINAL_VARIABLES, so that
    rprpr writes without colour, at its default width, whoever runs the tests and how.
    Those it removed are put back after the test (as ``monkeypatch.delenv`` would: after
    the test's own fixtures have undone theirs)."""
    environ = os.environ
    removed = {name: environ.pop(name) for name in TERMINAL_VARIABLES if name in environ}
    try:
        yield
    finally:
        environ.update(removed)


@contextmanager
def plain_terminal(**variables: str) -> Iterator[None]:
    """Outside pytest: os.environ without TERMINAL_VARIABLES, plus ``variables``; restored
    on exit."""
    saved = dict(os.environ)
    for name in TERMINAL_VARIABLES:
        os.environ.pop(name, None)
    os.environ.update(variables)
    try:
        yield
    finally:
        os.environ.clear()
        os.environ.update(saved)


def _stream(encoding: str = "utf-8", errors: str = "strict") -> io.TextIOWrapper:
    """A text stream like a pipe's: UTF-8 (or ``encoding``), with a binary buffer, not a
    terminal."""
    return io.TextIOWrapper(
        io.BytesIO(), encoding=encoding, errors=errors, newline="", write_through=True
    )


def _text(stream: io.TextIOWrapper) -> str:
    buffer = stream.buffer
    assert isinstance(buffer, io.BytesIO)
    return buffer.getvalue().decode("utf-8")


def exit_status(exc: SystemExit) -> int:
    """The status a process exits with after ``exc`` (None is 0; a message is 1)."""
    if exc.code is None:
        return 0
    return exc.code if isinstance(exc.code, int) else 1


def run_cli(*args: str) -> tuple[int, str, str]:
    """``rprpr ARGS`` in this process: (exit status, stdout, stderr).

    Standard output and error are pipes here (not terminals), so the text report has no
    colour and is as wide as COLUMNS says (160 when unset)."""
    from rprpr.cli.main import main

    out, err = _stream(), _stream()
    with redirect_stdout(out), redirect_stderr(err), pytest.raises(SystemExit) as e:
        main(list(args))
    return exit_status(e.value), _text(out), _text(err)


def run_cli_encoded(encoding: str, *args: str) -> tuple[int, bytes, bytes]:
    """``rprpr ARGS`` in this process with standard streams in ``encoding``, as Python
    makes them for PYTHONIOENCODING=ENCODING (output strict, error backslashreplace):
    (exit status, stdout bytes, stderr bytes)."""
    from rprpr.cli.main import main

    out, err = _stream(encoding), _stream(encoding, "backslashreplace")
    with redirect_stdout(out), redirect_stderr(err), pytest.raises(SystemExit) as e:
        main(list(args))
    return (
        exit_status(e.value),
        _bytes(out),
        _bytes(err),
    )


def stdout_on(fd: int) -> io.TextIOWrapper:
    """The standard output Python makes for the descriptor ``fd`` (a file, a device, a
    pipe; not a terminal): UTF-8, strict, block-buffered. The stream owns ``fd``."""
    return io.TextIOWrapper(io.BufferedWriter(io.FileIO(fd, "w")), encoding="utf-8")


def run_cli_to(stdout: io.TextIOWrapper | None, *args: str) -> tuple[int, str]:
    """``rprpr ARGS`` in this process writing to ``stdout`` (from ``stdout_on``; None: as
    Python starts with its standard output closed): (exit status, stderr). The stream is
    then flushed and closed as the interpreter does at exit, and a failure there is what
    the interpreter would show: status 120 and a line on standard error."""
    from rprpr.cli.main import main

    err = _stream()
    with redirect_stdout(stdout), redirect_stderr(err), pytest.raises(SystemExit) as e:  # type: ignore[arg-type]
        main(list(args))
    code = exit_status(e.value)
    if stdout is not None:
        try:
            stdout.close()
        except OSError as exc:
            code = 120
            err.write(f"Exception ignored on flushing sys.stdout: {exc!r}\n")
    return code, _text(err)


def _bytes(stream: io.TextIOWrapper) -> bytes:
    buffer = stream.buffer
    assert isinstance(buffer, io.BytesIO)
    return buffer.getvalue()


# -- check's worker, in this process ------------------------------------------------------
# ``rprpr check`` audits in worker processes, forked from the process that runs it. Forking
# a test process (every test module's imports and caches: 200-500 MB) costs 30-60 ms of
# CPU, against a few ms for a small audit, and the suite runs ~600 checks. So a check with
# one worker and the default budget hands its tasks to ``InProcessWorker``: the same work
# function, the task and its outcome pickled both ways as between rprpr and a forked
# worker, a worker's death (an exception out of the work) reported as one. Checks with
# -j N, a budget of their own, or spawned workers start real workers, as do the tests marked
# ``real_workers`` (signals, pids, the workers themselves) and a run with RPRPR_REAL_WORKERS=1.


class InProcessWorker:
    """``rprpr.cli.workers.Workers`` for one worker that is this process (see above)."""

    def __init__(self, work: Any, stages: Any) -> None:
        self.work, self.stages = work, tuple(stages)

    def __enter__(self) -> InProcessWorker:
        return self

    def __exit__(self, *exc: object) -> None:
        return None

    def run(self, tasks: Any, budget: float | None) -> Iterator[tuple[Any, Any]]:
        import pickle
        import time

        from rprpr.cli import workers

        def on_stage(name: str) -> None:
            self.stages.index(name)  # a stage the worker knows, as its shared byte says

        for task in tasks:
            start = time.monotonic()
            sent = pickle.loads(pickle.dumps(task, pickle.HIGHEST_PROTOCOL))
            try:
                value = self.work(sent, on_stage)
                answer = pickle.dumps(value, pickle.HIGHEST_PROTOCOL)
            except Exception:  # a forked worker prints its traceback and exits 1
                yield task, workers.Died(time.monotonic() - start, 1)
                continue
            yield task, workers.Done(pickle.loads(answer))


def _workers_in_process(real: Any) -> Any:
    """``Workers`` as ``rprpr.cli.workers`` has it, but a check with one forked worker and
    the default budget (read from its work's options) gets an ``InProcessWorker``."""
    from rprpr.cli.config import DEFAULT_BUDGET
    from rprpr.cli.workers import FORK

    def workers(work: Any, jobs: int, stages: Any, **kwargs: Any) -> Any:
        options = getattr(work, "args", (None,))[0]
        budget = getattr(options, "budget", 0.0)
        default = budget is None or (isinstance(budget, int | float) and budget >= DEFAULT_BUDGET)
        if jobs == 1 and kwargs.get("fork", FORK) and default:
            return InProcessWorker(work, stages)
        return real(work, jobs, stages, **kwargs)

    workers.real = real  # type: ignore[attr-defined]  # for a forked rprpr (tests.cli.forked)
    return workers


@contextmanager
def _check_worker_in_process(test: pytest.Item) -> Iterator[None]:
    """The checks of ``test`` audit in this process (``InProcessWorker``) unless it is
    marked ``real_workers`` or RPRPR_REAL_WORKERS=1."""
    real_workers = test.get_closest_marker("real_workers")
    if real_workers or os.environ.get("RPRPR_REAL_WORKERS") == "1":
        yield
        return
    from rprpr.cli import workers

    real = workers.Workers
    workers.Workers = _workers_in_process(real)  # type: ignore[misc]
    try:
        yield
    finally:
        workers.Workers = real  # type: ignore[misc]


@pytest.fixture(autouse=True)
def _every_test(request: pytest.FixtureRequest) -> Iterator[None]:
    """What every test starts from: a plain terminal (``_plain_terminal``) and its checks'
    worker in this process (``_check_worker_in_process``). One fixture, not one each
    plus ``monkeypatch``: pytest's work to set up and tear down a fixture, ~0.05 ms a
    test, counts ~1,600 times in the suite."""
    with _plain_terminal(), _check_worker_in_process(request.node):
        yield


# -- one audit, many renderings ------------------------------------------------------------
# What a run of ``rprpr check`` prints differs by format, width, colour, -q and -o; what it
# audits does not. Tests that print one set of tasks many ways (the golden files, the text
# report at several widths) share one Run per set of tasks, inside ``reused_runs()``.
PRESENTATION = {
    "format": "text", "output_file": None, "quiet": False, "layout": "auto",
    "exit_zero": False, "color": "auto", "statistics": False,
}  # fmt: skip
_RUNS: dict[str, Any] = {}


def _content(path: str) -> bytes | None:
    try:
        return Path(path).read_bytes()
    except OSError:
        return None


_OUTCOMES: dict[str, Any] = {}


@contextmanager
def reused_runs() -> Iterator[None]:
    """``rprpr check`` (``cli.check.run_checks``) audits each set of task files once per
    test process: a run of the same files (by name and content), in the same directory,
    with options that differ only in PRESENTATION takes the Run of the first. Renderers
    only read a Run, so every byte printed is what a fresh audit would print.

    Within a new set, each task file audited in this process (``cli.check.check_one``, as
    ``InProcessWorker`` runs it) is audited once too: a file already audited for another
    set (configs/ after each of its files), by the same name and content, in the same
    directory and with the same options, gives its outcome again; the worker hands it
    over pickled, as a fresh one, and the Run is made from it as from a fresh audit."""
    from rprpr.cli import check

    real, real_one = check.run_checks, check.check_one

    def run_checks(files: Any, options: Any, progress: Any = None) -> Any:
        # the HTML report's run carries more (each task's lines, its sheet): its own key
        html = options.format == "html"
        key = repr(
            (html, os.getcwd(), [(f, _content(f)) for f in files], replace(options, **PRESENTATION))
        )
        if key not in _RUNS:
            _RUNS[key] = real(files, options, progress)
        return _RUNS[key]

    def check_one(path: str, options: Any, on_stage: Any = None) -> Any:
        content = _content(path)
        if content is None:  # standard input, or what is not a file to read: as it comes
            return real_one(path, options, on_stage)
        html = options.format == "html"
        key = repr((html, os.getcwd(), path, content, replace(options, **PRESENTATION)))
        if key not in _OUTCOMES:
            _OUTCOMES[key] = real_one(path, options, on_stage)
        return _OUTCOMES[key]

    check.run_checks, check.check_one = run_checks, check_one
    try:
        yield
    finally:
        check.run_checks, check.check_one = real, real_one


# -- start-up probes: one fresh interpreter for the suite ----------------------------------
@pytest.fixture(scope="session")
def fresh(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[int, str, str]]:
    """Each start-up probe the test modules registered (``tests.cli.forked.fresh_probe``):
    (exit status, standard output, standard error) by name, all from one interpreter."""
    from tests.cli.forked import run_fresh

    return run_fresh(tmp_path_factory.mktemp("fresh"))


# -- one test process per costly shared result ---------------------------------------------
# Helper modules whose results (functools caches) several test modules read: each module
# that imports one runs in the same test process as the others, so the result is computed
# once. tests/sheets.py: each config audited and each sheet drawn (~20 CPU-s in all).
SHARED_HELPERS = {"tests.sheets": "sheets"}


def _group(item: pytest.Item) -> str:
    """The group a test runs in under ``--dist loadgroup``: "fresh" for the readers of the
    start-up probes (``fresh``), else its module's shared helper (SHARED_HELPERS), else its
    module (the module's fixtures, caches and imports: one process pays for them)."""
    if "fresh" in getattr(item, "fixturenames", ()):
        return "fresh"
    module = getattr(item, "module", None)
    for value in vars(module).values() if module is not None else ():
        helper = SHARED_HELPERS.get(getattr(value, "__module__", None) or "")
        if helper is not None:
            return helper
    return item.nodeid.split("::", 1)[0]


# -- the order the groups are handed out in -------------------------------------------------
# pytest-xdist hands the groups out most tests first, so a group of a few costly tests (the
# two engine fuzzers, the workers waiting out their budgets) went out last and left one
# process working alone at the end. Here the costliest groups go first, each group's cost
# the sum of its tests' seconds in TEST_SECONDS (tests/test_seconds.json, written by
# ``pytest -n 2 --write-test-seconds tests/test_seconds.json``; a test it does not know
# counts SECONDS_UNKNOWN). The order decides only which process runs a group and when,
# never what a test does: a stale table costs wall time, not a result.
TEST_SECONDS = Path(__file__).with_name("test_seconds.json")
SECONDS_UNKNOWN = 0.01


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--write-test-seconds",
        metavar="PATH",
        help="write each test's seconds (setup, call and teardown) to PATH as JSON: the "
        "order groups are handed out in under --dist loadgroup (tests/conftest.py)",
    )


def _test_key(nodeid: str) -> str:
    """A test's key in TEST_SECONDS: its id without the group (cut as pytest-xdist cuts
    it: at the last ``@`` after the parameters) and without this clone's path."""
    if nodeid.rfind("@") > nodeid.rfind("]"):
        nodeid = nodeid[: nodeid.rfind("@")]
    return nodeid.replace(f"{ROOT}{os.sep}", "")


def _cost(nodeids: Any, table: dict[str, float]) -> float:
    return sum(table.get(_test_key(t), SECONDS_UNKNOWN) for t in nodeids)


@pytest.hookimpl(optionalhook=True)  # a run without pytest-xdist (-p no:xdist) knows no such hook
def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> Any:
    if config.getvalue("dist") != "loadgroup":
        return None
    from xdist.scheduler import LoadGroupScheduling

    table = json.loads(TEST_SECONDS.read_text()) if TEST_SECONDS.exists() else {}

    class CostliestFirst(LoadGroupScheduling):
        ordered = False

        def _assign_work_unit(self, node: Any) -> None:
            if not self.ordered:  # the first hand-out: the queue holds every group
                self.ordered = True
                units = sorted(self.workqueue.items(), key=lambda unit: -_cost(unit[1], table))
                self.workqueue.clear()
                self.workqueue.update(units)
            super()._assign_work_unit(node)

    return CostliestFirst(config, log)


class _TestSeconds:
    """Each test's seconds (setup, call and teardown), written to ``path`` at the end:
    registered by ``pytest_configure`` only when --write-test-seconds asks, in the
    process that receives every report (xdist's controller, or the one of -n 0)."""

    def __init__(self, path: str) -> None:
        self.path, self.seconds = Path(path), dict[str, float]()

    def pytest_runtest_logreport(self, report: pytest.TestReport) -> None:
        key = _test_key(report.nodeid)
        self.seconds[key] = self.seconds.get(key, 0.0) + report.duration

    def pytest_sessionfinish(self) -> None:
        kept = {k: round(v, 2) for k, v in sorted(self.seconds.items()) if v >= 0.02}
        self.path.write_text(json.dumps(kept, indent=0) + "\n")


def pytest_configure(config: pytest.Config) -> None:
    path = config.getoption("write_test_seconds")
    if path and not hasattr(config, "workerinput"):
        config.pluginmanager.register(_TestSeconds(path), "rprpr-test-seconds")
    if getattr(config.option, "numprocesses", None) and not hasattr(config, "workerinput"):
        _unicode_tables_before_the_workers()


def _unicode_tables_before_the_workers() -> None:
    """hypothesis's tables of the Unicode categories and of the characters UTF-8 encodes
    (what its text strategies draw from: ~1.4 CPU-s to build) are built by the first
    process that draws text and kept in .hypothesis/ (which git ignores). In a fresh clone
    every test process of a ``-n N`` run would build them; the process that starts the
    workers builds them first, and the workers read them (where they are kept already,
    this reads them: a few milliseconds). Only where they are kept changes, never what
    hypothesis draws; a hypothesis without these internals builds them as it always did."""
    try:
        from hypothesis.internal.charmap import charmap, intervals_from_codec

        with warnings.catch_warnings():  # some versions warn of a storage read while pytest
            warnings.simplefilter("ignore")  # starts (slow plugins): here it is the point
            charmap()
            intervals_from_codec("utf-8")
    except Exception:  # internals of hypothesis: another version may have others
        return


@pytest.hookimpl(tryfirst=True)
def pytest_unconfigure(config: pytest.Config) -> None:
    """Before pytest's own end-of-run collections (which report what finalizers raised):
    one full collection here, which frees every cycle left (one pass on CPython) and so
    reports the same, then the survivors frozen, so pytest's collections walk only what
    is made after them instead of the ~1 M objects a test process holds (~0.5 CPU-s each),
    and so do the several full collections of Python's finalization at the process's
    exit (~2-3 CPU-s a test process; it frees its memory as it ends anyway).
    A cycle that another plugin's end-of-run hook releases after this one is frozen with
    the rest, so an error in its finalizer goes unreported: no plugin of the suite's
    releases one (the tests' own cycles are freed here)."""
    gc.collect()
    gc.freeze()


@pytest.hookimpl(trylast=True)
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under ``--dist loadgroup`` (pyproject.toml) every test of a group runs in one test
    process, so that what its tests share is computed once, not once per process: each
    test is marked ``xdist_group(GROUP)`` (``_group``) unless it names its own group.
    The groups are handed out costliest first (``pytest_xdist_make_scheduler``).
    pytest-xdist schedules by a ``@GROUP`` suffix on the test's id,
    which its worker writes to ``item._nodeid`` before this hook has marked the test, and
    pytest 9.2 keeps the id in ``item._id``: the suffix is written here when it is missing
    (on any other layout the tests spread like the others: slower, never wrong)."""
    _fewer_examples_under_ci(items)
    if not getattr(config.option, "loadgroup", False):
        return
    for item in items:
        if not item.get_closest_marker("xdist_group"):
            item.add_marker(pytest.mark.xdist_group(_group(item)))
        names = sorted({str(m.args[0] if m.args else m.kwargs.get("name", "default"))
                        for m in item.iter_markers("xdist_group")})  # fmt: skip
        if not names or "@" in item.nodeid:
            continue
        node_id, suffixed = getattr(item, "_id", None), f"{item.nodeid}@{'_'.join(names)}"
        if hasattr(node_id, "parse"):  # pytest 9.2
            item._id = node_id.parse(suffixed)  # type: ignore[attr-defined]
        elif isinstance(getattr(item, "_nodeid", None), str):  # pytest 8
            item._nodeid = suffixed

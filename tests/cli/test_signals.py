"""Signals: SIGINT, SIGTERM and SIGHUP stop ``check -j 2``, ``check``, ``plot`` and
``export`` at once, whatever they are doing (the slow step below would take two minutes;
a hang guard of 30 s fails the test, which never asserts on elapsed time); no worker
process outlives rprpr, no temporary file is left, the previous ``-o`` output is intact,
and rprpr dies of the signal (``report/exit.py``: a shell sees 128 + N, ``subprocess`` -N).

Each run is a real process. A driver (``DRIVER``) makes one step slow on purpose, so
that the signal lands mid-batch or mid-write every time: the audit in a worker blocks
every catchable signal and sleeps (a computation in C, deaf to all but SIGKILL), or the
writer of the sheet or the samples sleeps after writing half its file. The slow step
says ``READY <pid>`` on standard error when it is reached; the test then sends the signal.

The driver runs in a process forked from the test process and set up as a fresh one
(``tests/cli/forked.py``: its own session, signal handlers and exit status, without the
start-up of an interpreter importing rprpr again); two tests start a real interpreter
(``python -c DRIVER``): SIGKILL of ``check -j 2`` and a SIGINT ignored from the start.
"""

from __future__ import annotations

import importlib
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from tests.cli.forked import Forked
from tests.conftest import CONFIGS

pytestmark = [
    pytest.mark.skipif(
        not Path("/proc/self/stat").exists() or not hasattr(signal, "SIGKILL"),
        reason="POSIX signals and /proc",
    ),
    pytest.mark.real_workers,  # the forked rprpr forks its workers, as rprpr does
]

DRIVER = """
import os, signal, sys, time

mode, argv = sys.argv[1], sys.argv[2:]

# rprpr as started from a terminal: a test run under nohup (SIGHUP ignored, which rprpr
# keeps ignored on purpose) must not turn the SIGHUP cases into hangs
signal.signal(signal.SIGHUP, signal.SIG_DFL)

def ready():
    os.write(2, f"READY {os.getpid()}\\n".encode())

def deaf_audit(*args, **kwargs):  # a long computation in C: only SIGKILL ends it
    signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM, signal.SIGHUP})
    ready()
    time.sleep(120)

def slow_audit(*args, **kwargs):  # a long computation in Python
    ready()
    time.sleep(120)

def stubborn(*args, **kwargs):  # swallows the first interruption
    for _ in range(2):
        try:
            ready()
            time.sleep(120)
        except BaseException:
            pass

def half_written(path):
    with open(path, "w") as f:
        f.write("half of it")
    ready()
    time.sleep(120)

# each mode imports only the module it patches: a check never loads matplotlib
if mode in ("deaf", "slow"):
    import rprpr.engine.audit
    rprpr.engine.audit.audit = {"deaf": deaf_audit, "slow": slow_audit}[mode]
elif mode == "stubborn":  # rprpr itself, not a worker, stuck as it takes in a report
    import rprpr.report.run
    rprpr.report.run.Run.add = stubborn
elif mode == "sheet":
    import rprpr.render.sheet
    rprpr.render.sheet.save = lambda fig, path, *a, **k: half_written(path)
elif mode == "samples":
    import rprpr.render.export
    rprpr.render.export.write = lambda result, out, *a, **k: half_written(out.name)

from rprpr.cli.main import main
main(argv)
"""

PREVIOUS = "the previous output, kept\n"
# The slow steps outlast the default work budget (10 s of wall time): only the signal may
# end them, however long a busy machine takes to deliver it.
NO_BUDGET = ("--budget", "0")


def _default_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_DFL)


# what each mode of the driver imports, imported in the test process before it forks
PREIMPORT = {
    "deaf": "rprpr.engine.audit",
    "slow": "rprpr.engine.audit",
    "stubborn": "rprpr.report.run",
    "sheet": "rprpr.render.sheet",
    "samples": "rprpr.render.export",
}


def _driver(mode: str, args: tuple[str, ...]) -> None:
    """The driver, run in the forked child as ``python -c DRIVER MODE ARGS`` runs it."""
    sys.argv = ["-c", mode, *args]
    exec(compile(DRIVER, "<string>", "exec"), {"__name__": "__main__"})


class Rprpr:
    """One rprpr process under the driver, in a session of its own (so that a signal to
    its process group reaches rprpr and its workers only, as Ctrl-C at a terminal does):
    forked from the test process (``Forked``), or a new interpreter when ``fresh``."""

    def __init__(self, mode: str, *args: str, cwd: Path, fresh: bool = False) -> None:
        self.proc: subprocess.Popen[bytes] | Forked
        if fresh:
            self.proc = subprocess.Popen(
                [sys.executable, "-c", DRIVER, mode, *args],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                cwd=cwd,
                start_new_session=True,
                # SIGINT as a terminal's job has it, whatever the test runner inherited (a
                # background job of a script starts with SIGINT ignored, and rprpr keeps it)
                preexec_fn=_default_sigint,
            )
        else:
            importlib.import_module(PREIMPORT[mode])
            importlib.import_module("rprpr.cli.main")
            self.proc = Forked(lambda: _driver(mode, args), cwd=cwd)
        self.ready: list[int] = []

    def wait_ready(self, count: int = 1) -> list[int]:
        """The pids of the slow steps, once ``count`` of them are reached."""
        assert self.proc.stderr is not None
        while len(self.ready) < count:
            line = self.proc.stderr.readline().decode()
            assert line, f"rprpr ended first: {self.proc.wait()}"
            if line.startswith("READY "):
                self.ready.append(int(line.split()[1]))
        return self.ready

    def stop(self, signum: int, *, group: bool = False) -> tuple[int, str]:
        """Send ``signum`` (to the group: as a terminal does); (status, rest of the
        standard error). The slow step sleeps 120 s: an exit within the hang guard's 30 s
        shows that rprpr did not wait for it."""
        if group:
            os.killpg(self.proc.pid, signum)
        else:
            os.kill(self.proc.pid, signum)
        try:
            _, err = self.proc.communicate(timeout=30)
        except (subprocess.TimeoutExpired, TimeoutError):
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.communicate()
            pytest.fail(f"rprpr still running 30 s after {signal.Signals(signum).name}")
        return self.proc.returncode, err.decode()


def alive(pid: int) -> bool:
    """Whether process ``pid`` still runs (a zombie, dead but not yet reaped, does not)."""
    try:
        with open(f"/proc/{pid}/stat", encoding="ascii") as f:
            state = f.read().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return False
    return state != "Z"


def gone(pids: list[int], within: float = 30.0) -> bool:
    """Whether every process of ``pids`` has ended, waiting for it (a hang guard of
    ``within`` seconds, not a measure: the kernel ends them as their parent dies)."""
    deadline = time.monotonic() + within
    while any(alive(p) for p in pids):
        if time.monotonic() > deadline:
            return False
        time.sleep(0.02)
    return True


def temporaries(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp"))


def batch(folder: Path, n: int = 6) -> Path:
    """A folder of ``n`` task files."""
    tasks = folder / "tasks"
    tasks.mkdir()
    for i in range(n):
        shutil.copy(CONFIGS / "paper_path2.rprpr.yaml", tasks / f"t{i}.rprpr.yaml")
    return tasks


STOPS = [
    pytest.param(signal.SIGTERM, False, id="SIGTERM"),
    pytest.param(signal.SIGINT, False, id="SIGINT"),
    pytest.param(signal.SIGINT, True, id="Ctrl-C-to-the-group"),
    pytest.param(signal.SIGHUP, False, id="SIGHUP"),
]


@pytest.mark.parametrize(("signum", "group"), STOPS)
def test_check_j2_stopped_mid_batch_leaves_no_worker_no_temporary_and_the_old_report(
    signum: int, group: bool, tmp_path: Path
) -> None:
    tasks = batch(tmp_path)
    report = tmp_path / "report.json"
    report.write_text(PREVIOUS)
    r = Rprpr("deaf", "check", *NO_BUDGET, "-j", "2", "--format", "json", "-o", str(report),
              str(tasks), cwd=tmp_path)  # fmt: skip
    workers = r.wait_ready(2)  # both workers deep in a task that ignores every signal
    status, err = r.stop(signum, group=group)
    assert status == -signum  # died of the signal: a shell shows 128 + N
    assert err == f"rprpr: interrupted ({signal.Signals(signum).name})\n"
    assert gone(workers), "a worker outlived rprpr"
    assert report.read_text() == PREVIOUS
    assert temporaries(tmp_path) == []


def test_workers_die_with_a_parent_killed_by_sigkill(tmp_path: Path) -> None:
    """SIGKILL cannot be handled: the kernel takes the workers along (PR_SET_PDEATHSIG)."""
    if not sys.platform.startswith("linux"):
        pytest.skip("PR_SET_PDEATHSIG is Linux's")
    r = Rprpr(
        "deaf", "check", *NO_BUDGET, "-j", "2", str(batch(tmp_path)), cwd=tmp_path, fresh=True
    )
    workers = r.wait_ready(2)
    status, _ = r.stop(signal.SIGKILL)
    assert status == -signal.SIGKILL
    assert gone(workers), "a worker outlived its parent"


@pytest.mark.parametrize("signum", [signal.SIGINT, signal.SIGTERM])
def test_check_j1_stopped_while_auditing_keeps_the_previous_report(
    signum: int, tmp_path: Path
) -> None:
    report = tmp_path / "report.xml"
    report.write_text(PREVIOUS)
    r = Rprpr("slow", "check", *NO_BUDGET, "--format", "junit", "-o", str(report),
              str(batch(tmp_path, 2)), cwd=tmp_path)  # fmt: skip
    r.wait_ready()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".report.xml.")] != []
    status, err = r.stop(signum)
    assert (status, err) == (-signum, f"rprpr: interrupted ({signal.Signals(signum).name})\n")
    assert report.read_text() == PREVIOUS
    assert temporaries(tmp_path) == []


def test_a_second_signal_stops_at_once_and_still_cleans_up(tmp_path: Path) -> None:
    """The first interruption is swallowed (as by a computation that will not stop, here
    in rprpr itself: audits run in workers); the second one removes the temporary file
    from the signal handler and dies."""
    report = tmp_path / "report.json"
    report.write_text(PREVIOUS)
    r = Rprpr("stubborn", "check", "--format", "json", "-o", str(report),
              str(CONFIGS / "paper_path2.rprpr.yaml"), cwd=tmp_path)  # fmt: skip
    r.wait_ready()
    os.kill(r.proc.pid, signal.SIGINT)
    r.wait_ready(2)  # it swallowed the first and goes on
    assert temporaries(tmp_path) != []
    status, err = r.stop(signal.SIGTERM)
    assert (status, err) == (-signal.SIGTERM, "rprpr: stopped (SIGTERM)\n")
    assert report.read_text() == PREVIOUS
    assert temporaries(tmp_path) == []


@pytest.mark.parametrize(
    ("mode", "command", "output", "signum"),
    [
        ("sheet", "plot", "sheet.png", signal.SIGTERM),
        ("sheet", "plot", "sheet.svg", signal.SIGINT),
        ("samples", "export", "samples.csv", signal.SIGINT),
        ("samples", "export", "samples.json", signal.SIGTERM),
    ],
)
def test_plot_and_export_stopped_while_writing_leave_no_temporary_file(
    signum: int, mode: str, command: str, output: str, tmp_path: Path
) -> None:
    previous = tmp_path / output
    previous.write_text(PREVIOUS)
    args = [command, str(CONFIGS / "paper_path2.rprpr.yaml"), "-o", output, "--samples", "51"]
    if command == "plot":  # what is drawn does not matter here, only that its writing stops
        args += ["--panels", "delta"]
    r = Rprpr(mode, *args, cwd=tmp_path)
    r.wait_ready()
    [half] = temporaries(tmp_path)  # the half-written temporary file is there ...
    assert half.startswith(f".{output}.")
    status, err = r.stop(signum)
    assert (status, err) == (-signum, f"rprpr: interrupted ({signal.Signals(signum).name})\n")
    assert temporaries(tmp_path) == []  # ... and gone
    assert previous.read_text() == PREVIOUS
    assert sorted(p.name for p in tmp_path.iterdir()) == [output]


def test_an_ignored_sigint_stays_ignored(tmp_path: Path) -> None:
    """A job started with SIGINT ignored (``nohup``, ``cmd &`` in a script) keeps it so:
    rprpr does not make itself interruptible where its caller chose otherwise."""
    r = subprocess.Popen(
        [
            sys.executable,
            "-c",
            DRIVER,
            "slow",
            "check",
            *NO_BUDGET,
            str(CONFIGS / "paper_path2.rprpr.yaml"),
        ],
        stderr=subprocess.PIPE,
        stdout=subprocess.DEVNULL,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),
        start_new_session=True,
    )
    assert r.stderr is not None
    assert r.stderr.readline().startswith(b"READY ")
    # Both signals at once, no sleep between: a pending SIGINT would be delivered before a
    # pending SIGTERM (the lower number first) and end rprpr as "interrupted (SIGINT)"; an
    # ignored one is discarded as it is sent, so SIGTERM is what ends it.
    os.kill(r.pid, signal.SIGINT)
    os.kill(r.pid, signal.SIGTERM)
    _, err = r.communicate(timeout=30)
    assert (r.returncode, err) == (-signal.SIGTERM, b"rprpr: interrupted (SIGTERM)\n")

"""The worker processes of ``check`` (``cli.workers``), on both ways of starting them: forked
(Linux, ``os.fork`` and two pipes) and spawned (multiprocessing, elsewhere): the results
come back in task order, a task over its budget is stopped at its stage, a worker that dies
is reported with its exit code and replaced, and none outlives the ``with`` block."""

from __future__ import annotations

import os
import signal
import sys

import pytest

from rprpr.cli.workers import Died, Done, OverBudget, Workers
from tests.cli.worker_tasks import work

STAGES = ("begun", "sleeping")

needs_fork = pytest.mark.skipif(not hasattr(os, "fork"), reason="os.fork")
WAYS = [pytest.param(True, marks=needs_fork, id="forked"), pytest.param(False, id="spawned")]


@pytest.mark.parametrize("fork", WAYS)
def test_results_in_task_order_whatever_the_workers(fork: bool) -> None:
    with Workers(work, 2, STAGES, fork=fork) as pool:
        got = list(pool.run([3, 1, 2, "big", 5], None))
    assert [t for t, _ in got] == [3, 1, 2, "big", 5]
    assert all(isinstance(r, Done) for _, r in got)
    assert [r.value for t, r in got if t != "big"] == [9, 1, 4, 25]  # type: ignore[union-attr]
    assert got[3][1].value == b"x" * (3 << 20)  # type: ignore[union-attr]


# Spawned, the task over budget waits out 6 s: a budget counts from the task's hand-out,
# so it must hold a fresh interpreter's start-up on a busy machine (the replacements of the
# dead worker and of the stopped one): slow by nature, as is waiting for any clock.
BUDGET_WAYS = [WAYS[0], pytest.param(False, marks=pytest.mark.slow, id="spawned")]


@pytest.mark.parametrize("fork", BUDGET_WAYS)
def test_a_dead_worker_and_a_task_over_budget_are_reported_and_replaced(fork: bool) -> None:
    with Workers(work, 1, STAGES, fork=fork) as pool:
        got = dict(pool.run(["die", 4, "hang", 6], 2.0 if fork else 6.0))
    died, over = got["die"], got["hang"]
    assert isinstance(died, Died) and died.exitcode == -signal.SIGKILL
    assert isinstance(over, OverBudget) and over.stage == "sleeping"
    assert [got[4].value, got[6].value] == [16, 36]  # type: ignore[union-attr]


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc")
@pytest.mark.parametrize("fork", WAYS)
def test_no_worker_outlives_the_block(fork: bool) -> None:
    with Workers(work, 2, STAGES, fork=fork) as pool:
        pids = [r.value for _, r in pool.run(["pid", "pid"], None)]  # type: ignore[union-attr]
    assert pids and all(pid != os.getpid() for pid in pids)
    assert not any(os.path.exists(f"/proc/{pid}") for pid in pids)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="/proc")
@needs_fork
def test_a_forked_worker_holds_no_other_workers_pipes() -> None:
    # were a sibling's ends open in a worker, that sibling's task pipe would never end
    with Workers(work, 3, STAGES, fork=True) as pool:
        mine = {w.pid: {os.readlink(f"/proc/self/fd/{fd}") for fd in w.fds()} for w in pool.workers}  # type: ignore[attr-defined]
        got = list(pool.run(["pipes"] * 3, None))
    held = dict(r.value for _, r in got)  # type: ignore[union-attr]
    assert len(held) == 3  # each worker answered once
    for pid, pipes in held.items():
        others = set().union(*(ends for p, ends in mine.items() if p != pid))
        assert mine[pid] <= set(pipes) and not others & set(pipes), pid


@needs_fork
def test_a_forked_worker_ignores_sigint_dies_on_sigterm_and_holds_no_signal_back() -> None:
    # the stop signals are held back across the fork (so the parent's handler never runs
    # in a worker) and released in both once each has its own handlers
    before = signal.pthread_sigmask(signal.SIG_BLOCK, [])
    with Workers(work, 1, STAGES, fork=True) as pool:
        ((_, r),) = list(pool.run(["signals"], None))
    assert r.value == (signal.SIG_IGN, signal.SIG_DFL, [])  # type: ignore[union-attr]
    assert signal.pthread_sigmask(signal.SIG_BLOCK, []) == before

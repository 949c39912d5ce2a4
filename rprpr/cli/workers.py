"""Worker processes (``check``) that do each task under a work budget and never outlive
rprpr.

``check`` hands its task files, one at a time, to worker processes (``-j N``: N of them,
at least one: rprpr itself never audits), so that it stays responsive whatever a task
does: an audit can be deep in one long call into flint (C), deaf to everything but
SIGKILL. The parent only waits on its workers' pipes (``Workers``, a ``with`` block, and
its ``run``). A task still running when its budget runs out (wall-clock seconds since it
was handed out) is stopped by killing its worker and reported with the stage it had
reached (a worker writes the number of each stage into shared memory as it begins); a
fresh worker takes the dead one's place and the batch goes on. A worker that dies on its
own (a crash in C, the out-of-memory killer) is reported likewise, and replaced. The
results come back in task order, so a report does not depend on N.

A worker holds a copy of standard output, so a worker left behind keeps whoever reads
rprpr's pipe waiting. Hence:

* the workers are killed whenever their block ends, however it ends (a signal turned
  into ``Interrupted``, a bug), and the same kill is registered with ``signals`` for a
  hard stop;
* each worker dies with its parent, whatever kills the parent (SIGKILL too): on Linux
  the kernel sends it SIGKILL (``prctl(PR_SET_PDEATHSIG)``); elsewhere a thread of the
  worker polls its parent's pid (best effort: it needs the worker to be running Python);
* a worker ignores SIGINT (Ctrl-C reaches the whole process group; the parent decides)
  and dies of SIGTERM, never running the parent's handlers.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import signal
import sys
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from typing import Any, Generic, TypeVar

from .signals import STOPPING, killed_on_signal

T = TypeVar("T")
R = TypeVar("R")

OnStage = Callable[[str], None]  # told the name of each stage of a task as it begins
PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
POLL_SECONDS = 0.5  # how often a worker without prctl looks for its parent


@dataclass(frozen=True)
class Done(Generic[R]):
    """The task ran to its end: ``value`` is what ``work`` returned."""

    value: R


@dataclass(frozen=True)
class OverBudget:
    """The task was stopped at its budget, ``seconds`` after it began, during ``stage``."""

    seconds: float
    stage: str


@dataclass(frozen=True)
class Died:
    """The worker doing the task died on its own after ``seconds``: ``exitcode`` as
    multiprocessing gives it (-N: killed by signal N)."""

    seconds: float
    exitcode: int | None


Result = Done[R] | OverBudget | Died


class Workers(Generic[T, R]):
    """``jobs`` worker processes doing ``work(task, on_stage)``, for a ``with`` block: they
    start when it begins (before any thread of the caller's, such as a progress bar's) and
    are killed when it ends, however it ends. ``work`` tells ``on_stage`` the name of each
    stage (one of ``stages``; the first is where every task begins) and must be
    picklable where workers are spawned rather than forked."""

    def __init__(self, work: Callable[[T, OnStage], R], jobs: int, stages: Sequence[str]) -> None:
        self.context = multiprocessing.get_context(
            "fork" if sys.platform.startswith("linux") else "spawn"
        )
        self.work, self.jobs, self.stages = work, max(1, jobs), tuple(stages)
        self.workers: list[_Worker] = []

    def __enter__(self) -> Workers[T, R]:
        self._hard_stop = killed_on_signal(self._kill_now)
        self._hard_stop.__enter__()
        try:
            self.workers = [self._start() for _ in range(self.jobs)]
        except BaseException:
            self.__exit__()
            raise
        return self

    def __exit__(self, *exc: object) -> None:
        for w in self.workers:
            w.kill()
        self.workers = []
        self._hard_stop.__exit__(None, None, None)

    def _kill_now(self) -> None:
        """For a hard stop (``signals``): SIGKILL every worker, from a signal handler."""
        for w in list(self.workers):
            w.kill(reap=False)

    def _start(self) -> _Worker:
        return _Worker(self.context, self.work, self.stages)

    def run(self, tasks: Sequence[T], budget: float | None) -> Iterator[tuple[T, Result[R]]]:
        """(task, result) for each of ``tasks``, in order, each task stopped after
        ``budget`` seconds (None: no limit)."""
        todo = deque(range(len(tasks)))
        results: dict[int, Result[R]] = {}
        given = 0
        while given < len(tasks):
            for w in self.workers:
                if w.index is None and todo:
                    i = todo.popleft()
                    w.hand(i, tasks[i], budget)
            _wait_for(self.workers)
            for n, w in enumerate(self.workers):
                index, result = w.result()
                if result is None:
                    continue
                results[index] = result
                if not isinstance(result, Done):  # the worker is dead: a fresh one
                    self.workers[n] = self._start()
            while given in results:
                yield tasks[given], results.pop(given)
                given += 1


def _wait_for(workers: list[_Worker]) -> None:
    """Until a busy worker answers or dies, or the earliest budget runs out."""
    busy = [w for w in workers if w.index is not None]
    deadlines = [w.deadline for w in busy if w.deadline is not None]
    timeout = max(0.0, min(deadlines) - time.monotonic()) if deadlines else None
    wait([w.conn for w in busy] + [w.process.sentinel for w in busy], timeout)


class _Worker:
    """One worker process, its end of the pipe, the stage number it writes, and the task
    it is doing (``index``, None when idle)."""

    def __init__(self, context: Any, work: Callable[..., Any], stages: Sequence[str]) -> None:
        self.stages = tuple(stages)
        self.stage = context.RawValue("i", 0)
        self.conn, child = context.Pipe()
        self.process = context.Process(
            target=_serve,
            args=(child, self.stage, work, self.stages, os.getpid()),
            daemon=True,
        )
        self.process.start()
        child.close()  # the parent's copy: the pipe then ends when the worker does
        self.index: int | None = None
        self.started = 0.0
        self.deadline: float | None = None

    def hand(self, index: int, task: object, budget: float | None) -> None:
        self.index, self.started = index, time.monotonic()
        self.deadline = None if budget is None else self.started + budget
        with contextlib.suppress(OSError):  # a worker dead while idle: ``result`` finds it
            self.conn.send(task)

    def result(self) -> tuple[int, Result[Any] | None]:
        """(index, result) of the task in hand: Done when the worker answered, Died when
        it died, OverBudget (after killing it) when its time is up; None meanwhile."""
        index = self.index
        if index is None:
            return -1, None
        seconds = time.monotonic() - self.started
        if self.conn.poll():
            try:
                value = self.conn.recv()
            except (EOFError, OSError):
                self.kill()
                return index, Died(seconds, self.process.exitcode)
            self.index = None
            return index, Done(value)
        if not self.process.is_alive():
            self.kill()
            return index, Died(seconds, self.process.exitcode)
        if self.deadline is not None and time.monotonic() >= self.deadline:
            stage = self.stages[self.stage.value]
            self.kill()
            return index, OverBudget(seconds, stage)
        return index, None

    def kill(self, *, reap: bool = True) -> None:
        """SIGKILL the worker (it holds nothing worth saving) and reap it (not from a
        signal handler: ``reap`` False)."""
        with contextlib.suppress(Exception):
            self.process.kill()
        if reap:
            self.process.join()
            self.conn.close()


def _serve(
    conn: Connection, stage: Any, work: Callable[..., Any], stages: Sequence[str], parent: int
) -> None:
    """A worker's life: do each task that comes down the pipe, send back the result."""
    start_worker(parent)
    number = {name: i for i, name in enumerate(stages)}

    def on_stage(name: str) -> None:
        stage.value = number[name]

    while True:
        try:
            task = conn.recv()
        except (EOFError, OSError):  # the parent is gone
            return
        stage.value = 0
        conn.send(work(task, on_stage))


def start_worker(parent: int) -> None:
    """The initializer of a worker: its signals as above, and death with ``parent``."""
    for signum in STOPPING:
        signal.signal(signum, signal.SIG_IGN if signum == signal.SIGINT else signal.SIG_DFL)
    if not _die_with_parent_linux():
        threading.Thread(target=_watch_parent, args=(parent,), daemon=True).start()
    if os.getppid() != parent:  # the parent died before the worker could watch it
        os._exit(1)


def _die_with_parent_linux() -> bool:
    """Have the kernel SIGKILL this process when its parent ends; False where it cannot."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return bool(libc.prctl(PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) == 0)
    except (OSError, AttributeError):
        return False


def _watch_parent(parent: int) -> None:
    """Poll the parent's pid; when the worker has been re-parented, die."""
    while os.getppid() == parent:
        time.sleep(POLL_SECONDS)
    os._exit(1)

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

On Linux a worker is forked (``os.fork``, a pipe each way, a byte of shared memory for
the stage): multiprocessing alone would cost a single ``check`` more start-up than its
audit. Elsewhere workers are spawned by multiprocessing, imported only there.

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
import os
import pickle
import signal
import sys
import threading
import time
from collections import deque
from collections.abc import Callable, Iterator, Sequence
from typing import Any, Generic, TypeVar

from .signals import STOPPING, killed_on_signal

T = TypeVar("T")
R = TypeVar("R")

OnStage = Callable[[str], None]  # told the name of each stage of a task as it begins
PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
POLL_SECONDS = 0.5  # how often a worker without prctl looks for its parent
FORK = sys.platform.startswith("linux")  # elsewhere: multiprocessing's spawn (``_Spawned``)


class Done(Generic[R]):
    """The task ran to its end: ``value`` is what ``work`` returned."""

    __slots__ = ("value",)

    def __init__(self, value: R) -> None:
        self.value = value


class OverBudget:
    """The task was stopped at its budget, ``seconds`` after it began, during ``stage``."""

    __slots__ = ("seconds", "stage")

    def __init__(self, seconds: float, stage: str) -> None:
        self.seconds, self.stage = seconds, stage


class Died:
    """The worker doing the task died on its own after ``seconds``: ``exitcode`` as
    multiprocessing gives it (-N: killed by signal N)."""

    __slots__ = ("exitcode", "seconds")

    def __init__(self, seconds: float, exitcode: int | None) -> None:
        self.seconds, self.exitcode = seconds, exitcode


Result = Done[R] | OverBudget | Died


class Workers(Generic[T, R]):
    """``jobs`` worker processes doing ``work(task, on_stage)``, for a ``with`` block: they
    start when it begins (before any thread of the caller's, such as a progress bar's) and
    are killed when it ends, however it ends. ``work`` tells ``on_stage`` the name of each
    stage (one of ``stages``; the first is where every task begins) and must be
    picklable where workers are spawned rather than forked (``fork``: on Linux, with
    ``os.fork`` and two pipes, without multiprocessing's start-up cost)."""

    def __init__(
        self,
        work: Callable[[T, OnStage], R],
        jobs: int,
        stages: Sequence[str],
        *,
        fork: bool = FORK,
    ) -> None:
        self.fork = fork
        self.work, self.jobs, self.stages = work, max(1, jobs), tuple(stages)
        self.workers: list[_Worker] = []

    def __enter__(self) -> Workers[T, R]:
        self._hard_stop = killed_on_signal(self._kill_now)
        self._hard_stop.__enter__()
        try:
            self.workers = []
            for _ in range(self.jobs):  # one by one: each closes the earlier ones' pipes
                self.workers.append(self._start())
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
        if self.fork:
            others = [fd for w in self.workers if isinstance(w, _Forked) for fd in w.fds()]
            return _Forked(self.work, self.stages, others)
        return _Spawned(self.work, self.stages)

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
    forked = [w for w in busy if isinstance(w, _Forked)]
    if len(forked) == len(busy):
        import select

        poll = select.poll()
        for w in forked:  # readable: an answer, or the end of the pipe (the worker died)
            poll.register(w.answers, select.POLLIN)
        poll.poll(None if timeout is None else timeout * 1000)
        return
    from multiprocessing.connection import wait

    wait([o for w in busy for o in w.waitables()], timeout)


class _Worker:
    """One worker process and the task it is doing (``index``, None when idle): its
    subclasses say how it is started, spoken to and stopped."""

    stages: tuple[str, ...]
    index: int | None = None
    started = 0.0
    deadline: float | None = None

    def hand(self, index: int, task: object, budget: float | None) -> None:
        self.index, self.started = index, time.monotonic()
        self.deadline = None if budget is None else self.started + budget
        with contextlib.suppress(OSError):  # a worker dead while idle: ``result`` finds it
            self.send(task)

    def result(self) -> tuple[int, Result[Any] | None]:
        """(index, result) of the task in hand: Done when the worker answered, Died when
        it died, OverBudget (after killing it) when its time is up; None meanwhile."""
        index = self.index
        if index is None:
            return -1, None
        seconds = time.monotonic() - self.started
        if self.answered():
            try:
                value = self.receive()
            except (EOFError, OSError):
                self.kill()
                return index, Died(seconds, self.exitcode())
            self.index = None
            return index, Done(value)
        if not self.alive():
            self.kill()
            return index, Died(seconds, self.exitcode())
        if self.deadline is not None and time.monotonic() >= self.deadline:
            stage = self.stages[self.stage_number()]
            self.kill()
            return index, OverBudget(seconds, stage)
        return index, None

    # what each kind of worker provides
    def send(self, task: object) -> None:
        raise NotImplementedError

    def answered(self) -> bool:
        """Whether the worker's pipe has something to read (an answer, or its end)."""
        raise NotImplementedError

    def receive(self) -> Any:
        """The answer (EOFError when the worker died instead)."""
        raise NotImplementedError

    def alive(self) -> bool:
        raise NotImplementedError

    def exitcode(self) -> int | None:
        """As multiprocessing says it: the exit status, -N when killed by signal N."""
        raise NotImplementedError

    def stage_number(self) -> int:
        raise NotImplementedError

    def waitables(self) -> list[Any]:
        """What ``multiprocessing.connection.wait`` waits on for this worker."""
        raise NotImplementedError

    def kill(self, *, reap: bool = True) -> None:
        """SIGKILL the worker (it holds nothing worth saving) and reap it (not from a
        signal handler: ``reap`` False)."""
        raise NotImplementedError


class _Forked(_Worker):
    """A worker made by ``os.fork``: tasks go down one pipe and answers come up another,
    each a pickle after its 8-byte length; the stage number is a byte of shared memory.
    ``others``: the parent's ends of the other workers' pipes, closed in this one."""

    def __init__(self, work: Callable[..., Any], stages: Sequence[str], others: list[int]) -> None:
        import mmap

        self.stages = tuple(stages)
        self.stage = mmap.mmap(-1, 1)  # anonymous and shared: the worker writes, we read
        tasks_r, tasks_w = os.pipe()
        answers_r, answers_w = os.pipe()
        for stream in (sys.stdout, sys.stderr):  # nothing buffered is written twice
            with contextlib.suppress(Exception):
                stream.flush()
        parent = os.getpid()
        # a stop signal between the fork and the worker's own handlers would run the
        # parent's handler in the worker: held back until each side has its own
        held = signal.pthread_sigmask(signal.SIG_BLOCK, STOPPING)
        pid = os.fork()
        if pid == 0:  # the worker: it never returns into the caller's code
            code = 1
            try:
                start_worker(parent)  # its own handlers, then the signals held back
                signal.pthread_sigmask(signal.SIG_SETMASK, held)
                for fd in (tasks_w, answers_r, *others):
                    os.close(fd)
                _quiet_stdin()
                _serve_pipes(tasks_r, answers_w, self.stage, work, self.stages)
                code = 0
            except BaseException:
                with contextlib.suppress(BaseException):
                    import traceback

                    traceback.print_exc()
            finally:
                os._exit(code)
        signal.pthread_sigmask(signal.SIG_SETMASK, held)
        os.close(tasks_r)  # the worker's ends: the pipes then end when the worker does
        os.close(answers_w)
        self.pid, self.tasks, self.answers = pid, tasks_w, answers_r
        self.status: int | None = None  # the exit code, once reaped
        self.closed = False

    def fds(self) -> tuple[int, ...]:
        """The parent's ends of the pipes, while open."""
        return () if self.closed else (self.tasks, self.answers)

    def send(self, task: object) -> None:
        _write_message(self.tasks, task)

    def answered(self) -> bool:
        import select

        poll = select.poll()
        poll.register(self.answers, select.POLLIN)
        return bool(poll.poll(0))

    def receive(self) -> Any:
        return _read_message(self.answers)

    def _reap(self, block: bool) -> None:
        if self.status is None:
            with contextlib.suppress(ChildProcessError):
                pid, status = os.waitpid(self.pid, 0 if block else os.WNOHANG)
                if pid:
                    self.status = os.waitstatus_to_exitcode(status)

    def alive(self) -> bool:
        self._reap(block=False)
        return self.status is None

    def exitcode(self) -> int | None:
        self._reap(block=False)
        return self.status

    def stage_number(self) -> int:
        return self.stage[0]

    def kill(self, *, reap: bool = True) -> None:
        if self.status is None:
            with contextlib.suppress(OSError):
                os.kill(self.pid, signal.SIGKILL)
        if reap:
            self._reap(block=True)
            for fd in self.fds():
                with contextlib.suppress(OSError):
                    os.close(fd)
            self.closed = True


def _quiet_stdin() -> None:
    """A worker reads nothing: its standard input is the null device (as multiprocessing
    does; ``check -`` has read standard input before any worker starts)."""
    with contextlib.suppress(Exception):
        sys.stdin.close()
        sys.stdin = open(os.devnull, encoding="utf-8")  # noqa: SIM115


def _write_message(fd: int, obj: object) -> None:
    data = pickle.dumps(obj, pickle.HIGHEST_PROTOCOL)
    view = memoryview(len(data).to_bytes(8, "big") + data)
    while view:
        view = view[os.write(fd, view) :]


def _read_exactly(fd: int, n: int) -> bytes:
    chunks = []
    while n:
        chunk = os.read(fd, min(n, 1 << 20))
        if not chunk:
            raise EOFError
        chunks.append(chunk)
        n -= len(chunk)
    return b"".join(chunks)


def _read_message(fd: int) -> Any:
    size = int.from_bytes(_read_exactly(fd, 8), "big")
    return pickle.loads(_read_exactly(fd, size))


def _serve_pipes(
    tasks: int, answers: int, stage: Any, work: Callable[..., Any], stages: Sequence[str]
) -> None:  # fmt: skip
    """A forked worker's life (started by ``start_worker``): do each task that comes down
    the pipe, send back the result."""
    number = {name: i for i, name in enumerate(stages)}

    def on_stage(name: str) -> None:
        stage[0] = number[name]

    while True:
        try:
            task = _read_message(tasks)
        except (EOFError, OSError):  # the parent is gone
            return
        stage[0] = 0
        _write_message(answers, work(task, on_stage))


class _Spawned(_Worker):
    """A worker started by multiprocessing (spawn: where there is no ``fork``), its
    connection, and the stage number it writes into a shared value."""

    def __init__(self, work: Callable[..., Any], stages: Sequence[str]) -> None:
        import multiprocessing

        context = multiprocessing.get_context("spawn")
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

    def send(self, task: object) -> None:
        self.conn.send(task)

    def answered(self) -> bool:
        return bool(self.conn.poll())

    def receive(self) -> Any:
        return self.conn.recv()

    def alive(self) -> bool:
        return bool(self.process.is_alive())

    def exitcode(self) -> int | None:
        code: int | None = self.process.exitcode
        return code

    def stage_number(self) -> int:
        return int(self.stage.value)

    def waitables(self) -> list[Any]:
        return [self.conn, self.process.sentinel]

    def kill(self, *, reap: bool = True) -> None:
        with contextlib.suppress(Exception):
            self.process.kill()
        if reap:
            self.process.join()
            self.conn.close()


def _serve(
    conn: Any, stage: Any, work: Callable[..., Any], stages: Sequence[str], parent: int
) -> None:
    """A spawned worker's life: do each task that comes down the pipe, send back the result."""
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

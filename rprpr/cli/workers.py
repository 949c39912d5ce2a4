"""Worker processes (``check -j N``) that never outlive rprpr.

A worker may be deep in a long computation, in C, deaf to everything but SIGKILL; it
holds a copy of standard output, so a worker left behind keeps whoever reads rprpr's
pipe waiting. Hence:

* the pool (``pool``) kills its workers whenever its block ends by an exception (a
  signal turned into ``Interrupted``, a bug), and registers the same kill with
  ``signals`` for a hard stop;
* each worker dies with its parent, whatever kills the parent (SIGKILL too): on Linux
  the kernel sends it SIGKILL (``prctl(PR_SET_PDEATHSIG)``); elsewhere a thread of the
  worker polls its parent's pid (best effort: it needs the worker to be running Python);
* a worker ignores SIGINT (Ctrl-C reaches the whole process group; the parent decides)
  and dies of SIGTERM, never running the parent's handlers.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

from .signals import STOPPING, killed_on_signal

if TYPE_CHECKING:
    from concurrent.futures import ProcessPoolExecutor

PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
POLL_SECONDS = 0.5  # how often a worker without prctl looks for its parent


@contextmanager
def pool(jobs: int) -> Iterator[ProcessPoolExecutor]:
    """A pool of ``jobs`` worker processes for the block: shut down in order when the
    block ends normally, killed at once when it ends by an exception."""
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    # fork: workers start in milliseconds with the modules already imported
    ctx = multiprocessing.get_context("fork" if sys.platform.startswith("linux") else "spawn")
    executor = ProcessPoolExecutor(
        max_workers=jobs, mp_context=ctx, initializer=start_worker, initargs=(os.getpid(),)
    )
    try:
        with killed_on_signal(lambda: kill_workers(executor, reap=False)):
            yield executor
    except BaseException:
        kill_workers(executor)
        # no cancel_futures: the pool, finding its workers dead, fails every pending
        # future itself (cancelling them too races with that, and 3.11 then prints a
        # traceback from its manager thread)
        executor.shutdown(wait=False)
        raise
    executor.shutdown(wait=True)


def kill_workers(executor: ProcessPoolExecutor, *, reap: bool = True) -> None:
    """SIGKILL every worker of the pool (they hold no state worth saving), and reap them
    (not from a signal handler: ``reap`` False)."""
    processes = list((getattr(executor, "_processes", None) or {}).values())
    for p in processes:
        with contextlib.suppress(Exception):
            p.kill()
    for p in processes if reap else ():
        with contextlib.suppress(Exception):
            p.join(1.0)


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

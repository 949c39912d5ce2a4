"""The work of the worker tests (``tests/cli/test_workers.py``), in a module of its own:
a spawned worker imports the module of its work function, and this one imports neither
pytest nor the test module's imports (~0.1 CPU-s a spawned worker)."""

from __future__ import annotations

import os
import signal
from typing import Any


def work(task: Any, on_stage: Any) -> Any:
    """Square a number; "die" kills its own process; "hang" waits in its second stage."""
    if task == "die":
        os.kill(os.getpid(), signal.SIGKILL)
    if task == "hang":
        on_stage("sleeping")
        import time

        time.sleep(60)
    if task == "pid":
        return os.getpid()
    if task == "big":
        return b"x" * (3 << 20)  # several pipe buffers
    if task == "signals":  # what this process does with a stop signal, and what it holds back
        held = signal.pthread_sigmask(signal.SIG_BLOCK, [])
        return signal.getsignal(signal.SIGINT), signal.getsignal(signal.SIGTERM), sorted(held)
    if task == "pipes":  # the pipes this process holds open, by their inode
        fds = (os.path.join("/proc/self/fd", fd) for fd in os.listdir("/proc/self/fd"))
        return os.getpid(), sorted({os.readlink(f) for f in fds if os.path.exists(f)})
    return task * task

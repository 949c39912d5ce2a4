"""What a signal does to a running command: SIGINT (Ctrl-C), SIGTERM and SIGHUP stop it
cleanly and at once, whatever it is doing.

``handled()`` (around every command, in ``main``) turns the first such signal into
``report.exit.Interrupted``, raised where the main thread is: every ``finally`` and
context manager runs, so worker processes are killed (``workers``) and temporary output
files removed (``output.AtomicFile``), the previous output left as it was. ``main`` then
prints one line and dies of the same signal (``die_of``), so a shell reports 128 + N.

A second signal while that cleanup runs (or while the main thread is stuck in a long
computation in C that the first one could not interrupt) does the cleanup from here,
from the registries below, and dies at once: what is registered here is what must not
outlive rprpr (the worker processes; the temporary files), each call cheap and safe
from a signal handler.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from types import FrameType
from typing import Any

from ..report.exit import Interrupted

# the signals that stop a command; SIGHUP: the terminal went away (not on Windows)
STOPPING = tuple(
    getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name)
)

_temporaries: set[str] = set()  # files to remove on a hard stop
_killers: dict[int, Callable[[], None]] = {}  # what stops the worker processes
_received: list[int] = []  # the signals received while ``handled``


def discard_on_signal(path: str) -> None:
    """Remove ``path`` if rprpr is stopped hard before ``keep_on_signal(path)``."""
    _temporaries.add(path)


def keep_on_signal(path: str) -> None:
    """``path`` is no longer rprpr's to remove (renamed into place, or removed)."""
    _temporaries.discard(path)


@contextmanager
def killed_on_signal(kill: Callable[[], None]) -> Iterator[None]:
    """Within the block, a hard stop calls ``kill`` (it must be cheap and never block)."""
    key = id(kill)
    _killers[key] = kill
    try:
        yield
    finally:
        _killers.pop(key, None)


def _stop(signum: int, frame: FrameType | None) -> None:
    """The handler of the ``STOPPING`` signals: raise ``Interrupted`` the first time;
    stop hard (clean up from the registries, die) the next."""
    _received.append(signum)
    if len(_received) == 1:
        raise Interrupted(signum)
    hard_stop(signum)


def hard_stop(signum: int) -> None:
    """Kill the registered workers, remove the registered temporary files, say so, and
    die of ``signum``."""
    for kill in list(_killers.values()):
        with contextlib.suppress(Exception):
            kill()
    for path in list(_temporaries):
        with contextlib.suppress(OSError):
            os.unlink(path)
    with contextlib.suppress(OSError):
        os.write(2, f"rprpr: stopped ({signal_name(signum)})\n".encode())
    die_of(signum)


def die_of(signum: int) -> None:
    """End the process as killed by ``signum`` (the signal's default action), so that
    the caller sees the interruption; where that does not end it, exit 128 + N."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    try:
        signal.signal(signum, signal.SIG_DFL)
        os.kill(os.getpid(), signum)
    finally:
        os._exit(128 + signum)


def signal_name(signum: int) -> str:
    """``SIGTERM`` for 15, and so on."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


@contextmanager
def handled() -> Iterator[None]:
    """Within the block, the ``STOPPING`` signals raise ``Interrupted`` (see the module
    docstring); the handlers before it are restored after. Only the main thread can set
    handlers: elsewhere (rprpr called from a thread) the block changes nothing."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    before: dict[int, Any] = {}
    _received.clear()
    try:
        for signum in STOPPING:
            if signal.getsignal(signum) is signal.SIG_IGN:
                continue  # ignored on purpose (nohup, a background job): keep it so
            before[signum] = signal.signal(signum, _stop)
        yield
    finally:
        for signum, handler in before.items():
            signal.signal(signum, handler)
        _received.clear()

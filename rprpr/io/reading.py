"""Every byte stream rprpr takes, read through one capped reader: task files, standard
input (``check -``, ``plot -``, ``export -``), waypoint CSVs and the configuration.

A stream is read at most ``cap + 1`` bytes far, however much it holds or however long
it stalls after that: an endless or stalled pipe is stopped as soon as it passes the
cap, never read whole. A named file must be a regular file (a FIFO, a device or a
socket is refused before it is opened, so reading never waits on one); with
``inside``, it must also resolve (after symbolic links) inside that folder, and a file
that does not is refused before a byte of it is read. Every refusal is a
``ReadProblem`` whose message says why in words, for the caller to locate.
"""

from __future__ import annotations

import os
import stat
import time
from typing import BinaryIO

from .messages import too_large

CHUNK = 1 << 16  # bytes asked of a stream at a time


class ReadProblem(Exception):
    """A file or stream that cannot be read within the rules; ``message`` says why."""

    def __init__(self, message: str) -> None:
        super().__init__(message)
        self.message = message


def read_file(path: str, cap: int, what: str, *, inside: str | None = None) -> bytes:
    """The bytes of the regular file ``path``, at most ``cap``; ``what`` names what the
    file should be in messages ("a task file (YAML)"). ``inside``: a folder the file
    must resolve into. Raises ``ReadProblem``."""
    try:
        if inside is not None:
            path = _inside(path, inside)
        st = os.stat(path)
        if stat.S_ISDIR(st.st_mode):
            raise ReadProblem(f"is a directory, expected {what}")
        if not stat.S_ISREG(st.st_mode):
            raise ReadProblem(f"not a regular file (a device, pipe or socket), expected {what}")
        if st.st_size > cap:
            raise ReadProblem(too_large(cap, st.st_size))
        extra = getattr(os, "O_NONBLOCK", 0)  # never wait on a FIFO put there since
        if inside is not None:  # the path resolved: a link put there since is not followed
            extra |= getattr(os, "O_NOFOLLOW", 0)
        with open(path, "rb", opener=lambda p, flags: os.open(p, flags | extra)) as fh:
            if not stat.S_ISREG(os.fstat(fh.fileno()).st_mode):  # swapped since the stat
                raise ReadProblem(f"not a regular file, expected {what}")
            return read_stream(fh, cap, size_known=True)
    except FileNotFoundError:
        raise ReadProblem("no such file") from None
    except OSError as e:
        raise ReadProblem(f"cannot read the file: {e.strerror or e}") from None
    except ValueError as e:  # a NUL byte in the name
        raise ReadProblem(f"not a usable file name: {e}") from None


def read_stream(stream: BinaryIO | None, cap: int, *, size_known: bool = False) -> bytes:
    """The bytes of ``stream`` up to its end, at most ``cap``: reading stops as soon as
    it passes the cap (``ReadProblem``: file too large), so an endless or stalled stream
    is never read further. A missing or closed stream is empty. ``size_known``: the
    message gives the size read (a file that grew since it was measured)."""
    if stream is None:
        return b""
    chunks: list[bytes] = []
    held = 0
    while held <= cap:
        try:
            chunk = stream.read(min(CHUNK, cap + 1 - held))
        except (OSError, ValueError):  # closed, or not readable: nothing more
            break
        if chunk is None:  # a non-blocking stream with nothing yet
            time.sleep(0.01)
            continue
        if not chunk:
            break
        chunks.append(chunk)
        held += len(chunk)
    if held > cap:
        raise ReadProblem(too_large(cap, held if size_known else None))
    return b"".join(chunks)


def _inside(path: str, folder: str) -> str:
    """``path`` resolved (every symbolic link followed); ``ReadProblem`` when that lies
    outside ``folder`` (resolved too). Nothing of the file is read, so no message can
    quote it."""
    real = os.path.realpath(path)
    base = os.path.realpath(folder)
    try:
        within = os.path.commonpath([real, base]) == base
    except ValueError:  # another drive
        within = False
    if not within:
        raise ReadProblem(
            "resolves outside the task file's folder (a symbolic link?): not read; a CSV"
            " must lie in the task file's folder or below it"
        )
    return real

"""Where a command's output goes: standard output or ``-o FILE`` (opened before any work,
or written atomically), the rich consoles and their colour, and what a failed write means.

A failed write is one line and ``ExitCode.INPUT`` (the environment, not rprpr); a reader
that closes the pipe early fails nothing (``report.exit`` says so; here standard output is
only pointed at /dev/null, so that the interpreter's last flush raises nothing more).
"""

from __future__ import annotations

import os
import sys
import tempfile
from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TextIO

import click

from ..report.exit import ExitCode, InputError

NON_TTY_WIDTH = 160  # text report width when not writing to a terminal (COLUMNS overrides)
STDOUT = "standard output"


def silence_stdout() -> None:
    """Point standard output at /dev/null: after a closed pipe or a full disk nothing more
    can be written there, and the interpreter's last flush must not fail again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


@contextmanager
def writing(what: str, output_file: str | None, reached: ExitCode) -> Iterator[None]:
    """Write ``what`` ("the report") to ``output_file`` (None: standard output) in the
    block. A closed pipe ends the command at once with the status ``reached``; any other
    failure to write is an ``InputError`` naming ``what`` and where."""
    try:
        yield
    except BrokenPipeError:  # the reader went away (| head): the status reached stands
        silence_stdout()
        raise click.exceptions.Exit(int(reached)) from None
    except OSError as err:  # disk full and the like: the environment, not rprpr
        if output_file is None:
            silence_stdout()
        raise InputError(
            f"cannot write {what} to {output_file or STDOUT}: {err.strerror or err}"
        ) from None


def open_output(output_file: str | None) -> TextIO:
    """The stream of a report written as it is made: standard output, or ``output_file``
    opened now, so that a file that cannot be written is a usage error found before any
    task is audited."""
    if not output_file:
        return sys.stdout
    try:
        return open(output_file, "w", encoding="utf-8", newline="\n")
    except OSError as e:
        raise click.UsageError(
            f"cannot write the output file {output_file}: {e.strerror or e}"
        ) from None


def write_atomic(path: str, write: Callable[[str], None]) -> None:
    """Have ``write`` write a temporary file beside ``path`` (it gets the temporary's
    name), then rename it into place: an interrupted or failed run leaves no half-written
    file behind."""
    target = Path(path)
    try:
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
        os.close(fd)
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)  # mkstemp's 0600 would make the output private
    except OSError as e:
        raise InputError(f"cannot write {path}: {e.strerror or e}") from None
    try:
        write(tmp)
        os.replace(tmp, target)
    except OSError as e:
        raise InputError(f"cannot write {path}: {e.strerror or e}") from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)


def is_tty(stream: Any) -> bool:
    """Whether ``stream`` is a terminal (False for anything without a working isatty)."""
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):
        return False


def color_enabled(color: str, stream: Any, environ: Mapping[str, str] = os.environ) -> bool:
    """Whether to colour output on ``stream``: ``--color always``/``never`` win; else
    NO_COLOR (set and not empty) turns colour off, then FORCE_COLOR (set and not empty)
    turns it on; else colour only on a terminal (TERM not ``dumb``)."""
    if color != "auto":
        return color == "always"
    if environ.get("NO_COLOR"):
        return False
    if environ.get("FORCE_COLOR"):
        return True
    return is_tty(stream) and environ.get("TERM", "") not in ("dumb", "unknown")


def make_console(stream: Any, colored: bool, environ: Mapping[str, str] = os.environ) -> Any:
    """A rich Console on ``stream``: ANSI styles only when ``colored``; no markup, emoji or
    highlighting (task names and messages are printed as they are)."""
    from rich.console import Console

    tty = is_tty(stream)
    kw: dict[str, Any] = {"file": stream, "highlight": False, "markup": False, "emoji": False}
    if colored:
        kw.update(force_terminal=True, no_color=False, color_system="auto")
    else:
        kw.update(force_terminal=tty, no_color=True, color_system=None)
    if not tty:
        cols = environ.get("COLUMNS", "")
        kw["width"] = int(cols) if cols.isdigit() and int(cols) > 0 else NON_TTY_WIDTH
    console = Console(**kw)
    if colored and console.color_system is None:  # colour forced on a dumb terminal
        console = Console(**{**kw, "color_system": "standard"})
    console.on_broken_pipe = _broken_pipe  # type: ignore[method-assign]  # rich: exit 1
    return console


def _broken_pipe() -> None:
    raise BrokenPipeError("the report's reader closed the pipe")

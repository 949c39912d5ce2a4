"""Where a command's output goes: standard output or ``-o FILE`` (written atomically, its
temporary file created before any work; never onto an input of the run), the standard
streams (ASCII fallbacks, a closed one), the rich consoles and their colour, and what a
failed write means.

A failed write is one line and ``ExitCode.INPUT`` (the environment, not rprpr); a reader
that closes the pipe early fails nothing (``report.exit`` says so; here standard output is
only pointed at /dev/null, so that the interpreter's last flush raises nothing more).
"""

from __future__ import annotations

import codecs
import contextlib
import errno
import io
import os
import stat
import sys
from collections.abc import Callable, Iterable, Iterator, Mapping
from contextlib import contextmanager
from typing import Any, TextIO

import click

from ..report.exit import ExitCode
from .errors import InputError
from .signals import discard_on_signal, keep_on_signal

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


def echo(text: str) -> None:
    """A line of a command's own output on standard output, its control characters
    escaped (a newline too) and made ``inert`` for a CI runner (``render.escape``)."""
    from ..render.escape import inert, printable

    click.echo(inert(printable(text)))


def say(text: str, keep: str = "") -> None:
    """A line for people on standard error, its control characters escaped (a newline
    too, but those in ``keep``: the help's own) and made ``inert`` for a CI runner
    (``render.escape``: no line can start a workflow command); written through the stream's ASCII
    fallbacks (``standard_streams``). A standard error that cannot be written (closed, a
    full disk) loses the line but changes nothing else."""
    from ..render.escape import inert, printable

    with contextlib.suppress(OSError, ValueError, AttributeError):  # None: closed at start
        sys.stderr.write(inert(printable(text, keep)) + "\n")
        sys.stderr.flush()


class Inert(io.TextIOBase):
    """A text stream (a rich Console's file) whose lines a CI runner cannot take for its
    commands: each line goes through ``render.escape.inert`` once it is whole, however
    the console cut its writes (a wrapped line, a table row). What a flush finds of a
    line not yet ended is written too, but for a tail that could still become a
    command (blanks and a ``:`` at the start of a line, a ``#`` run), held for the rest."""

    def __init__(self, stream: Any) -> None:
        self.stream = stream
        self.pending = ""  # the line not yet written whole
        self.started = False  # part of the pending line was written already (at a flush)

    @property
    def encoding(self) -> str:  # type: ignore[override]
        return str(getattr(self.stream, "encoding", None) or "utf-8")

    def write(self, s: str) -> int:
        text = self.pending + s
        cut = text.rfind("\n") + 1
        if cut:
            self._emit(text[:cut])
            self.started = False
        self.pending = text[cut:]
        return len(s)

    def flush(self) -> None:
        text = self.pending
        keep = len(text) - len(text.rstrip("#"))  # a "#" run may become "##["
        head = text[: len(text) - keep]
        if not self.started and not head.strip(" \t:"):  # a line's start: may become "::"
            head = ""
        if head:
            self._emit(head)
            self.started = True
            self.pending = text[len(head) :]
        self.stream.flush()

    def _emit(self, text: str) -> None:
        from ..render.escape import inert

        if self.started:  # the line's start was written already: only the "##[" rule
            first, nl, rest = text.partition("\n")
            text = inert("x" + first)[1:] + nl + inert(rest)
        else:
            text = inert(text)
        self.stream.write(text)

    def isatty(self) -> bool:
        return is_tty(self.stream)

    def fileno(self) -> int:
        return int(self.stream.fileno())


class Lossy(io.TextIOBase):
    """A stream for what may be lost (messages and a progress bar on standard error):
    a write that fails (a full disk, a closed stream) is dropped, never fatal, so that
    a lost standard error never costs the report."""

    def __init__(self, stream: Any) -> None:
        self.stream = stream

    @property
    def encoding(self) -> str:  # type: ignore[override]
        return str(getattr(self.stream, "encoding", None) or "utf-8")

    def write(self, s: str) -> int:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            self.stream.write(s)
        return len(s)

    def flush(self) -> None:
        with contextlib.suppress(OSError, ValueError, AttributeError):
            self.stream.flush()

    def isatty(self) -> bool:
        return is_tty(self.stream)

    def fileno(self) -> int:
        return int(self.stream.fileno())


def identity(path: str) -> tuple[int, int] | None:
    """The identity of the file ``path`` names, (device, inode), following symbolic
    links; None when it cannot be told (no such file, no permission)."""
    try:
        st = os.stat(path)
    except (OSError, ValueError):
        return None
    return st.st_dev, st.st_ino


TASK_FILE = "a task file"


def refuse_overwriting_inputs(
    outputs: Iterable[str | None], inputs: Iterable[str] | Mapping[str, str]
) -> None:
    """A usage error when an output file would overwrite an input of the run, or another
    output: the same file by identity (``identity``), whatever the names (a link, ``./``,
    ``..``). ``inputs``: the files the run reads, each a task file, or a mapping of each
    to what it is ("the waypoint CSV of t.yaml", "the configuration")."""
    what = dict(inputs) if isinstance(inputs, Mapping) else dict.fromkeys(inputs, TASK_FILE)
    known: dict[object, str] = {}
    for path in what:
        key = identity(path)
        if key is not None:
            known.setdefault(key, path)
    for out in outputs:
        if not out:
            continue
        keys = [k for k in (identity(out), _spelling(out)) if k is not None]
        source = next((known[k] for k in keys if k in known), None)
        if source is not None:
            also = "" if source == out else f" ({source})"
            raise click.UsageError(
                f"the output file {out} is also {what[source]}{also}: it would be overwritten"
            )
        for k in keys:
            known[k] = out
        what[out] = "another output of this run"


def _spelling(path: str) -> str:
    """A file's name made absolute and normal (for a file that may not exist yet)."""
    try:
        return os.path.normcase(os.path.realpath(path))
    except (OSError, ValueError):
        return os.path.normcase(os.path.normpath(path))


class AtomicFile:
    """An output file written whole or not at all: the content goes to a temporary file
    beside the target (in the directory of the file a symbolic link points to, so the
    link stays), which replaces the target only once complete and flushed to disk. An
    interrupted or failed write removes the temporary file and leaves any previous
    target intact. A target that exists and is not a regular file (``/dev/null``, a
    pipe, a terminal) is written in place: there is nothing to replace there."""

    def __init__(self, path: str) -> None:
        self.path = path
        try:
            st: os.stat_result | None = os.stat(path)  # through links, as open() goes
        except OSError:
            st = None
        self.in_place = st is not None and not stat.S_ISREG(st.st_mode)
        # written in place through the name given (/dev/stdout's link ends in a "pipe:[n]"
        # no path reaches); a regular file through a link: beside the file it points to
        linked = not self.in_place and os.path.islink(path)
        self.target = os.path.realpath(path) if linked else path
        self.mode = stat.S_IMODE(st.st_mode) if st is not None else None
        self.temporary: str | None = None

    def create(self) -> str:
        """The path to write to: a new temporary file (or the target itself in place)."""
        if self.in_place:
            return self.target
        folder, name = os.path.split(self.target)
        import tempfile  # only when an output file is written (--version stays light)

        fd, tmp = tempfile.mkstemp(dir=folder or ".", prefix=f".{name}.", suffix=".tmp")
        os.close(fd)
        self.temporary = tmp
        discard_on_signal(tmp)
        # the target's mode, or a new file's (mkstemp's 0600 would make the output private)
        os.chmod(tmp, self.mode if self.mode is not None else 0o666 & ~_umask())
        return tmp

    def commit(self) -> None:
        """Put the written temporary file in the target's place (flushed to disk first,
        so a full disk fails here, not later)."""
        if self.temporary is None:
            return
        fd = os.open(self.temporary, os.O_RDWR)  # writable: Windows fsyncs no other
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(self.temporary, self.target)
        keep_on_signal(self.temporary)
        self.temporary = None

    def discard(self) -> None:
        """Remove the temporary file, if any (never raises)."""
        if self.temporary is not None:
            with contextlib.suppress(OSError):
                os.unlink(self.temporary)
            keep_on_signal(self.temporary)
            self.temporary = None


@contextmanager
def atomic(path: str, what: str, *, early: bool = False) -> Iterator[str]:
    """Write ``what`` ("the report") to ``path`` through an ``AtomicFile``: the block
    writes the file it is given, which takes ``path``'s place when the block ends
    normally; an exception or a signal removes it. A file that cannot be created is a
    usage error when ``early`` (found before any work), else an ``InputError``; a failed
    write (a full disk) is an ``InputError`` naming ``what`` and ``path``."""
    out = AtomicFile(path)
    try:
        tmp = out.create()
    except OSError as e:
        if early:
            raise click.UsageError(
                f"cannot write the output file {path}: {e.strerror or e}"
            ) from None
        raise InputError(f"cannot write {path}: {e.strerror or e}") from None
    try:
        yield tmp
        out.commit()
    except OSError as e:
        raise InputError(f"cannot write {what} to {path}: {e.strerror or e}") from None
    finally:
        out.discard()


def write_atomic(path: str, write: Callable[[str], None], what: str = "") -> None:
    """Have ``write`` write the file it is given (a temporary file beside ``path``), then
    put it in ``path``'s place (``atomic``): an interrupted or failed run leaves no
    half-written file behind, and any previous ``path`` intact."""
    with atomic(path, what or path) as tmp:
        write(tmp)


@contextmanager
def report_stream(output_file: str | None, what: str) -> Iterator[TextIO]:
    """The stream of a report: standard output, or ``output_file`` written atomically
    (``atomic``; the temporary file is created now, so an output that cannot be written
    is a usage error found before any task is audited)."""
    if not output_file:
        yield sys.stdout
        return
    with (
        atomic(output_file, what, early=True) as tmp,
        open(tmp, "w", encoding="utf-8", newline="\n") as out,
    ):
        yield out


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def utf8(stream: Any) -> bool:
    """Whether ``stream`` writes UTF-8 (anything but a text stream that says otherwise)."""
    encoding = getattr(stream, "encoding", None) or "utf-8"
    try:
        return codecs.lookup(encoding).name == "utf-8"
    except LookupError:
        return False


ASCII_ERRORS = "rprpr.ascii"  # the codec error handler of ``ascii_fallbacks``


def _ascii_errors(error: UnicodeError) -> tuple[str, int]:
    from ..render.escape import ascii_errors  # only once a character cannot be written

    return ascii_errors(error)


codecs.register_error(ASCII_ERRORS, _ascii_errors)


class _Closed(io.TextIOBase):
    """Standard output when the process was started without one (``>&-``): every write
    fails as a write to a closed descriptor does, so that it is reported (exit 2)."""

    encoding = "utf-8"

    def write(self, s: str) -> int:
        raise OSError(errno.EBADF, "standard output is closed")

    def isatty(self) -> bool:
        return False


def _occupy_closed_descriptors() -> None:
    """Open /dev/null on the standard descriptors 0, 1, 2 that are closed, as git does:
    else the next file opened would get the number 1 or 2, and a write meant for the
    terminal would land in it."""
    for fd in (0, 1, 2):
        try:
            os.fstat(fd)
        except OSError:
            with contextlib.suppress(OSError):
                null = os.open(os.devnull, os.O_RDWR)
                if null != fd:
                    os.dup2(null, fd)
                    os.close(null)


@contextmanager
def standard_streams() -> Iterator[None]:
    """Within the block, what standard output and error cannot encode (δ, σ, → on a
    cp1252 or ASCII stream; a file name's bytes that are not UTF-8) is written in ASCII
    (``render.escape.ascii_errors``: delta, sigma, ->, ``\\xff``) instead of failing,
    and a standard output that was closed at start fails every write (``_Closed``);
    the streams are restored after."""
    _occupy_closed_descriptors()
    closed = sys.stdout is None
    if closed:
        sys.stdout = _Closed()
    restore = []
    for stream in (sys.stdout, sys.stderr):
        reconfigure = getattr(stream, "reconfigure", None)
        errors = getattr(stream, "errors", None)
        if reconfigure is None or errors is None or (utf8(stream) and errors != "strict"):
            continue
        try:
            reconfigure(errors=ASCII_ERRORS)
        except (ValueError, OSError, TypeError):  # closed, or not a real text stream
            continue
        restore.append((reconfigure, errors))
    try:
        yield
    finally:
        for reconfigure, errors in restore:
            with contextlib.suppress(ValueError, OSError, TypeError):
                reconfigure(errors=errors)
        if closed:
            sys.stdout = None


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
    kw: dict[str, Any] = {
        "file": Inert(stream),  # no line of any console can start a CI runner's command
        "highlight": False,
        "markup": False,
        "emoji": False,
    }
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

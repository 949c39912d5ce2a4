"""The task files a command works on: finding them, loading one (a bad file is one line,
exit 2) and naming it when a bug is met while auditing it (one line, exit 3).

The loader (and with it YAML, numpy and flint) is imported only when a task is loaded.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import TYPE_CHECKING

import click

from ..model.errors import TaskFileError
from .config import FileSelection
from .errors import InputError, InternalError

if TYPE_CHECKING:
    from ..model.task import Task

STDIN = "-"  # the task file read from standard input


def collect_tasks(paths: Sequence[str], selection: FileSelection | None = None) -> list[str]:
    """The task files to check, in order: each file as given (with ``selection.force``,
    only if the selection takes it); each directory searched recursively for the files
    the selection includes (by default ``*.rprpr.yaml`` and ``*.rprpr.yml``), sorted by
    path, skipping what it excludes (hidden files and directories: .git, .venv, .github
    ...); a directory that cannot be read is kept as it is (``unreadable_folder`` tells
    why, for that entry alone). A file is checked once, at its first place, however many
    names it has: two paths are the same file when they have the same identity (device
    and inode, after symbolic links: ``t.yaml``, ``./t.yaml``, a link to it, a hard
    link). ``-`` is standard input."""
    select = selection or FileSelection()
    out: list[str] = []
    for p in paths:
        if p == STDIN:
            out.append(p)
        elif os.path.isdir(p):
            out.extend(_tasks_in(p, select))
        elif not select.force or (select.included(p) and not _excluded_on_the_way(p, select)):
            out.append(p)
    seen: set[object] = set()
    unique = []
    for f in out:
        key = _identity_or_name(f)
        if key not in seen:
            seen.add(key)
            unique.append(f)
    return unique


def _identity_or_name(path: str) -> object:
    """The file's identity (``output.identity``); for a path that names no file, its
    normalised name (a missing file named twice is one error, not two)."""
    from .output import identity

    key = identity(path)
    if key is not None:
        return key
    try:
        return os.path.normcase(os.path.abspath(path))
    except OSError:  # the working directory was deleted
        return os.path.normcase(os.path.normpath(path))


def _excluded_on_the_way(path: str, select: FileSelection) -> bool:
    """Whether the file ``path`` or a folder it lies in (below the project root) is
    excluded."""
    try:
        rel = os.path.relpath(os.path.abspath(path), os.path.abspath(select.root))
    except (OSError, ValueError):
        rel = os.pardir
    if rel.startswith(os.pardir):  # outside the project: the file alone
        return select.excluded(path)
    from pathlib import PurePath

    parts = PurePath(rel).parts
    root = select.root
    return any(select.excluded(os.path.join(root, *parts[: i + 1])) for i in range(len(parts)))


def _tasks_in(folder: str, select: FileSelection) -> list[str]:
    """The task files under ``folder`` (``select``), sorted by path; a directory that
    cannot be listed is returned in its place (see ``collect_tasks``)."""
    found: list[tuple[tuple[str, ...], str]] = []

    def unreadable(error: OSError) -> None:
        if error.filename:
            where = str(error.filename)
            found.append((_parts(where, folder), where))

    for top, dirs, files in os.walk(folder, onerror=unreadable):
        dirs[:] = [d for d in dirs if not select.excluded(os.path.join(top, d))]
        for f in files:
            full = os.path.join(top, f)
            if select.included(full) and not select.excluded(full) and _stays_in(full, folder):
                found.append((_parts(full, folder), full))
    return [full for _, full in sorted(found)]


def _stays_in(path: str, folder: str) -> bool:
    """Whether the file ``path`` found in ``folder`` resolves (after a symbolic link)
    inside it. A link out of it is not read: a searched repository cannot make rprpr
    quote a file of the machine (``/etc/passwd``, a key) in its reports; it is named
    on standard error, and checked only when named on the command line."""
    if not os.path.islink(path):
        return True
    try:
        real, base = os.path.realpath(path), os.path.realpath(folder)
        inside = os.path.commonpath([real, base]) == base
    except (OSError, ValueError):
        inside = False
    if not inside:
        from .output import say

        say(
            f"rprpr: {path}: a symbolic link out of {folder}: not read (name it on the"
            " command line to check it)"
        )
    return inside


def _parts(path: str, folder: str) -> tuple[str, ...]:
    """The components of ``path`` below ``folder`` (lexically: no working directory
    needed, so a deleted one does not matter)."""
    from pathlib import PurePath

    try:
        return PurePath(path).relative_to(folder).parts
    except ValueError:
        return PurePath(path).parts


def unreadable_folder(path: str) -> Task:
    """For a directory ``collect_tasks`` could not list: the ``TaskFileError`` saying
    why (that entry's error; the run goes on)."""
    try:
        os.listdir(path)
    except OSError as e:
        raise TaskFileError(f"cannot read the directory: {e.strerror or e}", file=path) from None
    raise TaskFileError("is a directory, expected a task file (YAML)", file=path)


def tasks_or_usage_error(paths: Sequence[str], selection: FileSelection | None = None) -> list[str]:
    """``collect_tasks(paths, selection)``; a usage error when it finds none (but for
    files that ``selection.force`` left out: then none is nothing to do)."""
    select = selection or FileSelection()
    files = collect_tasks(paths, select)
    if not files and not (select.force and not any(os.path.isdir(p) for p in paths)):
        globs = ", ".join(select.include)
        raise click.UsageError(f"no task files ({globs}) found in {', '.join(paths)}")
    return files


def read_task(path: str, stdin: bytes | None = None, name: str = STDIN) -> Task:
    """The task in the file ``path`` (``-``: ``stdin``, the bytes of standard input, or
    standard input itself when None, read through the capped reader; named ``name`` in
    errors); raises ``TaskFileError``."""
    from ..io.loader import load_task, parse_task, read_stdin

    if path == STDIN:
        return parse_task(stdin if stdin is not None else read_stdin(name), name)
    return load_task(path) if not os.path.isdir(path) else unreadable_folder(path)


def run_inputs(
    files: Sequence[str], stdin: bytes | None = None, config: str | None = None
) -> dict[str, str]:
    """Every file a run reads, each with what it is (for ``output.refuse_overwriting_inputs``):
    the task files, the waypoint CSV each names (``loader.waypoint_file``: found before
    any task is loaded; ``stdin``: the bytes of the task ``-``) and the configuration."""
    from ..io.loader import waypoint_file
    from .output import TASK_FILE

    inputs = {config: "the configuration"} if config else {}
    for f in files:
        if f == STDIN:
            csv = waypoint_file(f, stdin) if stdin is not None else None
        else:
            inputs.setdefault(f, TASK_FILE)
            csv = waypoint_file(f)
        if csv is not None:
            inputs.setdefault(csv, f"the waypoint CSV of {f}")
    return inputs


def task_inputs(path: str, task: Task) -> dict[str, str]:
    """The files the loaded ``task`` (from ``path``) was read from, each with what it is:
    the task file and its waypoint CSV."""
    from .output import TASK_FILE

    inputs = {} if path == STDIN else {path: TASK_FILE}
    for piece in task.pieces:
        if piece.file:
            inputs.setdefault(piece.file, f"the waypoint CSV of {path}")
    return inputs


def stdin_bytes(name: str = STDIN) -> bytes:
    """Standard input, whole, through the capped reader (``io.loader.read_stdin``): a
    stream past the cap is a ``TaskFileError`` naming ``name``."""
    from ..io.loader import read_stdin

    return read_stdin(name)


def load(path: str) -> Task:
    """The task in the file ``path`` (``-``: standard input); a bad task file is an
    ``InputError`` (its message names the file, line, column and key)."""
    from .uncertainty import needs_limit

    try:
        task = read_task(path)
        needs_limit(task)  # no configuration here: the task's own limit
    except TaskFileError as e:
        raise InputError(str(e)) from None
    return task


@contextmanager
def task_named(path: str) -> Iterator[None]:
    """Name the task file in the one-line report of a bug met while auditing it."""
    try:
        yield
    except click.ClickException:
        raise
    except TaskFileError as e:  # a task the audit refuses (a mechanism it cannot audit)
        raise InputError(str(e.naming(path))) from None
    except Exception as e:
        if os.environ.get("RPRPR_DEBUG"):
            import traceback

            traceback.print_exc()
        raise InternalError(
            f"{path}: internal error ({type(e).__name__}: {e}); please report it to the"
            " rprpr maintainers with this task file"
        ) from None

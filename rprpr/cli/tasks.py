"""The task files a command works on: finding them, loading one (a bad file is one line,
exit 2) and naming it when a bug is met while auditing it (one line, exit 3).

The loader (and with it YAML, numpy and flint) is imported only when a task is loaded.
"""

from __future__ import annotations

import os
import traceback
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import PurePath
from typing import TYPE_CHECKING

import click

from ..model.errors import TaskFileError
from ..report.exit import InputError, InternalError

if TYPE_CHECKING:
    from ..model.task import Task

TASK_SUFFIXES = (".yaml", ".yml")


def collect_tasks(paths: Sequence[str]) -> list[str]:
    """The task files to check, in order: each file as given; each directory searched
    recursively for *.yaml and *.yml, sorted by path, skipping hidden files and
    directories (.git, .venv, .github, .pre-commit-config.yaml ...); a directory that
    cannot be read is kept as it is (``unreadable_folder`` tells why, for that entry
    alone). A file is checked once, at its first place, however many names it has: two
    paths are the same file when they have the same identity (device and inode, after
    symbolic links: ``t.yaml``, ``./t.yaml``, a link to it, a hard link)."""
    out: list[str] = []
    for p in paths:
        out.extend(_tasks_in(p) if os.path.isdir(p) else [p])
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


def _tasks_in(folder: str) -> list[str]:
    """The *.yaml and *.yml files under ``folder``, sorted by path, hidden ones skipped;
    a directory that cannot be listed is returned in its place (see ``collect_tasks``)."""
    found: list[tuple[tuple[str, ...], str]] = []

    def unreadable(error: OSError) -> None:
        if error.filename:
            where = str(error.filename)
            found.append((_parts(where, folder), where))

    for top, dirs, files in os.walk(folder, onerror=unreadable):
        dirs[:] = [d for d in dirs if not d.startswith(".")]
        for f in files:
            if f.endswith(TASK_SUFFIXES) and not f.startswith("."):
                full = os.path.join(top, f)
                found.append((_parts(full, folder), full))
    return [full for _, full in sorted(found)]


def _parts(path: str, folder: str) -> tuple[str, ...]:
    """The components of ``path`` below ``folder`` (lexically: no working directory
    needed, so a deleted one does not matter)."""
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


def tasks_or_usage_error(paths: Sequence[str]) -> list[str]:
    """``collect_tasks(paths)``; a usage error when it finds none."""
    files = collect_tasks(paths)
    if not files:
        raise click.UsageError(f"no task files (*.yaml, *.yml) found in {', '.join(paths)}")
    return files


def load(path: str) -> Task:
    """The task in the file ``path``; a bad task file is an ``InputError`` (its message
    names the file, line, column and key)."""
    from ..io.loader import load_task

    try:
        return load_task(path) if not os.path.isdir(path) else unreadable_folder(path)
    except TaskFileError as e:
        raise InputError(str(e)) from None


@contextmanager
def task_named(path: str) -> Iterator[None]:
    """Name the task file in the one-line report of a bug met while auditing it."""
    try:
        yield
    except click.ClickException:
        raise
    except Exception as e:
        if os.environ.get("RPRPR_DEBUG"):
            traceback.print_exc()
        raise InternalError(
            f"{path}: internal error ({type(e).__name__}: {e}); please report it to the"
            " rprpr maintainers with this task file"
        ) from None

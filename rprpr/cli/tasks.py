"""The task files a command works on: finding them, loading one (a bad file is one line,
exit 2) and naming it when a bug is met while auditing it (one line, exit 3).

The loader (and with it YAML, numpy and flint) is imported only when a task is loaded.
"""

from __future__ import annotations

import os
import traceback
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
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
    directories (.git, .venv, .github, .pre-commit-config.yaml ...). A file named twice
    is checked once, at its first place."""
    out: list[str] = []
    for p in paths:
        out.extend(_tasks_in(p) if os.path.isdir(p) else [p])
    seen: set[str] = set()
    unique = []
    for f in out:
        key = os.path.normcase(os.path.abspath(f))
        if key not in seen:
            seen.add(key)
            unique.append(f)
    return unique


def _tasks_in(folder: str) -> list[str]:
    """The *.yaml and *.yml files under ``folder``, sorted by path, hidden ones skipped."""
    found: list[tuple[tuple[str, ...], str]] = []
    for top, dirs, files in os.walk(folder):
        dirs[:] = [d for d in dirs if not d.startswith(".")]
        for f in files:
            if f.endswith(TASK_SUFFIXES) and not f.startswith("."):
                full = os.path.join(top, f)
                found.append((Path(os.path.relpath(full, folder)).parts, full))
    return [full for _, full in sorted(found)]


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
        return load_task(path)
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

"""The options of the commands: declared once here, and ``check``'s taken as one value.

``CheckOptions`` is built once from the command line and passed down, to the workers and
the renderers, instead of one parameter per option. What in it changes a verdict is one
value of its own, ``audit`` (``model.options.AuditOptions``, like black's ``Mode``); the
rest is the command line's plumbing.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import field
from typing import Any, TypeVar

import click

from ..model.dataclass import dataclass
from ..model.defaults import DEFAULT_SAMPLES
from ..model.options import AuditOptions
from .config import DEFAULT_BUDGET, FORMATS, TaskDefaults
from .errors import InputError

F = TypeVar("F", bound=Callable[..., Any])

CHECK_FORMATS = FORMATS
COLORS = ("auto", "always", "never")
SHEET_FORMATS = (".png", ".svg", ".pdf")  # the sheet of plot and repair --plot


PLOT_EXTRA = "pip install 'rprpr[plot]'"  # matplotlib and Pillow: the sheet and the GIF


def require_plotting(what: str) -> None:
    """Go on only where matplotlib can be imported (the extra ``rprpr[plot]``): else an
    ``InputError`` (one line, exit 2) saying that ``what`` ("plot") needs it and
    how to install it. The light install (``pip install rprpr``) checks, exports and
    repairs without it."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise InputError(
            f"{what} draws with matplotlib, which is not installed: {PLOT_EXTRA}"
        ) from None


@dataclass(frozen=True)
class CheckOptions:
    """How ``rprpr check`` audits and reports; the defaults are the command line's.

    ``audit``: what changes a verdict (``AuditOptions``: ``--samples``, ``--strict``,
    ``--peak``, ``--warn-unbounded``; each None or False leaves every task its own
    choice). ``output_file`` None is standard output; ``jobs`` is the number of worker
    processes; ``budget``
    the wall-clock seconds each task may take before it is stopped (None: no limit).
    ``defaults``: what the repository's configuration sets in every task
    (``config.configure``); ``statistics``: counts per rule instead of the report;
    ``stdin``: the bytes of the task file ``-``, named ``stdin_filename`` in the report
    (``stdin_error``: why it could not be read); ``sheets``: the HTML report draws each
    task's audit sheet (``check`` clears it for any other format and where matplotlib is
    not installed).
    """

    audit: AuditOptions = field(default_factory=AuditOptions)
    format: str = "text"
    output_file: str | None = None
    jobs: int = 1
    quiet: bool = False
    layout: str = "auto"  # the text report's instants: "auto", "table" or "rows"
    exit_zero: bool = False
    budget: float | None = DEFAULT_BUDGET
    color: str = "auto"
    defaults: TaskDefaults = field(default_factory=TaskDefaults)
    statistics: bool = False
    stdin: bytes | None = None
    stdin_error: str = ""  # why standard input could not be read (over the cap)
    stdin_filename: str = "-"
    sheets: bool = True  # --format html: each task's audit sheet (matplotlib)


def tasks_argument(name: str = "tasks") -> Callable[[F], F]:
    """TASKS: task files, or directories searched for them."""
    return click.argument(name, nargs=-1, required=True, type=click.Path(readable=False))


def output_file_option(help: str, dash_is_stdout: bool = False) -> Callable[[F], F]:
    """``-o/--output-file FILE``; with ``dash_is_stdout``, ``-o -`` is standard output
    (the value None, as without ``-o``)."""

    def dash(ctx: click.Context, param: click.Parameter, value: str | None) -> str | None:
        return None if dash_is_stdout and value == "-" else value

    return click.option(
        "-o",
        "--output-file",
        type=click.Path(dir_okay=False, readable=False),
        callback=dash,
        help=help,
    )


def samples_option(low: int, high: int, help: str) -> Callable[[F], F]:
    """``--samples N``, between ``low`` and ``high``, by default ``DEFAULT_SAMPLES``."""
    return click.option(
        "--samples",
        type=click.IntRange(low, high),
        default=DEFAULT_SAMPLES,
        show_default=True,
        help=help,
    )


def color_option() -> Callable[[F], F]:
    """``--color auto|always|never``."""
    return click.option(
        "--color",
        type=click.Choice(COLORS),
        default="auto",
        show_default=True,
        help="Colour in the text report; auto honours NO_COLOR, FORCE_COLOR and a "
        "non-terminal output.",
    )


def suffix_choice(path: str, allowed: Sequence[str], what: str, param: str) -> str:
    """The lower-case extension of ``path``, one of ``allowed``; else a usage error naming
    ``what`` the file holds and the option ``param`` that named it."""
    from pathlib import Path

    suffix = Path(path).suffix.lower()
    if suffix not in allowed:
        raise click.BadParameter(
            f"{path!r} has extension {suffix or '(none)'!r}; {what} can be written as "
            f"{', '.join(allowed)}",
            param_hint=param,
        )
    return suffix

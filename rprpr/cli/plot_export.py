"""``rprpr plot`` and ``rprpr export``: argument handling, loading, writing, exit status.

matplotlib is imported only inside ``plot`` (through ``rprpr_cli.plot`` and
``rprpr_cli.animate``), never by ``rprpr check`` or ``rprpr export``. Bad invocations and
bad task files exit 2 with one line (``errors.ExitCode.INPUT``); both commands exit 0
once their output is written, whatever the audit's verdict (``rprpr check`` is the gate).
"""

from __future__ import annotations

import os
import sys
import tempfile
import traceback
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import click

from ..model.errors import TaskFileError
from ..report.exit import ExitCode

SHEET_FORMATS = (".png", ".svg", ".pdf")
EXPORT_FORMATS = ("csv", "json")
MAX_TASKS = 8  # overlaid on one sheet: beyond this the legend stops being readable


class InputError(click.ClickException):
    """A bad task file or an unwritable output: one line, exit 2."""

    exit_code = int(ExitCode.INPUT)


class InternalError(click.ClickException):
    """A bug met while working on a named task file: one line, exit 3."""

    exit_code = int(ExitCode.INTERNAL)


@contextmanager
def _task_named(path: str) -> Iterator[None]:
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


def _load(path: str) -> Any:
    from ..io.loader import load_task

    try:
        return load_task(path)
    except TaskFileError as e:
        raise InputError(str(e)) from None


def _write_atomic(path: str, write: Callable[[str], None]) -> None:
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


def _suffix_choice(path: str, allowed: Sequence[str], what: str, param: str) -> str:
    suffix = Path(path).suffix.lower()
    if suffix not in allowed:
        raise click.BadParameter(
            f"{path!r} has extension {suffix or '(none)'!r}; {what} can be written as "
            f"{', '.join(allowed)}",
            param_hint=param,
        )
    return suffix


def _panels(spec: str | None, known: Sequence[str]) -> list[str]:
    if spec is None:
        return list(known)
    names = [p.strip().lower() for p in spec.split(",") if p.strip()]
    if not names:
        raise click.BadParameter(
            f"no panel named; choose from {', '.join(known)}", param_hint="--panels"
        )
    for n in names:
        if n not in known:
            raise click.BadParameter(
                f"unknown panel {n!r}; choose from {', '.join(known)}", param_hint="--panels"
            )
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise click.BadParameter(f"panel {', '.join(dup)} given twice", param_hint="--panels")
    return names


PANEL_NAMES = ("path", "x", "delta", "joints", "torques")  # = plot.PANELS, without matplotlib


@click.command()
@click.argument("tasks", nargs=-1, required=True, type=click.Path())
@click.option(
    "-o",
    "--output-file",
    type=click.Path(dir_okay=False),
    help="The sheet, as .png, .svg or .pdf (format from the extension). "
    "Default: <first task's stem>.png in the current directory.",
)
@click.option(
    "--panels",
    "panels_spec",
    metavar="LIST",
    help=f"Comma-separated panels, drawn in this order: {','.join(PANEL_NAMES)} (default: all).",
)
@click.option(
    "--animate",
    "animate_file",
    type=click.Path(dir_okay=False),
    metavar="FILE.gif",
    help="Also write an animated GIF of the robot moving along the motion.",
)
@click.option(
    "--show",
    is_flag=True,
    help="Open the sheet in a window (where a display exists); with -o, also write it.",
)
@click.option(
    "--samples",
    type=click.IntRange(11, 100_000),
    default=1001,
    show_default=True,
    help="Sample points t = 0 .. t_f per task (the singular instants are added).",
)
@click.option(
    "--dpi",
    type=click.IntRange(50, 600),
    default=150,
    show_default=True,
    help="Resolution of a .png sheet.",
)
def plot(
    tasks: tuple[str, ...],
    output_file: str | None,
    panels_spec: str | None,
    animate_file: str | None,
    show: bool,
    samples: int,
    dpi: int,
) -> None:
    """Draw the audit sheet of TASK (files or directories; several tasks overlay on the same
    axes): the workspace, x_E(t) and y_E(t), δ(t), the joints and the torques, as in the
    paper's Figs. 2-5. Exits 0 once written, whatever the verdict."""
    from .main import collect_tasks

    if output_file is not None:
        _suffix_choice(output_file, SHEET_FORMATS, "the sheet", "-o")
    if animate_file is not None:
        _suffix_choice(animate_file, (".gif",), "the animation", "--animate")
    panels = _panels(panels_spec, PANEL_NAMES)
    files = collect_tasks(tasks)
    if not files:
        raise click.UsageError(f"no task files (*.yaml, *.yml) found in {', '.join(tasks)}")
    if len(files) > MAX_TASKS:
        raise click.UsageError(
            f"{len(files)} tasks given; at most {MAX_TASKS} overlay on one sheet"
        )
    loaded = [(_load(f), f) for f in files]

    from ..engine.audit import audit
    from ..render import sheet as P

    motions = []
    for task, src in loaded:
        with _task_named(src):
            motions.append(P.motion(audit(task, samples=samples), src))
    written = []
    if show:
        written += _show(motions, panels, output_file, files[0], dpi)
    else:
        out = output_file or f"{Path(files[0]).stem}.png"
        fig = P.render(motions, panels)
        _write_atomic(out, lambda tmp: P.save(fig, tmp, P.format_of(out), dpi=dpi, motions=motions))
        written.append(out)
    if animate_file is not None:
        from ..render import animation as A

        def gif(tmp: str) -> None:
            A.write_gif(motions, tmp)

        _write_atomic(animate_file, gif)
        written.append(animate_file)
    for w in written:
        click.echo(f"rprpr: wrote {w}", err=True)


def _show(
    motions: list[Any], panels: list[str], output_file: str | None, first: str, dpi: int
) -> list[str]:
    """Open the sheet with pyplot where a window can open; write it when -o is given, or
    when no window can open (then to the default file, and say so)."""
    from ..render import sheet as P

    if not P.can_show():
        out = output_file or f"{Path(first).stem}.png"
        click.echo(f"rprpr: no display for --show; writing {out} instead", err=True)
        fig = P.render(motions, panels)
        _write_atomic(out, lambda tmp: P.save(fig, tmp, P.format_of(out), dpi=dpi, motions=motions))
        return [out]
    import matplotlib.pyplot as plt

    fig = P.render(motions, panels, figure=plt.figure())
    written = []
    if output_file is not None:
        _write_atomic(
            output_file,
            lambda tmp: P.save(fig, tmp, P.format_of(output_file), dpi=dpi, motions=motions),
        )
        written.append(output_file)
    plt.show()
    return written


@click.command()
@click.argument("task", type=click.Path())
@click.option(
    "-o",
    "--output-file",
    type=click.Path(dir_okay=False),
    help="Write here, as .csv or .json (format from the extension); standard output when omitted.",
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(EXPORT_FORMATS),
    help="Output format (default: from the -o extension, else csv).",
)
@click.option(
    "--samples",
    type=click.IntRange(2, 1_000_000),
    default=1001,
    show_default=True,
    help="Sample points t_i = i t_f/(N-1), i = 0..N-1.",
)
def export(task: str, output_file: str | None, fmt: str | None, samples: int) -> None:
    """Write the sampled motion of TASK: t, the end point, the joints, δ, λ and the torques,
    one row per sample (SI units, angles in radians)."""
    if output_file is not None:
        suffix = Path(output_file).suffix.lower()
        implied = {".csv": "csv", ".json": "json"}.get(suffix)
        if fmt is None:
            if implied is None:
                _suffix_choice(output_file, (".csv", ".json"), "the samples", "-o")
            fmt = implied
        elif implied is not None and implied != fmt:
            raise click.BadParameter(
                f"--format {fmt} contradicts the extension of {output_file!r}", param_hint="-o"
            )
    fmt = fmt or "csv"
    loaded = _load(task)

    from ..engine.audit import audit
    from ..render import export as E

    with _task_named(task):
        result = audit(loaded, samples=samples)
    if output_file is None:
        try:
            E.write(result, sys.stdout, fmt, task)
            sys.stdout.flush()
        except BrokenPipeError:  # | head: click would exit 1 by itself
            from .main import _silence_stdout

            _silence_stdout()
    else:

        def write(tmp: str) -> None:
            with open(tmp, "w", encoding="utf-8", newline="") as fh:
                E.write(result, fh, fmt, task)

        _write_atomic(output_file, write)
        click.echo(f"rprpr: wrote {output_file} ({samples} samples)", err=True)

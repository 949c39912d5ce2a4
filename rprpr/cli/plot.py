"""``rprpr plot``: draw the audit sheet of one or more tasks (``render.sheet``) and, on
request, an animated GIF of the robot (``render.animation``).

matplotlib is imported only when a sheet is drawn, never by the other commands; it is the
extra ``rprpr[plot]``, and without it ``plot`` says how to install it (exit 2). Exits 0
once written, whatever the audit's verdict (``rprpr check`` is the gate).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from ..model.dataclass import dataclass
from ..report.exit import ExitCode
from .options import (
    SHEET_FORMATS,
    output_file_option,
    require_plotting,
    samples_option,
    suffix_choice,
    tasks_argument,
)
from .output import refuse_overwriting_inputs, say, write_atomic
from .tasks import load, task_inputs, task_named, tasks_or_usage_error

if TYPE_CHECKING:
    from ..model.task import Task
    from ..render.sheet import Motion

MAX_TASKS = 8  # overlaid on one sheet: beyond this the legend stops being readable
PANEL_NAMES = ("path", "x", "delta", "joints", "torques")  # = sheet.PANELS, without matplotlib


@click.command()
@tasks_argument()
@output_file_option(
    "The sheet, as .png, .svg or .pdf (format from the extension). "
    "Default: <first task's stem>.png in the current directory."
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
    type=click.Path(dir_okay=False, readable=False),
    metavar="FILE.gif",
    help="Also write an animated GIF of the robot moving along the motion.",
)
@click.option(
    "--pole-inset",
    is_flag=True,
    help="Beside the torques, log|T| against log|t - t_s| near the first unbounded instant "
    "(the slope reads as minus the pole's order).",
)
@click.option(
    "--show",
    is_flag=True,
    help="Open the sheet in a window (where a display exists); with -o, also write it.",
)
@samples_option(
    11, 100_000, "Sample points t = 0 .. t_f per task (the singular instants are added)."
)
@click.option(
    "--dpi",
    type=click.IntRange(50, 600),
    default=150,
    show_default=True,
    help="Resolution of a .png sheet.",
)
@click.option(
    "--size",
    "--figsize",
    "size_spec",
    metavar="W,H",
    help="A figure of exactly W x H inches for a paper (e.g. 3.5,2.4): the panels without "
    "the sheet's title, legends and keys under the axes. Best with one panel (--panels).",
)
@click.option(
    "--font-scale",
    type=click.FloatRange(0.25, 4),
    default=1.0,
    show_default=True,
    metavar="F",
    help="Multiply every text size by F (e.g. 1.4 for a figure printed small).",
)
def plot(
    tasks: tuple[str, ...],
    output_file: str | None,
    panels_spec: str | None,
    animate_file: str | None,
    pole_inset: bool,
    show: bool,
    samples: int,
    dpi: int,
    size_spec: str | None,
    font_scale: float,
) -> ExitCode:
    """Draw the audit sheet of TASK (files or directories; several tasks overlay on the same
    axes): the workspace, x_E(t) and y_E(t), δ(t), the joints and the torques, as in the
    paper's Figs. 2-5. Exits 0 once written, whatever the verdict."""
    require_plotting("plot")
    if output_file is not None:
        suffix_choice(output_file, SHEET_FORMATS, "the sheet", "-o")
    if animate_file is not None:
        suffix_choice(animate_file, (".gif",), "the animation", "--animate")
    panels = panels_of(panels_spec, PANEL_NAMES)
    size = size_of(size_spec)
    files = tasks_or_usage_error(tasks)
    if len(files) > MAX_TASKS:
        raise click.UsageError(
            f"{len(files)} tasks given; at most {MAX_TASKS} overlay on one sheet"
        )
    default = f"{Path(files[0]).stem.removesuffix('.rprpr')}.png"  # in the working directory
    refuse_overwriting_inputs([output_file or default, animate_file], files)  # before any work
    if size is not None and len(files) > 3:
        raise click.BadParameter(
            "a figure of a given size holds at most 3 tasks (overlaid)", param_hint="--size"
        )
    loaded = [(load(f), f) for f in files]  # every bad file reported before any audit
    inputs: dict[str, str] = {}
    for task, f in loaded:
        inputs.update(task_inputs(f, task))
    refuse_overwriting_inputs([output_file or default, animate_file], inputs)
    motions = _motions(loaded, samples)
    look = Look(pole_inset, size, font_scale)
    if show:
        written = _show(motions, panels, output_file, default, dpi, look)
    else:
        out = output_file or default
        _write_sheet(motions, panels, out, dpi, look)
        written = [out]
    if animate_file is not None:
        from ..render import animation as A

        def gif(tmp: str) -> None:
            A.write_gif(motions, tmp)

        write_atomic(animate_file, gif, "the animation")
        written.append(animate_file)
    for w in written:
        say(f"rprpr: wrote {w}")
    return ExitCode.PASSED


@dataclass(frozen=True)
class Look:
    """How the sheet is drawn: the pole inset, a paper figure's size [in], the text scale."""

    pole_inset: bool = False
    size: tuple[float, float] | None = None
    font_scale: float = 1.0


PLAIN = Look()  # the sheet as drawn by default


def size_of(spec: str | None) -> tuple[float, float] | None:
    """``--size W,H`` in inches (a usage error unless two positive numbers up to 50)."""
    if spec is None:
        return None
    parts = spec.replace("x", ",").split(",")
    try:
        w, h = (float(p) for p in parts)
    except ValueError:
        raise click.BadParameter(
            f"expected W,H in inches such as 3.5,2.4, found {spec!r}", param_hint="--size"
        ) from None
    if not (0 < w <= 50 and 0 < h <= 50):
        raise click.BadParameter(
            f"each side must be in (0, 50] inches, found {spec!r}", param_hint="--size"
        )
    return w, h


def panels_of(spec: str | None, known: Sequence[str]) -> list[str]:
    """The panels ``--panels`` names, in its order (all of ``known`` when not given); a
    usage error for an unknown, repeated or empty list."""
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


def _motions(loaded: Sequence[tuple[Task, str]], samples: int) -> list[Motion]:
    """Each loaded task (with its file) audited on ``samples`` points and made ready to
    draw."""
    from ..engine.audit import audit
    from ..model.five_bar import FIVE_BAR
    from ..model.options import AuditOptions
    from ..render import sheet as P

    refuse_mixed_overlay(loaded)
    motions = []
    for task, src in loaded:
        with task_named(src):
            # a 5R's sheet draws no torque peak (its exact audit and samples): not computed
            peak = task.robot.mechanism != FIVE_BAR
            motions.append(P.motion(audit(task, AuditOptions(samples, peak=peak)), src))
    return motions


def refuse_mixed_overlay(loaded: Sequence[tuple[Task, str]]) -> None:
    """Tasks of two mechanisms (an RPRPR and a 5R) overlaid on one set of axes (at most
    ``OVERLAID`` tasks) are refused: a ``TaskFileError`` at the first task whose
    ``robot.mechanism`` differs from the first task's. Beyond ``OVERLAID`` each task has
    its own column, and the mechanisms may differ."""
    from ..model.errors import TaskFileError
    from ..render.sheet.style import OVERLAID

    if len(loaded) > OVERLAID:
        return
    first = loaded[0][0].robot.mechanism
    for task, src in loaded[1:]:
        if task.robot.mechanism == first:
            continue
        with task_named(src):
            raise TaskFileError(
                f"{_named(task.robot.mechanism)} task cannot be overlaid with"
                f" {_named(first)} task on one sheet's axes (plot them apart, or with more"
                f" than {OVERLAID} tasks, one column each)",
                file=task.source,
                line=task.lines.get("robot.mechanism") or task.lines.get("robot", 0),
                key="robot.mechanism",
            )


def _named(mechanism: str) -> str:
    """``an RPRPR`` or ``a 5R``."""
    return "an RPRPR" if mechanism == "rprpr" else f"a {mechanism}"


def _write_sheet(
    motions: list[Motion], panels: list[str], out: str, dpi: int, look: Look = PLAIN
) -> None:
    """Draw the sheet headless and write it to ``out`` (format from its extension)."""
    from ..render import sheet as P

    fig = _render(motions, panels, look)
    write_atomic(
        out, lambda tmp: P.save(fig, tmp, P.format_of(out), dpi=dpi, motions=motions), "the sheet"
    )


def _render(motions: list[Motion], panels: list[str], look: Look, figure: Any = None) -> Any:
    """The sheet's figure (a usage error when the asked size cannot hold it)."""
    from ..render import sheet as P

    try:
        return P.render(
            motions,
            panels,
            figure=figure,
            pole_inset=look.pole_inset,
            size=look.size,
            font_scale=look.font_scale,
        )
    except ValueError as e:
        if look.size is None:
            raise
        raise click.BadParameter(str(e), param_hint="--size") from None


def _show(
    motions: list[Motion],
    panels: list[str],
    output_file: str | None,
    default: str,
    dpi: int,
    look: Look = PLAIN,
) -> list[str]:
    """Open the sheet with pyplot where a window can open; write it when -o is given, or
    when no window can open (then to the default file, and say so)."""
    from ..render import sheet as P

    if not P.can_show():
        out = output_file or default
        say(f"rprpr: no display for --show; writing {out} instead")
        _write_sheet(motions, panels, out, dpi, look)
        return [out]
    import matplotlib.pyplot as plt

    fig = _render(motions, panels, look, figure=plt.figure())
    written = []
    if output_file is not None:
        write_atomic(
            output_file,
            lambda tmp: P.save(fig, tmp, P.format_of(output_file), dpi=dpi, motions=motions),
            "the sheet",
        )
        written.append(output_file)
    plt.show()
    return written

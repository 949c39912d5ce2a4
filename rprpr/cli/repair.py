"""``rprpr repair``: turn a failing motion into the nearest one that passes, exactly
(``engine.repair``), write it as a task file and say what changed.

The output is written only after it has been read back (``io.loader``) and checked in
strict mode; a task that would fail is never written. Exits 0 when the repaired task is
written (or nothing needed repair), 1 when no repair exists within the constraints (the
reason on standard error, nothing written), 2 for bad input.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import click
from flint import fmpq

from ..model.actuation import SCHEMES
from ..model.errors import TaskFileError
from ..report.exit import ExitCode
from .options import output_file_option
from .output import refuse_overwriting_inputs, say, write_atomic
from .tasks import load, task_named

if TYPE_CHECKING:
    from ..engine.repair import Repair


@click.command()
@click.argument("task", type=click.Path(readable=False))
@output_file_option("The repaired task file. Default: <stem>.repaired.rprpr.yaml beside TASK.")
@click.option(
    "--keep",
    type=click.Choice(["path", "timing"]),
    help="Change only the timing law (keep path) or only the path (keep timing).",
)
@click.option(
    "--window",
    metavar="SECONDS",
    help="Half-width of each local change about t_s [s], a decimal or fraction "
    "(default: the largest that fits, then halves).",
)
@click.option(
    "--slope",
    metavar="DYDX",
    help="|dy/dx| to give a zero-slope crossing (default max(0.2, 2 checks.min_slope)).",
)
@click.option(
    "--plot",
    "plot_file",
    type=click.Path(dir_okay=False, readable=False),
    metavar="FILE",
    help="Also draw the old and new motions overlaid on one sheet (.png, .svg, .pdf).",
)
def repair(
    task: str,
    output_file: str | None,
    keep: str | None,
    window: str | None,
    slope: str | None,
    plot_file: str | None,
) -> ExitCode:
    """Write the nearest passing motion of a failing TASK: local, exact changes of the
    timing law and/or the path around each failing singular instant (zero slope, zero
    speed, inconsistency of eq. 34, a touch), checked strictly before it is written."""
    from ..engine.repair import NoRepair
    from ..engine.repair import repair as repaired
    from ..io.loader import parse_task
    from ..io.writer import task_text

    old = load(task)
    out = output_file or str(Path(task).with_name(_stem(task) + ".repaired.rprpr.yaml"))
    refuse_overwriting_inputs([out, plot_file], [task])
    with task_named(task):
        try:
            r = repaired(
                old, keep=keep, window=_rational(window, "--window"),
                slope=_rational(slope, "--slope"),
            )  # fmt: skip
        except NoRepair as why:
            say(f"rprpr: {task}: no repair: {why}; nothing written")
            return ExitCode.FAILED
    if not r.changed:
        click.echo(f"{task}: passes the strict check: nothing to repair, nothing written")
        return ExitCode.PASSED
    comment = f"{old.name}, repaired by rprpr repair from {Path(task).name}"
    text = task_text(r.task, comment)
    from ..engine.audit import audit

    try:
        back = parse_task(text, out)
    except TaskFileError as e:  # exact, but beyond a task file's number limits
        say(
            f"rprpr: {task}: the repaired motion is exact but its coefficients exceed what a"
            f" task file holds ({e.message}); use the Python API (rprpr.repair) for the"
            " task itself; nothing written"
        )
        return ExitCode.FAILED
    check = audit(back, strict=True)
    if not check.passed:  # never write a failing task
        say(f"rprpr: {task}: the repaired task read back fails the strict check; nothing written")
        return ExitCode.INTERNAL

    def write(tmp: str) -> None:
        Path(tmp).write_text(text, encoding="utf-8")

    write_atomic(out, write, "the task")
    for line in summary(r):
        click.echo(line)
    click.echo(f"checked {out} (strict): pass")
    say(f"rprpr: wrote {out}")
    if plot_file is not None:
        _plot(r, task, out, plot_file)
        say(f"rprpr: wrote {plot_file}")
    return ExitCode.PASSED


def summary(r: Repair) -> list[str]:
    """The account of the change, one line each."""
    e = SCHEMES[r.task.robot.actuation]  # the efforts' words: T [N m] or F [N]
    lines = list(r.notes)  # the knots blended, first
    for c in r.changes:
        lines.append(
            f"t = {c.t} s, x = {c.x} m: {', '.join(c.actions)} within ±{c.window} s;"
            f" ẋ {_f(c.speed[0])} -> {_f(c.speed[1])} m/s, ẍ {_f(c.acceleration[0])} ->"
            f" {_f(c.acceleration[1])} m/s², ẏ {_f(c.ydot[0])} -> {_f(c.ydot[1])} m/s"
            + (f", ÿ {_f(c.yddot[0])} -> {_f(c.yddot[1])} m/s²" if c.yddot is not None else "")
        )
    for s in r.after.singularities:
        lines.append(
            f"  now at t = {s.t:.6g} s: order {s.order}, slope {s.slope:.6g}, speed"
            f" {s.speed:.6g} m/s, {e.condition} residual {s.consistency_residual:.6g} N"
        )
    if r.path_deviation is not None:
        d, x = r.path_deviation
        lines.append(f"path: max deviation {d:.6g} m at x = {x:.6g} m")
    else:
        lines.append("path: kept")
    if r.timing_change is not None:
        d, t = r.timing_change
        lines.append(f"timing: max |Δx(t)| {d:.6g} m at t = {t:.6g} s; duration kept")
    else:
        lines.append("timing: kept")
    for name, a in (("before", r.before), ("after", r.after)):
        peak = a.torque_peak
        if peak is not None:
            lines.append(
                f"{e.noun[:-1]} peak {name}: |{e.letter}1| {peak[0].value:.6g} {e.unit},"
                f" |{e.letter}2| {peak[1].value:.6g} {e.unit}"
            )
    return lines


def _f(q: fmpq) -> str:
    return f"{float(q):.6g}"


def _stem(path: str) -> str:
    name = Path(path).name
    for suffix in (".rprpr.yaml", ".rprpr.yml", ".yaml", ".yml"):
        if name.endswith(suffix):
            return name[: -len(suffix)]
    return name


def _rational(text: str | None, option: str) -> fmpq | None:
    """A positive exact number from the option's text (the task file's number rules: a
    decimal or a fraction, digits and exponent capped)."""
    if text is None:
        return None
    from ..io.expression import parse_fraction
    from ..model.errors import ExpressionError

    try:
        q = parse_fraction(text)
    except ExpressionError as e:
        raise click.BadParameter(str(e), param_hint=option) from None
    if q <= 0:
        raise click.BadParameter(f"expected a positive number, found {text}", param_hint=option)
    return q


def _plot(r: Repair, old: str, new: str, out: str) -> None:
    """The sheet of the old and the new motion overlaid (as ``rprpr plot OLD NEW``)."""
    from ..engine.audit import audit
    from ..render import sheet as P

    motions = [
        P.motion(audit(r.before.task, peak=True), old),
        P.motion(audit(r.task, peak=True), new),
    ]
    fig = P.render(motions, list(P.PANELS))
    write_atomic(out, lambda tmp: P.save(fig, tmp, P.format_of(out), motions=motions), "the sheet")

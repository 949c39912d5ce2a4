"""``rprpr repair``: turn a failing motion into the nearest one that passes, exactly
(``rprpr.repair``), write it as a task file and say what changed.

What is written is the task file itself with only the keys the repair changed rewritten
(``io.edit``): its comments, key order, formatting and number spelling elsewhere are
kept, byte for byte. To a new file (``-o``, by default ``<stem>.repaired.rprpr.yaml``
beside TASK) the task is renamed "(repaired)", a comment names its origin, and the first
line is ``rprpr init``'s schema modeline (or the task's own, when it still points at the
same schema from there); ``--in-place`` writes over TASK (atomically, its permissions
kept) and changes nothing but the motion; ``--diff`` prints the unified diff that
``--in-place`` would make and writes nothing (exit 1 when a change is needed, 0 when
none, as ``ruff --diff``). A file whose form cannot be edited key by key (anchors, a
robot or checks the repair changed) is written whole, and the command says so.

The output is written only after it has been read back (``io.loader``), found to be the
repaired motion exactly, and checked in strict mode; a task that would fail is never
written. Exits 0 when the repaired task is written (or nothing needed repair), 1 when no
repair exists within the constraints (the reason on standard error, nothing written) or
``--diff`` shows a change, 2 for bad input.
"""

from __future__ import annotations

import difflib
import os
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import click
from flint import fmpq

from ..model.actuation import SCHEMES
from ..model.defaults import SCHEMA_MODELINE
from ..model.errors import TaskFileError
from ..model.names import file_name
from ..model.numbers import number, outward
from ..model.options import AuditOptions
from ..report.exit import ExitCode
from .errors import InputError
from .options import SHEET_FORMATS, output_file_option, require_plotting, suffix_choice
from .output import echo, refuse_overwriting_inputs, say, write_atomic, writing
from .tasks import STDIN, load, read_task, stdin_bytes, task_inputs, task_named
from .uncertainty import needs_limit

if TYPE_CHECKING:
    from ..model.task import Task
    from ..repair import Repair


@click.command()
@click.argument("task", type=click.Path(readable=False))
@output_file_option("The repaired task file. Default: <stem>.repaired.rprpr.yaml beside TASK.")
@click.option(
    "--in-place",
    "-i",
    "in_place",
    is_flag=True,
    help="Write the repaired motion over TASK (atomically, its permissions kept): only the "
    "keys that change are rewritten.",
)
@click.option(
    "--diff",
    "show_diff",
    is_flag=True,
    help="Print the unified diff --in-place would make, write nothing; exit 1 when a change "
    "is needed, 0 when none.",
)
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
    in_place: bool,
    show_diff: bool,
    keep: str | None,
    window: str | None,
    slope: str | None,
    plot_file: str | None,
) -> ExitCode:
    """Write the nearest passing motion of a failing TASK: local, exact changes of the
    timing law and/or the path around each failing singular instant (zero slope, zero
    speed, inconsistency of eq. 34, a touch), checked strictly before it is written. Only
    the keys that change are rewritten: comments and formatting elsewhere are kept."""
    from ..repair import NoRepair
    from ..repair import repair as repaired

    # every usage error before any work or write
    _exclusive(task, output_file, in_place, show_diff, plot_file)
    if plot_file is not None:  # the sheet needs the extra rprpr[plot], in a known format
        require_plotting("repair --plot")
        suffix_choice(plot_file, SHEET_FORMATS, "the sheet", "--plot")
    window_q, slope_q = _rational(window, "--window"), _rational(slope, "--slope")
    out = task if in_place or show_diff else output_file or _default_output(task)
    outputs = [plot_file] if in_place or show_diff else [out, plot_file]
    if task != STDIN:
        refuse_overwriting_inputs(outputs, [task])  # before any work
    old, data = _read(task)
    refuse_overwriting_inputs(outputs, task_inputs(task, old))
    from ..engine.five_bar_audit import refuse_command

    with task_named(task):
        refuse_command(old, "repair")
        try:
            r = repaired(old, keep=keep, window=window_q, slope=slope_q)
        except NoRepair as why:
            say(f"rprpr: {task}: no repair: {why}; nothing written")
            return ExitCode.FAILED
    if not r.changed:
        line = f"{task}: passes the {_strict(old)} check: nothing to repair, nothing written"
        if show_diff:
            say(f"rprpr: {line}")
        else:
            echo(line)
        return ExitCode.PASSED
    with task_named(task):
        text = _repaired_text(r, task, data, out, new_file=not (in_place or show_diff))
    if text is None:
        return ExitCode.FAILED
    if show_diff:
        return _show_diff(r, task, data, text)
    return _write(r, task, text, out, plot_file)


def _show_diff(r: Repair, task: str, data: str, text: str) -> ExitCode:
    """The repair as a unified diff of TASK on standard output (nothing written)."""
    for line in summary(r):
        say(line)
    with writing("the diff", None, ExitCode.FAILED):
        sys.stdout.write(unified_diff(data, text, task))
        sys.stdout.flush()
    return ExitCode.FAILED


def _write(r: Repair, task: str, text: str, out: str, plot_file: str | None) -> ExitCode:
    """The repaired text written to ``out`` (atomically), then the sheet if asked for."""

    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            fh.write(text)

    write_atomic(out, write, "the task")
    for line in summary(r):
        echo(line)
    echo(f"checked {out} ({_strict(r.task)}): pass")
    say(f"rprpr: wrote {out}")
    if plot_file is not None:
        _plot(r, task, out, plot_file)
        say(f"rprpr: wrote {plot_file}")
    return ExitCode.PASSED


def _exclusive(
    task: str, output_file: str | None, in_place: bool, show_diff: bool, plot_file: str | None
) -> None:
    """Usage errors for options that cannot go together."""
    if in_place and show_diff:
        raise click.UsageError("--in-place and --diff cannot go together (--diff writes nothing)")
    if output_file is not None and (in_place or show_diff):
        option = "--in-place" if in_place else "--diff"
        raise click.UsageError(f"-o and {option} cannot go together ({option} is about TASK)")
    if show_diff and plot_file is not None:
        raise click.UsageError("--diff writes nothing: draw with --plot without --diff")
    if in_place and task == STDIN:
        raise click.UsageError("--in-place needs a task file, not standard input")


def _read(task: str) -> tuple[Task, str]:
    """The task in ``task`` (``-``: standard input) and the text of its file."""
    if task == STDIN:
        try:
            raw = stdin_bytes()
            old = read_task(STDIN, raw)
            needs_limit(old)  # no configuration here: the task's own limit
        except TaskFileError as e:
            raise InputError(str(e)) from None
    else:
        old = load(task)
        try:
            raw = Path(task).read_bytes()
        except OSError as e:  # gone since it was read: the environment
            raise InputError(f"{task}: cannot read it again: {e.strerror or e}") from None
    return old, raw.decode("utf-8")  # the loader read it as UTF-8 already


def _default_output(task: str) -> str:
    return str(Path(task).with_name(_stem(task) + ".repaired.rprpr.yaml"))


def _repaired_text(r: Repair, task: str, data: str, out: str, *, new_file: bool) -> str | None:
    """The text to write: ``data`` with the changed keys edited (``io.edit``), else the
    task written whole; read back, found to be the repaired motion and checked strictly
    first. None (the reason said) when it cannot be written."""
    from ..engine.audit import audit
    from ..io.edit import edit, same_motion
    from ..io.loader import parse_task
    from ..io.writer import task_text
    from ..repair import passes

    comment = f"{r.before.task.name}, repaired by rprpr repair from {file_name(Path(task).name)}"
    folder = os.path.dirname(os.path.abspath(task)) if task != STDIN else os.getcwd()
    edited = edit(data, r.before.task, r.task, rename=new_file)
    if edited is not None and new_file:
        edited = _head(edited, comment, task, out)
    whole = task_text(r.task if new_file else _named(r.task, r.before.task), comment)
    for candidate, is_whole in ((edited, False), (whole, True)):
        if candidate is None:
            continue
        try:
            back = parse_task(candidate, out, directory=folder)
        except TaskFileError as e:  # exact, but beyond a task file's number limits
            say(
                f"rprpr: {task}: the repaired motion is exact but its coefficients exceed what"
                f" a task file holds ({e.message}); use the Python API (rprpr.repair) for the"
                " task itself; nothing written"
            )
            return None
        if not same_motion(back, r.task):
            continue  # an edit that reads back otherwise: the task written whole instead
        if not passes(audit(back, AuditOptions(strict=True))):  # never write a failing task
            say(
                f"rprpr: {task}: the repaired task read back fails the strict check;"
                " nothing written"
            )
            return None
        if is_whole:
            say(
                f"rprpr: {task}: its form cannot be edited key by key; the repaired task is"
                " written whole (its comments are not kept)"
            )
        return candidate
    say(f"rprpr: {task}: the repaired task does not read back as written; nothing written")
    return None


def _named(new: Task, old: Task) -> Task:
    from dataclasses import replace

    return replace(new, name=old.name)


def _head(text: str, comment: str, task: str, out: str) -> str:
    """A new file's first lines: the schema modeline (the task's own when it points at the
    same schema from ``out``: a URL, or a path from the same folder; else ``rprpr
    init``'s), then ``comment``; the rest of ``text`` as it is."""
    from ..io.edit import modeline

    newline = "\r\n" if "\r\n" in text else "\n"
    target = modeline(text)
    if target is not None:
        text = text.split("\n", 1)[1] if "\n" in text else ""
    same_folder = task != STDIN and (
        os.path.dirname(os.path.abspath(task)) == os.path.dirname(os.path.abspath(out))
    )
    keep = target is not None and ("://" in target or same_folder)
    first = f"# yaml-language-server: $schema={target}" if keep else SCHEMA_MODELINE
    return f"{first}{newline}# {comment}{newline}{text}"


def unified_diff(old: str, new: str, name: str) -> str:
    """The unified diff from ``old`` to ``new`` (``--- name`` / ``+++ name``, as ruff's);
    a last line without a line break is marked as diff marks it."""
    lines = difflib.unified_diff(
        old.splitlines(keepends=True), new.splitlines(keepends=True), name, name
    )
    return "".join(ln if ln.endswith("\n") else ln + "\n\\ No newline at end of file\n"
                   for ln in lines)  # fmt: skip


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
    lines += robust_lines(r)
    return lines + [f"warning: {w}" for w in r.warnings]


def robust_lines(r: Repair) -> list[str]:
    """With declared uncertainty, the repaired motion's worst case at each singular
    instant (``docs/robust.md``): the residual over the box and the proven window."""
    u = r.task.uncertainty
    if u is None:
        return []
    out = []
    for s, b in zip(r.after.singularities, r.after.robust, strict=False):
        lo, hi = outward(*b.residual)
        window = f"{number(b.window, 3, 1, 3)} ms" if b.window > 0 else "none"
        out.append(
            f"  over the box at t = {s.t:.6g} s: residual [{lo}, {hi}] N, saturation"
            f" window {window} (period {float(u.period) * 1e3:.3g} ms)"
        )
    return out


def _strict(task: Task) -> str:
    """The check a repair passes: strict, but with uncertainty RPR201 is RPR205's to
    decide (``repair.passes``)."""
    return "strict" if task.uncertainty is None else "strict, RPR201 left to RPR205"


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
    """The sheet of the old and the new motion overlaid (as ``rprpr plot OLD NEW``), in
    the legends "before" and "after", with the change itself: its own panel (new - old in
    mm, the account's largest change marked) and insets zoomed at that change."""
    from dataclasses import replace

    from ..engine.audit import audit
    from ..render import sheet as P

    motions = [
        replace(P.motion(audit(r.before.task, AuditOptions(peak=True)), old), label="before"),
        replace(P.motion(audit(r.task, AuditOptions(peak=True)), new), label="after"),
    ]
    change = P.Change(timing=r.timing_change, path=r.path_deviation)
    fig = P.render(motions, list(P.PANELS), change=change)
    write_atomic(out, lambda tmp: P.save(fig, tmp, P.format_of(out), motions=motions), "the sheet")

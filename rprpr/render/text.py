"""The human report of ``rprpr check`` (rich), from the plain reports of ``report``.

For each task, as a linter writes it (ruff's concise style): one line per finding,
``FILE:LINE:COL: RPRnnn [severity] name: message`` (editors and terminals jump to it),
then the task (file and name), its singular instants (the table when it fits the width,
else stacked ``key  value`` rows per instant, so that nothing is cut at any width: 80
columns, 60) and its verdict line with the certified torque peak. A finding's line is
never wrapped, on a terminal or not (a terminal folds it for the eye, but the text keeps
it one line: grep, editors and problem matchers see its ``FILE:LINE`` with all of it);
the other lines wrap at the width, and only a token longer than the width is folded.

Every text that came from outside (a file name, a task's name, a value quoted in a
message) is printed through ``escape.printable``: no control character reaches the
terminal, and no line can be forged."""

from __future__ import annotations

from typing import Any

from rich.console import Console
from rich.measure import Measurement
from rich.table import Table
from rich.text import Text

from ..model.actuation import REVOLUTE
from ..model.numbers import CELL, number
from ..report.records import instant_times, scheme
from ..report.run import Run
from . import phrases
from .escape import printable

# the columns of an instant: (title, justify in the table)
COLUMNS = (
    ("t [s]", "right"), ("(x, y) [m]", "left"), ("case σ ψ", "left"), ("order", "left"),
    ("dy/dx", "right"), ("speed [m/s]", "right"), ("slope", "left"), ("velocity", "left"),
    ("eq.(34) [N]", "right"), ("bounded", "left"), ("T(t_s) [N m]", "left"),
)  # fmt: skip


def _cell(v: float | None) -> str:
    return "—" if v is None else number(v, CELL)


def _pf(v: str) -> Text:
    return Text("pass", style="green") if v == "pass" else Text("FAIL", style="bold red")


def columns(rep: dict[str, Any]) -> tuple[tuple[str, str], ...]:
    """``COLUMNS`` with the titles of the task's actuation scheme (prismatic: the
    moment balance residual and F(t_s) [N])."""
    e = scheme(rep)
    if e.name == REVOLUTE:
        return COLUMNS
    named = {"eq.(34) [N]": e.column, "T(t_s) [N m]": f"{e.letter}(t_s) [{e.unit}]"}
    return tuple((named.get(title, title), just) for title, just in COLUMNS)


def _cells(s: dict[str, Any], t: str) -> list[Text]:
    """The cells of one singular instant, in the order of ``COLUMNS``."""
    order = f"{s['order']} {s['kind']}"
    bounded = f"{s['conditions_met']}/{s['conditions_required']}"
    torque = (
        ", ".join(_cell(v) for v in s["torque_at_singularity"])
        if s["torque_at_singularity"]
        else "sides differ"  # a knot whose two one-sided limits are finite but differ
        if s["torque_bounded"]
        else "unbounded"
    )
    return [
        Text(t),
        Text(f"({_cell(s['x'])}, 0)"),
        Text(f"{s['case']}  {s['sigma']:+d} {s['psi']:+d}"),
        Text(order, style="bold red" if s["high_order"] else ""),
        Text(_cell(s["slope"])),
        Text(_cell(s["speed"])),
        _pf(s["slope_principle"]),
        _pf(s["velocity_principle"]),
        Text(_cell(s["consistency_residual"])),
        Text(
            bounded + (" yes" if s["torque_bounded"] else f" no, pole {s['pole_order']}"),
            style="green" if s["torque_bounded"] else "yellow",
        ),
        Text(torque),
    ]


def singularity_table(rep: dict[str, Any]) -> Table:
    """The singular instants of ``rep`` as one table, a row per instant."""
    table = Table(title=None, show_lines=False, header_style="bold")
    for col, just in columns(rep):
        table.add_column(Text(col), justify=just, no_wrap=True)  # type: ignore[arg-type]
    times = instant_times(rep)
    for s in rep["singularities"]:
        table.add_row(*_cells(s, times[s["t"]]))
    return table


def stacked(rep: dict[str, Any]) -> Table:
    """The singular instants of ``rep`` as ``key  value`` rows, one block per instant:
    every cell of the table, in any width."""
    grid = Table.grid(padding=(0, 2))
    grid.add_column(style="bold", no_wrap=True)
    grid.add_column(overflow="fold")
    times = instant_times(rep)
    for i, s in enumerate(rep["singularities"]):
        cells = _cells(s, times[s["t"]])
        grid.add_row(Text(f"instant {i + 1}"), Text.assemble("t = ", cells[0], " s"))
        for (title, _), cell in zip(columns(rep)[1:], cells[1:], strict=True):
            grid.add_row(Text(f"  {title}"), cell)
    return grid


def _natural(console: Console, table: Table) -> int:
    """The width ``table`` takes with no cell wrapped or cut."""
    unbounded = console.options.update_width(1 << 16)  # its natural width, not capped
    return Measurement.get(console, unbounded, table).maximum


def _fits(console: Console, table: Table) -> bool:
    """Whether ``table`` fits the console's width with no cell wrapped or cut."""
    return _natural(console, table) <= console.width


def render(
    run: Run, console: Console, err_console: Console, quiet: bool = False,
    errors_inline: bool = False, layout: str = "auto",
) -> None:  # fmt: skip
    """Print each task's report in task order, then a summary line when more than one
    task was checked. A task file that could not be read (or met a bug) is one line per
    error on ``err_console``, or in the report itself when ``errors_inline``. ``quiet``
    leaves out passing tasks, and the summary when every task passed. ``layout``: the
    singular instants as a "table", as key/value "rows", or "auto" (the table where it
    fits the width)."""
    for kind, item, _ in run.entries():
        if kind != "report":
            style = "red" if kind == "input" else "bold red"
            target = console if errors_inline else err_console
            for e in item.get("errors", [item]):  # a bad task file: each of its errors
                target.print(Text(printable(e["text"]), style=style), soft_wrap=True)
            continue
        if quiet and item["verdict"] == "pass":
            continue
        _task(item, console, layout)
    s = run.summary()
    if s["tasks"] > 1 and not (quiet and s["passed"] == s["tasks"]):
        errors = f"{s['errors']} error{'s' if s['errors'] != 1 else ''}"
        console.print(
            f"{s['tasks']} tasks: {s['passed']} passed, {s['failed']} failed, {errors}",
            style="bold",
        )


def finding_line(rep: dict[str, Any], f: dict[str, Any]) -> Text:
    """``FILE:LINE:1: RPRnnn [severity] name: message`` (the column: the key starts its
    line); a warning is a strict-mode-only finding, which fails only with --strict."""
    style = "red" if f["severity"] == "error" else "yellow"
    return Text.assemble(
        (f"{printable(rep['task'])}:{f['line']}:1:", "bold"),
        " ",
        (f["rule"], style),
        f" [{f['severity']}] {f['name']}: {printable(f['message'])}",
    )


def _task(rep: dict[str, Any], console: Console, layout: str = "auto") -> None:
    for f in rep["findings"]:  # one line each, never wrapped (grep, editors, matchers)
        console.print(finding_line(rep, f), soft_wrap=True)
    console.print(Text.assemble((printable(rep["task"]), "bold"), " — ", printable(rep["name"])))
    times = instant_times(rep)
    for line in phrases.details(rep, times):
        console.print(Text(f"  {line}"))
    if rep["singularities"]:
        table = singularity_table(rep)
        if layout == "table":  # asked for: at its natural width, however narrow the terminal
            narrow = console.width
            console.width = max(_natural(console, table), narrow)
            console.print(table)
            console.width = narrow
        else:
            wide = layout == "auto" and _fits(console, table)
            console.print(table if wide else stacked(rep))
    console.print(_verdict(rep))


def _verdict(rep: dict[str, Any]) -> Text:
    """``  verdict: FAIL — 1 singular instant, 1 high-order; <the torque peak>``."""
    n = len(rep["singularities"])
    high = sum(s["high_order"] for s in rep["singularities"])
    peak = phrases.peak(rep)
    verdict = (
        Text("PASS", style="bold green")
        if rep["verdict"] == "pass"
        else Text("FAIL", style="bold red")
    )
    return Text.assemble(
        "  verdict: ", verdict,
        f" — {n} singular instant{'s' if n != 1 else ''}, {high} high-order",
        f"; {peak}" if peak else "", " (strict)" if rep["strict"] else "",
    )  # fmt: skip

"""The human report of ``rprpr check`` (rich), from the plain reports of ``report``.

Every text that came from outside (a file name, a task's name, a value quoted in a
message) is printed through ``escape.printable``: no control character reaches the
terminal, and no line can be forged."""

from __future__ import annotations

from typing import Any

from rich.console import Console
from rich.table import Table
from rich.text import Text

from ..model.numbers import CELL, number
from ..report.records import instant_times
from ..report.run import Run
from . import phrases
from .escape import printable


def _cell(v: float | None) -> str:
    return "—" if v is None else number(v, CELL)


def _pf(v: str) -> Text:
    return Text("pass", style="green") if v == "pass" else Text("FAIL", style="bold red")


def singularity_table(rep: dict[str, Any]) -> Table:
    table = Table(title=None, show_lines=False, header_style="bold")
    for col, just in (
        ("t [s]", "right"), ("(x, y) [m]", "left"), ("case σ ψ", "left"), ("order", "left"),
        ("dy/dx", "right"), ("speed [m/s]", "right"), ("slope", "left"), ("velocity", "left"),
        ("eq.(34) [N]", "right"), ("bounded", "left"), ("T(t_s) [N m]", "left"),
    ):  # fmt: skip
        table.add_column(Text(col), justify=just)  # type: ignore[arg-type]
    times = instant_times(rep)
    for s in rep["singularities"]:
        order = f"{s['order']} {s['kind']}"
        order_text = Text(order, style="bold red" if s["high_order"] else "")
        bounded = f"{s['conditions_met']}/{s['conditions_required']}"
        bounded_text = Text(
            bounded + (" yes" if s["torque_bounded"] else f" no, pole {s['pole_order']}"),
            style="green" if s["torque_bounded"] else "yellow",
        )
        torque = (
            ", ".join(_cell(v) for v in s["torque_at_singularity"])
            if s["torque_at_singularity"]
            else "unbounded"
        )
        table.add_row(
            times[s["t"]],
            f"({_cell(s['x'])}, 0)",
            f"{s['case']}  {s['sigma']:+d} {s['psi']:+d}",
            order_text,
            _cell(s["slope"]),
            _cell(s["speed"]),
            _pf(s["slope_principle"]),
            _pf(s["velocity_principle"]),
            _cell(s["consistency_residual"]),
            bounded_text,
            torque,
        )
    return table


def render(
    run: Run, console: Console, err_console: Console, quiet: bool = False,
    errors_inline: bool = False,
) -> None:  # fmt: skip
    """Print each task's report in task order, then a summary line when more than one
    task was checked. A task file that could not be read (or met a bug) is one line on
    ``err_console``, or in the report itself when ``errors_inline``. ``quiet`` leaves out
    passing tasks, and the summary when every task passed."""
    for kind, item, _ in run.entries():
        if kind != "report":
            style = "red" if kind == "input" else "bold red"
            target = console if errors_inline else err_console
            for e in item.get("errors", [item]):  # a bad task file: each of its errors
                target.print(Text(printable(e["text"]), style=style), soft_wrap=True)
            continue
        if quiet and item["verdict"] == "pass":
            continue
        _task(item, console)
    s = run.summary()
    if s["tasks"] > 1 and not (quiet and s["passed"] == s["tasks"]):
        errors = f"{s['errors']} error{'s' if s['errors'] != 1 else ''}"
        console.print(
            f"{s['tasks']} tasks: {s['passed']} passed, {s['failed']} failed, {errors}",
            style="bold",
        )


def _task(rep: dict[str, Any], console: Console) -> None:
    console.print(Text.assemble((printable(rep["task"]), "bold"), " — ", printable(rep["name"])))
    times = instant_times(rep)
    n = len(rep["singularities"])
    if n:
        console.print(singularity_table(rep))
    elif rep["on_singular_line"]:
        console.print("  the path lies on the singular line y = 0", style="red")
    else:
        console.print("  no Type II singular instant in [0, t_f]")
    for k in rep["kinematic_singularities"]:
        joint = "A" if k["leg"] == 1 else "B"
        console.print(
            f"  inverse-kinematic singularity at t = {times[k['t']]} s: E at {joint}", style="red"
        )
    for b in rep["beyond_double_range"]:
        console.print(f"  {b['quantity']} = {b['value']}: beyond the double range", style="yellow")
    for f in rep["findings"]:
        if f["severity"] == "error":
            title = (f"{f['rule']} {f['name']}", "red")
        else:  # strict-mode-only, not strict: shown, does not fail the task
            title = (f"{f['rule']} {f['name']} (warning, fails with --strict)", "yellow")
        console.print(Text.assemble("  ", title, f": {printable(f['message'])}"), soft_wrap=True)
    near = phrases.approach(rep)
    if near:
        console.print(f"  {near}", soft_wrap=True)
    peak = phrases.peak(rep)
    peak_text = f"; {peak}" if peak else ""
    verdict = (
        Text("PASS", style="bold green")
        if rep["verdict"] == "pass"
        else Text("FAIL", style="bold red")
    )
    high = sum(s["high_order"] for s in rep["singularities"])
    console.print(
        Text.assemble(
            "  verdict: ", verdict,
            f" — {n} singular instant{'s' if n != 1 else ''}, {high} high-order{peak_text}",
            " (strict)" if rep["strict"] else "",
        ),
        soft_wrap=True,  # one line, as the findings: the terminal wraps it, if at all
    )  # fmt: skip

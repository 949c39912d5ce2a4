"""What the panels share: the look of a task's curve, the lines at the singular instants
and at the knots of a piecewise motion on a time axis, degree ticks, and the legend
entries (quantities and tasks, the knots once)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from matplotlib import ticker
from matplotlib.axes import Axes
from matplotlib.lines import Line2D

from .motion import Motion
from .page import Indexed, Sheet
from .style import (
    KNOT,
    KNOT_LABEL,
    QUANTITY_STYLES,
    SEVERITY,
    STATUS_COLOUR,
    style,
    task_colour,
)
from .words import short


def look(sheet: Sheet, i: int, colour: str, leg: int = 0, pair: bool = False) -> dict[str, Any]:
    """Colour and line style of task i's curve whose one-task colour is ``colour``: leg
    ``leg`` (0 or 1) of a ``pair`` of quantities, or a single quantity."""
    if not sheet.overlay:
        return {"color": colour, "ls": "-"}
    return {"color": task_colour(i), "ls": QUANTITY_STYLES[leg] if pair else style(i)}


def handles(sheet: Sheet, quantities: Sequence[tuple[str, str]]) -> list[Any]:
    """Legend entries: the quantities (label, one-task colour) and, in an overlay, the
    tasks by colour (and by line style for a single quantity)."""
    if not sheet.overlay:
        return [Line2D([], [], color=c, label=q) for q, c in quantities]
    col = sheet.columns[0]
    if len(quantities) == 1:
        return [
            Line2D([], [], label=m.label or short(m.name, 34), **look(sheet, i, quantities[0][1]))
            for i, m in col
        ]
    out: list[Any] = [
        Line2D([], [], color="#555555", ls=QUANTITY_STYLES[j], label=q)
        for j, (q, _) in enumerate(quantities)
    ]
    out += [
        Line2D([], [], color=task_colour(i), label=m.label or short(m.name, 34)) for i, m in col
    ]
    return out


def instant_lines(ax: Axes, column: Indexed, name: str) -> None:
    """Vertical lines at each task's singular instants (gid ``<name>-tsline-<task>-<k>``;
    in its status's colour, grey when it passes), inverse-kinematic ones (red, dotted) and
    the knots of a piecewise motion (light, ``KNOT``; gid ``<name>-knot-<task>-<k>``)."""
    for i, m in column:
        _lines(ax, m, i, name)
        knot_lines(ax, m, f"{name}-knot-{i}")


def knot_lines(ax: Axes, m: Motion, gid: str) -> None:
    """A light vertical line at each knot of ``m``'s motion (gid ``<gid>-<k>``), on the
    sheet and in the GIF alike; none for a motion of one polynomial."""
    for k, t in enumerate(m.task.knots):
        ax.axvline(float(t), gid=f"{gid}-{k}", **KNOT)


def knot_handles(sheet: Sheet) -> list[Any]:
    """The knots' legend entry, for the first time panel's legend only (none when no
    task has knots)."""
    if sheet.knot_said or not any(m.task.knots for m in sheet.motions):
        return []
    sheet.knot_said = True
    return [Line2D([], [], label=KNOT_LABEL, **{k: v for k, v in KNOT.items() if k != "zorder"})]


def _lines(ax: Axes, m: Motion, i: int, name: str) -> None:
    for k, s in enumerate(m.result.singularities):
        st = m.result.status_of(s)
        ax.axvline(
            s.t,
            color="#888888" if st == "ok" else STATUS_COLOUR[st],
            ls=(0, (4, 3)),
            lw=0.9,
            zorder=0.6 + 0.01 * SEVERITY[st],
            gid=f"{name}-tsline-{i}-{k}",
        )
    for k, ks in enumerate(m.result.kinematic_singularities):
        ax.axvline(
            ks.t,
            color=STATUS_COLOUR["fail"],
            ls=":",
            lw=1.2,
            zorder=0.65,
            gid=f"{name}-kinematic-{i}-{k}",
        )


def degree_ticks(ax: Axes, lo: float, hi: float) -> None:
    """Ticks on the y axis at a round number of degrees, at most 6 over [lo, hi]."""
    span = max(hi - lo, 1e-9)
    for step in (5, 10, 15, 30, 45, 90, 180, 360, 720):
        if span / step <= 6:
            ax.yaxis.set_major_locator(ticker.MultipleLocator(step))
            return

"""The ``delta`` panel: the Type II determinant δ(t) = sin(θ1 - θ2) (eq. 29, the paper's
Fig. 4), each singular instant marked and keyed to its order and what vanishes; the
closest approach of a motion that never meets the singular line marked with min |δ|."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.lines import Line2D

from ....model.numbers import number
from ..axes import handles, instant_lines, knot_handles, look
from ..drawing import kinds
from ..markers import badge, mark
from ..motion import finite
from ..page import Indexed, Sheet
from ..style import DELTA, NEAR_DELTA
from ..words import near_miss_delta, order_text, vanishing

ROW = 1.9  # in
APPROACH: dict[str, Any] = {
    "marker": "o",
    "ms": 6,
    "mfc": "white",
    "mew": 1.4,
    "ls": "none",
    "zorder": 7,
}


def draw(sheet: Sheet, pole_inset: bool = False) -> list[Axes]:
    sheet.heading(*headings(sheet))
    (row,) = sheet.rows("delta", (ROW,))
    for ax, col in zip(row, sheet.columns, strict=True):
        ax.axhspan(-NEAR_DELTA, NEAR_DELTA, color="#999999", alpha=0.12, lw=0, zorder=0.2)
        ax.axhline(0, color="#444444", lw=0.8, zorder=0.7)
        instant_lines(ax, col, "delta")
        for i, m in col:
            kw = look(sheet, i, DELTA)
            ax.plot(m.s.t, finite(m.s.delta), lw=1.7, gid=f"delta-{i}", **kw)
        mark(ax, "delta", sheet, col, lambda m, s: 0.0)
        _approaches(sheet, ax, col)
    row[0].set_ylabel(r"$\delta$ [–]")
    near = f"near singular: |δ| < {number(NEAR_DELTA)}"
    band = Line2D([], [], color="#999999", alpha=0.35, lw=6, label=near)
    sheet.lane(row[-1], [*handles(sheet, [("δ", DELTA)]), band, *knot_handles(sheet)], notes(sheet))
    return row


FIVE_BAR_DELTA = "(E − C) × (E − D)/(l3 l4)"  # a 5R's δ: the sine between its distal links


def headings(sheet: Sheet) -> tuple[str, ...]:
    """The panel's heading and its shorter forms: the RPRPR's δ = sin(θ1 − θ2) (eq. 29),
    a 5R's δ (the sine of the angle between its distal links), or both named."""
    rprpr, five = kinds(sheet.motions)
    if not five:
        return (
            "Type II determinant δ(t) = sin(θ1 − θ2), eq. (29) (paper Fig. 4)",
            "Type II determinant δ(t) = sin(θ1 − θ2), eq. (29)",
            "δ(t) = sin(θ1 − θ2), eq. (29)",
        )
    if not rprpr:
        return (
            f"Type II determinant δ(t) = {FIVE_BAR_DELTA}, the sine between the distal links",
            f"Type II determinant δ(t) = {FIVE_BAR_DELTA}",
            f"δ(t) = {FIVE_BAR_DELTA}",
        )
    return (
        "Type II determinant δ(t) = sin(θ1 − θ2), eq. (29) (paper Fig. 4) for an RPRPR,"
        f" {FIVE_BAR_DELTA} for a 5R",
        "Type II determinant δ(t) (RPRPR, 5R)",
        "δ(t)",
    )


def _approaches(sheet: Sheet, ax: Axes, col: Indexed) -> None:
    """Where |δ| is least on a motion that never reaches δ = 0: a ring, keyed."""
    for i, m in col:
        a = m.result.closest_approach
        if a is None:
            continue
        d = float(m.result.resample(np.array([a.t_delta])).delta[0])
        colour = look(sheet, i, DELTA)["color"]
        ax.plot([a.t_delta], [d], mec=colour, gid=f"delta-approach-{i}", **APPROACH)
        badge(
            ax,
            sheet.keys[i, "approach"],
            (a.t_delta, d),
            0,
            12 if d >= 0 else -12,
            f"delta-approach-key-{i}",
        )


def notes(sheet: Sheet) -> list[str]:
    """The keys of the marks: each singular instant's time, order and what vanishes;
    each closest approach's min |δ|."""
    out = []
    for i, m in enumerate(sheet.motions):
        who = sheet.who(m)
        for key, s, t in sheet.keyed(i):
            out.append(f"{key}  {who}t = {t} s, {order_text(s)} ({vanishing(s.order)})")
        if m.result.closest_approach is not None:
            out.append(
                f"{sheet.keys[i, 'approach']}  {who}{near_miss_delta(m.result.closest_approach)}"
            )
    return out + sheet.crowded()

"""The ``x`` panel: the end point's coordinates x_E(t) (the paper's Fig. 2) over y_E(t)."""

from __future__ import annotations

from matplotlib.axes import Axes
from matplotlib.lines import Line2D

from ..axes import handles, instant_lines, knot_handles, look
from ..drawing import drawing, kinds
from ..markers import mark
from ..motion import finite
from ..page import Sheet
from ..style import LINE, LINE_DASH, POINT

ROW = 1.35  # in, each of x_E and y_E


def draw(sheet: Sheet, pole_inset: bool = False) -> list[Axes]:
    rprpr, _ = kinds(sheet.motions)
    sheet.heading(
        "End-point coordinates x_E(t) (paper Fig. 2) and y_E(t)"
        if rprpr
        else "End-point coordinates x_E(t) and y_E(t)",
        "End-point x_E(t), y_E(t)",
    )
    row_x, row_y = sheet.rows("x", (ROW, ROW))
    for ax_x, ax_y, col in zip(row_x, row_y, sheet.columns, strict=True):
        if any(drawing(m).y_line for _, m in col):  # the RPRPR's singular line y = 0
            ax_y.axhline(0, color=LINE, lw=1.0, ls=LINE_DASH, zorder=1)
        for ax, v, name in ((ax_x, "x", "x"), (ax_y, "y", "y")):
            instant_lines(ax, col, name)
            for i, m in col:
                kw = look(sheet, i, POINT)
                ax.plot(m.s.t, finite(getattr(m.s, v)), lw=1.6, gid=f"{name}-{i}", **kw)
        mark(ax_x, "x", sheet, col, lambda m, s: s.x)
        mark(ax_y, "y", sheet, col, lambda m, s: drawing(m).y_mark(s))
    row_x[0].set_ylabel("$x_E$ [m]")
    row_y[0].set_ylabel("$y_E$ [m]")
    line = Line2D([], [], color=LINE, lw=1.0, ls=LINE_DASH, label="singular line y = 0")
    lines = [line] if rprpr else []
    sheet.lane(
        row_x[-1], [*handles(sheet, [("$x_E$, $y_E$", POINT)]), *lines, *knot_handles(sheet)]
    )
    return [*row_x, *row_y]

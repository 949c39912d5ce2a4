"""The ``x`` panel: the end point's coordinates x_E(t) (the paper's Fig. 2) and y_E(t)."""

from __future__ import annotations

from collections.abc import Sequence

from matplotlib.axes import Axes
from matplotlib.figure import SubFigure
from matplotlib.lines import Line2D

from ..axes import legend, panel_title, time_axes
from ..markers import mark
from ..motion import Motion, finite
from ..style import LINE, LINE_DASH, POINT, style


def height(motions: Sequence[Motion]) -> float:
    return 3.0


def draw(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    panel_title(sf, "End-point coordinates (paper Fig. 2)", motions)
    ax_x, ax_y = sf.subplots(1, 2)
    time_axes(ax_x, motions, "$x_E(t)$", "$x_E$ [m]", "x")
    time_axes(ax_y, motions, "$y_E(t)$", "$y_E$ [m]", "y")
    ax_y.axhline(0, color=LINE, lw=1.0, ls=LINE_DASH, zorder=1)
    for i, m in enumerate(motions):
        ax_x.plot(m.s.t, finite(m.s.x), color=POINT, ls=style(i), lw=1.6, gid=f"x-{i}")
        ax_y.plot(m.s.t, finite(m.s.y), color=POINT, ls=style(i), lw=1.6, gid=f"y-{i}")
    mark(ax_x, "x", motions, lambda m, s: s.x)
    mark(ax_y, "y", motions, lambda m, s: 0.0)
    legend(ax_x, [("$x_E$", POINT)], motions)
    line = Line2D([], [], color=LINE, lw=1.0, ls=LINE_DASH, label="singular line y = 0")
    legend(ax_y, [("$y_E$", POINT)], motions, [line])
    return [ax_x, ax_y]

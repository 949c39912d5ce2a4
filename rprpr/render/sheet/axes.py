"""The pieces every panel shares: its title, a time axis with the singular instants,
degree ticks, and the legend (quantities by colour, tasks by line style)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from matplotlib import ticker
from matplotlib.axes import Axes
from matplotlib.figure import SubFigure
from matplotlib.lines import Line2D

from .motion import Motion
from .style import SEVERITY, STATUS_COLOUR, style
from .words import names

OUTSIDE = {  # the legend of a full-width panel, right of the axes
    "loc": "upper left",
    "bbox_to_anchor": (1.01, 1.0),
    "borderaxespad": 0,
}


def panel_title(sf: SubFigure, what: str, motions: Sequence[Motion]) -> None:
    """The panel's title: what it shows, and for which tasks."""
    sf.suptitle(f"{what} — {names(motions)}", fontsize=10.5, fontweight="bold")


def time_axes(ax: Axes, motions: Sequence[Motion], title: str, ylabel: str, name: str) -> None:
    """A time axis over [0, max t_f] with a line at each singular instant (gid
    ``<name>-tsline-<task>-<k>``) and each inverse-kinematic one."""
    ax.set_title(title)
    ax.set_xlabel("t [s]")
    ax.set_ylabel(ylabel)
    ax.set_xlim(0, max(m.duration for m in motions))
    for i, m in enumerate(motions):
        _instant_lines(ax, m, i, name)


def _instant_lines(ax: Axes, m: Motion, i: int, name: str) -> None:
    """The vertical lines of task i's singular instants (in its status's colour, grey when
    it passes) and of its inverse-kinematic ones (red, dotted)."""
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
    """Ticks on the y axis at a round number of degrees, at most 8 over [lo, hi]."""
    span = max(hi - lo, 1e-9)
    for step in (5, 10, 15, 30, 45, 90, 180, 360, 720):
        if span / step <= 8:
            ax.yaxis.set_major_locator(ticker.MultipleLocator(step))
            return


def legend(
    ax: Axes,
    quantities: Sequence[tuple[str, str]],
    motions: Sequence[Motion],
    extra: Sequence[Any] = (),
    **kw: Any,
) -> None:
    """Quantities (label, colour) by colour; with several tasks, tasks by line style; then
    the ``extra`` handles."""
    if len(motions) == 1:
        handles = [Line2D([], [], color=c, label=q) for q, c in quantities]
    elif len(quantities) == 1:
        c = quantities[0][1]
        handles = [
            Line2D([], [], color=c, ls=style(i), label=m.name) for i, m in enumerate(motions)
        ]
    else:
        handles = [Line2D([], [], color=c, label=q) for q, c in quantities]
        handles += [
            Line2D([], [], color="#555555", ls=style(i), label=m.name)
            for i, m in enumerate(motions)
        ]
    handles += list(extra)
    ax.legend(handles=handles, **{"loc": "best", "framealpha": 0.88, **kw})

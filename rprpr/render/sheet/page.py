"""The sheet laid out on the page, in inches.

The figure is laid out by hand, in inches, top to bottom (``Sheet``): the title, then
each panel's heading and its rows of axes, each row as wide as every other time row and
at the same left edge, so that one vertical line at a time t runs through every time
axis; every time axis shares the first one's x-limits. Right of the axes runs the lane:
each row's legend and, keyed by number to the marks in the data, what the marks mean.
Text sizes are measured (with an Agg renderer at the figure's resolution) before a panel
is given its height, so nothing is clipped or overlaps; the figure's height is known and
set only when the last panel is placed.

Up to ``OVERLAID`` tasks share one column of axes; more get a column each (small
multiples) sharing the x- and y-limits of each row, except where that would mislead: a
row of efforts shares its y-limits only among columns in one unit (torques in N m,
forces in N: ``Sheet.rows``' groups, each with its own labelled y axis), and when the
shortest task lasts less than ``SHARED_TIME`` of the longest each column has its own time
axis over its own [0, t_f] (a 0.5 s task is not drawn on a 5 s axis). Times stay in
seconds rather than normalised by t_f: the keys, the check and the task file give t_s in
seconds, and the reader compares them with the axis.
"""

from __future__ import annotations

import functools
import textwrap
from collections.abc import Sequence
from dataclasses import field
from typing import Any

import matplotlib
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import RendererAgg
from matplotlib.figure import Figure
from matplotlib.text import Text

from ...engine.exact.singular import SingularInstant
from ...model.dataclass import dataclass
from .heads import Heads
from .labels import MAX_LABELS
from .measures import (
    COLUMN,
    COLUMN_GAP,
    DPI,
    LANE,
    LANE_GAP,
    LEFT,
    MARGIN,
    PANEL_GAP,
    PAPER_MARGIN,
    ROW_GAP,
    SHARED_TIME,
    UNIT_GAP,
    X_DECOR,
)
from .motion import Motion
from .style import FONT_SCALE, LABEL_SIZE, OVERLAID, WIDTH, pt, task_colour
from .words import instant_times, short

Indexed = list[tuple[int, Motion]]  # the motions of a column, each with its task index


@functools.cache
def measuring_renderer(dpi: float) -> RendererAgg:
    """The Agg renderer every sheet of the process measures its text with at ``dpi``.
    matplotlib keeps the size of each text a renderer has measured, and the sheets share
    most of theirs (tick labels, headings, keys); what it measures depends on its
    resolution only, never on its canvas, which is never painted (1 x 1)."""
    return RendererAgg(1, 1, dpi)  # type: ignore[no-untyped-call]


@functools.lru_cache(maxsize=64)
def _decor(width: float, settings: str) -> float:
    """``Sheet._measured_decor`` on a figure ``width`` inches wide, measured while
    matplotlib's settings are those ``settings`` (their values, as text) stands for."""
    fig = Figure()
    fig.set_layout_engine("none")
    fig.set_dpi(DPI)
    fig.set_size_inches(width, 20.0)
    ax = fig.add_axes((0.2, 0.4, 0.6, 0.2))
    ax.set_xlim(0, 1)
    ax.set_xlabel("t [s]")
    renderer = measuring_renderer(DPI)
    box = ax.get_window_extent(renderer=renderer)
    tight = ax.get_tightbbox(renderer=renderer)
    return float(box.y0 - (tight.y0 if tight is not None else box.y0)) / DPI + 0.02


@dataclass
class Sheet(Heads):
    """A sheet being laid out: the figure, its columns of tasks, and what has been placed
    where (inches from the top left; positions are set in figure fractions by
    ``finish``)."""

    fig: Figure
    motions: Sequence[Motion]
    columns: list[Indexed] = field(init=False)
    width: float = field(init=False)
    column_width: float = field(init=False)
    y: float = MARGIN  # in from the top: the next free height
    axes: list[tuple[Axes, tuple[float, float, float, float]]] = field(default_factory=list)
    texts: list[tuple[Text, float, float]] = field(default_factory=list)
    time: list[Axes] = field(default_factory=list)  # every time axis (the first leads)
    lead: dict[int, Axes] = field(default_factory=dict)  # each column's first time axis
    keys: dict[tuple[int, Any], int] = field(default_factory=dict)
    knot_said: bool = False  # the knots' legend entry is on the sheet (once)
    # a figure for a paper: its size [in] given, the lane under the axes, no title
    size: tuple[float, float] | None = None
    row_scale: float = 1.0  # every row's height times this (to fit ``size``)
    rows_total: float = 0.0  # in, the rows' heights so far
    smallest_row: float = float("inf")  # in, the lowest row so far

    def __post_init__(self) -> None:
        indexed = list(enumerate(self.motions))
        many = len(indexed) > OVERLAID
        self.columns = [[im] for im in indexed] if many else [indexed]
        n = len(self.columns)
        scale = FONT_SCALE.get()
        self.left_edge = LEFT * max(1.0, scale)
        self.decor = X_DECOR * max(1.0, scale)
        units = {m.task.robot.actuation for m in self.motions}
        # overlaid in two units: the second's y axis on the right, its labels before the lane
        twin = not many and len(units) > 1
        self.lane_gap = UNIT_GAP if twin else LANE_GAP
        self.column_width = COLUMN if many else WIDTH - LEFT - self.lane_gap - LANE - MARGIN
        if self.size is not None:
            if many:
                raise ValueError(
                    f"a figure of a given size holds one column of axes: at most {OVERLAID} tasks"
                )
            right = self.lane_gap * max(1.0, scale) if twin else 0.1
            self.column_width = self.size[0] - self.left_edge - MARGIN - right
            if self.column_width < 1.0:
                raise ValueError(f"{self.size[0]:g} in is too narrow: at least 2.3 in")
        durations = [m.duration for m in self.motions]
        self.own_time = many and min(durations) < SHARED_TIME * max(durations)
        self.column_gap = UNIT_GAP if many and len(units) > 1 else COLUMN_GAP
        self.width = self.left_edge + n * self.column_width + (n - 1) * self.column_gap
        self.width += self.lane_gap + LANE + MARGIN
        if self.size is not None:
            self.width = self.size[0]
        self.renderer = measuring_renderer(DPI)
        self.fig.set_dpi(DPI)
        self.fig.set_size_inches(self.width, 20.0)  # provisional: text is measured in inches
        if self.size is not None:  # a paper's figure: the decoration as measured, no more
            self.decor = self._measured_decor()
            self.y = PAPER_MARGIN
        instants = sum(len(m.result.singularities) for m in self.motions)
        for i, m in enumerate(self.motions):  # every mark's number, in the check's order
            for k in range(len(m.result.singularities) if instants <= MAX_LABELS else 0):
                self.keys[i, k] = len(self.keys) + 1
            if m.result.closest_approach is not None:
                self.keys[i, "approach"] = len(self.keys) + 1

    @property
    def overlay(self) -> bool:
        """Whether tasks share axes (colour is then the task's)."""
        return len(self.columns[0]) > 1

    @property
    def duration(self) -> float:
        return max(m.duration for m in self.motions)

    def who(self, m: Motion) -> str:
        """The prefix naming task ``m`` in the lane ("" when the sheet has one task)."""
        return f"{m.label or short(m.name, 30)}: " if len(self.motions) > 1 else ""

    def keyed(self, i: int) -> list[tuple[int, SingularInstant, str]]:
        """Task i's singular instants that carry a key number: (key, instant, its time as
        written); none when there are too many to key (``crowded``)."""
        if (i, 0) not in self.keys:
            return []
        r = self.motions[i].result
        times = instant_times(r)
        return [(self.keys[i, k], s, times[k]) for k, s in enumerate(r.singularities)]

    def left(self, c: int) -> float:
        """The left edge of column c's axes [in]."""
        return self.left_edge + c * (self.column_width + self.column_gap)

    @property
    def lane_left(self) -> float:
        if self.size is not None:
            return MARGIN
        return self.left(len(self.columns) - 1) + self.column_width + self.lane_gap

    @property
    def lane_width(self) -> float:
        """The lane's width [in]: beside the axes, or under them in a sized figure."""
        return LANE if self.size is None else self.width - 2 * MARGIN

    def _measured_decor(self) -> float:
        """The height under a time axes of its tick labels and its label [in], measured
        (a sized figure gives the axes every inch that text does not take): once per
        process for each sheet width and each state of matplotlib's settings (the text
        sizes of the font scale among them), on a figure of its own."""
        rc = matplotlib.rcParams  # all but the backend: reading it would pick one (pyplot)
        settings = repr([rc[k] for k in rc if k != "backend"])
        return _decor(self.width, settings)

    # -- axes ------------------------------------------------------------------------------

    def rows(
        self,
        gid: str,
        heights: Sequence[float],
        *,
        time: bool = True,
        groups: Sequence[Any] | None = None,
    ) -> list[list[Axes]]:
        """Rows of axes of these ``heights`` [in], one axes per column; time rows share
        the sheet's t axis (labelled under the last row only; per column when the tasks'
        durations differ widely, ``own_time``) and each row its y-limits across the
        columns, or across the columns of one of ``groups`` (a key per column: columns in
        different units), a column whose unit differs from its left neighbour's
        labelling its y axis (other rows set
        equal limits themselves: a workspace at equal scales cannot share). Advances the
        next free height past them."""
        out = []
        for r, h in enumerate(heights):
            row: list[Axes] = []
            h *= self.row_scale
            self.rows_total += h
            self.smallest_row = min(self.smallest_row, h)
            for c in range(len(self.columns)):
                ax = self.fig.add_axes((0, 0, 1, 1))
                ax.set_gid(f"panel-{gid}")
                self.axes.append((ax, (self.left(c), self.y, self.column_width, h)))
                key = groups[c] if groups is not None else None
                first = next(j for j in range(c + 1) if groups is None or groups[j] == key)
                if c != first and time:
                    ax.sharey(row[first])
                    if groups is None or groups[c - 1] == key:  # else its unit is written
                        ax.tick_params(labelleft=False)
                if time:
                    self._time(ax, c, last=r == len(heights) - 1)
                row.append(ax)
            out.append(row)
            self.y += h + (ROW_GAP if r < len(heights) - 1 else 0)
        self.y += self.decor
        return out

    def _time(self, ax: Axes, c: int, last: bool) -> None:
        """Share the sheet's t axis over [0, the longest t_f], or with ``own_time`` the
        column's over [0, its t_f]."""
        lead = self.lead.get(c if self.own_time else 0)
        if lead is not None:
            ax.sharex(lead)
        else:
            tf = max(m.duration for _, m in self.columns[c]) if self.own_time else self.duration
            ax.set_xlim(0, tf)
            self.lead[c if self.own_time else 0] = ax
        self.time.append(ax)
        if last:
            ax.set_xlabel("t [s]")
        else:
            ax.tick_params(labelbottom=False)

    def top_of(self, ax: Axes) -> float:
        """The top of ``ax`` [in from the sheet's top]."""
        return next(box[1] for a, box in self.axes if a is ax)

    def lane(
        self, ax: Axes, handles: Sequence[Any], notes: Sequence[str] = (), *, inset: bool = False
    ) -> Axes | None:
        """The lane beside ``ax`` (the last column's): the legend of ``handles`` (a tuple of
        artists is one entry, drawn one over the other, labelled as its last), then the
        ``notes`` (each starting with its key number, wrapped to the lane), then, with
        ``inset``, a small axes returned. The panel grows when the lane is longer."""
        top = self.top_of(ax) if self.size is None else self.y
        x = self.lane_left
        used = 0.0
        if handles:
            ncol = 1 if self.size is None else 3  # a sized figure: as many as fit its width
            while True:
                leg = self.fig.legend(
                    ncol=ncol,
                    handles=list(handles),
                    labels=[(h[-1] if isinstance(h, tuple) else h).get_label() for h in handles],
                    loc="upper left",
                    bbox_to_anchor=(0, 1),
                    frameon=False,
                    fontsize=pt(LABEL_SIZE),
                    borderaxespad=0,
                    borderpad=0.4 if self.size is None else 0.1,  # sized: no invisible band
                    handlelength=2.6,
                    columnspacing=1.2,
                )
                width, height = self.inches(leg)  # laid out once: both are read
                if ncol == 1 or width <= self.lane_width:
                    break
                leg.remove()
                ncol -= 1
            self.texts.append((leg, x, top))  # type: ignore[arg-type]
            used += height + (0.08 if self.size is None else 0.05)
        if notes:
            per_char = 0.56 if self.size is None else 0.45  # then measured, down to fit
            chars = int((self.lane_width - 0.05) * 72 / (per_char * pt(LABEL_SIZE)))
            while True:  # a sized figure: as many characters as fit the lane, measured
                text = "\n".join(
                    textwrap.fill(n, chars, subsequent_indent="    ") for n in notes if n
                )
                t = self.fig.text(0, 0, text, fontsize=pt(LABEL_SIZE), va="top", ha="left")
                width, height = self.inches(t)
                if self.size is None or chars <= 20 or width <= self.lane_width:
                    break
                t.remove()
                chars -= 2
            self.texts.append((t, x, top + used))
            used += height + (0.1 if self.size is None else 0.0)
        small = None
        if inset:
            small = self.fig.add_axes((0, 0, 1, 1))
            small.set_gid("inset")
            self.axes.append(
                (small, (x + 0.5, top + used + 0.25, min(LANE, self.lane_width) - 0.7, 1.45))
            )
            used += 0.25 + 1.45 + 0.45
        self.y = max(self.y, top + used + (0.05 if self.size is None else 0.0))
        return small

    def crowded(self) -> list[str]:
        """The note that stands for the instants' keys when there are too many to key."""
        n = sum(len(m.result.singularities) for m in self.motions)
        if n <= MAX_LABELS:
            return []
        return [f"-  {n} singular instants: too many to key here; rprpr check lists them"]

    def gap(self) -> None:
        self.y += PANEL_GAP

    def finish(self) -> None:
        """Give the figure its height and every axes and text its place."""
        h = self.y + MARGIN if self.size is None else self.size[1]
        w = self.width
        self.fig.set_size_inches(w, h)
        for ax, (x0, top, bw, bh) in self.axes:
            ax.set_position((x0 / w, 1 - (top + bh) / h, bw / w, bh / h))
        for t, x, top in self.texts:
            if hasattr(t, "set_bbox_to_anchor"):
                t.set_bbox_to_anchor((x / w, 1 - top / h), transform=self.fig.transFigure)
            else:
                t.set_position((x / w, 1 - top / h))


def column_heads(sheet: Sheet) -> None:
    """Small multiples: each column's task, abbreviated, in its colour, numbered as in
    the title."""
    chars = int(sheet.column_width * 72 / (0.6 * pt(8.5)))
    height = 0.0
    for c, col in enumerate(sheet.columns):
        i, m = col[0]
        t = sheet.fig.text(
            0,
            0,
            short(m.name, chars),
            fontsize=pt(8.5),
            fontweight="bold",
            color=task_colour(i),
            va="top",
        )
        sheet.texts.append((t, sheet.left(c), sheet.y))
        height = max(height, sheet.inches(t)[1])
    sheet.y += height + 0.1


__all__ = ["DPI", "PAPER_MARGIN", "Indexed", "Sheet", "column_heads"]  # the measures as before

"""The sheet's text, measured in inches: lines wrapped to the figure, the title and the
panels' headings (``Heads``, a part of ``page.Sheet``: what it reads of the sheet is
declared here)."""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from typing import Any

from matplotlib.backends.backend_agg import RendererAgg
from matplotlib.figure import Figure
from matplotlib.text import Text

from ..._version import __version__
from .measures import DPI, FONT_SCALE_TICK, LEADING, MARGIN, PANEL_GAP, PAPER_HEADING, TITLE_GAP
from .motion import Motion
from .style import pt, task_colour
from .words import heading_lines


class Heads:
    """The text of a ``Sheet``: lines, headings and the title (a part of it)."""

    fig: Figure
    motions: Sequence[Motion]
    renderer: RendererAgg
    texts: list[tuple[Text, float, float]]
    y: float  # in from the top: the next free height
    width: float
    size: tuple[float, float] | None

    def inches(self, artist: Any) -> tuple[float, float]:
        """The width and height of ``artist`` [in], as it will be drawn."""
        bb = artist.get_window_extent(renderer=self.renderer)
        return bb.width / DPI, bb.height / DPI

    def line(self, text: str, x: float, *, size: float, **kw: Any) -> float:
        """Write ``text`` with its top left at (x, the next free height) [in], wrapped to
        the figure; returns its height [in] (the next free height does not move)."""
        chars = max(20, int((self.width - x - MARGIN) * 72 / (0.58 * size)))
        wrapped = "\n".join(textwrap.fill(p, chars) for p in text.split("\n"))
        t = self.fig.text(0, 0, wrapped, fontsize=pt(size), va="top", ha="left", **kw)
        self.texts.append((t, x, self.y))
        return self.inches(t)[1] + LEADING

    def heading(self, text: str, *shorter: str) -> None:
        """A panel's heading, bold, over its axes. On a figure of a given size, one line:
        the first of ``text`` and its ``shorter`` forms that fits the width at
        ``PAPER_HEADING`` pt, else the shortest at the size that fits (never a break
        inside a formula)."""
        if self.size is None:
            self.y += self.line(text, MARGIN, size=10.5, fontweight="bold") + TITLE_GAP
            return
        room = self.width - 2 * MARGIN
        for candidate in (text, *shorter):
            t = self.fig.text(
                0, 0, candidate, fontsize=pt(PAPER_HEADING), fontweight="bold", va="top"
            )
            w, h = self.inches(t)
            if w <= room:
                break
            t.remove()
        else:
            t = self.fig.text(0, 0, candidate, fontweight="bold", va="top")
            t.set_fontsize(pt(PAPER_HEADING) * room / w * 0.98)
            h = self.inches(t)[1]
        self.texts.append((t, MARGIN, self.y))
        tick = pt(8) * FONT_SCALE_TICK / 72  # half a tick label stands above the axes
        self.y += h + tick / 2 + 0.04

    def title(self) -> None:
        """The sheet's title: per task, its name and verdict (in the task's colour when
        tasks share axes or columns), and its file in small print; none on a figure of
        a given size (a paper's figure has its caption)."""
        if self.size is not None:
            return
        self.y += self.line(f"rprpr {__version__} audit sheet", MARGIN, size=8, color="#555555")
        self.y += 0.04
        several = len(self.motions) > 1
        for i, m in enumerate(self.motions):
            head, source = heading_lines(m)
            colour = task_colour(i) if several else "black"
            self.y += self.line(head, MARGIN, size=10, fontweight="bold", color=colour)
            if source:
                self.y += self.line(source, MARGIN, size=7, color="#555555") + 0.03
        self.y += PANEL_GAP / 2

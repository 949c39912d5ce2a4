"""Where the sheet writes its labels, so that they hide little and never each other.

The layout is done only when the sheet is saved (text extents depend on the resolution),
so the sizes here are estimates from the character count and the font size."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .motion import Motion
from .style import LABEL_SIZE, WIDTH

MAX_LABELS = 12  # singular instants labelled one by one; beyond, the markers speak alone

Box = tuple[float, float, float, float]  # x0, x1, y0, y1 in data units


def labelled(motions: Sequence[Motion]) -> bool:
    """Whether the singular instants get text labels (not when they would pile up)."""
    return sum(len(m.result.singularities) for m in motions) <= MAX_LABELS


def place(
    text: str,
    at: tuple[float, float],
    obstacles: np.ndarray,
    boxes: list[Box],
    ppu: float,
    view: Box,
    fontsize: float = LABEL_SIZE,
) -> tuple[tuple[float, float], Box]:
    """An offset (points) for a label at ``at`` whose box covers the fewest obstacle
    points, overlaps no placed box and stays in the view; and that box (data units).
    ``ppu`` is points per data unit (an estimate: the layout is not yet done)."""
    lines = text.split("\n")
    w = (max(len(line) for line in lines) * 0.58 * fontsize + 8) / ppu
    h = (len(lines) * 1.25 * fontsize + 6) / ppu
    best: tuple[float, tuple[float, float], Box] | None = None
    rank = 0
    for dist in (16, 34, 60, 90):
        for sx, sy in ((1, -1), (-1, -1), (1, 1), (-1, 1)):
            dx, dy = 14 * sx, dist * sy
            bx, by = at[0] + dx / ppu, at[1] + dy / ppu
            box = (
                min(bx, bx + sx * w),
                max(bx, bx + sx * w),
                min(by, by + sy * h),
                max(by, by + sy * h),
            )
            score = _cost(box, obstacles, boxes, view) + 0.5 * rank
            rank += 1
            if best is None or score < best[0]:
                best = (score, (float(dx), float(dy)), box)
    assert best is not None
    return best[1], best[2]


def _cost(box: Box, obstacles: np.ndarray, boxes: list[Box], view: Box) -> float:
    """How badly a label's box sits: one per obstacle point it covers, far more for each
    placed box it overlaps and for leaving the view."""
    inside = np.sum(
        (obstacles[:, 0] >= box[0])
        & (obstacles[:, 0] <= box[1])
        & (obstacles[:, 1] >= box[2])
        & (obstacles[:, 1] <= box[3])
    )
    clash = sum(
        not (box[1] < b[0] or b[1] < box[0] or box[3] < b[2] or b[3] < box[2]) for b in boxes
    )
    out = box[0] < view[0] or box[1] > view[1] or box[2] < view[2] or box[3] > view[3]
    return float(inside) + 1000.0 * clash + 500.0 * out


def case_label_x(lo: float, hi: float, avoid: np.ndarray) -> float:
    """Where along [lo, hi] a label sits farthest from the points ``avoid`` (x, y)."""
    cands = np.linspace(lo, hi, 11)
    if avoid.size == 0:
        return float(cands[len(cands) // 2])
    dist = np.min(np.hypot(cands[:, None] - avoid[None, :, 0], avoid[None, :, 1]), axis=1)
    return float(cands[int(np.argmax(dist))])


class Rows:
    """Stacks labels written beside points along a time axis so that none overlap: each
    label goes to the right of its time (to the left where only that has room), on the
    free level nearest the anchor, above or (with ``below``) under it. Widths are estimated
    from the character count: the layout is not done yet."""

    LINE = 10.5  # points per line of 7.5-point text, with leading

    def __init__(
        self,
        tmax: float,
        *,
        below: bool = False,
        axes_inches: float = WIDTH - 4.0,
        fontsize: float = LABEL_SIZE,
    ) -> None:
        self.per_char = 0.62 * fontsize / 72 / axes_inches * tmax
        self.pad = 14 / 72 / axes_inches * tmax
        self.tmax = tmax
        self.sides = (1, -1) if below else (1,)
        self.placed: dict[int, list[Box]] = {1: [], -1: []}

    def place(self, t: float, text: str) -> tuple[int, float, bool]:
        """(side: 1 above, -1 below; level in points from the anchor; written to the left
        of t?) for a label at t."""
        lines = text.split("\n")
        width = self.per_char * max(len(line) for line in lines) + self.pad
        right = t + width > self.tmax and t - width >= 0  # else the right, overflowing
        lo, hi = (t - width, t) if right else (t, t + width)
        height = self.LINE * len(lines) + 3
        levels = {side: self._free(side, lo, hi, height) for side in self.sides}
        side = min(self.sides, key=lambda sd: levels[sd])  # above, when both are as low
        level = levels[side]
        self.placed[side].append((lo, hi, level, level + height))
        return side, level, right

    def _free(self, side: int, lo: float, hi: float, height: float) -> float:
        """The lowest level on ``side`` where a label over [lo, hi] of this height fits."""
        level = 0.0
        while True:
            hits = [
                p
                for p in self.placed[side]
                if p[0] < hi and lo < p[1] and p[2] < level + height and level < p[3]
            ]
            if not hits:
                return level
            level = max(p[3] for p in hits)

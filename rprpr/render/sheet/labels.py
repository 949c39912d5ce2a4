"""Where the sheet writes what is not in the lane: how many instants get a key number,
and where a case's name sits on the singular line."""

from __future__ import annotations

import numpy as np

MAX_LABELS = 12  # singular instants keyed one by one; beyond, the marks speak alone


def case_label_place(
    lo: float,
    hi: float,
    avoid: np.ndarray,
    box: tuple[float, float],
    gap: float,
    margin: float = 0.0,
) -> tuple[float, int]:
    """Where along [lo, hi] a label of ``box`` (width, height) [m] sits on the singular
    line: (x of its centre, +1 above the line or -1 below it, ``gap`` [m] off it), so
    that the fewest of the points ``avoid`` (x, y) fall in its box grown by ``margin``
    [m] (a thick line's half width) all round (ties: above, then farthest from them)."""
    w, h = box
    best: tuple[tuple[int, int, float], tuple[float, int]] | None = None
    for x in np.linspace(lo, hi, 21):
        for side in (1, -1):
            y0, y1 = sorted((side * gap, side * (gap + h)))
            inside = (
                (np.abs(avoid[:, 0] - x) <= w / 2 + margin)
                & (avoid[:, 1] >= y0 - margin)
                & (avoid[:, 1] <= y1 + margin)
            )
            near = (
                float(np.min(np.hypot(avoid[:, 0] - x, avoid[:, 1] - side * (gap + h / 2))))
                if avoid.size
                else 0.0
            )
            score = (int(np.sum(inside)), 0 if side > 0 else 1, -near)
            if best is None or score < best[0]:
                best = (score, (float(x), side))
    assert best is not None
    return best[1]

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
) -> tuple[float, int, float]:
    """Where along [lo, hi] a label of ``box`` (width, height) [m] sits by the singular
    line: (x of its centre, +1 above the line or -1 below it, how far beyond ``gap``
    [m] it is lifted off the line), so that the fewest of the points ``avoid`` (x, y)
    fall in its box grown by ``margin`` [m] (a thick line's half width) all round; ties
    go to the label nearest the line, then above it, then farthest from the points.
    Lifted (by up to 2.5 of its heights) only where no place at the line is clear."""
    w, h = box
    best: tuple[tuple[int, int, int, float], tuple[float, int, float]] | None = None
    for lift in (0.0, 0.5 * h, h, 1.5 * h, 2.5 * h):
        for x in np.linspace(lo, hi, 21):
            for side in (1, -1):
                y0, y1 = sorted((side * (gap + lift), side * (gap + lift + h)))
                inside = (
                    (np.abs(avoid[:, 0] - x) <= w / 2 + margin)
                    & (avoid[:, 1] >= y0 - margin)
                    & (avoid[:, 1] <= y1 + margin)
                )
                centre = side * (gap + lift + h / 2)
                near = (
                    float(np.min(np.hypot(avoid[:, 0] - x, avoid[:, 1] - centre)))
                    if avoid.size
                    else 0.0
                )
                score = (int(np.sum(inside)), int(lift / h * 2), 0 if side > 0 else 1, -near)
                if best is None or score < best[0]:
                    best = (score, (float(x), side, lift))
        if best is not None and best[0][0] == 0:
            break  # a clear place this near the line
    assert best is not None
    return best[1]

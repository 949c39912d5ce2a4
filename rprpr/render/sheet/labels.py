"""Where the sheet writes what is not in the lane: how many instants get a key number,
and where a case's name sits on the singular line."""

from __future__ import annotations

import numpy as np

MAX_LABELS = 12  # singular instants keyed one by one; beyond, the marks speak alone


def case_label_x(lo: float, hi: float, avoid: np.ndarray) -> float:
    """Where along [lo, hi] a label sits farthest from the points ``avoid`` (x, y)."""
    cands = np.linspace(lo, hi, 11)
    if avoid.size == 0:
        return float(cands[len(cands) // 2])
    dist = np.min(np.hypot(cands[:, None] - avoid[None, :, 0], avoid[None, :, 1]), axis=1)
    return float(cands[int(np.argmax(dist))])

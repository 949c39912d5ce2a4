"""One branch and bound over boxes of time, for every source of torque enclosures.

A *source* (``Source``) encloses T1, T2 over boxes [lo_j, hi_j] and gives certified
values at their ends (``Bounds``): ``envelope.Envelope`` for one motion (with the zone,
Taylor and factored forms near its instants), ``batch.Batch`` for many plain pieces at
once (box j of piece idx[j]). The search is the same for both: the boxes whose upper
bound of |T_i| can still exceed the best certified value are cut (``fan`` boxes each)
and passed again, the others set aside; it stops when none is left (the peak is then
certified to PEAK_REL, or PEAK_ABS for a peak near 0 N m), after MAX_ROUNDS passes, or
when more than a cap of boxes would stay alive (the peak is then an uncertified
bracket, still proven). The stopping rule and its constants are stated here only.
"""

from __future__ import annotations

import numpy as np

from .boxes import Bounds

PEAK_REL = 1e-6  # torque_peak: certified to this relative width ...
PEAK_ABS = 1e-9  # ... or this absolute one [N m], whichever is larger (a peak of 0 N m)
SPLIT_BUDGET = 1024  # boxes per refining pass, about (live boxes times their fan)
MAX_FAN = 512  # a live box is cut into at most this many
MAX_ROUNDS = 60  # refining passes, at most
MAX_LIVE = 4096  # boxes kept alive, at most


def fan(n_live: int) -> int:
    """How many boxes each live box is cut into: the pass costs its calls, not its length."""
    return int(min(MAX_FAN, max(2, SPLIT_BUDGET // max(n_live, 1))))


def prune(
    b: Bounds, best: np.ndarray, best_t: np.ndarray, dropped: np.ndarray, rel: float
) -> tuple[np.ndarray, list[int | None]]:
    """One round of the peak's branch and bound: ``best``/``best_t`` (per torque) raised
    to the boxes' largest certified lower bound, and ``dropped`` to the largest upper
    bound of a box set aside (it cannot hold a value above best (1 + rel) + PEAK_ABS);
    returns the boxes kept and, per torque, the box whose lower bound became the best
    (None where the best stayed)."""
    better: list[int | None] = []
    for i in (0, 1):
        j = int(np.argmax(b.low[i]))
        better.append(j if b.low[i, j] > best[i] else None)
        if better[i] is not None:
            best[i], best_t[i] = float(b.low[i, j]), float(b.low_t[i, j])
    keep_i = b.up > (best * (1 + rel) + PEAK_ABS)[:, None]
    dropped[:] = np.maximum(dropped, np.where(keep_i, 0.0, b.up).max(axis=1))
    return np.asarray(keep_i.any(axis=0)), better

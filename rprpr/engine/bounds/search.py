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

from typing import Protocol

import numpy as np

from .boxes import Bounds, split
from .verdicts import Peak

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


class Source(Protocol):
    """What the branch and bound reads of a source: enclosures over boxes and certified
    values at their ends, in one pass (``Bounds``); ``idx`` gives each box's piece (one
    motion: zeros), ``need`` the bound below which an enclosure need not be sharpened."""

    def bounds(
        self, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray | None = None, need: float = 0.0
    ) -> Bounds: ...


def cut(
    lo: np.ndarray, hi: np.ndarray, idx: np.ndarray, keep: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The boxes [lo, hi] picked by ``keep`` (of pieces idx) cut into ``fan`` boxes each
    for the next pass, with the piece of each new box; the others are dropped."""
    k = fan(int(keep.sum()))
    los, his = split(lo[keep], hi[keep], k)
    return los, his, np.repeat(idx[keep], k)


def maximise(
    source: Source, b: Bounds, idx: np.ndarray, best: np.ndarray, best_t: np.ndarray,
    rel: float, cap: int,
) -> tuple[tuple[Peak, Peak], tuple[int, int]]:  # fmt: skip
    """max |T1| and max |T2| over the boxes of ``b`` (the first pass of ``source``; box j
    of piece idx[j]) by branch and bound (module docstring), from the certified values
    ``best`` at ``best_t`` known beforehand (0 when none); with the piece where each
    value is reached. ``cap``: the live boxes beyond which the search stops."""
    best_j = np.zeros(2, dtype=int)
    dropped = np.zeros(2)  # the largest upper bound of a box set aside
    certified = False
    for _ in range(MAX_ROUNDS):
        keep, better = prune(b, best, best_t, dropped, rel)
        for i, j in enumerate(better):
            if j is not None:
                best_j[i] = idx[j]
        n = int(keep.sum())
        if not n:
            certified = True
            break
        if n > cap:
            break
        lo, hi, idx = cut(b.lo, b.hi, idx, keep)
        b = source.bounds(lo, hi, idx, float(best.min() * (1 + rel)))
    out = []
    for i in (0, 1):
        up = max(best[i], dropped[i])
        if not certified:
            up = max(up, float(b.up[i].max(initial=0.0)))
        out.append(Peak(float(best[i]), float(best_t[i]), float(up), certified))
    return (out[0], out[1]), (int(best_j[0]), int(best_j[1]))

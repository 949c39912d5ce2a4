"""The worst-case effort peak over the box of ``docs/robust.md``, between the singular
instants: for each effort, a certified [lower, upper] of sup |E_i(t)| over every link
parameter in the box, every tracking error within the bound, and every time t of the
motion outside the proven saturation windows (``Robust.span``; within them some |E_i|
may exceed the limit, and near a possible pole it is unbounded).

Branch and bound on time intervals, every interval at once (``balls.Ball`` arrays): an
interval's upper bound is ``worst``'s closed form evaluated over it (the end point's balls
over the interval), a lower bound of the peak is the closed form's lower bound at
interval midpoints; intervals whose upper bound cannot beat the best lower bound are
dropped, the others halved, until the two meet within ``REL`` or ``ROUNDS`` rounds.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from typing import Any

import numpy as np

from ...model.numbers import to_float
from ...model.task import Task
from ..certified.balls import Ball, quiet
from .windows import Box, Robust
from .worst import bands_at

REL = 1e-6  # the peak's bounds meet within this relative width
ROUNDS = 48  # halvings at most
START = 256  # intervals per piece at the start
CAP = 1 << 15  # intervals kept at most per round


def worst_peak(
    task: Task, parts: Sequence[Any], robust: Sequence[Robust]
) -> tuple[tuple[float, float], tuple[float, float]]:
    """((lower, upper) of sup |E1|, (lower, upper) of sup |E2|) over the box and the
    times outside the proven windows (``robust``: the audit's, one per singular
    instant); upper is +inf where it cannot be bounded (a possible pole without a proven
    window around it)."""
    u = task.uncertainty
    assert u is not None
    box = Box.of(task.robot, u)
    spans = [r.span for r in robust if r.span is not None]
    a, b, k = _domain(parts, spans)
    best = np.full(2, -np.inf)
    top = np.full(2, np.inf)
    with quiet():
        for _ in range(ROUNDS):
            if not len(a):
                top = best.copy()
                break
            mid = 0.5 * a + 0.5 * b
            best = np.maximum(best, [lo.max() for lo in _at(task, parts, box, mid, k, True)])
            ups = _over(task, parts, box, a, b, k)
            top = np.array([up.max() for up in ups])
            if np.all(top <= best * (1 + REL) + 1e-12):
                break
            live = (ups[0] > best[0] * (1 + REL)) | (ups[1] > best[1] * (1 + REL))
            a, b, k = a[live], b[live], k[live]
            if len(a) > CAP:
                break
            m = 0.5 * a + 0.5 * b
            a, b, k = np.concatenate([a, m]), np.concatenate([m, b]), np.concatenate([k, k])
    return (float(best[0]), float(max(top[0], best[0]))), (
        float(best[1]),
        float(max(top[1], best[1])),
    )


def _domain(
    parts: Sequence[Any], spans: Sequence[tuple[float, float]]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The starting intervals [a, b] (absolute [s]) and their pieces: each piece cut in
    ``START``, less the spans."""
    edges: list[tuple[float, float, int]] = []
    for i, p in enumerate(parts):
        lo, hi = to_float(p.start), to_float(p.end)
        cuts = [lo, hi]
        for s0, s1 in spans:
            cuts += [c for c in (s0, s1) if lo < c < hi]
        cuts.sort()
        for c0, c1 in itertools.pairwise(cuts):
            if any(s0 <= c0 and c1 <= s1 for s0, s1 in spans) or c1 <= c0:
                continue  # inside a window
            n = max(1, int(START * (c1 - c0) / max(hi - lo, 1e-300)))
            grid = np.linspace(c0, c1, n + 1)
            edges += [(x, y, i) for x, y in itertools.pairwise(grid)]
    a = np.array([e[0] for e in edges])
    b = np.array([e[1] for e in edges])
    return a, b, np.array([e[2] for e in edges], dtype=int)


def _at(
    task: Task, parts: Sequence[Any], box: Box, t: np.ndarray, k: np.ndarray, lower: bool
) -> list[np.ndarray]:
    """max |E_j| over the box at the times ``t`` (pieces ``k``): lower bounds."""
    out = [np.full(len(t), -np.inf), np.full(len(t), -np.inf)]
    for i in np.unique(k):
        sel = np.nonzero(k == i)[0]
        p = parts[int(i)]
        kin = p.motion.end_point(t[sel] - to_float(p.origin))
        for j, (lo, hi) in enumerate(bands_at(task, kin, box, lower)):
            out[j][sel] = np.maximum(hi, -lo)
    return out


def _over(
    task: Task, parts: Sequence[Any], box: Box, a: np.ndarray, b: np.ndarray, k: np.ndarray
) -> list[np.ndarray]:
    """Upper bounds of max |E_j| over the box and the intervals [a, b] (pieces ``k``)."""
    out = [np.full(len(a), np.inf), np.full(len(a), np.inf)]
    for i in np.unique(k):
        sel = np.nonzero(k == i)[0]
        p = parts[int(i)]
        o = to_float(p.origin)
        pad = 4 * np.spacing(np.maximum(np.abs(b[sel]), abs(o)) + 1.0)  # o and a - o rounded
        lo, hi = a[sel] - o - pad, b[sel] - o + pad
        kin = p.motion.end_point(Ball.hull(lo, hi))
        for j, (l_, h_) in enumerate(bands_at(task, kin, box)):
            out[j][sel] = np.maximum(h_, -l_)
    return out

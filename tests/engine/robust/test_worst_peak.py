"""The worst-case effort peak over the box between the singular instants
(``engine.worst_peak``) against the independent mpmath reference (``tests/reference.py``,
50 digits): with r exact the largest |T_j| over the box at a time is the largest over the
box's corners; its supremum over the times outside the proven window is found by a grid,
a golden-section search and the values at both edges of the window (where the peak sits
when the window is the limit's) on the reference, and must lie in the certified
[lower, upper], which is narrow.
"""

from __future__ import annotations

import functools
import math
from fractions import Fraction

from rprpr import audit, load_task
from tests.engine.robust.test_windows import P2, _at_corners, _robots, _u
from tests.engine.robust.test_worst import _links

Q = Fraction


def test_the_peak_between_the_instants_holds_the_references_supremum() -> None:
    task = load_task(P2)  # its own limit: 300 N m
    u = _u({3: (Q(1, 20), Q(1, 20), Q(0))}, Q(1, 100))
    result = audit(task, uncertainty=u, peak=True)
    assert result.robust_peak is not None
    (r,) = result.robust
    assert r.span is not None
    a = u.acceleration
    corners = [(lk, (sx * a, sy * a)) for lk in _links(task, u) for sx in (-1, 1) for sy in (-1, 1)]
    robots = _robots(task, corners)  # each corner's robot made once

    @functools.cache
    def both(t: float) -> tuple[float, float]:
        """max over the corners of |T1(t)| and of |T2(t)|, each corner evaluated once."""
        values = list(_at_corners(task, Q(t), robots))
        return max(abs(float(v["T1"])) for v in values), max(abs(float(v["T2"])) for v in values)

    def worst(t: float, j: int) -> float:
        return both(t)[j - 1]

    pieces = [(0.0, r.span[0]), (r.span[1], 5.0)]
    for j, (lo, hi) in ((1, result.robust_peak[0]), (2, result.robust_peak[1])):
        assert lo <= hi <= lo * (1 + 1e-5) + 1e-9  # certified and narrow
        grid = [(p0 + (p1 - p0) * k / 60, p0, p1) for p0, p1 in pieces for k in range(31)]
        values = [(worst(t, j), t, p0, p1) for t, p0, p1 in grid]
        best, t, p0, p1 = max(values)
        assert best <= hi * (1 + 1e-12)
        step = (p1 - p0) / 30
        x0, x1 = max(p0, t - step), min(p1, t + step)
        g = (math.sqrt(5) - 1) / 2
        for _ in range(32):  # golden section on the reference's largest over the corners
            c, d = x1 - g * (x1 - x0), x0 + g * (x1 - x0)
            if worst(c, j) >= worst(d, j):  # (one new evaluation a step, the other cached)
                x1 = d
            else:
                x0 = c
        ends = [worst(t, j) for piece in pieces for t in piece]  # the window's two edges too
        sup = max(best, worst(0.5 * (x0 + x1), j), *ends)
        assert sup <= hi * (1 + 1e-12)
        assert lo <= sup * (1 + 1e-9)  # the certified lower bound is attained
        assert sup >= lo * (1 - 1e-6)


def test_the_peak_is_computed_only_when_asked() -> None:
    task = load_task(P2)
    u = _u({3: (Q(1, 20), Q(1, 20), Q(0))}, Q(1, 100))
    assert audit(task, uncertainty=u).robust_peak is None
    assert audit(task, peak=True).robust_peak is None

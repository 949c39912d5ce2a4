"""The worst case over the box and over an interval of time (``worst.bands_at``, what the
worst-case peak's branch and bound reads) where a link's coefficient of m r² + I is
about 0: on paper path 2 at rest just after t = 0, with r uncertain. There the parabola
in r is nearly flat and its vertex ball too wide to place, and the vertex's value
A - B²/4C alone was a vast bound (about 1e8 N m over [0.005048, 0.005055] s, where the
efforts are about 21 and 62 N m); the quadratic's enclosure over r's whole interval bounds
the same maximum. Against the independent mpmath reference (``tests/reference.py``, 50
digits): the bound holds the largest |T_j| over the box's corners and a grid in r at
both ends and the middle of the interval, and is within 1 % of it.
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np

from rprpr import audit, load_task
from rprpr.engine.certified.balls import Ball, quiet
from rprpr.engine.robust.windows import Box
from rprpr.engine.robust.worst import bands_at
from tests.engine.robust.test_windows import P2, _u
from tests.engine.robust.test_worst import _reference_max

Q = Fraction


def test_a_flat_parabola_in_r_gives_a_tight_bound_over_an_interval() -> None:
    u = _u({3: (Q(1, 20), Q(1, 20), Q(1, 20))}, Q(1, 100))
    result = audit(load_task(P2), uncertainty=u)
    task, (part,) = result.task, result.parts
    lo, hi = 0.005048, 0.005055
    with quiet():
        kin = part.motion.end_point(Ball.hull(np.array([lo]), np.array([hi])))
        bands = bands_at(task, kin, Box.of(task.robot, u))
    upper = [max(float(h[0]), -float(b[0])) for b, h in bands]
    refs = [_reference_max(task, u, Q(t), r_grid=4) for t in (lo, 0.5 * lo + 0.5 * hi, hi)]
    for j in (0, 1):
        top = max(float(r[j]) for r in refs)
        assert top <= upper[j] <= top * 1.01, (j, top, upper[j])

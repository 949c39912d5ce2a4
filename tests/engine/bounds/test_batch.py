"""A motion of many pieces (quintic waypoint segments of a known arc): what the batch
reports (peak brackets and instants, closest approach, verdict) against the independent
reference (``tests/reference.py``) and against the same motion given as one piece."""

from __future__ import annotations

import math

from flint import fmpq, fmpq_poly

from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.model.task import Task
from rprpr.model.waypoints import Waypoint, pieces
from tests.conftest import PATH2_FILE
from tests.reference import reference

N = 300  # segments over 5 s


def _tasks() -> tuple[Task, Task]:
    """x = 2 + 2 s, y = 1 + s (1 - s), s = t/5: as N quintic waypoint segments (exact
    positions, velocities, accelerations) and in the paper's form (the path
    y = 1 + w (1 - w), w = (x - 2)/2, with x(t) = 2 + 2 s)."""
    base = load_task(PATH2_FILE)
    pts = []
    for i in range(N + 1):
        t = fmpq(5 * i, N)
        s = t / 5
        p = (2 + 2 * s, 1 + s * (1 - s))
        pts.append(Waypoint(t, p, (fmpq(2, 5), (1 - 2 * s) / 5), (fmpq(0), fmpq(-2, 25))))
    many = Task("many", base.robot, None, None, fmpq(5), base.checks, "waypoints",
                pieces=tuple(pieces(pts)))  # fmt: skip
    w = fmpq_poly([-1, fmpq(1, 2)])
    path = 1 + w * (1 - w)
    single = Task("one", base.robot, path, fmpq_poly([2, fmpq(2, 5)]), fmpq(5), base.checks)
    return many, single


def test_many_pieces_agree_with_the_reference_and_with_one_piece() -> None:
    many, single = _tasks()
    assert all(p.local is not None for p in many.pieces)
    a, b = audit(many, peak=True), audit(single, peak=True)
    assert a.verdict == b.verdict == "pass"
    assert a.singularities == b.singularities == []
    assert a.torque_peak is not None and b.torque_peak is not None
    grid = [fmpq(5 * k, 200) for k in range(201)]
    ref = [reference(single, t) for t in grid]
    for i, name in enumerate(("T1", "T2")):
        pa, pb = a.torque_peak[i], b.torque_peak[i]
        assert pa.certified and pb.certified
        assert max(pa.value, pb.value) <= min(pa.upper, pb.upper)  # the brackets meet
        assert pa.upper - pa.value <= 1e-6 * pa.upper
        assert max(abs(float(r[name])) for r in ref) <= pa.upper
        at = abs(float(reference(single, pa.t)[name]))  # reached where it is reported
        assert math.isclose(at, pa.value, rel_tol=1e-9)
        assert abs(pa.t - pb.t) < 0.05
    # y = 1 + s (1 - s) >= 1, exactly 1 at t = 0 and t = 5
    ca = a.closest_approach
    assert ca is not None and b.closest_approach is not None
    assert ca.distance == 1.0 and ca.t_y in (0.0, 5.0)
    assert ca.delta_lo <= b.closest_approach.delta_hi
    assert b.closest_approach.delta_lo <= ca.delta_hi

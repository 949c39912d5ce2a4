"""A planner's long waypoint output: the pieces are kept in the controller's local form
(absolute-time polynomials made only where read), each segment's coefficients are formed
on integers, and knots continuous by construction are not evaluated. Each test compares
with an exact computation written apart (rational arithmetic on the controller's
formulas, the knot jumps evaluated exactly) or pins a count (polynomials made, bytes
held per row).
"""

from __future__ import annotations

import random
import tracemalloc
from dataclasses import replace
from pathlib import Path

import pytest
from flint import fmpq, fmpq_poly

from rprpr.engine.audit import audit
from rprpr.engine.exact import knots as K
from rprpr.io.loader import load_task
from rprpr.model.waypoints import Waypoint, pieces
from tests.conftest import LINKS_ALIKE

q = fmpq
ROBOT = f"name: planned\nrobot:\n  a1: 6\n{LINKS_ALIKE}motion:\n  waypoints: planned.csv\n"


def _points(rng: random.Random, n: int, fields: int, digits: int = 17) -> list[Waypoint]:
    """Random waypoints whose numbers are decimals of up to ``digits`` digits (a
    planner's doubles) or small fractions."""

    def r() -> fmpq:
        if rng.random() < 0.3:
            return q(rng.randint(-50, 50), rng.randint(1, 9))
        return q(rng.randint(-(10**digits), 10**digits), 10 ** rng.randint(0, digits))

    out, t = [], fmpq(0)
    for i in range(n):
        v = (r(), r()) if fields >= 2 else None
        a = (r(), r()) if fields >= 3 else None
        out.append(Waypoint(t, (r(), r()), v, a, line=i + 1))
        t += q(rng.randint(1, 10**6), 10 ** rng.randint(3, 9))
    return out


def _controller(w0: Waypoint, w1: Waypoint, i: int) -> fmpq_poly:
    """joint_trajectory_controller's segment (Trajectory::interpolate_between_points),
    one rational operation at a time, in u = t - t0."""
    T = w1.t - w0.t
    p0, p1 = w0.p[i], w1.p[i]
    if w0.v is None or w1.v is None:
        return fmpq_poly([p0, (p1 - p0) / T])
    v0, v1 = w0.v[i], w1.v[i]
    if w0.a is None or w1.a is None:
        c2 = (-3 * p0 + 3 * p1 - 2 * v0 * T - v1 * T) / T**2
        c3 = (2 * p0 - 2 * p1 + v0 * T + v1 * T) / T**3
        return fmpq_poly([p0, v0, c2, c3])
    a0, a1 = w0.a[i], w1.a[i]
    c3 = (-20 * p0 + 20 * p1 - 3 * a0 * T**2 + a1 * T**2 - 12 * v0 * T - 8 * v1 * T) / (2 * T**3)
    c4 = (30 * p0 - 30 * p1 + 3 * a0 * T**2 - 2 * a1 * T**2 + 16 * v0 * T + 14 * v1 * T) / (
        2 * T**4
    )
    c5 = (-12 * p0 + 12 * p1 - a0 * T**2 + a1 * T**2 - 6 * v0 * T - 6 * v1 * T) / (2 * T**5)
    return fmpq_poly([p0, v0, a0 / 2, c3, c4, c5])


@pytest.mark.parametrize("fields", [1, 2, 3])
def test_local_forms_are_the_controllers_segments_exactly(fields: int) -> None:
    points = _points(random.Random(100 + fields), 40, fields)
    got = pieces(points, "p.csv")
    for piece, w0, w1 in zip(got, points, points[1:], strict=False):
        assert piece.local == (_controller(w0, w1, 0), _controller(w0, w1, 1))
        assert (piece.start, piece.end, piece.line, piece.file) == (w0.t, w1.t, w1.line, "p.csv")


@pytest.mark.parametrize("fields", [1, 2, 3])
def test_absolute_forms_are_made_when_read_and_are_the_local_ones_shifted(fields: int) -> None:
    points = _points(random.Random(fields), 12, fields)
    for piece in pieces(points):
        assert piece.__dict__["_x"] is None and piece.__dict__["_y"] is None  # not made yet
        u = fmpq_poly([-piece.start, 1])
        assert (piece.x, piece.y) == (piece.local[0](u), piece.local[1](u))  # type: ignore[index]
        assert piece.__dict__["_x"] is not None  # made once, kept


@pytest.mark.parametrize("fields", [1, 2, 3])
def test_smooth_knots_say_exactly_what_an_exact_evaluation_finds(fields: int) -> None:
    """The knots of waypoint segments are continuous in velocity (C1) and acceleration
    (C2) by construction: the jumps left out are those the exact evaluation finds zero,
    and every jump evaluated is the same."""
    points = _points(random.Random(7 * fields), 30, fields)
    got = pieces(points)
    assert [p.smooth for p in got] == [0] + [fields - 1] * (len(got) - 1)
    robot = _robot()
    fast = K.knots(tuple(got), robot)
    slow = K.knots(tuple(replace(p, smooth=0) for p in got), robot)
    assert fast == slow
    for k in slow:
        assert (k.velocity_jump is None) == (fields >= 2)
        assert (k.acceleration_jump is None) == (fields != 2)  # linear: none on either side


def test_each_segment_ends_at_the_next_waypoints_p_v_a() -> None:
    """What ``Piece.smooth`` relies on, in the local forms themselves."""
    points = _points(random.Random(3), 25, 3)
    for piece, w1 in zip(pieces(points), points[1:], strict=True):
        T = piece.end - piece.start
        for i in (0, 1):
            x = piece.local[i]  # type: ignore[index]
            assert (x(T), x.derivative()(T), x.derivative().derivative()(T)) == (
                w1.p[i], w1.v[i], w1.a[i],  # type: ignore[index]
            )  # fmt: skip


def _robot():  # type: ignore[no-untyped-def]
    from rprpr.io.loader import parse_task

    text = ROBOT.replace("planned.csv", "[{t: 0, p: [2, -1]}, {t: 1, p: [3, 1]}]")
    return parse_task(text, "t.yaml").robot


def _quintic_csv(rows: int, seconds: int) -> str:
    """``benchmarks/bench_waypoints.py``'s motion (the paper's path 2, quintic law),
    sampled ``rows`` + 1 times as a planner writes doubles."""
    t = fmpq_poly([0, fmpq(1, seconds)])
    x = 2 + 2 * (10 * t**3 - 15 * t**4 + 6 * t**5)
    y = fmpq_poly([q(-222, 10), q(218, 10), q(-72, 10), q(8, 10)])(x)
    polys = [x, y, x.derivative(), y.derivative()]
    polys += [x.derivative().derivative(), y.derivative().derivative()]
    lines = ["t,x,y,vx,vy,ax,ay"]
    for k in range(rows + 1):
        s = fmpq(k * seconds, rows)
        lines.append(",".join(repr(int(v.p) / int(v.q)) for v in (s, *(p(s) for p in polys))))
    return "\n".join(lines) + "\n"


def _folder(root: Path, rows: int) -> Path:
    (root / "planned.csv").write_text(_quintic_csv(rows, max(1, rows // 1000)), encoding="utf-8")
    (root / "task.rprpr.yaml").write_text(ROBOT, encoding="utf-8")
    return root / "task.rprpr.yaml"


def test_a_plain_planner_output_is_audited_without_absolute_polynomials(tmp_path: Path) -> None:
    """Of 400 segments along path 2 (one crossing y = 0), only the few the batch cannot
    prove apart from y = 0 are analysed exactly, and none needs x(t), y(t) in absolute
    time: the long rationals of a segment far from t = 0 are never made."""
    task = load_task(_folder(tmp_path, 400))
    result = audit(task)
    assert len(task.pieces) == 400 and len(result.singularities) == 1
    assert sum(p.__dict__["_x"] is not None for p in task.pieces) == 0
    assert sum(not part.apart for part in result.parts) <= 4


def test_memory_per_waypoint_row(tmp_path: Path) -> None:
    """Loading and auditing a 2,000-row quintic CSV holds at most 2,300 bytes per row at
    its peak (tracemalloc: Python's own allocations, flint's integers not counted;
    measured ~1,850)."""
    path = _folder(tmp_path, 2000)
    tracemalloc.start()
    try:
        result = audit(load_task(path))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert result.passed
    assert peak / 2001 <= 2300, peak / 2001

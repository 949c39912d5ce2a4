"""A planner's waypoints on integers: a CSV row of plain decimals read by one match, its
numbers kept as integers (``Waypoint.row``), a segment held on them (``Segment``) and
the batch's ball coefficients rounded from them. Each test compares with an exact
computation written apart: Python's ``Fraction`` reading the cell's text, the
controller's formulas in rational arithmetic (``waypoints.segment``), flint's
composition for the recentring, and the exact rationals for the balls' containment.
"""

from __future__ import annotations

import itertools
import math
import pickle
import random
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
from flint import fmpq, fmpq_poly

from rprpr.engine.bounds.batch import Batch
from rprpr.engine.certified.balls import Ball
from rprpr.engine.certified.motion import dyadic_middle
from rprpr.io.loader import load_task
from rprpr.io.waypoint_csv import parse_waypoints
from rprpr.model.motion import Motion
from rprpr.model.numbers import to_float
from rprpr.model.task import Robot
from rprpr.model.waypoints import Segment, Waypoint, pieces, segment
from tests.conftest import PATH2_FILE
from tests.engine.test_waypoint_scale import _points

HEADER = "t,x,y,vx,vy,ax,ay"


def _robot() -> Robot:
    return load_task(PATH2_FILE).robot


def _cell(rng: random.Random) -> str:
    """A number as planners and people write it: signs, exponents, spaces, bare
    points, leading zeros, 17 significant digits."""
    whole = str(rng.randint(0, 10 ** rng.randint(0, 3)))
    frac = "".join(rng.choice("0123456789") for _ in range(rng.randint(0, 17)))
    text = ("-" if rng.random() < 0.4 else "") + whole
    if frac or rng.random() < 0.2:
        text += "." + frac
    if rng.random() < 0.3:
        text += rng.choice("eE") + rng.choice(["", "+", "-"]) + str(rng.randint(0, 30))
    return " " * rng.randint(0, 2) + text + " " * rng.randint(0, 2)


def _exact(text: str) -> fmpq:
    f = Fraction(text.strip())
    return fmpq(f.numerator, f.denominator)


def test_rows_of_plain_decimals_are_the_numbers_of_their_text() -> None:
    rng = random.Random(5)
    rows = []
    for k in range(400):
        cells = [f"{k}.{rng.randint(0, 999)}"] + [_cell(rng) for _ in range(6)]
        rows.append(cells)
    text = HEADER + "\n" + "\n".join(",".join(r) for r in rows) + "\n"
    points, problems = parse_waypoints(text.encode())
    assert problems == []
    for w, cells in zip(points, rows, strict=True):
        want = [_exact(c) for c in cells]
        assert w.numbers is not None  # read on integers, not cell by cell
        assert (w.t, *w.p, *w.v, *w.a) == tuple(want)  # type: ignore[misc]
        assert w.given == "p, v, a"
        tn, td, D, *rest = w.numbers
        assert fmpq(tn, td) == want[0] and [fmpq(n, D) for n in rest] == want[1:]


def test_a_row_read_on_integers_equals_the_same_point_given_as_rationals() -> None:
    text = f"{HEADER}\n0,1.5,-2e-3,0.25,3,1E+2,-0.0\n1,2,3,4,5,6,7\n"
    (w, w1), _ = parse_waypoints(text.encode())
    eager = Waypoint(fmpq(0), (fmpq(3, 2), fmpq(-2, 1000)), (fmpq(1, 4), fmpq(3)),
                     (fmpq(100), fmpq(0)), line=2)  # fmt: skip
    assert w == eager and repr(w) == repr(eager)
    copied = pickle.loads(pickle.dumps(w1))  # its pairs not made yet
    assert (copied.p, copied.v, copied.a) == ((2, 3), (4, 5), (6, 7))
    plain = Waypoint(w1.t, w1.p, w1.v, w1.a, line=w1.line)  # rationals only
    assert pieces([w, w1])[0].local == pieces([eager, plain])[0].local


def test_rows_that_are_not_plain_decimals_are_read_cell_by_cell() -> None:
    text = f"{HEADER}\n0,1/3,2,+1,4,5,6\n1,2,3,4,5,6,7e40\n2,2,3,4,5,6,x\n"
    points, problems = parse_waypoints(text.encode())
    assert points[0].p == (fmpq(1, 3), fmpq(2)) and points[0].v == (fmpq(1), fmpq(4))
    assert [row for row, _ in problems] == [3, 4]
    assert "ay" in problems[0][1] and "ay" in problems[1][1]


@pytest.mark.parametrize("fields", [1, 2, 3])
def test_a_segment_is_the_controllers_polynomial_made_where_read(fields: int) -> None:
    points = _points(random.Random(40 + fields), 30, fields)
    for piece, w0, w1 in zip(pieces(points), points, points[1:], strict=False):
        assert isinstance(piece.form, Segment)
        assert piece.__dict__["_local"] is None  # not made yet
        for i in (0, 1):
            assert piece.local[i] == _reference_segment(w0, w1, i, fields)  # type: ignore[index]


def _reference_segment(w0: Any, w1: Any, i: int, fields: int) -> fmpq_poly:
    """Coordinate i of the segment from w0 to w1 by the controller's formulas (``segment``:
    written apart from the loader), from the p (v, a) the rows give."""
    ends = [w0.p[i], w1.p[i]]
    if fields > 1:
        ends += [w0.v[i], w1.v[i]]
    if fields > 2:
        ends += [w0.a[i], w1.a[i]]
    return fmpq_poly(segment(w1.t - w0.t, *ends))


def _ball_ok(q: fmpq, mid: float, rad: float) -> None:
    """The ball of the exact rational q: its nearest double, radius 0 exactly when that
    double is q, and q inside."""
    assert mid == to_float(q)
    m = fmpq(*mid.as_integer_ratio())
    assert (rad == 0) == (m == q)
    assert abs(q - m) <= fmpq(*rad.as_integer_ratio())


@pytest.mark.parametrize("fields", [1, 2, 3])
def test_the_batch_rounds_the_exact_coefficients_of_each_segment(fields: int) -> None:
    """x's coefficients, and y's about the centre c of the piece, of every segment:
    nearest doubles of the exact rationals (written apart: the controller's formulas,
    flint's composition y(u + c)), zero-padded to the batch's degree."""
    points = _points(random.Random(70 + fields), 40, fields, digits=(3, 10, 17)[fields - 1])
    got = pieces(points)
    batch = Batch(got, _robot())
    for j, (w0, w1) in enumerate(itertools.pairwise(points)):
        polys = [_reference_segment(w0, w1, i, fields) for i in (0, 1)]
        c = dyadic_middle(0.0, float(batch.t_last[j]))
        assert batch.center.mid[j] == to_float(c) and batch.center.rad[j] == 0
        y = polys[1](fmpq_poly([c, 1]))
        for poly, (mid, rad) in ((polys[0], batch.x[0]), (y, batch.q[0])):
            coeffs = poly.coeffs()
            assert len(mid) == 2 * fields  # the degree of the batch (none vanishes)
            for k in range(len(mid)):
                _ball_ok(coeffs[k] if k < len(coeffs) else fmpq(0), mid[k, j], rad[k, j])
        lo, hi = float(batch.t_last[j]), float(batch.t_end[j])  # the floats about T
        T = w1.t - w0.t
        assert fmpq(*lo.as_integer_ratio()) <= T <= fmpq(*hi.as_integer_ratio())
        assert hi in (lo, math.nextafter(lo, math.inf))


def test_a_batch_taken_shares_its_coefficients_and_reads_its_own_pieces() -> None:
    points = _points(random.Random(9), 30, 3)
    batch = Batch(pieces(points), _robot())
    ids = [3, 1, 7, 20]
    taken = batch.take(ids)
    assert taken.q is batch.q and taken.cols is not None and list(taken.cols) == ids
    idx = np.array([2, 0])
    lo = batch.t_last[[ids[k] for k in idx]] * 0.25
    box = Ball.hull(lo, 2 * lo)
    got = taken.jets(box, idx)
    same = batch.jets(box, np.array([ids[k] for k in idx]))
    for a, b in zip(got, same, strict=True):
        assert (a.v.mid == b.v.mid).all() and (a.v.rad == b.v.rad).all()


def test_a_motion_from_waypoints_checks_its_knots_without_absolute_polynomials() -> None:
    """Consecutive segments share their waypoint: continuous by construction. Segments
    that do not (two runs of waypoints put together) are still checked, exactly."""
    t = [k / 1000 for k in range(2001)]
    p = [(2 + k * 1e-5, -1 + k * 2e-5) for k in range(2001)]
    m = Motion.from_waypoints(t, p, [(0.01, 0.02)] * 2001, [(0.0, 0.0)] * 2001)
    assert len(m.pieces) == 2000
    assert all(piece.__dict__["_x"] is None for piece in m.pieces)
    first = pieces([Waypoint(fmpq(0), (fmpq(0), fmpq(0))), Waypoint(fmpq(1), (fmpq(1), fmpq(0)))])
    second = pieces([Waypoint(fmpq(1), (fmpq(1), fmpq(1, 10**9))),
                     Waypoint(fmpq(2), (fmpq(2), fmpq(0)))])  # fmt: skip
    with pytest.raises(ValueError, match="the position jumps at the knot t = 1"):
        Motion((*first, *second))
    Motion((*first, *pieces([Waypoint(fmpq(1), (fmpq(1), fmpq(0))),
                             Waypoint(fmpq(2), (fmpq(2), fmpq(0)))])))  # fmt: skip

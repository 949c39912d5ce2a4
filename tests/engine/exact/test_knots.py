"""Piecewise motions: the audit between and at knots, checked against values derived
here (exact rational arithmetic) and against tests/reference.py (independent mpmath)."""

from __future__ import annotations

import itertools
import math
from dataclasses import replace
from fractions import Fraction

import numpy as np
from flint import fmpq, fmpq_poly

from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.model.task import Piece, Task
from rprpr.model.timing import timing_law, trapezoidal
from rprpr.model.waypoints import Waypoint, interpolate
from tests import reference as R
from tests.conftest import PATH2_FILE

T = fmpq_poly([0, 1])
BASE = load_task(PATH2_FILE)  # the paper's robot of Example 2 (alike legs, a1 = 6)
P2 = BASE.path  # eq. (51): p(x) = (x - 3)(0.8 (x - 3)^2 + 0.2)


def task(pieces: list[Piece], path: fmpq_poly | None = None) -> Task:
    return Task("piecewise", BASE.robot, path, None, pieces[-1].end, BASE.checks,
                law="motion", pieces=tuple(pieces))  # fmt: skip


def on_path(bounds: list[tuple[fmpq, fmpq, fmpq_poly]]) -> Task:
    """The path of Example 2 with x(t) given by pieces (start, end, x)."""
    assert P2 is not None
    return task([Piece(a, b, x, P2(x), P2) for a, b, x in bounds], P2)


def side_task(x: fmpq_poly) -> Task:
    """One side's motion extended as the paper's one-polynomial task (for the reference)."""
    return replace(BASE, x_of_t=x, pieces=())


def multiplicity(p: fmpq_poly, t: fmpq) -> int:
    k = 0
    while not p.is_zero() and p(t) == 0:
        p, k = p.derivative(), k + 1
    return k


def rules(result: object) -> list[str]:
    return [f.rule for f in result.findings]  # type: ignore[attr-defined]


QUINTIC = timing_law("quintic", fmpq(2), fmpq(4), fmpq(5))
HALF = fmpq(5, 2)


def test_crossing_at_a_c2_knot_has_the_same_order_on_both_sides() -> None:
    r = audit(on_path([(fmpq(0), HALF, QUINTIC), (HALF, fmpq(5), QUINTIC)]))
    (s,) = r.singularities
    assert s.knot and s.t_exact == Fraction(5, 2)
    before, after = s.side("before"), s.side("after")
    assert before is not None and after is not None
    assert before.order == after.order == s.order == multiplicity(P2(QUINTIC), HALF) == 1
    ref = R.limit(side_task(QUINTIC), HALF)
    assert ref is not None and s.torque_at_singularity is not None
    for side in (before, after, s):
        assert side.torque_bounded and side.torque_at_singularity is not None
        for j, name in enumerate(("T1", "T2")):
            assert math.isclose(side.torque_at_singularity[j], float(ref[name]), rel_tol=1e-12)
    assert math.isclose(s.slope, 0.2, rel_tol=1e-15)  # p'(3) = 0.2
    assert r.knots == (2.5,) and r.verdict == "pass" and "RPR204" not in rules(r)


def test_c1_knot_where_the_acceleration_jump_breaks_consistency_after_it() -> None:
    v = QUINTIC.derivative()(HALF)  # the same velocity, x'' = 0 before and 1/5 after
    eps = T - HALF
    after = 3 + v * eps + fmpq(1, 10) * eps**2
    r = audit(on_path([(fmpq(0), HALF, QUINTIC), (HALF, fmpq(5), after)]))
    (s,) = r.singularities
    b, a = s.side("before"), s.side("after")
    assert b is not None and a is not None
    assert R.limit(side_task(QUINTIC), HALF) is not None  # bounded before (reference)
    assert R.limit(side_task(after), HALF) is None  # a pole after (reference)
    assert b.consistent and b.torque_bounded and b.order == 1
    assert not a.consistent and not a.torque_bounded and a.pole_order == 1
    assert not s.torque_bounded and s.torque_at_singularity is None and not s.consistent
    assert "RPR201" in rules(r) and r.verdict == "fail"
    assert r.knot_jumps[0].acceleration_jump == (0.2, 0.04)  # Δx'' = 1/5, Δy'' = p'(3) Δx''


def test_touch_with_different_orders_on_its_two_sides() -> None:
    two = fmpq(2)
    x = 3 + (T - two)
    pieces = [Piece(fmpq(0), two, x, (T - two) ** 2), Piece(two, fmpq(4), x, (T - two) ** 4)]
    r = audit(task(pieces))
    (s,) = r.singularities
    b, a = s.side("before"), s.side("after")
    assert b is not None and a is not None
    assert (b.order, a.order, s.order) == (2, 4, 4) and s.kind == "touch"
    assert b.conditions_required == 2 and a.conditions_required == 4
    assert b.slope == a.slope == 0.0 and not s.slope_principle.passed  # ẏ/ẋ = 0
    assert "RPR101" in rules(r) and "RPR204" in rules(r)  # y'' jumps from 2 to 0


def test_a_velocity_jump_fails_with_its_own_rule() -> None:
    pts = [Waypoint(fmpq(0), (fmpq(2), fmpq(1))), Waypoint(fmpq(1), (fmpq(3), fmpq(1))),
           Waypoint(fmpq(2), (fmpq(3), fmpq(2)))]  # fmt: skip
    r = audit(task([Piece(a, b, x, y) for a, b, x, y, _ in interpolate(pts)]))
    (f,) = [f for f in r.findings if f.rule == "RPR203"]
    assert f.t == 1.0 and "t = 1 s" in f.message and "(-1, 1) m/s" in f.message
    assert r.verdict == "fail" and r.knot_jumps[0].velocity_jump == (-1.0, 1.0)


def test_instants_at_the_first_and_the_last_waypoint() -> None:
    one, zero = fmpq(1), fmpq(0)
    pts = [
        Waypoint(fmpq(0), (fmpq(2), zero), (one, one), (zero, zero)),
        Waypoint(fmpq(1), (fmpq(3), fmpq(1, 2)), (one, zero), (zero, zero)),
        Waypoint(fmpq(2), (fmpq(4), zero), (one, -one), (zero, zero)),
    ]
    r = audit(task([Piece(a, b, x, y) for a, b, x, y, _ in interpolate(pts)]))
    first, last = r.singularities
    assert (first.t_exact, last.t_exact) == (0, 2) and first.knot and last.knot
    assert [n for n, _ in first.sides] == ["after"] and [n for n, _ in last.sides] == ["before"]
    assert (first.slope, last.slope) == (1.0, -1.0)  # ẏ/ẋ of the waypoints' velocities
    assert first.speed == last.speed == math.sqrt(2) and first.order == last.order == 1


def _three_ways() -> list[Task]:
    x = QUINTIC
    y = (T - HALF) / 2 + (T - HALF) ** 3 / 10
    whole = task([Piece(fmpq(0), fmpq(5), x, y)])
    cuts = [fmpq(0), fmpq(7, 5), HALF, fmpq(37, 10), fmpq(5)]
    split = task([Piece(a, b, x, y) for a, b in itertools.pairwise(cuts)])
    d1, d2 = (
        (x.derivative(), y.derivative()),
        (x.derivative().derivative(), y.derivative().derivative()),
    )
    pts = [Waypoint(t, (x(t), y(t)), (d1[0](t), d1[1](t)), (d2[0](t), d2[1](t)))
           for t in (fmpq(0), fmpq(1), fmpq(33, 10), fmpq(5))]  # fmt: skip
    way = task([Piece(a, b, px, py) for a, b, px, py, _ in interpolate(pts)])
    return [whole, split, way]


def test_the_same_motion_three_ways_gives_the_same_report() -> None:
    results = [audit(t, peak=True) for t in _three_ways()]
    ref = results[0]
    (s0,) = ref.singularities
    assert s0.t_exact == Fraction(5, 2) and s0.order == 1
    for r in results:
        (s,) = r.singularities
        assert (s.t_exact, s.order, s.case, s.kind) == (s0.t_exact, 1, s0.case, "crossing")
        assert r.verdict == ref.verdict and rules(r) == rules(ref)
        assert s.slope_principle.passed and s.velocity_principle.passed
        assert s.torque_at_singularity is not None and s0.torque_at_singularity is not None
        for j in (0, 1):
            assert math.isclose(s.torque_at_singularity[j], s0.torque_at_singularity[j],
                                rel_tol=1e-12)  # fmt: skip
        assert r.torque_peak is not None and ref.torque_peak is not None
        for p, q in zip(r.torque_peak, ref.torque_peak, strict=True):
            assert p.value <= q.upper and q.value <= p.upper  # both bracket the maximum
    u = [r.resample(np.array([0.3, 1.4, 2.5, 4.1])) for r in results]
    for other in u[1:]:
        for name in ("T1", "T2", "theta1", "x_ddot", "s2_ddot"):
            a, b = getattr(u[0], name), getattr(other, name)
            assert all(
                math.isclose(p, q, rel_tol=1e-9, abs_tol=1e-9) for p, q in zip(a, b, strict=False)
            )


def test_example_2_as_a_trapezoidal_law() -> None:
    laws = trapezoidal(fmpq(2), fmpq(4), fmpq(5), fmpq(3, 5))  # t_b = 5/3
    starts = [fmpq(0)] + [end for end, _ in laws[:-1]]
    bounds = [(a, end, x) for a, (end, x) in zip(starts, laws, strict=True)]
    r = audit(on_path(bounds))
    cruise = laws[1][1]
    assert [e for e, _ in laws] == [fmpq(5, 3), fmpq(10, 3), fmpq(5)]
    assert cruise(HALF) == 3 and cruise.derivative()(HALF) == fmpq(3, 5)
    (s,) = r.singularities  # by hand: x = 3 at t = 5/2 only (p has the one root 3)
    assert s.t_exact == Fraction(5, 2) and not s.knot and s.order == 1 and s.x == 3.0
    assert math.isclose(s.slope, 0.2, rel_tol=1e-15)
    assert math.isclose(s.speed, 0.6 * math.sqrt(1 + 0.04), rel_tol=1e-15)
    assert s.slope_principle.passed and s.velocity_principle.passed
    ref = R.limit(side_task(cruise), HALF)  # x'' = 0 at the midpoint: consistent
    assert ref is not None and s.consistent and s.torque_bounded
    assert s.torque_at_singularity is not None
    for j, name in enumerate(("T1", "T2")):
        assert math.isclose(s.torque_at_singularity[j], float(ref[name]), rel_tol=1e-12)
    # the two C1 knots: x'' jumps by -0.36 and -0.36 (a = V/t_b = 9/25, then 0, then -9/25)
    assert [f.rule for f in r.findings] == ["RPR204", "RPR204"]
    for k, (left, right) in zip(r.knot_jumps, itertools.pairwise(laws), strict=True):
        tk = fmpq(k.t_exact.numerator, k.t_exact.denominator)
        lo, hi = R.reference(side_task(left[1]), tk), R.reference(side_task(right[1]), tk)
        jumps = [float(hi[n] - lo[n]) for n in ("T1", "T2")]
        assert k.torque_jump is not None
        for got, want in zip(k.torque_jump, jumps, strict=True):
            assert math.isclose(got, want, rel_tol=1e-9, abs_tol=1e-9)
    assert r.verdict == "pass"


def test_a_crossing_at_a_c0_knot_with_finite_but_different_sides_says_so() -> None:
    """Linear waypoints (2, -1) at 0, (3, 0) at 2, (4, 1.5) at 5: the crossing at the knot
    t = 2 has a different velocity on each side, each side's torques are bounded (a first
    order crossing, consistent: ẍ = 0 and the legs alike at the midpoint) but their
    limits differ, so the combined limit is null, and the table says the sides differ
    rather than calling bounded torques unbounded."""
    from rprpr.render.text import instant_cells
    from rprpr.report.records import task_report

    pts = [Waypoint(fmpq(0), (fmpq(2), fmpq(-1))), Waypoint(fmpq(2), (fmpq(3), fmpq(0))),
           Waypoint(fmpq(5), (fmpq(4), fmpq(3, 2)))]  # fmt: skip
    r = audit(task([Piece(a, b, x, y) for a, b, x, y, _ in interpolate(pts)]))
    (s,) = task_report(r, "t.yaml")["singularities"]
    assert s["knot"] and s["torque_bounded"] and s["torque_at_singularity"] is None
    before, after = (
        s["sides"]["before"]["torque_at_singularity"],
        s["sides"]["after"]["torque_at_singularity"],
    )
    assert before is not None and after is not None and before != after
    assert s["sides"]["before"]["slope"] == 1.0 and s["sides"]["after"]["slope"] == 1.5
    assert [text for text, _ in instant_cells(s, "2")][-1] == "sides differ"

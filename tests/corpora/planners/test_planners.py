"""Real float planner output (``plans.json``, written by ``generate.py`` with the planner
versions it records): scipy's ``CubicSpline`` and ``make_interp_spline`` and a Ruckig
plan, each designed to cross AB consistently at (3, 0) for the paper's path 2 robot, and
a Ruckig plan asked for zero vertical velocity there (``docs/robust.md``, README
*Piecewise motions*).

Without ``uncertainty`` the exact verdict on the rounded binary values holds: an
unbounded torque (RPR201, RPR202). With declared uncertainty the consistent crossings
pass — consistent to the input's precision — and the flat one fails on its window.

The reference (mpmath and fractions, nothing from ``rprpr``): the pieces from the JSON
as exact binary values, each knot's rounding jump closed as ``Motion.from_pieces``
documents (a jump no larger than the tolerance in value, slope or curvature continued by
d0 + d1 u + d2 u²/2), the crossing y(t) = 0 bisected in fractions to 1e-30 s, and the
residual of eq. (34) there from ``tests/engine/robust/box_reference.py`` at 50 digits.
"""

from __future__ import annotations

import json
from fractions import Fraction
from functools import cache
from pathlib import Path
from typing import Any

import mpmath
import pytest

from rprpr import Motion, Uncertainty, audit, load_task, with_motion
from rprpr.engine.audit import AuditResult
from rprpr.model.task import Task
from tests.conftest import CONFIGS
from tests.engine.robust import box_reference as B

Q = Fraction
DATA = json.loads((Path(__file__).parent / "plans.json").read_text(encoding="utf-8"))
PLANS = DATA["plans"]
TOLERANCE = Q(1, 10**12)
CONSISTENT = ("cubic_spline", "interp_spline", "ruckig_line")
FLAT = "ruckig_flat"  # asked for zero vertical velocity at (3, 0)
ISSUE = {  # the crossing residual's magnitude the issue reports for each (N)
    "cubic_spline": 8.9e-16,
    "interp_spline": 2.6e-15,
    "ruckig_line": 7.3e-15,
}
# links 5 %, acceleration 1 mm/s², a 1 ms period, the config's 300 N m limit
BOX = Uncertainty({i: (Q(1, 20),) * 3 for i in (2, 3, 4, 5)}, Q(1, 1000), Q(1, 1000))
POINT = Uncertainty({i: (Q(0),) * 3 for i in (2, 3, 4, 5)}, Q(0), Q(1, 1000))  # no box


@cache
def _task(name: str) -> Task:
    p = PLANS[name]
    motion = Motion.from_pieces(p["breaks"], p["x"], p["y"], tolerance=TOLERANCE)
    return with_motion(load_task(CONFIGS / "paper_path2.rprpr.yaml"), motion)


@cache
def _audit(name: str, box: str = "") -> AuditResult:
    u = {"": None, "box": BOX, "point": POINT}[box]
    return audit(_task(name)) if u is None else audit(_task(name), uncertainty=u)


# -- the reference ------------------------------------------------------------------------


def _pieces(name: str) -> list[tuple[Q, Q, list[list[Q]]]]:
    """(start, end, [x, y] ascending local coefficients) with the knots' rounding closed."""
    p = PLANS[name]
    breaks = [Q(v) for v in p["breaks"]]
    out: list[tuple[Q, Q, list[list[Q]]]] = []
    k = len(p["x"])
    for i in range(len(breaks) - 1):
        axes = [[Q(p[a][k - 1 - j][i]) for j in range(k)] for a in ("x", "y")]
        if out:
            start, end, before = out[-1]
            for c, b in zip(axes, before, strict=True):
                for order in range(3):
                    jump = _at(b, end - start)[order] - _at(c, Q(0))[order]
                    if abs(jump) <= TOLERANCE:
                        c[order] += jump / (1 if order < 2 else 2)
        out.append((breaks[i], breaks[i + 1], axes))
    return out


def _at(c: list[Q], u: Q) -> tuple[Q, Q, Q]:
    """p(u), p'(u), p''(u) of the ascending coefficients ``c``."""
    v = d1 = d2 = Q(0)
    for a in reversed(c):
        d2 = d2 * u + 2 * d1
        d1 = d1 * u + v
        v = v * u + a
    return v, d1, d2


def _crossing(name: str) -> tuple[Q, B.Motion]:
    """The time where y = 0 (to 1e-30 s) and the motion there."""
    for start, end, (x, y) in _pieces(name):
        lo, hi = Q(0), end - start
        if _at(y, lo)[0] < 0 <= _at(y, hi)[0]:
            while hi - lo > Q(1, 10**30):
                mid = (lo + hi) / 2
                lo, hi = (mid, hi) if _at(y, mid)[0] < 0 else (lo, mid)
            return start + lo, _at(x, lo) + _at(y, lo)
    raise AssertionError("no crossing")


@cache
def _reference(name: str) -> tuple[float, Any, Any]:
    """t_s, the residual of eq. (34) there (nominal links, no error) and dy/dx."""
    t, motion = _crossing(name)
    task = _task(name)
    v = B.joints(task, motion, (Q(0), Q(0)))
    with mpmath.workdps(B.DPS):
        return float(t), B.residual_of(task, task.robot.links, v), v["y_dot"] / v["x_dot"]


# -- the tests --------------------------------------------------------------------------------


def test_the_data_name_the_planners_and_their_versions() -> None:
    assert set(DATA["versions"]) == {"scipy", "numpy", "ruckig"}
    assert all(DATA["versions"].values())
    assert set(PLANS) == {*CONSISTENT, FLAT}


@pytest.mark.parametrize("name", sorted(PLANS))
def test_every_plan_needs_a_tolerance_at_its_knots(name: str) -> None:
    p = PLANS[name]
    with pytest.raises(ValueError, match="the position jumps at the knot"):
        Motion.from_pieces(p["breaks"], p["x"], p["y"])
    jump = float(Motion.from_pieces(p["breaks"], p["x"], p["y"], tolerance=1e-12).snapped)
    assert 0 < jump < 1e-14  # with it, the rounding is closed: a change of 1e-15 m


@pytest.mark.parametrize("name", sorted(PLANS))
def test_without_uncertainty_the_exact_verdicts_fail_and_match_the_reference(name: str) -> None:
    result = _audit(name)
    assert result.verdict == "fail"
    assert [f.rule for f in result.findings] == ["RPR201", "RPR202"]
    (s,) = result.singularities
    t, residual, slope = _reference(name)
    assert abs(s.t - t) <= 5e-16 and s.order == 1 and not s.consistent
    assert s.consistency_residual == pytest.approx(float(residual), rel=1e-9)
    assert s.slope == pytest.approx(abs(float(slope)), rel=1e-9)
    if name in ISSUE:  # a rounding residual, of the issue's magnitude
        assert ISSUE[name] / 20 < abs(s.consistency_residual) < ISSUE[name] * 20
    else:  # flat in exact arithmetic (order 3, slope 0); order 1 after rounding
        assert 1e-11 < s.slope < 1e-10  # the issue's 3.9e-11


def test_the_cubic_spline_crosses_where_the_issue_says() -> None:
    (s,) = _audit("cubic_spline").singularities
    assert s.t == 2.4999999999999996 and _reference("cubic_spline")[0] == s.t


@pytest.mark.parametrize("name", CONSISTENT)
def test_the_consistent_crossings_pass_with_declared_uncertainty(name: str) -> None:
    for box in ("point", "box"):
        result = _audit(name, box)
        assert result.verdict == "pass"
        assert [f.rule for f in result.findings] == ["RPR201", "RPR202"]
        assert all(f.severity == "warning" for f in result.findings)
        (pole,) = [f for f in result.findings if f.rule == "RPR201"]
        (r,) = result.robust
        if box == "point":  # the nominal model alone: a pole of the input's rounding
            assert "consistent to the input's precision" in pole.message
            assert r.window < 1e-15
        else:  # 5 % and 1 mm/s²: a window of a fraction of the period
            assert "(RPR205 decides)" in pole.message
            assert 1e-5 < r.window < float(BOX.period)


def test_the_zero_vertical_velocity_plan_fails_on_its_window() -> None:
    for box in ("point", "box"):
        result = _audit(FLAT, box)
        assert result.verdict == "fail"
        (f,) = [f for f in result.findings if f.rule == "RPR205"]
        assert f.severity == "error" and "longer than the 1 ms period" in f.message
        assert result.robust[0].window > 0.9  # hundreds of ms: the velocity principle


def test_the_flat_plans_window_goes_on_across_its_knots() -> None:
    """The crossing is 7.5 µs after a knot (3.3722813 s) and the nominal |T1| exceeds the
    limit from 2.95 s to 3.85 s, across that knot and the one at 3.8722813 s: the robust
    window of the nominal model (no box) is that span, found by the robust analysis on its
    own (root finding and ball proofs over the pieces) and by the certified limit check
    (``engine/bounds``) apart; the box's is wider still."""
    point = _audit(FLAT, "point")
    (r,) = point.robust
    (sat,) = point.saturation
    w1 = sat[1]  # |T1|'s window (``Window``: each end bracketed)
    assert r.span is not None and r.joint == 1
    assert r.span[0] <= w1.start_hi and w1.end_lo <= r.span[1]
    assert r.window <= (w1.end_hi - w1.start_lo) + 1e-6
    assert r.span[0] < 3.3722813 < sat[0].t < r.span[1]  # past the knot before t_s
    assert 0.901 < r.window < 0.9011  # 901 ms, as RPR202 says
    boxed = _audit(FLAT, "box").robust[0]
    assert boxed.span is not None and boxed.span[0] < r.span[0] and r.span[1] < boxed.span[1]

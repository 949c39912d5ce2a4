"""Property tests of the engine (hypothesis): random paths, timings and robots."""

from __future__ import annotations

import math

import numpy as np
from flint import fmpq, fmpq_poly
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from rprpr.engine.audit import audit
from rprpr.model.task import Checks, Link, Robot, Task

from .test_engine import at_times, mechanical_energy

SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])

small = st.integers(-6, 6)
frac = st.builds(lambda p, q: fmpq(p, q), small, st.integers(1, 4))
positive = st.builds(lambda p, q: fmpq(p, q), st.integers(1, 12), st.integers(1, 4))


@st.composite
def tasks(draw):  # type: ignore[no-untyped-def]
    """A random robot and motion; paths are often built from chosen roots so that singular
    instants (of several orders, rational and irrational) are common."""
    a1 = draw(positive)
    x = fmpq_poly(draw(st.lists(frac, min_size=2, max_size=4)))
    assume(x.degree() >= 1)
    if draw(st.booleans()):
        roots = draw(st.lists(frac, min_size=1, max_size=3))
        p = fmpq_poly([draw(frac) or 1])
        for r in roots:
            p *= fmpq_poly([-r, 1]) ** draw(st.integers(1, 3))
    else:
        p = fmpq_poly(draw(st.lists(frac, min_size=1, max_size=4)))
    assume(not p.is_zero())
    links = {i: Link(draw(positive), draw(positive) / 10, draw(positive) / 4) for i in (2, 3, 4, 5)}
    no_margins = Checks(fmpq(0), fmpq(0), None, False)
    return Task("random", Robot(a1, links, fmpq(981, 100)), p, x, draw(positive), no_margins)


def _f(q: fmpq) -> float:
    return int(q.p) / int(q.q)


@SETTINGS
@given(tasks())
def test_singular_instants_are_the_real_roots_with_their_multiplicity(task):  # type: ignore[no-untyped-def]
    r = audit(task, samples=201)
    y = task.path(task.x_of_t)
    ts = [s.t for s in r.singularities] + [k.t for k in r.kinematic_singularities]
    for s in r.singularities:
        assert 0 <= s.t <= _f(task.duration)
        d = y
        if s.t_exact is not None:  # exact: y and its first m-1 derivatives vanish, y^(m) not
            for _ in range(s.order):
                assert d(s.t_exact) == 0
                d = d.derivative()
            assert d(s.t_exact) != 0
        else:  # irrational root: y^(m) is clearly nonzero there, y is zero to rounding
            scale = max(abs(_f(c)) for c in y.coeffs()) * max(1.0, abs(s.t)) ** y.degree()
            assert (
                abs(np.polynomial.polynomial.polyval(s.t, [_f(c) for c in y.coeffs()]))
                < 1e-9 * scale
            )
        assert s.kind == ("crossing" if s.order % 2 else "touch")
        assert s.conditions_met <= s.conditions_required == s.order
        assert s.torque_bounded == (s.torque_at_singularity is not None)
    # every sign change of y on a fine grid lies next to a reported instant (within one
    # step: next to a multiple root the floating-point sign of y is noise)
    t = np.linspace(0, _f(task.duration), 2001)
    dt = t[1] - t[0]
    yv = np.polynomial.polynomial.polyval(t, [_f(c) for c in y.coeffs()])
    for i in np.nonzero(np.sign(yv[:-1]) * np.sign(yv[1:]) < 0)[0]:
        assert any(t[i] - dt <= tc <= t[i + 1] + dt for tc in ts)


@SETTINGS
@given(tasks())
def test_joint_values_reproduce_the_end_point(task):  # type: ignore[no-untyped-def]
    r = audit(task, samples=101)
    assume(not r.kinematic_singularities)
    s = r.samples
    a1 = _f(task.robot.a1)
    scale = 1 + np.max(np.abs(s.x)) + np.max(np.abs(s.y))
    assert np.allclose(s.s1 * np.cos(s.theta1), s.x, atol=1e-12 * scale)
    assert np.allclose(s.s1 * np.sin(s.theta1), s.y, atol=1e-12 * scale)
    assert np.allclose(a1 + s.s2 * np.cos(s.theta2), s.x, atol=1e-12 * scale)
    assert np.allclose(s.s2 * np.sin(s.theta2), s.y, atol=1e-12 * scale)
    # θ continuous: no jump of about 2π between samples
    assert np.all(np.abs(np.diff(s.theta1)) < math.pi) and np.all(
        np.abs(np.diff(s.theta2)) < math.pi
    )


@SETTINGS
@given(tasks())
def test_power_balance_away_from_singular_instants(task):  # type: ignore[no-untyped-def]
    r = audit(task, samples=21)
    assume(not r.on_singular_line)
    tf = _f(task.duration)
    t = np.linspace(0.05 * tf, 0.95 * tf, 9)
    bad = [s.t for s in r.singularities] + [k.t for k in r.kinematic_singularities]
    t = np.array([ti for ti in t if all(abs(ti - b) > 0.02 * tf for b in bad)])
    assume(len(t) > 0)
    s = at_times(r, t)
    assume(np.all(s.s1 > 1e-3) and np.all(s.s2 > 1e-3) and np.all(np.abs(s.delta) > 1e-3))
    h = 1e-6 * max(1.0, tf)
    dE = (mechanical_energy(r, t + h) - mechanical_energy(r, t - h)) / (2 * h)
    power = s.T1 * s.theta1_dot + s.T2 * s.theta2_dot
    scale = np.max(np.abs(np.concatenate([power, dE]))) + 1e-9
    assert np.allclose(power, dE, rtol=1e-4, atol=1e-4 * scale)

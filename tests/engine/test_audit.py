"""The engine against the paper's numbers and independent derivations."""

from __future__ import annotations

import dataclasses
import math
import subprocess
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import numpy as np
import pytest
from flint import fmpq

from rprpr.engine.audit import AuditResult, audit
from rprpr.engine.bounds.verdicts import LimitCheck
from rprpr.engine.certified.sampling import grid
from rprpr.io.loader import load_task, parse_task
from rprpr.model.rules import Finding
from rprpr.model.task import Checks, Task
from tests.cli.forked import fresh_probe
from tests.conftest import CONFIGS, PATH2_YAML, QUINTIC, task_text
from tests.reference import reference

HEAVY5 = """\
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 3.0, inertia: 0.05, r: 0.5}
"""


@pytest.fixture(scope="module")
def path1():  # type: ignore[no-untyped-def]
    return audit(load_task(CONFIGS / "paper_path1.rprpr.yaml"))


@pytest.fixture(scope="module")
def path2():  # type: ignore[no-untyped-def]
    return audit(load_task(CONFIGS / "paper_path2.rprpr.yaml"))


def _f(q: fmpq) -> float:
    return int(q.p) / int(q.q)


def at_times(result, t):  # type: ignore[no-untyped-def]
    """Samples of an audited task at the given times."""
    return result.resample(np.asarray(t, dtype=float))


# -- the paper's numbers (Section 4) ------------------------------------------------


def test_initial_joints_are_the_papers(path2):  # type: ignore[no-untyped-def]
    s = path2.samples
    assert math.degrees(s.theta1[0]) == pytest.approx(-26.5651, abs=5e-5)
    assert s.s1[0] == pytest.approx(2.2361, abs=5e-5)
    assert math.degrees(s.theta2[0]) == pytest.approx(-165.9638, abs=5e-5)
    assert s.s2[0] == pytest.approx(4.1231, abs=5e-5)


def test_quintic_is_eq_49(path2):  # type: ignore[no-untyped-def]
    x = path2.task.x_of_t
    assert [x[k] for k in range(6)] == [2, 0, 0, fmpq(4, 25), fmpq(-6, 125), fmpq(12, 3125)]


def test_path1_singularity_is_third_order_at_2_5(path1):  # type: ignore[no-untyped-def]
    (s,) = path1.singularities
    assert s.t_rational == fmpq(5, 2)
    assert (s.x, s.y) == (3.0, 0.0)
    assert s.order == 3 and s.kind == "crossing"
    assert s.delta_derivatives[:3] == [0.0, 0.0, 0.0]
    # δ = -a1 y/(s1 s2) with y = (x-3)^3: δ''' = -6 * 6 x'^3 / (3 * 3), x'(2.5) = 3/4
    assert s.delta_derivatives[3] == pytest.approx(-6 * 6 * 0.75**3 / 9, rel=1e-15)
    assert s.case.number == 3 and (s.case.sigma, s.case.psi) == (-1, 1)


def test_path1_fails_slope_principle_passes_velocity(path1):  # type: ignore[no-untyped-def]
    (s,) = path1.singularities
    assert not s.slope_principle.passed and s.slope == 0.0
    assert s.velocity_principle.passed and s.speed == pytest.approx(0.75)
    assert path1.verdict == "fail"
    assert [f.rule for f in path1.findings if f.fails(False)] == ["RPR101", "RPR201"]


def test_path2_first_order_slope_0_2_and_passes(path2):  # type: ignore[no-untyped-def]
    (s,) = path2.singularities
    assert s.t_rational == fmpq(5, 2) and s.order == 1
    assert s.slope == pytest.approx(0.2, rel=1e-15)
    assert s.delta_derivatives[0] == 0.0
    assert s.delta_derivatives[1] == pytest.approx(-6 * 0.2 * 0.75 / 9, rel=1e-15)
    assert s.slope_principle.passed and s.velocity_principle.passed
    assert path2.verdict == "pass" and path2.findings == []


# -- independent cross-checks -------------------------------------------------------


def test_delta_from_angles_equals_product_form(path2):  # type: ignore[no-untyped-def]
    s = path2.samples
    assert np.allclose(np.sin(s.theta1 - s.theta2), s.delta, rtol=0, atol=1e-14)
    a1 = 6.0
    assert np.allclose(s.delta, -a1 * s.y / (s.s1 * s.s2), rtol=1e-14, atol=1e-16)


def test_forward_kinematics_reproduce_the_end_point(path2):  # type: ignore[no-untyped-def]
    s = path2.samples
    assert np.allclose(s.s1 * np.cos(s.theta1), s.x, atol=1e-13)
    assert np.allclose(s.s1 * np.sin(s.theta1), s.y, atol=1e-13)
    assert np.allclose(6 + s.s2 * np.cos(s.theta2), s.x, atol=1e-13)
    assert np.allclose(s.s2 * np.sin(s.theta2), s.y, atol=1e-13)


def test_derivatives_agree_with_finite_differences(path2):  # type: ignore[no-untyped-def]
    h = 1e-5
    t = np.array([0.3, 1.1, 2.0, 3.3, 4.6])
    c, lo, hi = at_times(path2, t), at_times(path2, t - h), at_times(path2, t + h)
    pairs = [
        ("theta1", "theta1_dot"), ("theta2", "theta2_dot"), ("s1", "s1_dot"), ("s2", "s2_dot"),
        ("theta1_dot", "theta1_ddot"), ("theta2_dot", "theta2_ddot"), ("s1_dot", "s1_ddot"),
        ("s2_dot", "s2_ddot"), ("delta", "delta_dot"), ("x", "x_dot"), ("y", "y_dot"),
    ]  # fmt: skip
    for q, qd in pairs:
        fd = (hi.column(q) - lo.column(q)) / (2 * h)
        assert np.allclose(fd, c.column(qd), rtol=1e-6, atol=1e-8), q


def test_torques_of_eq28_equal_a_direct_solve_of_eq4(path2):  # type: ignore[no-untyped-def]
    """Solve M q'' + N = Q + J^T λ (eq. 4) for (T1, T2, λ1, λ2) as a 4x4 linear system."""
    s = at_times(path2, np.linspace(0.05, 4.95, 36))  # t_s = 2.5 is not among them
    L = path2.task.robot.links
    m2, I2, r2 = (_f(v) for v in (L[2].mass, L[2].inertia, L[2].r))
    m3, I3, r3 = (_f(v) for v in (L[3].mass, L[3].inertia, L[3].r))
    m4, I4, r4 = (_f(v) for v in (L[4].mass, L[4].inertia, L[4].r))
    m5, I5, r5 = (_f(v) for v in (L[5].mass, L[5].inertia, L[5].r))
    g = 9.81
    for i in range(len(s.t)):
        th1, s1, th2, s2 = s.theta1[i], s.s1[i], s.theta2[i], s.s2[i]
        w1, v1, w2, v2 = s.theta1_dot[i], s.s1_dot[i], s.theta2_dot[i], s.s2_dot[i]
        qdd = np.array([s.theta1_ddot[i], s.s1_ddot[i], s.theta2_ddot[i], s.s2_ddot[i]])
        M = np.diag([
            m2 * r2**2 + I2 + m3 * (s1 - r3) ** 2 + I3, m3,
            m4 * r4**2 + I4 + m5 * (s2 - r5) ** 2 + I5, m5,
        ])  # fmt: skip
        N = np.array([
            2 * m3 * v1 * w1 * (s1 - r3) + (m2 * r2 + m3 * (s1 - r3)) * g * np.cos(th1),
            -m3 * (s1 - r3) * w1**2 + m3 * g * np.sin(th1),
            2 * m5 * v2 * w2 * (s2 - r5) + (m4 * r4 + m5 * (s2 - r5)) * g * np.cos(th2),
            -m5 * (s2 - r5) * w2**2 + m5 * g * np.sin(th2),
        ])  # fmt: skip
        J = np.array([
            [-s1 * np.sin(th1), np.cos(th1), s2 * np.sin(th2), -np.cos(th2)],
            [s1 * np.cos(th1), np.sin(th1), -s2 * np.cos(th2), -np.sin(th2)],
        ])  # fmt: skip
        # unknowns u = (T1, T2, λ1, λ2):  Q(u) + J^T λ = M q'' + N
        A = np.zeros((4, 4))
        A[0, 0] = A[2, 1] = 1.0
        A[:, 2:] = J.T
        T1, T2, l1, l2 = np.linalg.solve(A, M @ qdd + N)
        assert s.T1[i] == pytest.approx(T1, rel=1e-9, abs=1e-9)
        assert s.T2[i] == pytest.approx(T2, rel=1e-9, abs=1e-9)
        assert s.lambda1[i] == pytest.approx(l1, rel=1e-9, abs=1e-9)
        assert s.lambda2[i] == pytest.approx(l2, rel=1e-9, abs=1e-9)


def mechanical_energy(result, t):  # type: ignore[no-untyped-def]
    """Kinetic + potential energy from the mass centres' positions and velocities, derived
    independently of the paper's M and N: G2 = A + r2 u1, G3 = A + (s1 - r3) u1,
    G4 = B + r4 u2, G5 = B + (s2 - r5) u2 with u = (cos θ, sin θ)."""
    s = at_times(result, t)
    L = result.task.robot.links
    a1 = _f(result.task.robot.a1)
    g = _f(result.task.robot.gravity)
    e = np.zeros_like(s.t)
    for th, w, ss, sd, base, (lin, lout) in (
        (s.theta1, s.theta1_dot, s.s1, s.s1_dot, 0.0, (L[2], L[3])),
        (s.theta2, s.theta2_dot, s.s2, s.s2_dot, a1, (L[4], L[5])),
    ):
        u = np.array([np.cos(th), np.sin(th)])
        n = np.array([-np.sin(th), np.cos(th)])
        for dist, ddist, link in ((_f(lin.r), 0.0, lin), (ss - _f(lout.r), sd, lout)):
            pos = np.array([base, 0.0])[:, None] + dist * u
            vel = ddist * u + dist * w * n
            m, inertia = _f(link.mass), _f(link.inertia)
            e += 0.5 * m * (vel**2).sum(axis=0) + 0.5 * inertia * w**2 + m * g * pos[1]
    return e


@pytest.mark.parametrize("config", ["paper_path1.rprpr.yaml", "paper_path2.rprpr.yaml"])
def test_power_balance_away_from_singular_instants(config):  # type: ignore[no-untyped-def]
    result = audit(load_task(CONFIGS / config), samples=11)
    t = np.concatenate([np.linspace(0.2, 2.3, 8), np.linspace(2.7, 4.8, 8)])
    h = 1e-5
    dE = (mechanical_energy(result, t + h) - mechanical_energy(result, t - h)) / (2 * h)
    s = at_times(result, t)
    power = s.T1 * s.theta1_dot + s.T2 * s.theta2_dot
    assert np.allclose(power, dE, rtol=1e-6, atol=1e-6 * np.max(np.abs(power)))


# -- boundedness through the singularity ---------------------------------------------


def test_path2_alike_legs_torque_limit_is_finite_and_continuous(path2):  # type: ignore[no-untyped-def]
    (s,) = path2.singularities
    assert s.consistent and s.consistency_residual == 0.0
    assert (s.conditions_required, s.conditions_met) == (1, 1) and s.torque_bounded
    T1, T2 = s.torque_at_singularity
    # an independent estimate of the limit: the direct formula at t_s ± 1e-3 s, averaged
    # (the first-order terms cancel; the remainder is O(1e-6) of T'')
    side = at_times(path2, [2.5 - 1e-3, 2.5 + 1e-3])
    assert pytest.approx(side.T1.mean(), abs=1e-4) == T1
    assert pytest.approx(side.T2.mean(), abs=1e-4) == T2
    near = at_times(path2, [2.5 - 1e-6, 2.5 - 1e-9, 2.5, 2.5 + 1e-9, 2.5 + 1e-6])
    assert np.all(np.isfinite(near.T1)) and np.all(np.isfinite(near.T2))
    assert np.allclose(near.T1, T1, atol=1e-4) and np.allclose(near.T2, T2, atol=1e-4)
    # the sampled curve has no spike anywhere: second differences are O(h^2 T'')
    g = path2.samples
    assert np.max(np.abs(np.diff(g.T1, 2))) < 1e-2 and np.max(np.abs(np.diff(g.T2, 2))) < 1e-2


def test_grid_of_11_hits_the_singular_instant_with_the_limit(path2):  # type: ignore[no-untyped-def]
    r = audit(path2.task, samples=11)
    assert r.samples.t[5] == 2.5
    assert r.samples.T1[5] == pytest.approx(63.225, abs=1e-9)
    assert r.samples.T2[5] == pytest.approx(-5.445, abs=1e-9)


def test_path2_with_heavier_link5_is_inconsistent_and_unbounded(write_task):  # type: ignore[no-untyped-def]
    r = audit(load_task(write_task(task_text(PATH2_YAML, QUINTIC, links=HEAVY5))), samples=11)
    (s,) = r.singularities
    # eq. (34) in case 3 at y = 0, x'' = 0: -m3 r3 y'^2/x^2 + m5 r5 y'^2/s2^2, y' = 0.15
    assert s.consistency_residual == pytest.approx((-1 * 0.5 + 3 * 0.5) * 0.15**2 / 9, rel=1e-14)
    assert not s.consistent and s.conditions_met == 0 and s.pole_order == 1
    assert s.torque_at_singularity is None and not s.torque_bounded
    assert np.isnan(r.samples.T1[5]) and np.isnan(r.samples.lambda2[5])
    # a pole of order 1: λ2 = c/ε + d + O(ε); the symmetric mean of λ2 ε is c + O(ε^2)
    near = at_times(r, [2.5 - 1e-6, 2.5 + 1e-6, 2.5 - 1e-9, 2.5 + 1e-9])
    prod = near.lambda2 * np.array([-1e-6, 1e-6, -1e-9, 1e-9])
    residue = [(prod[0] + prod[1]) / 2, (prod[2] + prod[3]) / 2]
    assert residue[0] == pytest.approx(residue[1], rel=1e-6) and abs(residue[0]) > 1e-3
    assert r.verdict == "fail"  # the principles hold, but unbounded torque cannot be executed
    assert [f.rule for f in r.findings] == ["RPR201"]
    (f,) = r.findings
    assert f.message.endswith(
        "torques unbounded (pole of order 1): inconsistent: eq. (34) residual 0.0025 N ≠ 0"
    )  # (-1 * 0.5 + 3 * 0.5) * 0.15^2 / 9
    accepted = _accepting_unbounded(r.task)
    assert audit(accepted, samples=11).verdict == "pass"  # checks.unbounded_torque: warn
    assert audit(accepted, samples=11, strict=True).verdict == "fail"


def _accepting_unbounded(task):  # type: ignore[no-untyped-def]
    """``task`` with checks.unbounded_torque: warn."""
    checks = dataclasses.replace(task.checks, unbounded_torque="warn")
    return dataclasses.replace(task, checks=checks)


def test_path1_high_order_has_a_pole_of_order_two(path1):  # type: ignore[no-untyped-def]
    (s,) = path1.singularities
    assert s.consistent and s.conditions_met == 1 and s.pole_order == 2
    near = at_times(path1, [2.5 - 1e-4, 2.5 + 1e-4, 2.5 - 1e-5, 2.5 + 1e-5])
    eps = np.array([-1e-4, 1e-4, -1e-5, 1e-5])
    prod = near.lambda2 * eps**2
    assert np.allclose(prod, prod[2], rtol=2e-3) and abs(prod[2]) > 0


# -- the shipped configs of the three cases, touch and zero speed ---------------------


@pytest.mark.parametrize(
    ("config", "case", "order", "kind", "slope_ok", "speed_ok"),
    [
        ("case1_crossing.rprpr.yaml", 1, 1, "crossing", True, True),
        ("case2_crossing.rprpr.yaml", 2, 1, "crossing", True, True),
        ("touch.rprpr.yaml", 3, 2, "touch", False, True),
        ("zero_speed_crossing.rprpr.yaml", 3, 3, "crossing", True, False),
    ],
)
def test_shipped_configs(config, case, order, kind, slope_ok, speed_ok):  # type: ignore[no-untyped-def]
    r = audit(load_task(CONFIGS / config), samples=101)
    (s,) = r.singularities
    assert (s.case.number, s.order, s.kind) == (case, order, kind)
    assert (s.slope_principle.passed, s.velocity_principle.passed) == (slope_ok, speed_ok)
    assert not s.torque_bounded and r.verdict == "fail"  # every one has unbounded torques
    accepted = audit(_accepting_unbounded(r.task), samples=101)
    assert accepted.verdict == ("pass" if slope_ok and speed_ok else "fail")


def test_theta_stays_continuous_through_the_cut_behind_A():  # type: ignore[no-untyped-def]
    r = audit(load_task(CONFIGS / "case2_crossing.rprpr.yaml"), samples=11)
    (s,) = r.singularities
    assert s.case.number == 2
    for res in (r, audit(r.task, samples=2001)):
        th1, th2 = res.samples.theta1, res.samples.theta2
        assert np.max(np.abs(np.diff(th1))) < 0.5 and np.max(np.abs(np.diff(th2))) < 0.5
    # θ1 starts at atan2 (y < 0 behind A: near -π) and runs on through -π, no 2π jump
    assert r.samples.theta1[0] == pytest.approx(math.atan2(r.samples.y[0], r.samples.x[0]))
    assert r.samples.theta1[5] == pytest.approx(-math.pi, abs=1e-15)  # at t_s = 2
    assert np.min(r.samples.theta1) < -math.pi < np.max(r.samples.theta1)
    assert np.all(np.diff(r.samples.theta1) < 0)  # y grows from -0.3 to 0.3 behind A


# -- exactness --------------------------------------------------------------------------


def test_irrational_root_is_certified_and_exact_order(write_task):  # type: ignore[no-untyped-def]
    # y = x^2 - 2 along x = t: t_s = sqrt(2), simple root, case 3
    text = task_text("x^2 - 2", "timing:\n  duration: 3\n  x: t\n")
    r = audit(load_task(write_task(text)), samples=101)
    (s,) = r.singularities
    assert s.t_exact is None and s.t == pytest.approx(math.sqrt(2), rel=1e-15)
    assert s.order == 1 and s.slope == pytest.approx(2 * math.sqrt(2), rel=1e-15)


def test_high_multiplicity_touch_and_crossing(write_task):  # type: ignore[no-untyped-def]
    for power, kind in ((8, "touch"), (9, "crossing")):
        text = task_text(f"(x-3)^{power}", "timing:\n  duration: 2\n  x: 2 + t\n")
        (s,) = audit(load_task(write_task(text)), samples=51).singularities
        assert (s.order, s.kind, s.t_rational) == (power, kind, fmpq(1))
        assert s.delta_derivatives[:power] == [0.0] * power and s.delta_derivatives[power] != 0


def test_singular_instants_at_both_ends(write_task):  # type: ignore[no-untyped-def]
    text = task_text("(x-2)*(x-4)", "timing:\n  duration: 2\n  x: 2 + t\n")
    r = audit(load_task(write_task(text)), samples=21)
    assert [s.t_exact for s in r.singularities] == [0, 2]
    assert all(np.isfinite(r.samples.x)) and all(np.isfinite(r.samples.theta1))
    # both instants lie on leg 2's branch cut (x < a1): θ2 stays continuous to the end
    th2 = r.samples.theta2
    assert th2[0] == pytest.approx(math.pi) and th2[-1] == pytest.approx(math.pi)  # y < 0 between
    assert np.max(np.abs(np.diff(th2))) < 0.1


def test_path_through_A_is_a_kinematic_singularity(write_task):  # type: ignore[no-untyped-def]
    text = task_text("x", "timing:\n  duration: 2\n  x: t - 1\n")
    r = audit(load_task(write_task(text)), samples=21)
    assert r.singularities == []
    assert [(k.t, k.leg) for k in r.kinematic_singularities] == [(1.0, 1)]
    assert r.verdict == "fail" and [f.rule for f in r.findings] == ["RPR103"]
    assert r.samples.t[10] == 1.0 and np.isnan(r.samples.theta1[10])  # θ1 undefined at A
    assert np.isfinite(r.samples.theta2[10]) and np.isfinite(r.samples.theta1[9])


def test_path_on_the_singular_line_fails_cleanly(write_task):  # type: ignore[no-untyped-def]
    text = task_text("0", "timing:\n  duration: 2\n  x: 2 + t\n")
    r = audit(load_task(write_task(text)), samples=21)
    assert r.on_singular_line and r.singularities == [] and r.verdict == "fail"
    assert [f.rule for f in r.findings] == ["RPR104"]
    assert [(k.t, k.leg) for k in r.kinematic_singularities] == []


def test_margins_are_named_in_the_reason(write_task):  # type: ignore[no-untyped-def]
    extra = "checks:\n  min_slope: 0.25\n  min_speed: 0.8\n"
    r = audit(load_task(write_task(task_text(PATH2_YAML, QUINTIC, extra=extra))), samples=11)
    (s,) = r.singularities
    assert not s.slope_principle.passed and "checks.min_slope = 0.25" in s.slope_principle.reason
    assert (
        not s.velocity_principle.passed and "checks.min_speed = 0.8" in s.velocity_principle.reason
    )
    assert r.verdict == "fail"
    # exactly at the margin is not beyond it: slope 0.2 vs min_slope 0.2
    r = audit(
        load_task(write_task(task_text(PATH2_YAML, QUINTIC, extra="checks:\n  min_slope: 0.2\n"))),
        samples=11,
    )
    assert not r.singularities[0].slope_principle.passed


def test_torque_limit_gates_only_in_strict_mode(write_task):  # type: ignore[no-untyped-def]
    extra = "checks:\n  torque_limit: [50, 100]\n"
    r = audit(load_task(write_task(task_text(PATH2_YAML, QUINTIC, extra=extra))), peak=True)
    assert r.torque_peak[0].value > 50 and r.verdict == "pass"
    assert [f.rule for f in r.findings] == ["RPR202"]
    assert audit(r.task, strict=True).verdict == "fail"


def test_torque_limit_with_an_unbounded_instant_names_the_pole(write_task):  # type: ignore[no-untyped-def]
    text = (
        CONFIGS / "paper_path1.rprpr.yaml"
    ).read_text() + "checks:\n  torque_limit: [300, 300]\n"
    r = audit(load_task(write_task(text)))
    msgs = [f.message for f in r.findings if f.rule == "RPR202"]
    assert msgs == [
        "t = 2.5 s: the torques are unbounded (pole of order 2): beyond any limit:"
        " |T1| > 300 N m for 394 ms around t = 2.5 s (t = 2.30935 .. 2.70333 s);"
        " |T2| > 300 N m for 350.6 ms around t = 2.5 s (t = 2.32126 .. 2.67189 s)"
    ]
    # the window's ends are where the independent reference's |T_i| crosses 300 N m
    for name, (start, end) in (("T1", (2.30935, 2.70333)), ("T2", (2.32126, 2.67189))):
        for t, inside in ((start, 1e-5), (end, -1e-5)):
            assert (
                abs(reference(r.task, t - inside)[name])
                < 300
                < abs(reference(r.task, t + inside)[name])
            )


def test_decimal_text_is_exact():  # type: ignore[no-untyped-def]
    task = parse_task(task_text("0.1*x - 0.3", "timing:\n  duration: 0.1\n  x: 30*t\n"))
    assert task.path[1] == fmpq(1, 10) and task.duration == fmpq(1, 10)
    (s,) = audit(task, samples=11).singularities
    assert s.t_rational == fmpq(1, 10)  # exact, although 0.1 is no binary float


def test_sample_grid_is_exact_fractions_of_t_f():  # type: ignore[no-untyped-def]
    t = grid(fmpq(5), 11)
    assert t[5] == 2.5 and t[-1] == 5.0 and t[0] == 0.0


# One fresh Python process (a start-up probe, ``tests.cli.forked.fresh_probe``, from numpy
# and flint): the engine's core imported (then, on standard output, a line "core:" and the
# modules of the command line, YAML or plotting it pulled in), and then ``rprpr check`` run
# (then, on standard error, whether matplotlib was imported). The core imports nothing of
# the command line, so the check runs as from a fresh process; one probe serves both tests
# below.
fresh_probe(
    "test_audit core",
    "numpy, flint",
    "import sys, rprpr.engine.audit, rprpr.engine.certified.sampling\n"
    "import rprpr.engine.exact.singular\n"
    "bad = [m for m in ('click', 'rich', 'yaml', 'matplotlib') if m in sys.modules]\n"
    "print('core:' + ','.join(bad), flush=True)\n"
    "from rprpr.cli.main import main\n"
    "try:\n    main(['check', '--format', 'json', "
    f"{str(CONFIGS / 'paper_path2.rprpr.yaml')!r}])\n"
    "except SystemExit:\n    pass\n"
    "print('MPL' if 'matplotlib' in sys.modules else 'CLEAN', file=sys.stderr)",
)


@pytest.fixture
def fresh_imports(
    fresh: dict[str, tuple[int, str, str]],
) -> subprocess.CompletedProcess[str]:
    """The probe above, as its process ended."""
    return subprocess.CompletedProcess("probe", *fresh["test_audit core"])


def test_core_imports_no_cli_yaml_or_plotting(fresh_imports):  # type: ignore[no-untyped-def]
    assert fresh_imports.stdout.splitlines()[0] == "core:"


def test_check_path_never_imports_matplotlib(fresh_imports):  # type: ignore[no-untyped-def]
    assert fresh_imports.stderr.strip().endswith("CLEAN")


# -- regressions from review --------------------------------------------------------------


def _chebyshev_task(n: int) -> str:
    """The path T_n(x - 3) + 1/7 along x = 2 + t: n/2 pairs of close instants and huge
    coefficients (an ill-conditioned path polynomial)."""
    from flint import fmpq_poly, fmpz_poly

    from rprpr.io.expression import poly_text

    t_n = fmpq_poly([int(c) for c in fmpz_poly.chebyshev_t(n).coeffs()])
    path = t_n(fmpq_poly([-3, 1])) + fmpq(1, 7)
    return task_text(poly_text(path, "x"), "timing:\n  duration: 2\n  x: 2 + t\n")


def test_ill_conditioned_path_samples_match_a_high_precision_reference(write_task):  # type: ignore[no-untyped-def]
    # reference: eq. (4) solved as a 4x4 system in 600-bit ball arithmetic at these times
    r = audit(load_task(write_task(_chebyshev_task(40))), samples=11)
    near = at_times(r, [0.010, 0.012])
    assert near.lambda2[0] == pytest.approx(-21926.028, rel=1e-7)
    assert near.lambda2[1] == pytest.approx(-22272.461, rel=1e-7)


def test_instants_closer_than_double_precision_do_not_crash(write_task):  # type: ignore[no-untyped-def]
    # two irrational roots 2.8e-40 s apart: no float can tell them apart
    text = task_text("(x-3)^2 - 2*(1e-10)^8", "timing:\n  duration: 2\n  x: 2 + t\n")
    r = audit(load_task(write_task(text)), samples=101)
    assert [s.order for s in r.singularities] == [1, 1]
    assert [s.t_exact for s in r.singularities] == [None, None]
    assert all(s.t == 1.0 for s in r.singularities)


def test_torque_peak_is_the_maximum_over_the_interval_whatever_the_grid(write_task):  # type: ignore[no-untyped-def]
    extra = "checks:\n  torque_limit: [63.2, 1000]\n  strict: true\n"
    task = load_task(write_task(task_text(PATH2_YAML, QUINTIC, extra=extra)))
    peaks = {n: audit(task, samples=n, peak=True).torque_peak for n in (2, 11, 1001)}
    assert peaks[2] == peaks[11] == peaks[1001]
    p1 = peaks[2][0]
    # the value is |T1| at the time it names (independent reference), and no reference
    # value near that time is larger
    assert p1.value == pytest.approx(abs(reference(task, p1.t)["T1"]), rel=1e-9)
    near = [abs(reference(task, p1.t + d)["T1"]) for d in (-1e-3, -1e-4, 1e-4, 1e-3)]
    assert max(near) <= p1.upper and p1.upper <= p1.value * (1 + 1e-6)
    assert p1.value == pytest.approx(66.1221116, rel=1e-7)  # above the limit 63.225 at t_s
    r = audit(task, samples=2)
    assert r.verdict == "fail" and [f.rule for f in r.findings] == ["RPR202"]


def test_theta2_continuous_when_E_passes_A(write_task):  # type: ignore[no-untyped-def]
    r = audit(
        load_task(write_task(task_text("x", "timing:\n  duration: 2\n  x: -1 + t\n"))), samples=5
    )
    th2 = r.samples.theta2
    assert np.all(np.isfinite(th2)) and np.max(np.abs(np.diff(th2))) < 0.2
    assert th2[2] == pytest.approx(-math.pi)  # E at A, on leg 2's cut, y rising


def test_margin_messages_tell_value_and_margin_apart(write_task):  # type: ignore[no-untyped-def]
    extra = "checks:\n  min_slope: 0.19999999\n"
    r = audit(load_task(write_task(task_text(PATH2_YAML, QUINTIC, extra=extra))), samples=11)
    reason = r.singularities[0].slope_principle.reason
    assert r.singularities[0].slope_principle.passed
    assert reason == "|dy/dx| = 0.2 exceeds checks.min_slope = 0.19999999"


def test_readme_python_api_example_runs_as_written(monkeypatch):  # type: ignore[no-untyped-def]
    import re

    from tests.conftest import ROOT

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    block = re.search(r"## Python API.*?```python\n(.*?)```", readme, flags=re.S)
    assert block is not None
    monkeypatch.chdir(ROOT)
    scope: dict[str, object] = {}
    exec(block.group(1), scope)  # the README's own snippet, as a user would paste it
    result = scope["result"]
    assert result.verdict == "fail"  # type: ignore[attr-defined]
    assert scope["s"].order == 3 and scope["s"].t_rational == fmpq(5, 2)  # type: ignore[attr-defined]


def test_audit_scales_with_time_down_to_tiny_durations(write_task):  # type: ignore[no-untyped-def]
    """Without gravity the torques scale as 1/t_f^2 (time scaling of eq. 4); the series
    about t_s must stay within the double range even for t_f = 1e-30 s."""
    base = (CONFIGS / "paper_path2.rprpr.yaml").read_text().replace("gravity: 9.81", "gravity: 0")
    ref = audit(load_task(write_task(base.replace("duration: 5 ", "duration: 1 "))), samples=11)
    for tf in ("1e-10", "1e-30"):
        r = audit(
            load_task(write_task(base.replace("duration: 5 ", f"duration: {tf} "))), samples=11
        )
        k = float(tf) ** 2
        (s,) = r.singularities
        assert s.torque_at_singularity[0] * k == pytest.approx(722.25, rel=1e-12)
        assert np.allclose(r.samples.T1 * k, ref.samples.T1, rtol=1e-9)
        assert np.allclose(r.samples.T2 * k, ref.samples.T2, rtol=1e-9)


def test_a_finding_has_the_severity_of_the_audit_that_made_it() -> None:
    from rprpr.io.loader import load_task
    from tests.conftest import CONFIGS

    task = load_task(CONFIGS / "piecewise_timing.rprpr.yaml")  # two RPR204 torque jumps
    assert [f.severity for f in audit(task, samples=101).findings] == ["warning", "warning"]
    assert [f.severity for f in audit(task, samples=101, strict=True).findings] == ["error"] * 2
    failing = audit(load_task(CONFIGS / "paper_path1.rprpr.yaml"), samples=101)
    assert [(f.rule, f.severity) for f in failing.findings] == [
        ("RPR101", "error"),
        ("RPR201", "error"),
    ]
    import rprpr

    public = rprpr.audit(task, samples=101)  # the Python API: the reports' severity
    assert [f["severity"] for f in public.to_dict()["findings"]] == [
        f.severity for f in public.findings
    ]


# -- the certified peak: computed when asked, deciding nothing ---------------------------------

PEAK_LIMITS = ((300, 300), (66, 61), (20, 20))  # far above, about, far below the torques
C0_KNOT = """\
name: a corner at t = 1 (the velocity jumps)
robot:
  a1: 6
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
motion:
  pieces:
    - {until: 1, x: 2 + t, y: 1 + t}
    - {until: 2, x: 3 + (t - 1), y: 2 - (t - 1)/2}
"""


# degree-60 tasks of the hard corpus, audited as given only: under a limit their certified
# windows cost a third of the comparison and break no rule that another task leaves unbroken
AS_GIVEN_ONLY = frozenset({"multiplicity_60", "degree_60_with_17_digit_coefficients"})


def _with_limit(task: Task, limit: tuple[int, int]) -> Task:
    checks = dataclasses.replace(task.checks, torque_limit=(fmpq(limit[0]), fmpq(limit[1])))
    return dataclasses.replace(task, checks=checks)


@pytest.fixture(scope="module")
def with_and_without_peak() -> list[tuple[str, AuditResult, AuditResult]]:
    """Every shipped config, each as given and under limits far above, about and far below
    its torques, and every task of the hard corpus, as given and (but AS_GIVEN_ONLY) under
    a limit, audited with and without the certified peak."""
    from tests.corpora.test_hard_input import HARD

    tasks = []
    for p in sorted(CONFIGS.glob("*.yaml")):
        task = load_task(p)
        if task.robot.mechanism == "5R":  # a 5R's peak and limit are not in this build
            continue
        tasks.append((p.name, task))
        tasks += [(f"{p.name} {lim}", _with_limit(task, lim)) for lim in PEAK_LIMITS]
    corner = parse_task(C0_KNOT, "corner.yaml")
    tasks += [("corner", corner), ("corner (20, 20)", _with_limit(corner, (20, 20)))]
    for name, hard in HARD.items():
        task = parse_task(hard.text, f"{name}.yaml")
        tasks.append((name, task))
        if name not in AS_GIVEN_ONLY:
            tasks.append((f"{name} (50, 50)", _with_limit(task, (50, 50))))
    with _one_analysis_per_motion():
        plain = [audit(t, samples=11) for _, t in tasks]
    with _one_analysis_per_motion():  # the peak's audits make their own, shared among them
        peaked = [audit(t, samples=11, peak=True) for _, t in tasks]
    return [(name, a, b) for (name, _), a, b in zip(tasks, plain, peaked, strict=True)]


@contextmanager
def _one_analysis_per_motion() -> Iterator[None]:
    """Inside: each piece's exact singular analysis and certified motion (``pieces.part``,
    ``Part.motion``) made once per piece, robot and margins, and shared by the audits of
    that motion made inside (as given and under each limit; the fixture audits with and
    without the peak in two such blocks, so that each way prepares its own motions). Both
    read only the piece, the robot and the margins (checks.min_slope, checks.min_speed),
    none of which a limit changes, and the motion's caches (its zones) are filled the same
    whoever asks first; what the tests compare (the envelopes, limit checks, peaks and
    findings) every audit makes afresh, on a part of its own."""
    from rprpr.engine import pieces

    real = pieces.part
    made: list[tuple[Any, Any, Any, Any, pieces.Part]] = []

    def part(piece: Any, robot: Any, checks: Checks, tell: Any) -> pieces.Part:
        margins = (checks.min_slope, checks.min_speed)
        for p, r, m0, m1, first in made:
            if p is piece and r is robot and (m0, m1) == margins:
                again = pieces.Part(piece, robot, first.analysis)
                again.__dict__.update(traj=first.traj, motion=first.motion)
                return again
        fresh = real(piece, robot, checks, tell)
        made.append((piece, robot, *margins, fresh))
        return fresh

    pieces.part = part
    try:
        yield
    finally:
        pieces.part = real


def _decided(f: Finding) -> tuple[object, ...]:
    """What a finding decides (its message may name the peak when it is known)."""
    return (f.rule, f.t, f.downgraded, f.promoted, f.line, f.fails(False), f.fails(True))


@pytest.mark.parametrize(
    "rule", ["RPR101", "RPR102", "RPR103", "RPR104", "RPR201", "RPR202", "RPR203", "RPR204"]
)
def test_every_rule_decides_the_same_with_and_without_the_peak(
    rule: str, with_and_without_peak: list[tuple[str, AuditResult, AuditResult]]
) -> None:
    fired = 0
    for name, plain, peaked in with_and_without_peak:
        got = [_decided(f) for f in plain.findings if f.rule == rule]
        want = [_decided(f) for f in peaked.findings if f.rule == rule]
        assert got == want, name
        assert plain.verdict == peaked.verdict, name
        fired += len(got)
    assert fired, f"the corpus never breaks {rule}: the comparison would prove nothing"


def test_without_the_peak_every_certified_verdict_is_the_same(
    with_and_without_peak: list[tuple[str, AuditResult, AuditResult]],
) -> None:
    asked = 0
    for name, plain, peaked in with_and_without_peak:
        _same_checks(plain.torque_limit, peaked.torque_limit, name)
        assert [s.t for s, _, _ in plain.saturation] == [s.t for s, _, _ in peaked.saturation]
        for (_, *got), (_, *want) in zip(plain.saturation, peaked.saturation, strict=True):
            assert [w is None for w in got] == [w is None for w in want], name
        assert plain.closest_approach == peaked.closest_approach, name
        assert peaked.peak_computed
        finite = peaked.torque_peak is not None and all(
            math.isfinite(p.value) for p in peaked.torque_peak
        )
        if finite:  # bounded torques: the peak costs passes, computed only when asked
            assert not plain.peak_computed and plain.torque_peak is None, name
            asked += 1
        else:  # unbounded or undefined: known without a pass, reported either way
            assert plain.peak_computed and plain.torque_peak == peaked.torque_peak, name
        if rule_message := [f.message for f in plain.findings if f.rule == "RPR202"]:
            assert all("reaches" not in m for m in rule_message if "unbounded" not in m), name
    assert asked > 10


def _same_checks(
    got: tuple[LimitCheck, LimitCheck] | None, want: tuple[LimitCheck, LimitCheck] | None, name: str
) -> None:
    """The same certified limit verdicts: passed, the windows (pole or not) and their
    crossing brackets, each overlapping the other's (both hold the true crossing; the
    first partition differs without the peak, so the brackets' ends may)."""
    assert (got is None) == (want is None), name
    for g, w in zip(got or (), want or (), strict=True):
        assert (g.limit, g.passed, len(g.windows)) == (w.limit, w.passed, len(w.windows)), name
        for a, b in zip(g.windows, w.windows, strict=True):
            assert a.pole == b.pole, name
            assert max(a.start_lo, b.start_lo) <= min(a.start_hi, b.start_hi), name
            assert max(a.end_lo, b.end_lo) <= min(a.end_hi, b.end_hi), name


TWO_STOPS = """\
name: two stops at the roots of one irreducible factor
robot:
  a1: 6
  gravity: 0
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 0, inertia: 0.05, r: 0.5}
path:
  y: x^2 - 6*x + 7
timing:
  duration: 4
  x: 3 + ((t - 2)^3 - 6*(t - 2))/4
"""


def test_each_irrational_instant_of_one_factor_reports_its_own_limit_torque() -> None:
    """E stops on AB at x = 3 ± √2, t_s = 2 ∓ √2: touches at the two roots of one factor
    t^2 - 4t + 2 of y(t), with the same legs' signs (0 < x < a1), so one expansion in K
    serves both; each instant's finite torque limit is its own, the reference's two-sided
    limit at its t_s (mpmath, t_s to 50 digits); the first root's was reported for both."""
    from fractions import Fraction
    from math import isqrt

    from tests.reference import limit

    r = audit(parse_task(TWO_STOPS, "two_stops.yaml"), samples=11)
    assert [(s.t_exact, s.order, s.torque_bounded) for s in r.singularities] == [
        (None, 2, True),
        (None, 2, True),
    ]
    root2 = Fraction(isqrt(2 * 10**100), 10**50)  # √2 to 50 digits
    for s, ts in zip(r.singularities, (2 - root2, 2 + root2), strict=True):
        want = limit(r.task, ts)
        assert want is not None and s.torque_at_singularity is not None
        for got, name in zip(s.torque_at_singularity, ("T1", "T2"), strict=True):
            assert got == pytest.approx(float(want[name]), rel=1e-12), (s.t, name)


def test_checks_peak_asks_for_the_peak() -> None:
    task = load_task(CONFIGS / "paper_path2.rprpr.yaml")
    asked = dataclasses.replace(task, checks=dataclasses.replace(task.checks, peak=True))
    r = audit(asked, samples=11)
    assert r.peak_computed and r.torque_peak is not None
    assert r.torque_peak[0].value == pytest.approx(66.1221116, rel=1e-7)
    assert not audit(asked, samples=11, peak=False).peak_computed  # the caller's choice wins


def test_findings_are_tied_to_their_instant_not_to_its_rounded_time() -> None:
    # y = (x - 3)(x - 3 - 10⁻²⁰), x = 2 + t: two crossings of AB at t = 1 and 1 + 10⁻²⁰,
    # one double apart from nothing; only one of them has unbounded torques
    task = parse_task(
        task_text("(x-3)*(x-3.00000000000000000001)", "timing:\n  duration: 2\n  x: 2 + t\n")
    )
    r = audit(task)
    first, second = r.singularities
    assert first.t == second.t == 1.0
    assert {first.t_rational, second.t_rational} == {fmpq(1), 1 + fmpq(1, 10**20)}
    (pole,) = [s for s in r.singularities if not s.torque_bounded]
    (bounded,) = [s for s in r.singularities if s.torque_bounded]
    assert [f.rule for f in r.findings_at(pole)] == ["RPR201"]
    assert r.status_of(pole) == "fail"
    assert r.findings_at(bounded) == [] and r.status_of(bounded) == "ok"  # by time: "fail"


def test_the_robust_records_are_tied_to_their_instant_not_to_its_rounded_time() -> None:
    # the two instants above, one double apart, with a box of radius zero: each robust
    # record is made from its own instant's local analysis (the joined analysis names its
    # sources by index), so its residual is that instant's exact residual
    text = task_text("(x-3)*(x-3.00000000000000000001)", "timing:\n  duration: 2\n  x: 2 + t\n")
    text += "checks:\n  torque_limit: [300, 300]\nuncertainty:\n  links: 0%\n  period: 0\n"
    r = audit(parse_task(text))
    for s, rob in zip(r.singularities, r.robust, strict=True):
        assert rob.residual == (s.consistency_residual, s.consistency_residual)
    residuals = sorted(abs(s.consistency_residual) for s in r.singularities)
    assert residuals[0] == 0 and residuals[1] > 0


def test_the_saturation_record_is_the_unbounded_instants_alone() -> None:
    # the two instants above, one double apart, under a torque limit: only the pole has
    # windows above the limit; the bounded instant beside it has none
    from rprpr.report.records import task_report

    text = task_text("(x-3)*(x-3.00000000000000000001)", "timing:\n  duration: 2\n  x: 2 + t\n")
    r = audit(parse_task(text + "checks:\n  torque_limit: [300, 300]\n"))
    records = task_report(r, "t.yaml")["singularities"]
    by_bounded = {s.torque_bounded: rec for s, rec in zip(r.singularities, records, strict=True)}
    assert by_bounded[True]["saturation"] is None  # by time, the pole's windows
    assert len(by_bounded[False]["saturation"]) == 2

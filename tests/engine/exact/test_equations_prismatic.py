"""The prismatic actuation scheme (``robot.actuation: prismatic``, forces F1, F2 in the legs).

Values are checked against ``tests.reference`` (a direct solve of the four equations (4)
for (F1, F2, λ1, λ2), written apart from the engine), the power balance
F1 s1' + F2 s2' = dE/dt, and consistency conditions derived here by hand in fractions
(``_prismatic_ydd``, ``_revolute_residual``): never the engine against itself.
"""

from __future__ import annotations

import json
from fractions import Fraction
from functools import cache
from pathlib import Path

import mpmath
import numpy as np
import pytest

from rprpr.engine.certified.motion import CertifiedMotion
from rprpr.engine.exact.singular import SingularAnalysis, analyse
from rprpr.engine.exact.trajectory import trajectory
from rprpr.io.loader import parse_task
from rprpr.model.task import Task
from tests.conftest import CONFIGS, PATH1_YAML, PATH2_YAML, QUINTIC, run_cli, task_text
from tests.reference import energy, limit, reference

CONFIG = CONFIGS / "prismatic_crossing.rprpr.yaml"
G = Fraction(981, 100)
# the alike links of ``conftest.LINKS_ALIKE`` and of the config: (mass, inertia, r)
LINKS = {
    2: (Fraction(2), Fraction(1, 10), Fraction(1, 2)),
    3: (Fraction(1), Fraction(1, 20), Fraction(1, 2)),
    4: (Fraction(2), Fraction(1, 10), Fraction(1, 2)),
    5: (Fraction(1), Fraction(1, 20), Fraction(1, 2)),
}


def _with(text: str, actuation: str) -> str:
    return text.replace("robot:\n", f"robot:\n  actuation: {actuation}\n", 1)


@cache
def _task(path: str, actuation: str) -> Task:
    return parse_task(_with(task_text(path, QUINTIC), actuation))


def _crossing(ydd: Fraction, actuation: str) -> Task:
    """The config's motion with y''(t_s) = ydd: E along x = 15/4 + t and
    y = 3 (x - 4) + ydd/2 (x - 4)^2 for t in [0, 1/2], crossing AB at t = 1/4 with
    (x', y') = (1, 3)."""
    text = CONFIG.read_text(encoding="utf-8")
    y = f"3*(x - 4) + {ydd.numerator}/{2 * ydd.denominator}*(x - 4)^2"
    text = text.replace("3*(x - 4) - 37323/4900*(x - 4)^2", y)
    return parse_task(text.replace("actuation: prismatic", f"actuation: {actuation}"))


_ANALYSES: dict[int, tuple[Task, SingularAnalysis]] = {}


def _analysis(task: Task) -> SingularAnalysis:
    """One exact analysis per task object (tasks are not hashable)."""
    if id(task) not in _ANALYSES:
        _ANALYSES[id(task)] = (task, analyse(trajectory(task), task.robot, task.checks))
    return _ANALYSES[id(task)][1]


# -- the consistency conditions, derived by hand at y = 0 ----------------------------------
# With y = 0 (θ_i ∈ {0, π}, c_i = cos θ_i = sign u_i, s_i = |u_i|, u1 = x, u2 = x - a1):
#   s_i' = c_i x',  θ_i' = c_i y'/s_i,  θ_i'' = c_i y''/s_i - 2 s_i' θ_i'/s_i,
#   s_i'' = (y'^2 + u_i x'')/s_i   (eqs. 41-42 with y = 0).


def _legs(x: Fraction, a1: Fraction) -> list[tuple[int, Fraction, int, int]]:
    out = []
    for i, u in enumerate((x, x - a1)):
        c = 1 if u > 0 else -1
        out.append((c, abs(u), 2 + 2 * i, 3 + 2 * i))
    return out


def _prismatic_ydd(x: Fraction, xd: Fraction, yd: Fraction, a1: Fraction = Fraction(6)) -> Fraction:
    """The y''(t_s) that makes U1/s1 + σ U2/s2 = 0 (U_i = M_ii θ_i'' + N_i, linear in y'')."""
    legs = _legs(x, a1)
    sigma = legs[0][0] * legs[1][0]
    A = B = Fraction(0)
    for w, (c, s, inner, outer) in zip((1, sigma), legs, strict=True):
        m_in, I_in, r_in = LINKS[inner]
        m_out, I_out, r_out = LINKS[outer]
        sd, thd, d = c * xd, c * yd / s, s - r_out
        M = m_in * r_in**2 + I_in + m_out * d**2 + I_out  # eq. (7) / (9)
        N = 2 * m_out * sd * thd * d + (m_in * r_in + m_out * d) * G * c  # eq. (11) / (13)
        A += w * M * c / s / s  # U_i = (M c/s) y'' + (N - 2 M s' θ'/s)
        B += w * (N - 2 * M * sd * thd / s) / s
    return -B / A


def _revolute_residual(x: Fraction, xd: Fraction, xdd: Fraction, yd: Fraction) -> Fraction:
    """Eq. (34): σ F1 + F2 with F_i = m_i s_i'' + N_i (eqs. 12, 14 at y = 0)."""
    legs = _legs(x, Fraction(6))
    sigma = legs[0][0] * legs[1][0]
    F = []
    for i, (c, s, _, outer) in enumerate(legs):
        m, _, r = LINKS[outer]
        u = x if i == 0 else x - 6
        thd = c * yd / s
        F.append(m * (yd**2 + u * xdd) / s - m * (s - r) * thd**2)
    return sigma * F[0] + F[1]


# -- the inverse dynamics --------------------------------------------------------------------


@pytest.mark.parametrize("t", [Fraction(3, 10), Fraction(17, 10), Fraction(31, 10)])
def test_power_balance_of_the_direct_solve(t: Fraction) -> None:
    """F1 s1' + F2 s2' = dE/dt (λ does no work: J q' = 0), the reference's forces."""
    task = _task(PATH2_YAML, "prismatic")
    h = Fraction(1, 10**20)
    q = reference(task, t)
    with mpmath.workdps(80):
        dE = (energy(task, t + h) - energy(task, t - h)) / (
            2 * mpmath.mpf(h.numerator) / h.denominator
        )
        power = q["T1"] * q["s1_dot"] + q["T2"] * q["s2_dot"]
        assert abs(power - dE) < mpmath.mpf(10) ** -30 * (1 + abs(dE))
        assert abs(dE) > 1  # not trivially zero


def test_the_determinant_of_the_theta_rows_is_minus_a1_y() -> None:
    """det (J_a)^T = s1 s2 sin(θ1 - θ2) = -a1 y (the reference's joint values)."""
    task = _task(PATH1_YAML, "prismatic")
    for t in (Fraction(1, 3), Fraction(12, 5), Fraction(4)):
        q = reference(task, t)
        with mpmath.workdps(60):
            s1, s2 = q["s1"], q["s2"]
            th1, th2 = q["theta1"], q["theta2"]
            Ja = mpmath.matrix([[-s1 * mpmath.sin(th1), s2 * mpmath.sin(th2)],
                                [s1 * mpmath.cos(th1), -s2 * mpmath.cos(th2)]])  # fmt: skip
            assert abs(mpmath.det(Ja.T) + 6 * q["y"]) < mpmath.mpf(10) ** -40


@pytest.mark.parametrize("path", [PATH1_YAML, PATH2_YAML])
def test_certified_forces_match_the_direct_solve(path: str) -> None:
    task = _task(path, "prismatic")
    times = [0.3, 1.7, 2.4999, 2.5001, 3.1, 4.9]
    c = CertifiedMotion(trajectory(task), task.robot, _analysis(task)).sample(np.array(times))
    for j, t in enumerate(times):
        ref = reference(task, t)
        for name in ("lambda1", "lambda2", "T1", "T2"):
            e = c.value[name][j]
            assert abs(e - float(ref[name])) <= 1e-9 * (1 + abs(e)), (name, t)


# -- the same motion under both schemes -----------------------------------------------------


@pytest.mark.parametrize("path", [PATH1_YAML, PATH2_YAML])
def test_both_schemes_have_the_same_instants_and_orders(path: str) -> None:
    rev, pri = (_analysis(_task(path, a)) for a in ("revolute", "prismatic"))
    assert [(s.t_exact, s.order, s.case.number) for s in rev.instants] == [
        (s.t_exact, s.order, s.case.number) for s in pri.instants
    ]
    assert [s.order for s in pri.instants] == [3 if path == PATH1_YAML else 1]


def test_path2_is_consistent_for_motors_and_not_for_linear_actuators() -> None:
    """Path 2 with alike legs at the midpoint x = 3 (x'' = 0): eq. (34) holds, while the
    legs' moment balance fails by the legs' weight moments, 2 (m2 r2 + m3 (3 - r3)) g / 3
    less the inertia terms, both computed here."""
    (rev,) = _analysis(_task(PATH2_YAML, "revolute")).instants
    (pri,) = _analysis(_task(PATH2_YAML, "prismatic")).instants
    assert rev.consistent and rev.consistency_residual == 0
    xd, yd = Fraction(1, 2), Fraction(1, 10)  # x'(2.5) of eq. (49), y' = 0.2 x'
    assert _revolute_residual(Fraction(3), xd, Fraction(0), yd) == 0
    ydd = Fraction(0)  # y'' = p''(3) x'^2 + p'(3) x'' = 0 on path 2 at x = 3
    expected = _moment_residual(Fraction(3), xd, yd, ydd)
    assert not pri.consistent
    assert pri.consistency_residual == pytest.approx(float(expected), rel=1e-12)
    assert pri.torque_at_singularity is None and rev.torque_at_singularity is not None


def _moment_residual(x: Fraction, xd: Fraction, yd: Fraction, ydd: Fraction) -> Fraction:
    """U1/s1 + σ U2/s2 at y = 0 by hand (linear in y'': its zero is ``_prismatic_ydd``)."""
    k0 = _prismatic_ydd(x, xd, yd)
    legs = _legs(x, Fraction(6))
    sigma = legs[0][0] * legs[1][0]
    A = sum(
        w * (LINKS[i][0] * LINKS[i][2] ** 2 + LINKS[i][1] + LINKS[o][0] * (s - LINKS[o][2]) ** 2
             + LINKS[o][1]) * c / s / s
        for w, (c, s, i, o) in zip((1, sigma), legs, strict=True)
    )  # fmt: skip
    return A * (ydd - k0)


def test_a_crossing_consistent_for_linear_actuators_and_not_for_motors() -> None:
    """y''(t_s) chosen from the moment balance at (4, 0): consistent, bounded forces whose
    limit at t_s is the reference's two-sided limit; the same motion under motors is
    inconsistent with the hand-computed eq. (34) residual."""
    ydd = _prismatic_ydd(Fraction(4), Fraction(1), Fraction(3))
    assert ydd == Fraction(-37323, 2450)  # the config's y''
    pri_task, rev_task = _crossing(ydd, "prismatic"), _crossing(ydd, "revolute")
    (pri,) = _analysis(pri_task).instants
    (rev,) = _analysis(rev_task).instants
    assert (pri.t_exact, pri.order) == (rev.t_exact, rev.order) == (Fraction(1, 4), 1)
    assert pri.consistent and pri.consistency_residual == 0 and pri.torque_bounded
    assert not rev.consistent and not rev.torque_bounded
    expected = _revolute_residual(Fraction(4), Fraction(1), Fraction(0), Fraction(3))
    assert rev.consistency_residual == pytest.approx(float(expected), rel=1e-12)
    lim = limit(pri_task, Fraction(1, 4))
    assert lim is not None and pri.torque_at_singularity is not None
    for got, name in zip(pri.torque_at_singularity, ("T1", "T2"), strict=True):
        assert got == pytest.approx(float(lim[name]), rel=1e-12, abs=1e-12)
    # off by 1 m/s² in y'': inconsistent, residual = A (y'' - y''_0) by hand
    (off,) = _analysis(_crossing(ydd + 1, "prismatic")).instants
    assert not off.consistent and not off.torque_bounded
    want = _moment_residual(Fraction(4), Fraction(1), Fraction(3), ydd + 1)
    assert off.consistency_residual == pytest.approx(float(want), rel=1e-12)


def test_a_prismatic_pole_leaves_lambda2_bounded() -> None:
    """λ2 = (U1 + U2)/a1 for every prismatic motion: at an inconsistent crossing the pole
    is in λ1 (the samples at t_s: λ2 finite, λ1 undefined), λ2 the reference's limit."""
    task = _task(PATH2_YAML, "prismatic")
    c = CertifiedMotion(trajectory(task), task.robot, _analysis(task)).sample(np.array([2.5]))
    assert np.isnan(c.value["lambda1"][0]) and np.isnan(c.value["T1"][0])
    eps = Fraction(1, 10**30)
    sides = [reference(task, Fraction(5, 2) + s * eps)["lambda2"] for s in (-1, 1)]
    assert c.value["lambda2"][0] == pytest.approx(float(sides[0]), rel=1e-12)
    assert abs(sides[0] - sides[1]) < 1e-20


# -- every command -----------------------------------------------------------------------------


def test_check_names_forces_in_newtons() -> None:
    status, out, _ = run_cli("check", "--peak", str(CONFIG))
    assert status == 0
    assert "actuation: prismatic" in out and "F(t_s) [N]" in out and "|F1|" in out
    assert "N m" not in out


def test_json_report_names_the_scheme() -> None:
    status, out, _ = run_cli("check", "--format", "json", str(CONFIG))
    assert status == 0
    (rep,) = json.loads(out)["reports"]
    assert rep["actuation"] == "prismatic" and rep["effort_unit"] == "N"
    (s,) = rep["singularities"]
    assert s["consistent"] and s["torque_at_singularity"] is not None


def test_revolute_json_report_has_no_actuation_field() -> None:
    _, out, _ = run_cli("check", "--format", "json", str(CONFIGS / "paper_path2.rprpr.yaml"))
    (rep,) = json.loads(out)["reports"]
    assert "actuation" not in rep and "effort_unit" not in rep


def test_rpr201_and_rpr202_name_forces(tmp_path: Path) -> None:
    f = tmp_path / "p.rprpr.yaml"
    f.write_text(
        _with(
            task_text(PATH2_YAML, QUINTIC, extra="checks:\n  torque_limit: [30, 30]\n"), "prismatic"
        )
    )
    status, out, _ = run_cli("check", str(f))
    assert status == 1
    assert "forces unbounded (pole of order 1): inconsistent: moment balance residual" in out
    assert "|F1| > 30 N for" in out and "N m" not in out


def test_export_has_force_columns(tmp_path: Path) -> None:
    out_csv, out_json = tmp_path / "p.csv", tmp_path / "p.json"
    assert run_cli("export", str(CONFIG), "-o", str(out_csv), "--samples", "51")[0] == 0
    header = out_csv.read_text().splitlines()[1].split(",")
    assert "F1" in header and "F2" in header and "T1" not in header
    assert run_cli("export", str(CONFIG), "-o", str(out_json), "--samples", "51")[0] == 0
    doc = json.loads(out_json.read_text())
    assert doc["units"]["F1"] == "N" and doc["actuation"] == "prismatic"
    # at a pole it is λ1 that diverges under linear actuators, with F1, F2
    pole = "a singular instant with unbounded forces (a pole of λ1): λ1, F1, F2 undefined"
    assert doc["reasons"]["1"] == pole and pole in out_csv.read_text().splitlines()[0]


def test_plot_labels_forces(tmp_path: Path) -> None:
    out = tmp_path / "p.svg"
    args = ("-o", str(out), "--panels", "torques", "--samples", "21")  # the forces' panel
    assert run_cli("plot", str(CONFIG), *args)[0] == 0
    svg = out.read_text()
    assert "Leg forces F1, F2" in svg

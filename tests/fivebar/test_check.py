"""``rprpr check`` on 5R task files, in process, against the references of this folder.

The robot is the a = 14/13 unit-link robot of test_dynamics scaled by 13 (a = 14, links
13, decimal masses, inertias and centres of mass): its singular pose C = (0, 13),
D = (126/5, 33/5), E = (63/5, 49/5) (e1 = +1, e2 = -1, σ = -1) is rational and a task
file's numbers hold it. Motions through E at t_s = 1/10 are built as test_dynamics builds
them, from the derivation (theory.py: the reciprocity residual w and its derivatives set
to zero, or not); the Newton-Euler reference (reference.py) then says whether the torques
stay bounded, and the reference's instants (instants.py: sympy's exact roots of S_σ(E(t)),
δ of the robot's modes at 60 digits) say when the robot is singular and to what order.
The report must say the same: a transversal consistent crossing passes, an inconsistent
one fails on RPR201, a stop on the curve fails RPR102, a tangential touch RPR101; its JSON
carries the reference's instant times.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from fractions import Fraction as Q
from functools import cache
from pathlib import Path
from typing import Any

import mpmath
import numpy as np
import pytest
import sympy as sp

from tests.conftest import run_cli

from .instants import Instant, singular_instants
from .reference import DPS, FiveBar, Motion, torques
from .theory import derive

Z = Q(0)
MODES = (1, -1)
E13 = (Q(63, 5), Q(49, 5))  # the singular pose's end point
TS = Q(1, 10)  # the singular instant in every motion below
TF = Q(1, 5)  # the motions' duration
ROBOT = FiveBar(
    Q(14), (Q(13),) * 4,
    (Q(3), Q(2), Q(1), Q(3, 2)), (Q(13), Q(11), Q(8), Q(12)),
    (Q(13, 2), Q(26, 5), Q(4), Q(39, 5)), Q(981, 100),
)  # fmt: skip


def local(v: tuple[Q, Q], A: tuple[Q, Q], J: tuple[Q, Q] = (Z, Z)) -> Motion:
    """E(τ) = E13 + v τ + A τ²/2 + J τ³/6, τ = t - t_s (the reference's local motion)."""
    return Motion((E13[0], v[0], A[0] / 2, J[0] / 6), (E13[1], v[1], A[1] / 2, J[1] / 6))


def absolute(m: Motion) -> Motion:
    """The same motion in the task's time t = t_s + τ (coefficients from the constant up)."""
    t = sp.Symbol("t")
    out = []
    for cs in (m.x, m.y):
        p = sp.Poly(sum(sp.Rational(c.numerator, c.denominator) * (t - sp.Rational(1, 10)) ** i
                        for i, c in enumerate(cs)), t)  # fmt: skip
        out.append(tuple(Q(int(c.p), int(c.q)) for c in reversed(p.all_coeffs())))
    return Motion(out[0], out[1])


def solve(f: Callable[[Q], Q]) -> Q:
    """The root of an affine function of one rational."""
    f0, f1 = f(Z), f(Q(1))
    return -f0 / (f1 - f0)


def w_at(m: Motion, k: int) -> Q:
    """The k-th derivative at τ = 0 of the reciprocity residual (σ = -1), by theory.py."""
    out = derive(ROBOT, m, Z, MODES, 3 + k).w(-1)
    return out.d(k)  # type: ignore[no-any-return]


@cache
def motions() -> dict[str, Motion]:
    """The four motions of the module docstring, in local time."""
    v = (Q(1), Q(1, 2))  # transversal
    ay = solve(lambda s: w_at(local(v, (Z, s)), 0))
    g = [derive(ROBOT, local(d, (Z, Z)), Z, MODES, 3).delta.c[1] for d in ((Q(1), Z), (Z, Q(1)))]
    vt = (-g[1], g[0])  # along the curve's tangent
    at = (Z, solve(lambda s: w_at(local(vt, (Z, s)), 0)))
    jt = solve(lambda s: w_at(local(vt, at, (Z, s)), 1))
    sa = (Q(1), solve(lambda s: w_at(local((Z, Z), (Q(1), s)), 0)))
    sj = solve(lambda s: w_at(local((Z, Z), sa, (Z, s)), 1))
    return {
        "consistent": local(v, (Z, ay)),
        "inconsistent": local(v, (Z, ay + Q(1, 10))),
        "tangent": local(vt, at, (Z, jt)),
        "stop": local((Z, Z), sa, (Z, sj)),
    }


def _decimal(q: Q) -> str:
    """A rational with a finite decimal expansion, as a task file's decimal."""
    text = format(sp.Float(sp.Rational(q.numerator, q.denominator), 30), "f")
    assert Q(text) == q, q
    return text.rstrip("0").rstrip(".")


def _poly(cs: tuple[Q, ...]) -> str:
    return " + ".join(f"({c.numerator}/{c.denominator})*t^{i}" for i, c in enumerate(cs))


def robot_text() -> str:
    """ROBOT in working modes (+1, -1) as a task file's robot section."""
    rb = ROBOT
    links = "\n".join(
        f"    {i + 1}: {{mass: {_decimal(rb.mass[i])}, inertia: {_decimal(rb.inertia[i])},"
        f" r: {_decimal(rb.r[i])}}}"
        for i in range(4)
    )
    return (
        f"robot:\n  mechanism: 5R\n  base: {_decimal(rb.a)}\n"
        f"  lengths: [13, 13, 13, 13]\n  modes: [+1, -1]\n  gravity: {_decimal(rb.g)}\n"
        f"  links:\n{links}\n"
    )


def task_file(folder: Path, name: str, m: Motion, extra: str = "") -> Path:
    """A 5R task: ROBOT, the end point's x(t), y(t) as one piece of motion.pieces,
    0 <= t <= TF."""
    m = absolute(m)
    motion = f"motion:\n  pieces:\n    - until: 0.2\n      x: {_poly(m.x)}\n      y: {_poly(m.y)}\n"
    path = folder / f"{name}.rprpr.yaml"
    path.write_text(f"name: {name}\n{robot_text()}{motion}{extra}")
    return path


def check_json(path: Path, *options: str) -> tuple[int, dict[str, Any]]:
    code, out, err = run_cli("check", "--format", "json", *options, str(path))
    assert err == "", err
    doc = json.loads(out)
    assert len(doc["reports"]) == 1, doc
    return code, doc["reports"][0]


def reference_instants(name: str) -> list[Instant]:
    return singular_instants(ROBOT, absolute(motions()[name]), MODES, Z, TF)


def bounded_by_newton_euler(m: Motion) -> bool:
    """The torques stay bounded at t_s, by Newton-Euler at 60 digits: |T| at t_s ± 10^-11
    within twice |T| at t_s ± 10^-9 (a pole of order p multiplies it by 100^p)."""
    near, far = [], []
    for s in (1, -1):
        for k, out in ((9, far), (11, near)):
            T = torques(ROBOT, m, Q(s, 10**k), MODES)
            with mpmath.workdps(DPS):
                out.append(max(abs(T[0]), abs(T[1])))
    return bool(max(near) < 2 * max(far))


def _rules(rep: dict[str, Any]) -> list[str]:
    return [f["rule"] for f in rep["findings"]]


@pytest.mark.parametrize(
    ("name", "order", "rules", "code", "bounded"),
    [
        ("consistent", 1, [], 0, True),
        ("inconsistent", 1, ["RPR201"], 1, False),
        ("tangent", 2, ["RPR101"], 1, True),
        ("stop", 2, ["RPR102"], 1, True),
    ],
)
def test_check_gives_the_references_verdicts(
    tmp_path: Path, name: str, order: int, rules: list[str], code: int, bounded: bool
) -> None:
    m = motions()[name]
    assert bounded_by_newton_euler(m) == bounded  # the reference's word on the torques
    ref = reference_instants(name)
    assert [(i.t, i.order, i.sigma) for i in ref] == [(sp.Rational(1, 10), order, -1)]
    got, rep = check_json(task_file(tmp_path, name, m))
    assert got == code
    assert rep["mechanism"] == "5R"
    assert rep["verdict"] == ("pass" if code == 0 else "fail")
    assert _rules(rep) == rules
    (s,) = rep["singularities"]
    assert (s["t_exact"], s["t"], s["order"]) == ("1/10", 0.1, order)
    assert (s["sigma"], s["modes"]) == (-1, [1, -1])
    assert (s["x"], s["y"]) == (12.6, 9.8)
    assert s["torque_bounded"] == bounded
    assert s["consistent"] == (name != "inconsistent")
    assert s["slope_principle"] == ("fail" if name == "tangent" else "pass")
    assert s["velocity_principle"] == ("fail" if name == "stop" else "pass")
    assert all(f["t"] == 0.1 for f in rep["findings"])
    if name == "stop":
        assert s["speed"] == 0
    if bounded:  # the limit torques: Newton-Euler's at t_s ± 10^-8 tend to them
        T = torques(ROBOT, m, Q(1, 10**8), MODES)
        for i in (0, 1):
            assert abs(float(T[i]) - s["torque_at_singularity"][i]) <= 1e-5 * (1 + abs(float(T[i])))
    else:
        assert s["torque_at_singularity"] is None and s["pole_order"] == 1
        assert s["consistency_residual"] != 0


def test_the_text_report_names_the_instant_and_the_rule(tmp_path: Path) -> None:
    path = task_file(tmp_path, "inconsistent", motions()["inconsistent"])
    code, out, err = run_cli("check", str(path))
    assert (code, err) == (1, "")
    lines = out.splitlines()
    assert lines[0].startswith(f"{tmp_path / 'inconsistent.rprpr.yaml'}:")
    assert (
        " RPR201 [error] unbounded-torque: t = 0.1 s, (x, y) = (12.6, 9.8), modes (+1, -1),"
        " σ = -1, order 1: torques unbounded (pole of order 1): inconsistent: reciprocity"
        " residual "
    ) in lines[0]
    assert "modes σ" in out and "+1 -1  -1" in out
    assert lines[-1] == (
        "  verdict: FAIL — 1 singular instant, 0 high-order; torques unbounded at t = 0.1 s"
    )


def test_warn_unbounded_downgrades_rpr201_as_for_the_rprpr(tmp_path: Path) -> None:
    path = task_file(tmp_path, "inconsistent", motions()["inconsistent"])
    code, rep = check_json(path, "--warn-unbounded")
    assert code == 0 and rep["verdict"] == "pass"
    assert [(f["rule"], f["severity"]) for f in rep["findings"]] == [("RPR201", "warning")]


def test_a_leg_stretched_is_reported_as_the_rprprs_e_at_a(tmp_path: Path) -> None:
    """E(t) = (12.6 + 12 t, 9.8): leg 1 is stretched (|E| = l1 + l3 = 26) where
    (12.6 + 12 t)² + 9.8² = 26², t = (√579.96 - 12.6)/12; RPR103 fails the task there,
    and the analysis stops. Before it, the path starts on the Type II curve at the
    singular pose (t = 0, the reference's instant), inconsistently: RPR201 there too."""
    m = Motion((Q(63, 5), Q(12)), (Q(49, 5),))
    path = tmp_path / "stretch.rprpr.yaml"
    path.write_text(
        f"name: stretch\n{robot_text()}motion:\n  pieces:\n"
        "    - until: 1\n      x: 12.6 + 12*t\n      y: 9.8\n"
    )
    t = sp.Symbol("t")
    roots = [r for r in sp.real_roots(sp.Poly((sp.Rational(63, 5) + 12 * t) ** 2
             + sp.Rational(49, 5) ** 2 - 26**2, t)) if 0 <= r <= 1]  # fmt: skip
    assert len(roots) == 1 and m.x[1] == 12
    code, rep = check_json(path)
    assert code == 1 and rep["verdict"] == "fail"
    (k,) = rep["kinematic_singularities"]
    assert (k["leg"], k["kind"], k["t_exact"]) == (1, "stretched", None)
    assert abs(k["t"] - float(sp.N(roots[0], 30))) <= 1e-15
    ref = [r for r in singular_instants(ROBOT, m, MODES, Z, Q(1)) if r.t < roots[0]]
    assert [(r.t, r.order) for r in ref] == [(0, 1)]
    (s,) = rep["singularities"]
    assert (s["t_exact"], s["order"], s["sigma"]) == ("0", 1, ref[0].sigma)
    assert [(f["rule"], f["t"]) for f in rep["findings"]] == [("RPR103", k["t"]), ("RPR201", 0.0)]
    assert rep["findings"][0]["message"].endswith(
        "the analysis stops here (1 Type II instant before it)"
    )


def test_a_torque_limit_past_a_type_one_instant_is_said_not_checked(tmp_path: Path) -> None:
    """The stretched motion above with checks.torque_limit: the leg is stretched at
    t = (√579.96 - 12.6)/12 and the analysis stops there, so the limit is not decided
    (``torque_limit`` null): the report says so in an RPR202 finding located at that
    instant, in the task file's line for the limit, rather than saying nothing."""
    path = tmp_path / "stretch.rprpr.yaml"
    path.write_text(
        f"name: stretch\n{robot_text()}motion:\n  pieces:\n"
        "    - until: 1\n      x: 12.6 + 12*t\n      y: 9.8\n"
        "checks:\n  torque_limit: [1000, 1000]\n"
    )
    t_i = (math.sqrt(579.96) - 12.6) / 12
    code, rep = check_json(path)
    assert code == 1 and rep["torque_limit"] is None
    (f,) = [f for f in rep["findings"] if f["rule"] == "RPR202"]
    assert abs(f["t"] - t_i) <= 1e-12 and f["key"] == "checks.torque_limit"
    assert "the torque limit is not checked: leg 1 is stretched" in f["message"]
    assert f["line"] == path.read_text().splitlines().index("  torque_limit: [1000, 1000]") + 1


@pytest.mark.parametrize(("margin", "rules"), [("1.1", []), ("1.2", ["RPR102"])])
def test_the_speed_margin_is_the_rprprs(tmp_path: Path, margin: str, rules: list[str]) -> None:
    """The consistent crossing moves at |v| = |(1, 1/2)| = √5/2 = 1.1180 m/s through the
    pose: checks.min_speed 1.1 passes, 1.2 fails RPR102 with both numbers in the message."""
    m = motions()["consistent"]
    assert (m.x[1], m.y[1]) == (1, Q(1, 2))
    path = task_file(tmp_path, "consistent", m, f"checks:\n  min_speed: {margin}\n")
    code, rep = check_json(path)
    assert _rules(rep) == rules and code == (1 if rules else 0)
    if rules:
        message = rep["findings"][0]["message"]
        assert message.endswith(
            "velocity principle fails: speed 1.11803 m/s does not exceed the margin"
            " checks.min_speed = 1.2 m/s"
        )


@pytest.mark.parametrize(
    ("law", "x1", "rational"),
    [("quintic", Q(68, 5), True), ("cubic", Q(14), False)],
    ids=["symmetric-quintic", "asymmetric-cubic"],
)
def test_a_path_with_a_timing_law_has_the_references_instants(
    tmp_path: Path, law: str, x1: Q, rational: bool
) -> None:
    """y = 9.8 + (x - 12.6)/2 through the singular pose, x(t) rest to rest from 11.6 to
    ``x1`` in 1 s: the quintic to 13.6 passes the pose at t = 1/2 exactly, the cubic to 14
    at an irrational time (a root of 3τ² - 2τ³ = 5/12). Every instant the reference finds,
    at its time, with its order and line-up; at the pose Newton-Euler says the torques
    diverge, and RPR201 fails the task."""
    x0 = Q(58, 5)
    path = tmp_path / "line.rprpr.yaml"
    path.write_text(
        f"name: line\n{robot_text()}path:\n  y: 9.8 + 0.5*(x - 12.6)\n"
        f"  from: [11.6, 9.3]\n  to: [{_decimal(x1)}, {_decimal(Q(49, 5) + (x1 - Q(63, 5)) / 2)}]\n"
        f"timing:\n  duration: 1\n  law: {law}\n"
    )
    shape = (Z, Z, Z, Q(10), Q(-15), Q(6)) if law == "quintic" else (Z, Z, Q(3), Q(-2))
    x = tuple((x0 if i == 0 else Z) + (x1 - x0) * c for i, c in enumerate(shape))
    y = tuple((Q(49, 5) - Q(63, 10) if i == 0 else Z) + c / 2 for i, c in enumerate(x))
    ref = singular_instants(ROBOT, Motion(x, y), MODES, Z, Q(1))
    _, rep = check_json(path)
    got = rep["singularities"]
    assert len(got) == len(ref) >= 1
    for s, r in zip(got, ref, strict=True):
        assert abs(s["t"] - float(sp.N(r.t, 30))) <= 1e-15
        assert s["t_exact"] == (str(r.t) if r.t.is_Rational else None)
        assert (s["order"], s["sigma"]) == (r.order, r.sigma)
    pose = next((s, r) for s, r in zip(got, ref, strict=True) if (s["x"], s["y"]) == (12.6, 9.8))
    assert pose[1].t.is_Rational == rational
    # at the pose, Newton-Euler about the reference's t_s says the torques diverge
    t = sp.Symbol("t")
    ts = pose[1].t
    about = [
        sp.Poly(sum(sp.Rational(c.numerator, c.denominator) * (t + ts) ** i
                    for i, c in enumerate(cs)), t).all_coeffs()[::-1]
        for cs in (x, y)
    ]  # fmt: skip
    if rational:
        local = Motion(*(tuple(Q(int(c.p), int(c.q)) for c in cs) for cs in about))
        assert not bounded_by_newton_euler(local)
    assert not pose[0]["torque_bounded"] and not pose[0]["consistent"]
    assert ("RPR201", pose[0]["t"]) in [(f["rule"], f["t"]) for f in rep["findings"]]
    assert rep["verdict"] == "fail"


@pytest.mark.parametrize("form", ["concise", "github", "gitlab", "sarif", "junit", "html"])
def test_every_format_reports_a_5r_finding(tmp_path: Path, form: str) -> None:
    path = task_file(tmp_path, "inconsistent", motions()["inconsistent"])
    # html draws the sheet within the task's budget of wall time: no budget, so that a busy
    # machine never leaves it out (tests/render/test_html.py tests the budget's note)
    unbounded = ["--budget", "0"] if form == "html" else []
    code, out, err = run_cli("check", "--format", form, *unbounded, str(path))
    assert (code, err) == (1, "")
    assert "RPR201" in out and "internal" not in out
    assert "t = 0.1 s, (x, y) = (12.6, 9.8), modes (+1, -1)" in out  # σ: escaped in JSON


def test_samples_past_a_type_one_instant_carry_its_reason(tmp_path: Path) -> None:
    """E(t) = (t - 1/2, 1/2 - t) runs through A at t = 1/2: leg 1 (l1 = l3) is folded
    there, |E - A| = |l1 - l3| = 0, and its working mode is lost. From that instant on
    the samples hold the path but no joint, δ, α or torque: NaN, with the Type I reason
    code 7 (the export's reason for them); before it, every value is certified (0)."""
    from rprpr import audit
    from rprpr.engine.certified.five_bar_samples import TYPE_ONE
    from rprpr.io.loader import load_task

    path = tmp_path / "fold.rprpr.yaml"
    path.write_text(
        f"name: fold\n{robot_text()}motion:\n  pieces:\n"
        "    - until: 1\n      x: -0.5 + t\n      y: 0.5 - t\n"
    )
    r = audit(load_task(path), samples=11)
    assert [(k.leg, k.kind, str(k.t_exact)) for k in r.analysis.type_one] == [(1, "folded", "1/2")]
    got = r.samples
    past = got.t >= 0.5
    assert TYPE_ONE == 7 and list(got.reason) == [0] * 5 + [7] * 6
    for name in ("theta1", "theta2", "delta", "alpha", "T1", "T2"):
        assert not np.isnan(got.column(name)[~past]).any(), name
        assert np.isnan(got.column(name)[past]).all(), name
    assert np.allclose(got.x, got.t - 0.5, rtol=0, atol=1e-15)
    assert np.allclose(got.y, 0.5 - got.t, rtol=0, atol=1e-15)

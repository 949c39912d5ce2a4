"""The mechanism seam (``engine.mechanism``): both actuation schemes through the interface
against an independent reference, and a third implementation that the layers accept
without an edit.

References, written apart from the engine: ``tests.reference`` (mpmath, the paper's
equations and a direct solve of eq. (4) for the prismatic scheme) and the consistency
conditions derived by hand in fractions in ``test_equations_prismatic``.
"""

from __future__ import annotations

import ast
import dataclasses
from collections.abc import Callable, Iterator
from fractions import Fraction
from typing import Any

import mpmath
import numpy as np
import pytest
from flint import fmpq

from rprpr.engine.audit import audit
from rprpr.engine.certified.motion import CertifiedMotion
from rprpr.engine.certified.stacked import General, stacked_form
from rprpr.engine.exact import equations, mechanism
from rprpr.engine.exact.singular import analyse
from rprpr.engine.exact.trajectory import trajectory
from rprpr.engine.findings import findings
from rprpr.io.loader import parse_task
from rprpr.model.actuation import PRISMATIC, REVOLUTE
from rprpr.model.numbers import number
from rprpr.model.task import Link, Robot, Task
from tests.conftest import CONFIGS, PATH2_YAML, QUINTIC, ROOT, task_text
from tests.engine.exact.test_equations_prismatic import _moment_residual, _revolute_residual
from tests.reference import limit, reference

CROSSING = CONFIGS / "prismatic_crossing.rprpr.yaml"  # E crosses AB at (4, 0), t_s = 1/4


def _mpf(q: fmpq) -> Any:
    return mpmath.mpf(int(q.p)) / int(q.q)


def _path2(actuation: str) -> Task:
    text = task_text(PATH2_YAML, QUINTIC)
    return parse_task(text.replace("robot:\n", f"robot:\n  actuation: {actuation}\n", 1))


def _crossing(actuation: str) -> Task:
    text = CROSSING.read_text(encoding="utf-8")
    return parse_task(text.replace("actuation: prismatic", f"actuation: {actuation}"))


# -- both schemes through the interface, on a number type the engine never uses -------------


@pytest.mark.parametrize(
    ("task", "times"),
    [
        (_path2(REVOLUTE), ("0.3", "1.7", "2.4999", "3.1", "4.9")),
        (_path2(PRISMATIC), ("0.3", "1.7", "2.5001", "3.1", "4.9")),
        (_crossing(PRISMATIC), ("0.05", "0.2", "0.3", "0.45")),
        (_crossing(REVOLUTE), ("0.05", "0.2", "0.3", "0.45")),
    ],
    ids=["path2-revolute", "path2-prismatic", "crossing-prismatic", "crossing-revolute"],
)
def test_the_interface_in_mpmath_matches_the_reference(task: Task, times: tuple[str]) -> None:
    """legs, δ, δ', dynamics and efforts of ``mechanism.of(robot)`` evaluated in mpmath at
    60 digits from the reference's end point: every joint value, δ, λ and effort agrees
    with the reference's own to 1e-40 (mixed)."""
    mech = mechanism.of(task.robot)
    assert mech.name == task.robot.actuation
    for text in times:
        ref = reference(task, Fraction(text))
        with mpmath.workdps(60):
            p = mech.params(task.robot, _mpf)
            E = [ref[k] for k in ("x", "x_dot", "x_ddot", "y", "y_dot", "y_ddot")]
            leg1, leg2 = mech.legs(p, *E, mpmath.hypot)
            d = mech.dynamics(leg1, leg2, p)
            delta = mech.delta(p, E[3], leg1, leg2)
            lam = (d.mu1 / delta, d.mu2 / delta)
            got = {
                "s1": leg1.s, "s2": leg2.s, "s1_dot": leg1.s_d, "s2_dot": leg2.s_d,
                "theta1_dot": leg1.th_d, "theta2_dot": leg2.th_d,
                "s1_ddot": leg1.s_dd, "s2_ddot": leg2.s_dd,
                "theta1_ddot": leg1.th_dd, "theta2_ddot": leg2.th_dd,
                "delta": delta, "delta_dot": mech.delta_rate(p, E[3], E[4], leg1, leg2),
                "lambda1": lam[0], "lambda2": lam[1],
            }  # fmt: skip
            got["T1"], got["T2"] = mech.efforts(d, *lam)
            assert d.delta == pytest.approx(delta, rel=1e-40, abs=1e-40)  # eq. (29) both ways
            for name, value in got.items():
                assert abs(value - ref[name]) < mpmath.mpf(10) ** -40 * (1 + abs(ref[name])), (
                    name,
                    text,
                )


@pytest.mark.parametrize("actuation", [REVOLUTE, PRISMATIC])
def test_the_consistency_condition_through_the_interface(actuation: str) -> None:
    """At the crossing's instant (x, y) = (4, 0), (ẋ, ẏ) = (1, 3), ẍ = 0, ÿ = -37323/2450,
    in exact rationals: the prismatic residual U1/s1 + σ U2/s2 is 0 (the config is built
    so), the revolute residual is eq. (34) σ F1 + F2; both as derived by hand."""
    task = _crossing(actuation)
    mech = mechanism.of(task.robot)
    p = mech.params(task.robot)
    x, xd, xdd, yd, ydd = fmpq(4), fmpq(1), fmpq(0), fmpq(3), fmpq(-37323, 2450)
    leg1, leg2 = mech.legs(p, x, xd, xdd, fmpq(0), yd, ydd, lambda u, v: abs(u))
    d = mech.dynamics(leg1, leg2, p)
    num, den = mech.consistency(d, -1, lambda v: v)  # σ = -1: E between A and B
    value = num if den is None else num / den
    if actuation == PRISMATIC:
        expected = _moment_residual(Fraction(4), Fraction(1), Fraction(3), Fraction(-37323, 2450))
        assert mech.automatic == 1 and expected == 0
    else:
        expected = _revolute_residual(Fraction(4), Fraction(1), Fraction(0), Fraction(3))
        assert mech.automatic == 0 and expected != 0
    assert value == fmpq(expected.numerator, expected.denominator)
    assert [d.mu1, d.mu2][mech.automatic] == 0  # the automatic μ vanishes at y = 0


# -- a third implementation: the layers take it without an edit --------------------------------

SCALE = 3  # every mass and inertia tripled


class Tripled:
    """A test-only mechanism: the paper's revolute scheme with every mass and inertia
    tripled (written against the Protocol, not subclassing the RPRPR's)."""

    name = "revolute, masses x3"

    def __init__(self) -> None:
        self.inner = mechanism.of(Robot(fmpq(1), {}, fmpq(0), REVOLUTE))
        self.words = self.inner.words
        self.automatic = self.inner.automatic

    def params(self, robot: Robot, convert: Callable[[Any], Any] = lambda v: v) -> Any:
        links = {
            i: Link(link.mass * SCALE, link.inertia * SCALE, link.r)
            for i, link in robot.links.items()
        }
        p = self.inner.params(dataclasses.replace(robot, links=links), convert)
        return dataclasses.replace(p, mechanism=self)

    def __getattr__(self, name: str) -> Any:  # legs, locus, delta, dynamics, ...: the inner's
        return getattr(self.inner, name)


def _scaled_links(task: Task) -> Task:
    """The same task with every mass and inertia tripled in the task itself."""
    r = task.robot
    links = {i: Link(k.mass * SCALE, k.inertia * SCALE, k.r) for i, k in r.links.items()}
    return dataclasses.replace(task, robot=dataclasses.replace(r, links=links))


@pytest.fixture
def tripled() -> Iterator[Tripled]:
    m = Tripled()
    mechanism.register(m)
    yield m
    del mechanism.MECHANISMS[m.name]


def _as(task: Task, name: str) -> Task:
    return dataclasses.replace(task, robot=dataclasses.replace(task.robot, actuation=name))


def test_a_third_implementation_drives_the_exact_analysis(tripled: Tripled) -> None:
    """The exact analysis with the tripled mechanism: the same instants, 3× the hand-derived
    eq. (34) residual, and (path 2) the limit torques of the reference run on a task whose
    links are tripled in the task itself."""
    task = _as(_crossing(REVOLUTE), tripled.name)
    (s,) = analyse(trajectory(task), task.robot, task.checks).instants
    assert s.t_exact == Fraction(1, 4) and not s.consistent
    residual = SCALE * _revolute_residual(Fraction(4), Fraction(1), Fraction(0), Fraction(3))
    assert s.consistency_residual == float(residual)
    found = findings(task, analyse(trajectory(task), task.robot, task.checks), None, None)
    (rpr201,) = [f for f in found if f.rule == "RPR201"]
    assert f"eq. (34) residual {number(float(residual))} N" in rpr201.message

    path2 = _as(_path2(REVOLUTE), tripled.name)
    (s,) = analyse(trajectory(path2), path2.robot, path2.checks).instants
    ref = limit(_scaled_links(_path2(REVOLUTE)), Fraction(5, 2))
    assert ref is not None and s.torque_at_singularity is not None
    for got, name in zip(s.torque_at_singularity, ("T1", "T2"), strict=True):
        assert abs(got - float(ref[name])) <= 1e-12 * (1 + abs(got)), name


def test_a_third_implementation_drives_the_certified_values(tripled: Tripled) -> None:
    """Certified λ and T (ball pass, zone forms near t_s = 2.5 s, arb refinement) with the
    tripled mechanism equal the reference's on the task with tripled links."""
    task = _as(_path2(REVOLUTE), tripled.name)
    times = np.array([0.3, 1.7, 2.4999, 2.5, 2.5001, 3.1, 4.9])
    analysis = analyse(trajectory(task), task.robot, task.checks)
    c = CertifiedMotion(trajectory(task), task.robot, analysis).sample(times)
    scaled = _scaled_links(_path2(REVOLUTE))
    for j, t in enumerate(times):
        ref = reference(scaled, t) if t != 2.5 else limit(scaled, Fraction(5, 2))
        assert ref is not None
        for name in ("lambda1", "lambda2", "T1", "T2"):
            got = c.value[name][j]
            assert abs(got - float(ref[name])) <= 1e-9 * (1 + abs(got)), (name, t)
    plain = CertifiedMotion(trajectory(_path2(REVOLUTE)), _path2(REVOLUTE).robot, analysis)
    assert c.value["T1"][0] == pytest.approx(SCALE * plain.sample(times[:1]).value["T1"][0])


# -- the layers name no scheme ---------------------------------------------------------------

# every module of the engine but the seam itself (equations.py, mechanism.py); the RPRPR's
# stacked two-leg form (certified/stacked.py) is a fast path of the RPRPR's own, chosen by
# stacked_form for both its schemes (FORMS), and tells them apart there alone.
SEAM = {"exact/equations", "exact/mechanism"}
SCHEME_AWARE = {"certified/stacked"}
LAYERS = sorted(
    str(p.relative_to(ROOT / "rprpr" / "engine").with_suffix(""))
    for p in (ROOT / "rprpr" / "engine").rglob("*.py")
    if p.name != "__init__.py"
)


def test_the_guard_sees_every_layer() -> None:
    assert {
        "exact/singular",
        "certified/zones",
        "bounds/envelope",
        "robust/windows",
        "audit",
    } <= set(LAYERS)
    assert set(LAYERS) >= SEAM | SCHEME_AWARE


@pytest.mark.parametrize("layer", [m for m in LAYERS if m not in SEAM | SCHEME_AWARE])
def test_the_layers_do_not_branch_on_the_scheme(layer: str) -> None:
    """No layer reads ``.actuation`` or names a scheme: they ask the mechanism."""
    tree = ast.parse((ROOT / "rprpr" / "engine" / f"{layer}.py").read_text(encoding="utf-8"))
    names = {n.id for n in ast.walk(tree) if isinstance(n, ast.Name)}
    attributes = {n.attr for n in ast.walk(tree) if isinstance(n, ast.Attribute)}
    assert not {"PRISMATIC", "Prismatic", "Revolute"} & (names | attributes)
    assert "actuation" not in attributes
    assert "AUTOMATIC" not in attributes
    assert "actuation" not in attributes
    assert equations.MECHANISMS is mechanism.MECHANISMS


def test_a_third_implementation_drives_the_grid_free_peak(tripled: Tripled) -> None:
    """The certified torque peak over [0, t_f] (the bounds layer, through the general
    stacked form, since the tripled mechanism has none of its own) encloses the maximum of
    the reference's |T| on the task with tripled links, sampled on a grid, and is within
    the peak's tolerance of it."""
    task = _as(_path2(REVOLUTE), tripled.name)
    assert isinstance(stacked_form(task.robot), General)
    peaks = audit(task, peak=True).torque_peak
    assert peaks is not None
    scaled = _scaled_links(_path2(REVOLUTE))
    grid = [Fraction(k, 400) * 5 for k in range(401)]  # 0 .. 5 s, t_s = 2.5 s on it
    for i, name in enumerate(("T1", "T2")):
        best = 0.0
        for t in grid:
            ref = reference(scaled, float(t)) if t != Fraction(5, 2) else limit(scaled, t)
            assert ref is not None
            best = max(best, abs(float(ref[name])))
        peak = peaks[i]
        assert peak.certified and best <= peak.upper * (1 + 1e-12)
        assert abs(peak.value - best) <= 1e-3 * best, (name, peak, best)

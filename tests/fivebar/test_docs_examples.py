"""docs/five-bar.md §11's worked examples, as the task files docs/examples/five_bar_*.yaml:
``rprpr check`` gives the documented verdicts and numbers, and each number is the
independent references' (instants.py: sympy's roots of S_σ(E(t)) and δ at 60 digits;
theory.py: the reciprocity residual and its derivatives; reference.py: Newton-Euler at
60 digits; locus.py: the sympy curve for the crossing angle), never the engine's own.

The robot is test_check's (links 13 m, motors 14 m apart), the pose E = (63/5, 49/5) at
t_s = 1/10 in modes (+1, -1), σ = -1, on the path
y = 9.8 + (x - 12.6)/2 + c (x - 12.6)², c = -1703084711287583/234669795048360.
"""

from __future__ import annotations

import math
from fractions import Fraction as Q
from pathlib import Path

import mpmath
import sympy as sp

from .instants import singular_instants
from .reference import DPS, Motion, torques
from .test_check import MODES, ROBOT, TF, Z, absolute, bounded_by_newton_euler, check_json
from .test_engine_instants import _tangent
from .theory import derive

DOCS = Path(__file__).resolve().parents[2] / "docs"
EXAMPLES = DOCS / "examples"
C = Q(-1703084711287583, 234669795048360)  # the path's curvature term (the file's)
E = (Q(63, 5), Q(49, 5))

# the documented numbers (docs/five-bar.md §11)
TAN_ALPHA = Q(173, 94)
LIMIT = (68.85594552, -47.15904436)  # N m, example 1
RESIDUALS = (Q(9703071, 845000), Q(12282518, 60333), Q(0))  # N, N/s, N/s², example 2
RESIDUE = (-8.957081, 6.507280)  # N m s³: (t - t_s)³ T -> this at the stop, example 2


def _local(x: tuple[Q, ...]) -> Motion:
    """The path's motion in τ = t - t_s for x(τ) - 12.6 = the polynomial whose
    coefficients of τ, τ², ... are ``x``."""
    t = sp.Symbol("t")
    u = sum(sp.Rational(c.numerator, c.denominator) * t ** (i + 1) for i, c in enumerate(x))
    y = sp.Poly(sp.Rational(49, 5) + u / 2 + sp.Rational(C.numerator, C.denominator) * u**2, t)
    ys = tuple(Q(int(c.p), int(c.q)) for c in reversed(y.all_coeffs()))
    return Motion((E[0], *x), ys)


CROSSING = _local((Q(1),))  # x = 12.6 + τ
STOP = _local((Z, Z, Q(100)))  # x = 12.6 + 100 τ³


def _tan_alpha() -> Q:
    """tan α between the path's direction (1, 1/2) at the pose and S₋ (the sympy curve)."""
    tx, ty = _tangent(ROBOT, E, -1)
    gx, gy = ty, -tx
    v = (Q(1), Q(1, 2))
    return abs(gx * v[0] + gy * v[1]) / abs(gx * v[1] - gy * v[0])


def test_the_documented_numbers_are_the_references() -> None:
    assert _tan_alpha() == TAN_ALPHA
    assert derive(ROBOT, CROSSING, Z, MODES, 3).w(-1).d(0) == 0  # consistent
    w = derive(ROBOT, STOP, Z, MODES, 6).w(-1)
    assert tuple(w.d(i) for i in range(3)) == RESIDUALS
    for side in (1, -1):
        T = torques(ROBOT, CROSSING, Q(side, 10**10), MODES)
        assert all(abs(float(T[i]) - LIMIT[i]) <= 1e-7 for i in (0, 1))
    with mpmath.workdps(DPS):
        for s in (1, -1):
            h = mpmath.mpf(s) / 10**8
            T = torques(ROBOT, STOP, Q(s, 10**8), MODES)
            assert all(abs(float(T[i] * h**3) - RESIDUE[i]) <= 1e-5 for i in (0, 1))


def test_example_1_a_consistent_transversal_crossing_passes() -> None:
    path = EXAMPLES / "five_bar_crossing.rprpr.yaml"
    ref = singular_instants(ROBOT, absolute(CROSSING), MODES, Z, TF)
    assert [(r.t, r.order, r.sigma) for r in ref] == [(sp.Rational(1, 10), 1, -1)]
    assert bounded_by_newton_euler(CROSSING)
    code, rep = check_json(path)
    assert (code, rep["verdict"], rep["findings"]) == (0, "pass", [])
    (s,) = rep["singularities"]
    assert (s["t_exact"], s["order"], s["sigma"], s["modes"]) == ("1/10", 1, -1, [1, -1])
    assert (s["x"], s["y"]) == (12.6, 9.8)
    assert s["slope"] == float(TAN_ALPHA)
    assert s["speed"] == math.sqrt(5) / 2
    assert s["consistency_residual"] == 0 and s["torque_bounded"]
    for i in (0, 1):
        assert abs(s["torque_at_singularity"][i] - LIMIT[i]) <= 1e-7


def test_example_2_the_same_path_at_zero_speed_fails() -> None:
    path = EXAMPLES / "five_bar_stop.rprpr.yaml"
    ref = singular_instants(ROBOT, absolute(STOP), MODES, Z, TF)
    assert [(r.t, r.order, r.sigma) for r in ref] == [(sp.Rational(1, 10), 3, -1)]
    assert not bounded_by_newton_euler(STOP)
    code, rep = check_json(path)
    assert (code, rep["verdict"]) == (1, "fail")
    assert [f["rule"] for f in rep["findings"]] == ["RPR102", "RPR201"]
    (s,) = rep["singularities"]
    assert (s["t_exact"], s["order"], s["sigma"]) == ("1/10", 3, -1)
    assert s["speed"] == 0 and s["velocity_principle"] == "fail"
    assert s["slope"] == float(TAN_ALPHA)  # along the same direction as example 1
    assert not s["consistent"] and s["pole_order"] == 3
    for got, want in zip(s["residuals"], RESIDUALS, strict=True):
        assert abs(got - float(want)) <= 1e-12 * (1 + abs(float(want)))


def test_the_examples_are_the_same_path() -> None:
    """Both files give the same y = p(x) (the path text), timed differently."""
    texts = [(EXAMPLES / f"five_bar_{n}.rprpr.yaml").read_text() for n in ("crossing", "stop")]
    ys = [next(ln for ln in t.splitlines() if ln.startswith("  y:")) for t in texts]
    assert ys[0] == ys[1]
    assert f"{-C.numerator}/{C.denominator}" in ys[0]

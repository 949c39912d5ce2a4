"""The 5R engine's Type II instants (``five_bar_instants.analyse``) against the reference
(instants.py: sympy's exact real roots of S_σ(E(t)), each kept when the robot's own δ
vanishes at 60 digits, its order read from δ's Taylor series): the same instants, times,
line-ups σ and orders on motions of every kind (transversal crossings, tangential
touches, stops on the curve, order three, irrational instants, the node where two modes
are singular at once) and in each working mode; and the Type I refusals."""

from __future__ import annotations

import json
from fractions import Fraction as Q
from functools import cache
from pathlib import Path
from typing import Any

import mpmath
import pytest
import sympy as sp
from flint import arb, ctx, fmpq

from rprpr.engine.exact.five_bar_instants import FiveBarError, analyse

from .instants import Instant, singular_instants
from .locus import curve_at, x, y
from .reference import FiveBar, Motion, elbows
from .standin import polys, q, robot
from .test_dynamics import (
    A3,
    CONSISTENT,
    INCONSISTENT,
    J3,
    K3,
    MODES,
    ROBOT,
    STOP_A,
    STOP_J,
    TANGENT,
    _unequal,
    motion,
    motion4,
)

Z = Q(0)
H = Q(1, 2)
ALL = ((1, 1), (1, -1), (-1, 1), (-1, -1))

# rational Type II poses of unequal-link robots (l1 = 1, l3 = 3/2, l4 = 5/4), one for each
# line-up σ and working mode, both legs far from Type I (reference.lined_up: the
# geometry, not the engine)
POSES = {
    (-1, (-1, -1)): (Q(1, 3), Q(3, 4), Q(-1, 2)),
    (-1, (-1, 1)): (Q(3), Q(-1, 2), Q(1, 2)),
    (-1, (1, -1)): (Q(2), Q(1, 2), Q(3)),
    (-1, (1, 1)): (Q(1, 3), Q(-1, 2), Q(1, 2)),
    (1, (-1, -1)): (Q(1, 3), Q(3), Q(5, 3)),
    (1, (-1, 1)): (Q(1, 3), Q(1, 2), Q(-1, 2)),
    (1, (1, -1)): (Q(1, 2), Q(-1, 2), Q(3)),
    (1, (1, 1)): (Q(1, 2), Q(-1, 2), Q(3, 4)),
}


def _tangent(rb: FiveBar, E: tuple[Q, Q], sigma: int) -> tuple[Q, Q]:
    """The curve's tangent at E, from the sympy curve (∇S_σ turned by 90°)."""
    params = (sp.Rational(v.numerator, v.denominator) for v in (rb.a, *rb.length))
    X, Y = sp.Poly(x, x, y, domain="QQ"), sp.Poly(y, x, y, domain="QQ")
    S = curve_at(sigma, *params, X, Y)  # curve(σ) as a Poly in x, y
    at = (sp.Rational(E[0].numerator, E[0].denominator),
          sp.Rational(E[1].numerator, E[1].denominator))  # fmt: skip
    gx, gy = (S.diff(v)(*at) for v in (x, y))
    scale = max(abs(gx), abs(gy))  # a unit of the larger coordinate
    gx, gy = gx / scale, gy / scale
    return Q(-int(gy.p), int(gy.q)), Q(int(gx.p), int(gx.q))


def _cases() -> list[tuple[str, FiveBar, Motion, tuple[int, int], Q, Q]]:
    out = [
        ("consistent", ROBOT, CONSISTENT, MODES, -H, H),
        ("inconsistent", ROBOT, INCONSISTENT, MODES, -H, H),
        ("tangent", ROBOT, TANGENT, MODES, -H, H),
        ("stop", ROBOT, motion((Z, Z), STOP_A, (Z, STOP_J)), MODES, -H, H),
        ("order 3", ROBOT, motion4(A3, J3, K3), MODES, Q(-1, 20), Q(1, 20)),
    ]
    for modes in ((1, 1), (-1, 1), (-1, -1)):
        out.append((f"consistent in {modes}", ROBOT, CONSISTENT, modes, -H, H))
    for modes in ALL:
        line = Motion((Q(1, 5), Q(1)), (Q(3, 5),))
        out.append((f"straight, irrational, {modes}", ROBOT, line, modes, Z, Q(1)))
    node = Motion((Q(7, 13), Q(1)), (Z, Q(1)))
    for modes in ((1, 1), (-1, -1)):
        out.append((f"node {modes}", ROBOT, node, modes, -H, H))
    for (sigma, modes), s in POSES.items():
        rb, got, E = _unequal(sigma, s)
        assert got == modes
        v, A = (Q(1, 2), Q(1, 3)), (Q(-1, 3), Q(1, 4))
        crossing = motion(v, A, E=E)
        touch = motion(_tangent(rb, E, sigma), A, E=E)
        stop = motion((Z, Z), A, (Q(1), Q(1, 2)), E=E)
        span = (Q(-1, 32), Q(1, 32))
        out += [
            (f"crossing σ={sigma} {modes}", rb, crossing, modes, *span),
            (f"touch σ={sigma} {modes}", rb, touch, modes, *span),
            (f"stop σ={sigma} {modes}", rb, stop, modes, *span),
        ]
    return out


# The cases' names, in _cases()'s order: the tests are parametrized by them when the test
# module is collected, and the cases themselves (their tangents: sympy) are built at first
# use, in the one test process that runs them, not in every process that collects them.
NAMES = [
    "consistent", "inconsistent", "tangent", "stop", "order 3",
    *(f"consistent in {m}" for m in ((1, 1), (-1, 1), (-1, -1))),
    *(f"straight, irrational, {m}" for m in ALL),
    *(f"node {m}" for m in ((1, 1), (-1, -1))),
    *(f"{kind} σ={s} {m}" for s, m in POSES for kind in ("crossing", "touch", "stop")),
]  # fmt: skip


@cache
def cases() -> list[tuple[str, FiveBar, Motion, tuple[int, int], Q, Q]]:
    """_cases(), built at first use, in NAMES's order."""
    built = _cases()
    assert [c[0] for c in built] == NAMES
    return built


@cache
def _engine(i: int) -> Any:
    _, rb, m, modes, t0, t1 = cases()[i]
    return analyse(robot(rb, modes), q(rb.g), *polys(m), q(t0), q(t1))


def _ref_ball(t: Any) -> arb:
    old = ctx.prec
    ctx.prec = 300
    try:
        return arb(str(sp.N(t, 80)))
    finally:
        ctx.prec = old


# The reference's instants of each case (instants.py: sympy's exact real roots, δ at 60
# digits), stored beside this file by the case's robot, motion, modes and span: the
# reference's values never change, and sympy takes seconds to isolate them. Written by
# ``python -m tests.fivebar.test_engine_instants``; a slow test recomputes every stored
# case, and a case not stored (a new one, or one whose motion changed) is computed here.
STORED = Path(__file__).with_name("engine_instants_reference.json")


def _key(i: int) -> str:
    return repr(cases()[i][1:])


def _encode(instants: list[Instant]) -> list[dict[str, Any]]:
    """The reference's instants as stored: t exact (p/q) or as the 80 digits the tests
    read of it, and |δ| of the other working modes to 20 digits."""
    return [
        {
            "t": str(w.t) if w.t.is_Rational else None,
            "t80": None if w.t.is_Rational else str(sp.N(w.t, 80)),
            "sigma": w.sigma,
            "multiplicity": w.multiplicity,
            "order": w.order,
            "others": [mpmath.nstr(v, 20) for v in w.others],
        }
        for w in instants
    ]


def _decode(rows: list[dict[str, Any]]) -> list[Instant]:
    with mpmath.workdps(30):  # the 20 digits stored, read back as written
        return [
            Instant(
                sp.Rational(r["t"]) if r["t"] is not None else sp.Float(r["t80"], 80),
                r["sigma"],
                r["multiplicity"],
                r["order"],
                tuple(mpmath.mpf(v) for v in r["others"]),
            )
            for r in rows
        ]


@cache
def _stored() -> dict[str, list[dict[str, Any]]]:
    return json.loads(STORED.read_text(encoding="utf-8")) if STORED.exists() else {}


def _recomputed(i: int) -> list[Instant]:
    _, rb, m, modes, t0, t1 = cases()[i]
    return singular_instants(rb, m, modes, t0, t1)


def reference(i: int) -> list[Instant]:
    """The reference's instants of cases()[i]: stored, or computed when not stored."""
    rows = _stored().get(_key(i))
    return _recomputed(i) if rows is None else _decode(rows)


def _write_stored() -> None:
    table = {_key(i): _encode(_recomputed(i)) for i in range(len(NAMES))}
    for rows in table.values():  # the tests read back the digits stored
        assert _encode(_decode(rows)) == rows
    STORED.write_text(json.dumps(table, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")


@pytest.mark.slow  # sympy's exact roots of every case, and δ at 60 digits at each
@pytest.mark.parametrize("i", range(len(NAMES)), ids=NAMES)
def test_the_stored_instants_are_the_references(i: int) -> None:
    rows = _stored().get(_key(i))
    if rows is None:
        pytest.skip("not stored: the fast test computes it")
    assert _encode(_recomputed(i)) == rows
    assert _encode(_decode(rows)) == rows


@pytest.mark.parametrize("i", range(len(NAMES)), ids=NAMES)
def test_the_instants_orders_and_line_ups_are_the_references(i: int) -> None:
    name, _rb, _m, modes, _t0, _t1 = cases()[i]
    got = _engine(i)
    want = reference(i)
    assert not got.refused
    assert len(got.instants) == len(want), name
    for g, w in zip(got.instants, want, strict=True):
        if w.t.is_Rational:
            assert g.t_exact == fmpq(int(w.t.p), int(w.t.q))
        else:
            assert g.t_exact is None
            assert g.t_ball.overlaps(_ref_ball(w.t)) and g.t_ball.rad() < 1e-30
        assert (g.sigma, g.order, g.multiplicity) == (w.sigma, w.order, w.multiplicity), name
        assert g.degenerate == (min(w.others) < 1e-40)
        assert g.modes == modes


def test_the_cases_cover_every_kind_and_mode() -> None:
    seen = set()
    for i in range(len(NAMES)):
        for s in _engine(i).instants:
            kind = "rational" if s.t_exact is not None else "irrational"
            seen.add((s.modes, s.sigma, s.order, kind, s.degenerate))
    modes = {(m, sigma) for m, sigma, *_ in seen}
    assert modes == {(m, sigma) for m in ALL for sigma in (1, -1)}  # every mode, both line-ups
    assert {o for _, _, o, _, _ in seen} == {1, 2, 3}
    assert any(k == "irrational" for *_, k, _ in seen) and any(d for *_, d in seen)
    assert len(cases()) >= 20


def test_a_stop_and_a_touch_fail_their_principle_a_crossing_passes_both() -> None:
    for i, (name, *_rest) in enumerate(cases()):
        at_zero = [s for s in _engine(i).instants if s.t_exact == 0]
        if name.startswith("crossing") or name in ("consistent", "inconsistent"):
            (s,) = at_zero
            assert s.slope_principle.passed and s.velocity_principle.passed, name
            assert s.normal_rate != 0 and s.order == 1
        if name.startswith("touch") or name == "tangent":
            (s,) = at_zero
            assert not s.slope_principle.passed and s.velocity_principle.passed, name
            assert s.normal_rate == 0 and s.slope == 0
        if name.startswith("stop"):
            (s,) = at_zero
            assert not s.velocity_principle.passed and s.speed2 == 0, name
            assert s.slope_principle.passed  # along E'' the path crosses the curve


def test_the_slope_margin_is_the_tangent_of_the_crossing_angle() -> None:
    """tan α between E' = (1, 1/2) and the curve at the rational pose: |g·v|/|g × v| with
    the gradient of the sympy curve; a margin above it fails, one below passes."""
    g = _tangent(ROBOT, (Q(63, 65), Q(49, 65)), -1)  # (-gy, gx)
    gx, gy = g[1], -g[0]
    v = (Q(1), Q(1, 2))
    tan = abs(gx * v[0] + gy * v[1]) / abs(gx * v[1] - gy * v[0])
    x_, y_ = polys(CONSISTENT)
    for margin, passed in ((tan * Q(99, 100), True), (tan * Q(101, 100), False)):
        a = analyse(robot(ROBOT, MODES), q(ROBOT.g), x_, y_, q(-H), q(H), min_slope=q(margin))
        (s,) = [s for s in a.instants if s.t_exact == 0]
        assert s.slope == q(tan)
        assert s.slope_principle.passed == passed


def test_a_stretched_leg_refuses_the_path_at_the_exact_instant() -> None:
    """E(t) = (1, 1/2 + t): leg 1 (l1 + l3 = 2) is stretched where 1 + (1/2 + t)² = 4,
    t = √3 - 1/2; the reference finds no elbow beyond it. Before it the path crosses the
    Type II curve at an irrational instant: analysed all the same, the reference's."""
    m = Motion((Q(1),), (H, Q(1)))
    a = analyse(robot(ROBOT, MODES), q(ROBOT.g), *polys(m), q(Z), q(Q(5, 4)))
    stop = sp.sqrt(3) - H
    ref = [r for r in singular_instants(ROBOT, m, MODES, Z, Q(5, 4)) if r.t < stop]
    assert a.refused and len(a.instants) == len(ref) == 1
    for s, r in zip(a.instants, ref, strict=True):
        assert (s.t_exact, s.order, s.sigma) == (None, r.order, r.sigma)
        assert abs(s.t - float(sp.N(r.t, 30))) <= 1e-15
    (k,) = a.type_one
    assert (k.leg, k.kind, k.t_exact) == (1, "stretched", None)
    assert abs(k.t - (float(mpmath.sqrt(3)) - 0.5)) < 1e-15
    with pytest.raises(ValueError, match="reach"):
        elbows(ROBOT, (Q(1), Q(2) + H), MODES)


def test_a_path_through_A_with_l1_equal_to_l3_is_refused_as_folded() -> None:
    m = Motion((Q(-1, 2), Q(1)), (Q(-1, 2), Q(1)))  # E = A at t = 1/2
    a = analyse(robot(ROBOT, MODES), q(ROBOT.g), *polys(m), q(Z), q(Q(1)))
    assert [(k.leg, k.kind, k.t_exact) for k in a.type_one] == [(1, "folded", fmpq(1, 2))]


def test_a_start_out_of_reach_is_an_error() -> None:
    m = Motion((Q(3),), (Q(3), Q(1)))
    with pytest.raises(FiveBarError, match="out of leg 1's reach"):
        analyse(robot(ROBOT, MODES), q(ROBOT.g), *polys(m), q(Z), q(Q(1)))


def test_a_task_s_robot_is_read_through_its_five_bar_and_gravity() -> None:
    """The task side's ``Robot`` carries ``five_bar`` and ``gravity`` (a stand-in here)."""
    from types import SimpleNamespace

    from rprpr.engine.exact.five_bar import FIVE_BAR
    from rprpr.engine.exact.five_bar_instants import analyse_robot

    rb = SimpleNamespace(mechanism="5R", five_bar=robot(ROBOT, MODES), gravity=q(ROBOT.g))
    a = analyse_robot(rb, *polys(CONSISTENT), q(-H), q(H))
    assert [(s.t_exact, s.order) for s in a.instants if s.t_exact is not None] == [(0, 1)]
    p = FIVE_BAR.robot_params(rb)
    assert (p.a, p.g, p.m[2], p.r[3]) == (q(ROBOT.a), q(ROBOT.g), q(ROBOT.mass[2]), q(ROBOT.r[3]))


if __name__ == "__main__":
    _write_stored()

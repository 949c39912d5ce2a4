"""The 5R engine's inverse dynamics and consistency (``five_bar``, ``five_bar_instants``)
against the brute-force reference (reference.py: Newton-Euler of the four bodies at 60
digits, exact series for the motion and the elbows).

Away from Type II: the engine's torques, in arb balls, in mpmath and in exact rationals,
equal Newton-Euler's. At Type II instants: a motion built to satisfy the condition has
residual exactly 0 and torques tending to the engine's limit; one that violates it has a
nonzero residual w, equal to what the reference's pole says: h T1(h) tends to
-(C × u1) σ l3 l4 w/δ'(t_s) (u1 the unit distal link), so w is read off Newton-Euler."""

from __future__ import annotations

from fractions import Fraction as Q
from functools import cache
from typing import Any

import mpmath
import pytest
from flint import arb, ctx, fmpq

from rprpr.engine.exact import five_bar as fb
from rprpr.engine.exact.five_bar_instants import analyse

from .reference import DPS, FiveBar, Motion, delta, links, mp, newton_euler, rational_unit, torques
from .standin import polys, q, robot
from .test_dynamics import (
    A3,
    AT,
    CONSISTENT,
    GENERIC,
    INCONSISTENT,
    J3,
    JT,
    K3,
    MODES,
    ROBOT,
    STOP_A,
    STOP_J,
    TANGENT,
    VT,
    _unequal,
    motion,
    motion4,
    solve,
)
from .theory import derive

Z = Q(0)
H = Q(1, 2)


def _close(a: Any, b: Any, rel: float) -> bool:
    with mpmath.workdps(DPS):
        a, b = (mp(v) if isinstance(v, Q) else mpmath.mpf(v) for v in (a, b))
        return bool(abs(a - b) <= rel * (1 + abs(b)))


def _arb_float(v: arb) -> Any:
    return mpmath.mpf(v.mid().str(40, radius=False))


# -- away from singularities ------------------------------------------------------------------
def _posed_motions() -> list[tuple[FiveBar, tuple[int, int], Motion, Q]]:
    from .test_engine_instants import POSES

    out = []
    for (sigma, _), s in POSES.items():
        rb, modes, E = _unequal(sigma, s)
        out.append(
            (
                rb,
                modes,
                motion((Q(1, 2), Q(1, 3)), (Q(-1, 3), Q(1, 4)), (Q(1), Q(2)), E=E),
                Q(1, 40),
            )
        )
    return out


AWAY = [(rb, modes, m, t) for rb, modes, m in GENERIC for t in (Q(1, 10), Q(-1, 9))]
AWAY += _posed_motions()


def _jets(m: Motion, t: Any) -> list[Any]:
    xs, ys = m.at(t, 3)
    return [xs.c[0], xs.c[1], 2 * xs.c[2], ys.c[0], ys.c[1], 2 * ys.c[2]]


@pytest.mark.parametrize(("rb", "modes", "m", "t"), AWAY)
def test_torques_in_arb_and_mpmath_equal_newton_euler(
    rb: FiveBar, modes: tuple[int, int], m: Motion, t: Q
) -> None:
    ref = newton_euler(rb, links(rb, m, t, modes, 3))
    lk = links(rb, m, t, modes, 4)
    with mpmath.workdps(DPS):
        d_ref = delta(lk.joints["C"], lk.joints["D"], lk.joints["E"])
        assert abs(mp(d_ref.c[0])) > 1e-3  # away from Type II
    old = ctx.prec
    ctx.prec = 128
    try:
        p = fb.params(robot(rb, modes), q(rb.g), arb)
        E = [arb(q(v)) for v in _jets(m, t)]
        d = fb.dynamics(*fb.legs(p, modes, *E, lambda D, i: D.sqrt()), p)
        T = fb.torques(d)
        rate = fb.delta_rate(d)
    finally:
        ctx.prec = old
    for i, name in enumerate(("T1", "T2")):
        assert _close(_arb_float(T[i]), ref[name], 1e-9), name
        assert T[i].rad() < 1e-25
    assert _close(_arb_float(rate), d_ref.d(1), 1e-9)
    with mpmath.workdps(DPS):
        p = fb.params(robot(rb, modes), q(rb.g), lambda v: mpmath.mpf(int(v.p)) / int(v.q))
        E = [mp(v) for v in _jets(m, t)]
        T = fb.torques(fb.dynamics(*fb.legs(p, modes, *E, lambda D, i: mpmath.sqrt(D)), p))
    assert _close(T[0], ref["T1"], 1e-40) and _close(T[1], ref["T2"], 1e-40)


def test_torques_in_exact_rationals_at_a_pose_with_rational_elbows() -> None:
    """C = l1 c, E = C + l3 u, D = E - l4 v, D - B = l2 w for rational unit vectors: every
    root is rational, so the engine's torques are exact rationals; Newton-Euler agrees."""
    c, u, v, w = (rational_unit(s) for s in (Q(1, 2), Q(1, 5), Q(-3, 2), Q(2)))
    l1, l3, l4 = Q(1), Q(3, 2), Q(5, 4)
    C = (l1 * c[0], l1 * c[1])
    E = (C[0] + l3 * u[0], C[1] + l3 * u[1])
    D = (E[0] - l4 * v[0], E[1] - l4 * v[1])
    l2 = D[1] / w[1]
    a = D[0] - l2 * w[0]
    assert l2 > 0 and a > 0
    rb = FiveBar(
        a, (l1, l2, l3, l4),
        (Q(3), Q(2), Q(3, 2), Q(5, 4)), (Q(1, 10), Q(1, 12), Q(1, 6), Q(1, 9)),
        (Q(1, 2), Q(2, 5), Q(2, 3), Q(1, 2)), Q(981, 100),
    )  # fmt: skip
    modes = (1 if E[0] * C[1] - E[1] * C[0] > 0 else -1,
             1 if (E[0] - a) * D[1] - E[1] * (D[0] - a) > 0 else -1)  # fmt: skip
    m = motion((Q(1, 2), Q(1, 3)), (Q(-1, 3), Q(1, 4)), (Q(1), Q(2)), E=E)
    p = fb.params(robot(rb, modes), q(rb.g))
    d = fb.dynamics(*fb.legs(p, modes, *(q(v) for v in _jets(m, Z)), lambda D, i: D.sqrt()), p)
    assert (d.leg1.c[0], d.leg1.c[1]) == (q(C[0]), q(C[1]))
    assert (d.leg2.c[0] + p.a, d.leg2.c[1]) == (q(D[0]), q(D[1]))
    T = fb.torques(d)
    assert all(isinstance(v, fmpq) for v in T)
    ref = torques(rb, m, Z, modes)
    assert _close(Q(int(T[0].p), int(T[0].q)), ref[0], 1e-40)
    assert _close(Q(int(T[1].p), int(T[1].q)), ref[1], 1e-40)


# -- at Type II instants: consistency, the high-order conditions, the limits -----------------
@cache  # the engine's analysis of a motion, once per test process (its records are frozen)
def _instant(rb: FiveBar, m: Motion, modes: tuple[int, int], t0: Q, t1: Q, at: Q = Z) -> Any:
    a = analyse(robot(rb, modes), q(rb.g), *polys(m), q(t0), q(t1))
    (s,) = [s for s in a.instants if s.t_exact == q(at)]
    return s


def _ne_near(rb: FiveBar, m: Motion, modes: tuple[int, int], ts: Any, h: Any) -> list[Any]:
    """Newton-Euler's (T1, T2) at ts + h and ts - h."""
    with mpmath.workdps(DPS):
        return [torques(rb, m, ts + s * h, modes) for s in (1, -1)]


def _limit_matches(
    s: Any, rb: FiveBar, m: Motion, modes: tuple[int, int], h: Q, rel: float
) -> None:
    assert s.torque_at_singularity is not None
    for T in _ne_near(rb, m, modes, Z, h):
        for i in (0, 1):
            got = s.torque_at_singularity[i]
            got = Q(int(got.p), int(got.q)) if isinstance(got, fmpq) else _arb_float(got)
            assert _close(T[i], got, rel), (i, T[i], got)


@pytest.mark.parametrize(
    ("name", "m", "order", "h", "rel", "span"),
    [
        ("transversal", CONSISTENT, 1, Q(1, 10**8), 1e-6, H),
        ("tangent", TANGENT, 2, Q(1, 10**10), 1e-6, H),
        ("stop", motion((Z, Z), STOP_A, (Z, STOP_J)), 2, Q(1, 10**10), 1e-6, H),
        ("order three", motion4(A3, J3, K3), 3, Q(1, 10**10), 1e-6, Q(1, 20)),
    ],
)
def test_a_motion_built_to_be_consistent_has_zero_residuals_and_the_newton_euler_limit(
    name: str, m: Motion, order: int, h: Q, rel: float, span: Q
) -> None:
    s = _instant(ROBOT, m, MODES, -span, span)
    assert s.order == order and s.residuals == (0,) * order
    assert all(isinstance(r, fmpq) for r in s.residuals)  # exact: the pose is rational
    assert s.conditions_met == order and s.bounded
    _limit_matches(s, ROBOT, m, MODES, h, rel)


def test_the_doc_s_rational_limit_of_the_transversal_crossing() -> None:
    s = _instant(ROBOT, CONSISTENT, MODES, -H, H)
    assert s.torque_at_singularity == (
        fmpq(1067610682465843304181031, 221515964245874925900000),
        fmpq(-516181859311537391601059, 304910209609027839180000),
    )


def _pole_residual(rb: FiveBar, m: Motion, modes: tuple[int, int], ts: Any, sigma: int) -> Any:
    """w as the reference's pole gives it: h T1(h) -> -(C × u1) σ l3 l4 w/δ'(t_s), the mean of
    h = ±10^-12 (the O(h) terms cancel, O(h²) is below 10^-13 here)."""
    with mpmath.workdps(DPS):
        h = mpmath.mpf(10) ** -12
        lk = links(rb, m, ts, modes, 3)
        C, E = lk.joints["C"], lk.joints["E"]
        rate = delta(C, lk.joints["D"], E).d(1)
        C0, E0 = [(mp(P[0].c[0]), mp(P[1].c[0])) for P in (C, E)]
        l3, l4 = mp(rb.length[2]), mp(rb.length[3])
        u = ((E0[0] - C0[0]) / l3, (E0[1] - C0[1]) / l3)
        lever = C0[0] * u[1] - C0[1] * u[0]
        up, down = _ne_near(rb, m, modes, ts, h)
        residue = (up[0] - down[0]) * h / 2
        return -residue * rate / (lever * sigma * l3 * l4)


def test_a_motion_that_violates_the_condition_has_the_residual_of_the_reference_s_pole() -> None:
    s = _instant(ROBOT, INCONSISTENT, MODES, -H, H)
    w = s.consistency_residual
    assert isinstance(w, fmpq) and w != 0 and s.conditions_met == 0
    assert s.torque_at_singularity is None and not s.consistent
    assert _close(_pole_residual(ROBOT, INCONSISTENT, MODES, Z, -1), Q(int(w.p), int(w.q)), 1e-12)


def test_at_an_irrational_instant_the_residual_is_a_ball_holding_the_reference_s() -> None:
    m = Motion((Q(1, 5), Q(1)), (Q(3, 5),))
    a = analyse(robot(ROBOT, MODES), q(ROBOT.g), *polys(m), q(Z), q(Q(1)))
    (s,) = a.instants
    assert s.t_exact is None and isinstance(s.consistency_residual, arb)
    assert not s.consistent and s.consistency_residual.rad() < 1e-30
    with mpmath.workdps(DPS):
        ts = mpmath.mpf(s.t_ball.mid().str(45, radius=False))
        w = _pole_residual(ROBOT, m, MODES, ts, s.sigma)
    assert _close(w, _arb_float(s.consistency_residual), 1e-12)


def test_order_two_with_only_the_first_condition_meets_one() -> None:
    m = motion(VT, AT, (Z, JT + 1))
    s = _instant(ROBOT, m, MODES, -H, H)
    assert s.order == 2 and s.residuals[0] == 0 and s.residuals[1] != 0
    assert s.conditions_met == 1 and s.torque_at_singularity is None
    # the reference: h T(h) settles to a nonzero residue (a pole of order 2 - 1)
    a, b = (_ne_near(ROBOT, m, MODES, Z, Q(1, 10**k))[0] for k in (8, 10))
    assert _close(a[0] * Q(1, 10**8), b[0] * Q(1, 10**10), 1e-5)
    assert abs(b[0] * Q(1, 10**10)) > 1e-2


@pytest.mark.parametrize("sigma", [1, -1])
# the second pose in the other working modes ((-1, -1) and (-1, 1)), with B on the positive
# x-axis in both line-ups (a task's base is positive)
@pytest.mark.parametrize("s", [(Q(1, 3), Q(2, 7), Q(3, 4)), (Q(-5, 2), Q(-1), Q(2, 7))])
def test_unequal_links_both_line_ups_consistent_by_the_derivation_bounded_by_the_reference(
    sigma: int, s: tuple[Q, Q, Q]
) -> None:
    """A motion made consistent by the derivation's own residual (theory.py) is
    consistent for the engine (residual exactly 0, σ as built) and its limit is
    Newton-Euler's; an acceleration off by 1/10 is not (and its residual is the pole's)."""
    rb, modes, E = _unequal(sigma, s)
    v = (Q(1), Q(1, 2))
    l3, l4 = rb.length[2], rb.length[3]

    def w(ay: Q) -> Q:
        dv = derive(rb, motion(v, (Q(1), ay), E=E), Z, modes, 3)
        return (dv.legs[0].h / l3 + dv.legs[1].h * sigma / l4).c[0]  # type: ignore[no-any-return]

    ay = solve(w)
    good = motion(v, (Q(1), ay), E=E)
    st = _instant(rb, good, modes, Q(-1, 50), Q(1, 50))
    assert st.sigma == sigma and st.residuals == (0,) and st.order == 1
    _limit_matches(st, rb, good, modes, Q(1, 10**9), 1e-6)
    bad = motion(v, (Q(1), ay + Q(1, 10)), E=E)
    sb = _instant(rb, bad, modes, Q(-1, 50), Q(1, 50))
    wb = sb.consistency_residual
    assert _close(_pole_residual(rb, bad, modes, Z, sigma), Q(int(wb.p), int(wb.q)), 1e-12)


def test_torques_on_numpy_arrays_of_times_equal_newton_euler() -> None:
    """The same formulas on float arrays (a grid of times at once)."""
    import numpy as np

    rb, modes, m = GENERIC[2]
    ts = [Q(1, 10), Q(-1, 9), Q(1, 20), Q(-1, 30)]
    cols = [_jets(m, t) for t in ts]
    E = [np.array([float(c[k]) for c in cols]) for k in range(6)]
    p = fb.params(robot(rb, modes), q(rb.g), float)
    T = fb.torques(fb.dynamics(*fb.legs(p, modes, *E, lambda D, i: np.sqrt(D)), p))
    for j, t in enumerate(ts):
        ref = torques(rb, m, t, modes)
        assert _close(T[0][j], ref[0], 1e-12) and _close(T[1][j], ref[1], 1e-12)


def test_massless_distal_links_make_an_irrational_instant_consistent_with_the_reference_limit() -> (
    None
):
    """m3 = m4 = I3 = I4 = 0: w vanishes identically (docs/five-bar.md §6), so the crossing
    at an irrational instant is consistent, exactly; the limit the engine gives there (in
    K(√D1, √D2), one ball division) is what Newton-Euler tends to on both sides."""
    rb = FiveBar(
        ROBOT.a, ROBOT.length, (Q(3), Q(2), Z, Z), (Q(1, 10), Q(1, 12), Z, Z), ROBOT.r, ROBOT.g
    )
    m = Motion((Q(1, 5), Q(1)), (Q(3, 5),))
    a = analyse(robot(rb, MODES), q(rb.g), *polys(m), q(Z), q(Q(1)))
    (s,) = a.instants
    assert s.t_exact is None and s.residuals == (0,) and s.bounded
    with mpmath.workdps(DPS):
        ts = mpmath.mpf(s.t_ball.mid().str(45, radius=False))
        for T in _ne_near(rb, m, MODES, ts, mpmath.mpf(10) ** -12):
            for i in (0, 1):
                assert _close(T[i], _arb_float(s.torque_at_singularity[i]), 1e-9)

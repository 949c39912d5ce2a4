"""The 5R's dynamics: the derivation (theory.py, docs/five-bar.md §4-5) against the
brute-force reference (reference.py: Newton-Euler of the four bodies at 60 digits).

Motions through the rational singular pose of the a = 14/13 robot (C = (0, 1),
D = (126/65, 33/65), E = (63/65, 49/65), working modes e1 = +1, e2 = -1, σ = -1) are built
with exact rationals: E(t) = E + v t + A t²/2 + J t³/6 with t_s = 0, the acceleration (and
the jerk, at order two) solved from the derived conditions; Newton-Euler then says whether
the torques stay bounded at t = ±10^-k.
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction as Q
from typing import Any

import mpmath
import pytest

from .reference import (
    DPS,
    FiveBar,
    Jet,
    Motion,
    elbows,
    energy,
    lined_up,
    links,
    mp,
    newton_euler,
    torques,
)
from .theory import Derived, derive, value

Z = Q(0)
MODES = (1, -1)
E0 = (Q(63, 65), Q(49, 65))
ROBOT = FiveBar(
    Q(14, 13), (Q(1),) * 4,
    (Q(3), Q(2), Q(1), Q(3, 2)), (Q(1, 10), Q(1, 12), Q(1, 20), Q(1, 15)),
    (Q(1, 2), Q(2, 5), Q(1, 3), Q(3, 5)), Q(981, 100),
)  # fmt: skip
UNEQUAL = FiveBar(
    Q(3), (Q(2), Q(5, 2), Q(3, 2), Q(7, 3)),
    (Q(5, 2), Q(3), Q(3, 2), Q(2)), (Q(1, 3), Q(1, 2), Q(1, 7), Q(1, 5)),
    (Q(1), Q(6, 5), Q(1, 2), Q(3, 2)), Q(981, 100),
)  # fmt: skip


def motion(v: tuple[Q, Q], A: tuple[Q, Q], J: tuple[Q, Q] = (Z, Z), E: Any = E0) -> Motion:
    return Motion((E[0], v[0], A[0] / 2, J[0] / 6), (E[1], v[1], A[1] / 2, J[1] / 6))


def solve(f: Callable[[Q], Q]) -> Q:
    """The root of an affine function of one rational."""
    f0, f1 = f(Z), f(Q(1))
    return -f0 / (f1 - f0)


def w_at(m: Motion, k: int, rb: FiveBar = ROBOT, sigma: int = -1) -> Q:
    """The k-th derivative at t_s = 0 of the reciprocity residual h1/l3 + σ h2/l4."""
    dv = derive(rb, m, Z, MODES, 3 + k)
    out = dv.w(sigma)
    assert isinstance(out, Jet)
    return out.d(k)  # type: ignore[no-any-return]


def series(m: Motion, n: int, rb: FiveBar = ROBOT) -> Derived:
    return derive(rb, m, Z, MODES, n)


def ne(m: Motion, t: Q, rb: FiveBar = ROBOT) -> tuple[Any, Any]:
    return torques(rb, m, t, MODES)


def close(a: Any, b: Any, rel: float) -> bool:
    """|a - b| <= rel (1 + |b|), at the reference's precision."""
    with mpmath.workdps(DPS):
        a, b = (mpmath.mpf(v.numerator) / v.denominator if isinstance(v, Q) else v for v in (a, b))
        return bool(abs(a - b) <= rel * (1 + abs(b)))


# -- away from singularities: the derivation is Newton-Euler ---------------------------------
GENERIC = [
    (ROBOT, MODES, motion((Q(1), Q(1, 2)), (Q(2, 3), Q(2, 5)), (Q(-3), Q(6, 7)))),
    (ROBOT, (1, 1), motion((Q(-1, 2), Q(1, 3)), (Q(1), Q(-1)), (Q(1), Q(2)))),
    (UNEQUAL, (1, -1), motion((Q(1), Q(-1)), (Q(2), Q(1)), (Q(-1), Q(3)), E=(Q(3, 2), Q(3)))),
    (UNEQUAL, (-1, 1), motion((Q(1, 2), Q(1)), (Q(-2), Q(1)), (Q(1), Q(1)), E=(Q(3, 2), Q(3)))),
    (UNEQUAL, (-1, -1), motion((Q(0), Q(1)), (Q(1), Q(0)), (Q(0), Q(0)), E=(Q(3, 2), Q(3)))),
]


@pytest.mark.parametrize(("rb", "modes", "m"), GENERIC)
@pytest.mark.parametrize("t", [Q(1, 10), Q(-1, 9)])
def test_derived_torques_and_rates_equal_newton_euler_away_from_singularities(
    rb: FiveBar, modes: tuple[int, int], m: Motion, t: Q
) -> None:
    lk = links(rb, m, t, modes, 3)
    ref = newton_euler(rb, lk)
    dv = derive(rb, m, t, modes, 3)
    assert not close(value(dv.delta), 0, 1e-3)
    T = dv.torques()
    assert close(value(T[0]), ref["T1"], 1e-45)
    assert close(value(T[1]), ref["T2"], 1e-45)
    # the joint rates: θ' = (E - C)·E'/(C × E), φ' = -C·E'/(C × E) (leg 2 from B)
    for i, lg in enumerate(dv.legs):
        assert close(value(lg.w), value(lk.omega[i]), 1e-50)
        assert close(value(lg.W), value(lk.omega[i + 2]), 1e-50)
        assert close(value(lg.wd), lk.omega[i].d(1), 1e-50)
        assert close(value(lg.Wd), lk.omega[i + 2].d(1), 1e-50)
    # the multiplier λ is the pin force of link 4 on link 3 at E (Newton-Euler's F_E)
    l3 = rb.length[2]
    FE = ref["FE"]
    with mpmath.workdps(DPS):
        E, C = [(mp(value(p[0])), mp(value(p[1]))) for p in (dv.E, dv.C)]
        u = ((E[0] - C[0]) / l3, (E[1] - C[1]) / l3)
        axial = FE[0] * u[0] + FE[1] * u[1]
        transverse = u[0] * FE[1] - u[1] * FE[0]
        assert close(axial, value(dv.nu) / value(dv.delta), 1e-45)
        assert close(transverse, value(dv.legs[0].h) / l3, 1e-45)


@pytest.mark.parametrize(("rb", "modes", "m"), GENERIC)
def test_power_balance_of_the_newton_euler_torques(
    rb: FiveBar, modes: tuple[int, int], m: Motion
) -> None:
    """T1 θ1' + T2 θ2' = d(kinetic + potential energy)/dt."""
    for t in (Q(1, 10), Q(-1, 9)):
        lk = links(rb, m, t, modes, 4)
        ref = newton_euler(rb, lk)
        with mpmath.workdps(DPS):
            power = ref["T1"] * value(lk.omega[0]) + ref["T2"] * value(lk.omega[1])
            assert close(power, energy(rb, lk).d(1), 1e-45)
            assert abs(power) > 1  # a real test: the motion does work


def test_the_generic_motions_stay_in_their_working_modes() -> None:
    for rb, modes, m in GENERIC:
        for t in (Q(-1, 9), Q(0), Q(1, 10)):
            x, y = m.at(t, 1)
            C, D = elbows(rb, (x.c[0], y.c[0]), modes)
            assert all(isinstance(c, Q | mpmath.mpf) for c in (*C, *D))


# -- through the singular pose -----------------------------------------------------------------
V = (Q(1), Q(1, 2))  # a transversal velocity: δ' = 2249/1071
AY = solve(lambda s: w_at(motion(V, (Z, s)), 0))
CONSISTENT = motion(V, (Z, AY))
INCONSISTENT = motion(V, (Z, AY + Q(1, 10)))


def _scaled(m: Motion, h: Q, power: int) -> tuple[Any, Any]:
    """h^power·T at t = h by Newton-Euler."""
    T = ne(m, h)
    with mpmath.workdps(DPS):
        return T[0] * h**power, T[1] * h**power


def test_the_consistent_acceleration_is_rational_and_the_crossing_transversal() -> None:
    assert Q(-1205665402623859, 82769172571890) == AY
    dv = series(CONSISTENT, 5)
    assert dv.delta.c[0] == 0 and dv.delta.c[1] == Q(2249, 1071)
    assert dv.cos.c[0] == -1  # σ = -1: E between the elbows
    assert dv.w(-1).c[0] == 0 and dv.nu.c[0] == 0


@pytest.mark.parametrize("side", [1, -1])
def test_consistent_crossing_has_bounded_torques_tending_to_the_derived_limit(side: int) -> None:
    limit = series(CONSISTENT, 5).limit(1)  # ν'/δ' (l'Hôpital)
    for k in (4, 6, 8):
        h = Q(side, 10**k)
        T = ne(CONSISTENT, h)
        for i in (0, 1):  # T(h) = T(0) + O(h)
            assert close(T[i], value(limit[i]), 200 * abs(float(h)))
    # at this rational pose the limit is rational
    assert value(limit[0]) == Q(1067610682465843304181031, 221515964245874925900000)
    assert value(limit[1]) == Q(-516181859311537391601059, 304910209609027839180000)


@pytest.mark.parametrize("side", [1, -1])
def test_inconsistent_crossing_diverges_like_one_over_t_with_the_derived_residue(
    side: int,
) -> None:
    """h·T(h) tends to the residue -C⊥·u1 ν(0)/δ'(0) (T1) and (D - B)⊥·u1 ν(0)/δ'(0) (T2)."""
    dv = series(INCONSISTENT, 4)
    C, D, E = [(value(p[0]), value(p[1])) for p in (dv.C, dv.D, dv.E)]  # exact here
    u = (E[0] - C[0], E[1] - C[1])  # l3 = 1
    alpha = dv.nu.c[0] / dv.delta.c[1]
    residue = (
        -(C[0] * u[1] - C[1] * u[0]) * alpha,
        ((D[0] - ROBOT.a) * u[1] - D[1] * u[0]) * alpha,
    )
    assert residue[0] != 0 and residue[1] != 0
    for k in (5, 8):
        got = _scaled(INCONSISTENT, Q(side, 10**k), 1)
        for i in (0, 1):
            assert close(got[i], residue[i], 10 * 10.0**-k)
    T = ne(INCONSISTENT, Q(side, 10**8))
    assert abs(T[0]) > 10**6  # the torques blow up


def test_bounded_if_and_only_if_the_condition_holds() -> None:
    """Along a family E'' = (0, AY + ε), only ε = 0 keeps h·T(h) → 0."""
    for eps in (Z, Q(1, 1000), Q(-1, 7), Q(3)):
        m = motion(V, (Z, AY + eps))
        small = _scaled(m, Q(1, 10**9), 1)
        bounded = abs(small[0]) < 1e-7 and abs(small[1]) < 1e-7
        assert bounded == (eps == 0)


# -- order two: a tangential crossing and a stop on the curve ---------------------------------
def _gradient() -> tuple[Q, Q]:
    return (
        series(motion((Q(1), Z), (Z, Z)), 3).delta.c[1],
        series(motion((Z, Q(1)), (Z, Z)), 3).delta.c[1],
    )


G = _gradient()
VT = (-G[1], G[0])  # along the curve's tangent: δ' = 0
AT = (Z, solve(lambda s: w_at(motion(VT, (Z, s)), 0)))
JT = solve(lambda s: w_at(motion(VT, AT, (Z, s)), 1))
TANGENT = motion(VT, AT, (Z, JT))


def test_a_tangential_crossing_is_of_order_two_and_the_frozen_sigma_lemma_holds() -> None:
    dv = series(TANGENT, 7)
    assert dv.delta.c[0] == 0 and dv.delta.c[1] == 0 and dv.delta.c[2] != 0
    w = dv.w(-1)
    assert w.c[0] == 0 and w.c[1] == 0 and w.c[2] != 0
    # ν = σ l3 l4 w + (cos - σ) l4 h1, cos - σ vanishes to order 2k = 4: ν^(j) = σ l3 l4 w^(j)
    assert dv.cos.c[1] == dv.cos.c[2] == dv.cos.c[3] == 0 and dv.cos.c[4] != 0
    assert [dv.nu.c[j] for j in range(4)] == [-w.c[j] for j in range(4)]


@pytest.mark.parametrize(
    ("jerk", "power"),
    [(JT, 0), (JT + 1, 1)],
    ids=["both conditions: bounded", "first only: 1/t"],
)
def test_order_two_needs_the_derivative_condition_too(jerk: Q, power: int) -> None:
    m = motion(VT, AT, (Z, jerk))
    values = [_scaled(m, Q(s, 10**k), power) for s in (1, -1) for k in (8, 10)]
    for i in (0, 1):
        # h^power·T settles to one nonzero value from each side (a limit, or the residue)
        assert close(values[0][i], values[1][i], 1e-5)
        assert close(values[2][i], values[3][i], 1e-5)
        assert abs(values[1][i]) > 1e-2
    if power == 0:  # the limit l'Hôpital gives: ν''/δ''
        limit = series(m, 6).limit(2)
        assert close(values[1][0], value(limit[0]), 1e-6)
        assert close(values[1][1], value(limit[1]), 1e-6)


def test_order_two_violating_the_first_condition_diverges_like_one_over_t_squared() -> None:
    m = motion(VT, (Z, AT[1] + 1), (Z, JT))
    a, b = _scaled(m, Q(1, 10**8), 2), _scaled(m, Q(1, 10**10), 2)
    assert close(a[0], b[0], 1e-5) and abs(b[0]) > 1e-3


STOP_A = (Q(1), solve(lambda s: w_at(motion((Z, Z), (Q(1), s)), 0)))
STOP_J = solve(lambda s: w_at(motion((Z, Z), STOP_A, (Z, s)), 1))


@pytest.mark.parametrize(("jerk", "power"), [(STOP_J, 0), (STOP_J - 2, 1)])
def test_a_stop_on_the_curve_is_of_order_two_with_two_conditions(jerk: Q, power: int) -> None:
    m = motion((Z, Z), STOP_A, (Z, jerk))
    dv = series(m, 5)
    assert dv.delta.c[1] == 0 and dv.delta.c[2] != 0
    a, b = _scaled(m, Q(1, 10**8), power), _scaled(m, Q(1, 10**10), power)
    assert close(a[0], b[0], 1e-4) and close(a[1], b[1], 1e-4) and abs(b[0]) > 1e-2


# -- special robots -------------------------------------------------------------------------
def test_with_massless_distal_links_every_crossing_is_consistent() -> None:
    rb = FiveBar(
        ROBOT.a, ROBOT.length, (Q(3), Q(2), Z, Z), (Q(1, 10), Q(1, 12), Z, Z), ROBOT.r, ROBOT.g
    )
    m = motion(V, (Q(5), Q(-7)), (Q(1), Q(2)))
    assert w_at(m, 0, rb) == 0
    T = ne(m, Q(1, 10**8), rb)
    assert abs(T[0]) < 100 and abs(T[1]) < 100


def test_a_point_mass_at_E_is_consistent_iff_its_acceleration_plus_gravity_is_along_the_links() -> (
    None
):
    """Only link 3 has mass, all of it at E (r3 = l3, I3 = 0): h1/l3 = m u1 × (E'' + g ĵ)."""
    rb = FiveBar(ROBOT.a, ROBOT.length, (Z, Z, Q(2), Z), (Z,) * 4, (Z, Z, Q(1), Z), ROBOT.g)
    A = (Q(1), solve(lambda s: w_at(motion(V, (Q(1), s)), 0, rb)))
    C = (Z, Q(1))
    u = (E0[0] - C[0], E0[1] - C[1])
    assert u[0] * (A[1] + rb.g) - u[1] * A[0] == 0
    T = ne(motion(V, A), Q(1, 10**8), rb)
    assert abs(T[0]) < 100 and abs(T[1]) < 100


# -- unequal links, both line-ups: the weights 1/l3, 1/l4 and the sign σ are the right ones ----
def _unequal(sigma: int, s: tuple[Q, Q, Q]) -> tuple[FiveBar, tuple[int, int], tuple[Q, Q]]:
    a, l2, _, _, E, modes = lined_up(sigma, s, Q(1), Q(3, 2), Q(5, 4))
    rb = FiveBar(
        a, (Q(1), l2, Q(3, 2), Q(5, 4)),
        (Q(3), Q(2), Q(3, 2), Q(5, 4)), (Q(1, 10), Q(1, 12), Q(1, 6), Q(1, 9)),
        (Q(1, 2), Q(2, 5), Q(2, 3), Q(1, 2)), Q(981, 100),
    )  # fmt: skip
    return rb, modes, E


@pytest.mark.parametrize("sigma", [1, -1])
@pytest.mark.parametrize("s", [(Q(1, 3), Q(2, 7), Q(3, 4)), (Q(-1, 2), Q(5, 3), Q(1, 5))])
def test_only_the_condition_with_weights_one_over_l_and_sign_sigma_bounds_the_torques(
    sigma: int, s: tuple[Q, Q, Q]
) -> None:
    rb, modes, E = _unequal(sigma, s)
    v = (Q(1), Q(1, 2))

    def residual(A: tuple[Q, Q], form: Callable[[Any, Any], Any]) -> Q:
        dv = derive(rb, motion(v, A, E=E), Z, modes, 3)
        assert dv.delta.c[0] == 0 and dv.delta.c[1] != 0  # a transversal crossing
        assert dv.cos.c[0] == sigma
        return form(dv.legs[0].h, dv.legs[1].h).c[0]  # type: ignore[no-any-return]

    l3, l4 = rb.length[2], rb.length[3]
    forms = {
        "h1/l3 + σ h2/l4": lambda h1, h2: h1 / l3 + h2 * sigma / l4,
        "h1/l3 - σ h2/l4": lambda h1, h2: h1 / l3 - h2 * sigma / l4,
        "h1 + σ h2": lambda h1, h2: h1 + h2 * sigma,
    }
    for name, form in forms.items():
        A = (Q(1), solve(lambda q, f=form: residual((Q(1), q), f)))  # type: ignore[misc]
        m = motion(v, A, E=E)
        near, nearer = torques(rb, m, Q(1, 10**7), modes), torques(rb, m, Q(1, 10**9), modes)
        growth = [abs(nearer[i] / near[i]) for i in (0, 1)]  # ~1 bounded, ~100 like 1/t
        if name == "h1/l3 + σ h2/l4":
            assert max(growth) < 1.01, name
        else:
            assert min(growth) > 99, name


@pytest.mark.parametrize(("m", "k"), [(CONSISTENT, 1), (TANGENT, 2)], ids=["order 1", "order 2"])
def test_the_axial_force_at_the_instant_is_w_k_over_the_distal_angle_k(m: Motion, k: int) -> None:
    """λ·u1 → ν^(k)/δ^(k) = w^(k)(t_s)/(φ2 - φ1)^(k)(t_s) (δ = σ l3 l4 sin ψ, ψ → 0)."""
    dv = series(m, 3 + k + 1)
    gap = dv.legs[1].W - dv.legs[0].W  # (φ2 - φ1)'
    assert dv.nu.c[k] / dv.delta.c[k] == dv.w(-1).d(k) / gap.d(k - 1)


def test_at_a_stop_the_second_condition_is_the_first_ones_form_on_the_jerk() -> None:
    """At E' = 0: w' = κ·E''' (κ the coefficient of E'' in w): the jerk (0, 0) satisfies it."""
    assert STOP_J == 0
    kappa = [w_at(motion((Z, Z), (Z, Z), J), 1) for J in ((Q(1), Z), (Z, Q(1)))]
    assert kappa == [w_at(motion((Z, Z), A), 0) - w_at(motion((Z, Z), (Z, Z)), 0)
                     for A in ((Q(1), Z), (Z, Q(1)))]  # fmt: skip


def test_the_coefficient_of_the_acceleration_in_the_condition_is_kappa() -> None:
    """w = κ·E'' + w0 with κ = [-(I3 + m3 r3²) C + (m3 r3/l3)(C·(E - C))(E - C)]/(l3 k1)
    + σ [-(I4 + m4 r4²)(D - B) + (m4 r4/l4)((D - B)·(E - D))(E - D)]/(l4 k2)."""
    C, D, E, B = (Z, Q(1)), (Q(126, 65), Q(33, 65)), E0, (ROBOT.a, Z)
    m, inertia, r, length, sigma = ROBOT.mass, ROBOT.inertia, ROBOT.r, ROBOT.length, -1

    def part(i: int, c: tuple[Q, Q], e: tuple[Q, Q], base: tuple[Q, Q]) -> tuple[Q, Q]:
        p = (c[0] - base[0], c[1] - base[1])  # the proximal vector
        u = (e[0] - c[0], e[1] - c[1])  # the distal vector
        k = p[0] * (e[1] - base[1]) - p[1] * (e[0] - base[0])
        j = i + 2
        big, small = inertia[j] + m[j] * r[j] ** 2, m[j] * r[j] / length[j]
        dot_ = p[0] * u[0] + p[1] * u[1]
        return tuple((-big * p[n] + small * dot_ * u[n]) / (length[j] * k) for n in (0, 1))  # type: ignore[return-value]

    k1, k2 = part(0, C, E, (Z, Z)), part(1, D, E, B)
    kappa = (k1[0] + sigma * k2[0], k1[1] + sigma * k2[1])
    v = (Q(1), Q(1, 2))
    base = w_at(motion(v, (Z, Z)), 0)
    assert [w_at(motion(v, A), 0) - base for A in ((Q(1), Z), (Z, Q(1)))] == list(kappa)


# -- order three: tangent with the curve's curvature (an inflection-like crossing) ------------
def motion4(A: tuple[Q, Q], J: tuple[Q, Q], K: tuple[Q, Q]) -> Motion:
    return Motion(
        (E0[0], VT[0], A[0] / 2, J[0] / 6, K[0] / 24), (E0[1], VT[1], A[1] / 2, J[1] / 6, K[1] / 24)
    )


def _order_three_acceleration() -> tuple[Q, Q]:
    """E'' with δ''(0) = 0 (order ≥ 3 along the tangent) and w(0) = 0: two affine equations."""

    def both(A: tuple[Q, Q]) -> tuple[Q, Q]:
        dv = series(motion4(A, (Z, Z), (Z, Z)), 5)
        return dv.delta.d(2), dv.w(-1).d(0)

    f0, fx, fy = both((Z, Z)), both((Q(1), Z)), both((Z, Q(1)))
    a11, a12, a21, a22 = fx[0] - f0[0], fy[0] - f0[0], fx[1] - f0[1], fy[1] - f0[1]
    det = a11 * a22 - a12 * a21
    return ((a12 * f0[1] - a22 * f0[0]) / det, (a21 * f0[0] - a11 * f0[1]) / det)


A3 = _order_three_acceleration()
J3 = (Z, solve(lambda s: series(motion4(A3, (Z, s), (Z, Z)), 6).w(-1).d(1)))
K3 = (Z, solve(lambda s: series(motion4(A3, J3, (Z, s)), 7).w(-1).d(2)))


@pytest.mark.parametrize(("snap", "power"), [(K3[1], 0), (K3[1] + 1, 1)], ids=["C1-C3", "C1-C2"])
def test_order_three_needs_three_conditions(snap: Q, power: int) -> None:
    m = motion4(A3, J3, (Z, snap))
    dv = series(m, 8)
    assert dv.delta.c[:3] == [0, 0, 0] and dv.delta.c[3] != 0  # order 3: a crossing
    assert dv.w(-1).c[:2] == [0, 0]
    values = [_scaled(m, Q(s, 10**k), power) for s in (1, -1) for k in (8, 10)]
    for i in (0, 1):
        assert close(values[1][i], values[3][i], 1e-7)  # settled from both sides
        assert abs(values[3][i]) > 1e-3
    if power == 0:
        limit = dv.limit(3)
        assert close(values[1][0], value(limit[0]), 1e-7)
        assert close(values[1][1], value(limit[1]), 1e-7)

"""The reference's Type II instants (instants.py): which roots of S_σ(E(t)) are the
robot's, and their order, read from the multiplicity and from δ's own series."""

from __future__ import annotations

from fractions import Fraction as Q

import mpmath
import sympy as sp

from .instants import singular_instants
from .reference import FiveBar, Motion
from .test_dynamics import (
    A3,
    CONSISTENT,
    J3,
    K3,
    MODES,
    ROBOT,
    STOP_A,
    STOP_J,
    TANGENT,
    motion,
    motion4,
)

Z = Q(0)
HALF = Q(1, 2)


def _at_zero(rb: FiveBar, m: Motion, modes: tuple[int, int]):  # type: ignore[no-untyped-def]
    found = [i for i in singular_instants(rb, m, modes, -HALF, HALF) if i.t == 0]
    return found[0] if found else None


def test_transversal_tangent_stop_and_order_three_through_the_rational_pose() -> None:
    cases = [
        (CONSISTENT, 1),
        (TANGENT, 2),
        (motion((Z, Z), STOP_A, (Z, STOP_J)), 2),
        (motion4(A3, J3, K3), 3),
    ]
    for m, order in cases:
        i = _at_zero(ROBOT, m, MODES)
        assert i is not None
        assert (i.sigma, i.multiplicity, i.order) == (-1, order, order)
        assert min(i.others) > 1e-3  # the other modes are far from singular there


def test_a_root_on_another_modes_arc_is_not_an_instant() -> None:
    for modes in ((1, 1), (-1, 1), (-1, -1)):
        assert _at_zero(ROBOT, CONSISTENT, modes) is None
    # the root t = 0 of S₋(E(t)) is there all the same
    assert _at_zero(ROBOT, CONSISTENT, MODES) is not None


def test_irrational_instants_of_a_straight_move() -> None:
    """E(t) = (1/5 + t, 3/5), t in [0, 1], in modes (+1, -1): every instant is simple, its
    multiplicity equals its order, and δ changes sign across it."""
    m = Motion((Q(1, 5), Q(1)), (Q(3, 5),))
    found = singular_instants(ROBOT, m, MODES, Z, Q(1))
    assert found
    for i in found:
        assert not i.t.is_Rational
        assert i.multiplicity == i.order == 1
    from .theory import derive

    with mpmath.workdps(80):
        for i in found:
            ts = mpmath.mpf(str(sp.N(i.t, 80)))
            near = [ts + s * mpmath.mpf(10) ** -20 for s in (-1, 1)]
            side = [derive(ROBOT, m, t, MODES, 3).delta.c[0] for t in near]
            assert side[0] * side[1] < 0


def test_at_the_node_the_multiplicity_counts_two_modes_and_the_order_is_one() -> None:
    m = Motion((Q(7, 13), Q(1)), (Z, Q(1)))
    for modes in ((1, 1), (-1, -1)):
        i = _at_zero(ROBOT, m, modes)
        assert i is not None
        assert (i.sigma, i.multiplicity, i.order) == (-1, 2, 1)
        assert min(i.others) < 1e-40  # the mirror mode is singular too

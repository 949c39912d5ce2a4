"""The 5R's Type II locus: the four-mode norm, its factors and what each factor means.

References: sympy (locus.py) for the polynomials, the exact elbows of reference.py
(Fractions) for the poses."""

from __future__ import annotations

import json
from fractions import Fraction as Q
from functools import cache
from pathlib import Path
from typing import Any

import pytest
import sympy as sp

from .locus import curve, norm, product, x, y
from .reference import FiveBar, Jet, Motion, delta, elbows, lined_up
from .theory import derive

R1 = x**2 + y**2


def _R2(a: object) -> object:
    return (x - a) ** 2 + y**2


def test_the_norm_is_a_sixteenth_of_R1_squared_R2_squared_S_plus_S_minus_for_every_robot() -> None:
    gens = sp.symbols("a l1 l2 l3 l4")
    a, l1, l2, l3, l4 = gens
    F = norm(a, l1, l2, l3, l4, *gens)
    rhs = [R1**2, _R2(a) ** 2, curve(1, *gens), curve(-1, *gens)]
    assert (16 * F - product(rhs, *gens)).is_zero


ROBOTS = [
    (sp.Rational(14, 13), 1, 1, 1, 1),
    (3, 2, sp.Rational(5, 2), sp.Rational(3, 2), sp.Rational(7, 3)),
]


@pytest.mark.parametrize("robot", ROBOTS)
def test_the_norm_factors_into_the_base_circles_and_the_two_line_up_curves(robot) -> None:  # type: ignore[no-untyped-def]
    F = norm(*robot)
    a = robot[0]
    rhs = product([R1**2, _R2(a) ** 2, curve(1, *robot), curve(-1, *robot)])
    assert rhs == 16 * F


def test_equal_links_norm_is_base_circles_squared_times_a_quartic_and_a_sextic() -> None:
    F = norm(1, 1, 1, 1, 1)
    assert F.total_degree() == 18
    q4 = x**4 - 2 * x**3 + 2 * x**2 * y**2 + x**2 - 2 * x * y**2 + y**4 - 3 * y**2
    s6 = curve(-1, 1, 1, 1, 1, 1)
    assert sp.expand(curve(1, 1, 1, 1, 1, 1) - q4) == 0
    assert product([R1**2, _R2(1) ** 2, q4, s6]) == 16 * F
    for f in (q4, s6):  # irreducible over Q
        assert len(sp.factor_list(f, x, y)[1]) == 1
    # S₊ is the two circles of radius l3 about the elbows' common points (1/2, ±√3/2)
    circles = sp.factor_list(q4, extension=sp.sqrt(3))[1]
    assert sorted((sp.expand(f) for f, _ in circles), key=str) == sorted(
        [x**2 - x + y**2 - sp.sqrt(3) * y, x**2 - x + y**2 + sp.sqrt(3) * y], key=str
    )
    assert sp.Poly(curve(-1, 1, 1, 1, 1, 1), x, y).total_degree() == 6


def test_unequal_links_give_two_irreducible_sextics() -> None:
    robot = (3, 2, sp.Rational(5, 2), sp.Rational(3, 2), sp.Rational(7, 3))
    for sigma in (1, -1):
        S = curve(sigma, *robot)
        factors = sp.factor_list(S, x, y)[1]
        assert len(factors) == 1
        assert sp.Poly(S, x, y).total_degree() == 6
    # the degree drops to 4 exactly when σ = +1 and l3 = l4 (the leading form is
    # (l4 - σ l3)² |E|⁶)
    assert (
        sp.Poly(curve(1, 2, 1, 1, sp.Rational(3, 2), sp.Rational(3, 2)), x, y).total_degree() == 4
    )


ROBOT_14 = FiveBar(Q(14, 13), (Q(1),) * 4, (Q(1),) * 4, (Q(1),) * 4, (Q(1, 2),) * 4, Q(0))
E_14 = (Q(63, 65), Q(49, 65))


def test_the_rational_singular_pose_of_the_a_14_13_robot() -> None:
    C, D = elbows(ROBOT_14, E_14, (1, -1))
    assert ((Q(0), Q(1)), (Q(126, 65), Q(33, 65))) == (C, D)
    assert delta(C, D, E_14) == 0
    a = sp.Rational(14, 13)
    at = {x: sp.Rational(63, 65), y: sp.Rational(49, 65)}
    assert curve(-1, a, 1, 1, 1, 1).subs(at) == 0  # E between the elbows: σ = -1
    assert curve(1, a, 1, 1, 1, 1).subs(at) != 0
    # the mode is decided by the conjugates: only (e1, e2) = (+1, -1) is singular there
    for modes in ((1, 1), (-1, 1), (-1, -1)):
        C, D = elbows(ROBOT_14, E_14, modes)
        assert delta(C, D, E_14) != 0


@pytest.mark.parametrize("sigma", [1, -1])
@pytest.mark.parametrize("s", [(Q(1, 3), Q(2, 7), Q(3, 4)), (Q(-1, 2), Q(5, 3), Q(1, 5))])
def test_every_lined_up_pose_lies_on_its_curve_and_its_mode_is_the_singular_one(sigma, s) -> None:  # type: ignore[no-untyped-def]
    """Singular poses built from the geometry (C on its circle, the distal links along u,
    E - D = σ l4 u), on robots whose lengths make them rational."""
    l1, l3, l4 = Q(1), Q(3, 2), Q(5, 4)
    a, l2, C, D, E, modes = lined_up(sigma, s, l1, l3, l4)
    assert (D[0] - a) ** 2 + D[1] ** 2 == l2 * l2 and l2 > 0
    at = {x: sp.Rational(E[0].numerator, E[0].denominator),
          y: sp.Rational(E[1].numerator, E[1].denominator)}  # fmt: skip
    params = [sp.Rational(p.numerator, p.denominator) for p in (a, l1, l2, l3, l4)]
    assert curve(sigma, *params).subs(at) == 0
    assert curve(-sigma, *params).subs(at) != 0
    rb = FiveBar(a, (l1, l2, l3, l4), (Q(1),) * 4, (Q(1),) * 4, (Q(1, 2),) * 4, Q(0))
    assert elbows(rb, E, modes) == (C, D)
    assert delta(C, D, E) == 0
    others = [m for m in ((1, 1), (1, -1), (-1, 1), (-1, -1)) if m != modes]
    assert all(delta(*elbows(rb, E, m), E) != 0 for m in others)


def test_transversality_is_the_gradient_of_the_curve_times_the_velocity() -> None:
    """δ' = ∇δ_e·E' at the pose, and ∇δ_e is parallel to ∇S₋ (nonzero): the crossing is of
    order one iff ∇S₋·E' ≠ 0; a velocity along the tangent gives δ' = 0."""
    a = sp.Rational(14, 13)
    S = curve(-1, a, 1, 1, 1, 1)
    at = {x: sp.Rational(63, 65), y: sp.Rational(49, 65)}
    grad = (sp.diff(S, x).subs(at), sp.diff(S, y).subs(at))
    assert grad != (0, 0)

    def ddelta(v: tuple[Q, Q]) -> Q:
        m = Motion((E_14[0], v[0]), (E_14[1], v[1]))
        dv = derive(ROBOT_14, m, Q(0), (1, -1), 3)
        assert isinstance(dv.delta, Jet)
        return dv.delta.c[1]  # type: ignore[no-any-return]

    g = (ddelta((Q(1), Q(0))), ddelta((Q(0), Q(1))))
    assert g == (Q(104, 85), Q(9386, 5355))
    assert g[0] * grad[1] - g[1] * grad[0] == 0  # parallel
    tangent = (-g[1], g[0])
    assert ddelta(tangent) == 0
    assert ddelta((Q(1), Q(1, 2))) == Q(2249, 1071)


def test_the_equal_link_line_up_curve_has_a_node_where_two_modes_are_singular_at_once() -> None:
    """E = (a/2, 0) on S₋ of the a = 14/13 unit-link robot: ∇S₋ = 0, and the mirror modes
    (+1, +1) and (-1, -1) are both singular there, so the multiplicity of S₋(E(t)) counts
    both arcs and the order of one mode must be read from its own δ."""
    import mpmath

    a = sp.Rational(14, 13)
    S = curve(-1, a, 1, 1, 1, 1)
    at = {x: a / 2, y: 0}
    assert S.subs(at) == 0 and sp.diff(S, x).subs(at) == 0 and sp.diff(S, y).subs(at) == 0
    E = (Q(7, 13), Q(0))
    with mpmath.workdps(60):
        Em = (mpmath.mpf(7) / 13, mpmath.mpf(0))
        small = [abs(delta(*elbows(ROBOT_14, E, m), Em)) for m in ((1, 1), (-1, -1))]
        large = [abs(delta(*elbows(ROBOT_14, E, m), Em)) for m in ((1, -1), (-1, 1))]
    assert max(small) < 1e-50 and min(large) > 0.1
    # a transversal path through the node: S₋(E(t)) has a double root, each δ a simple one
    m = Motion((E[0], Q(1)), (E[1], Q(1)))
    t = sp.Symbol("t")
    St = sp.Poly(S.subs({x: a / 2 + t, y: t}), t)
    assert St.eval(0) == 0 and St.diff(t).eval(0) == 0 and St.diff(t).diff(t).eval(0) != 0
    for modes in ((1, 1), (-1, -1)):
        dv = derive(ROBOT_14, m, Q(0), modes, 3)
        assert abs(dv.delta.c[0]) < 1e-50 and abs(dv.delta.c[1]) > 0.1


ARCS = [
    ((1, 1, 1, 1, 1), (3, 3)),
    ((3, 2, sp.Rational(5, 2), sp.Rational(3, 2), sp.Rational(7, 3)), (4, 4)),
]


def _positive_roots(py: sp.Poly) -> list[str]:
    """The positive real roots of py (a polynomial in y) to 40 digits, as sympy prints
    them: ``nroots`` (mpmath's polyroots, hundreds of steps at 40 digits)."""
    return [str(r) for r in py.nroots(n=40, maxsteps=500) if r.is_real and r > 0]


# The positive roots of S_σ on the vertical lines of the arcs test (sympy's ``nroots``:
# ~0.6 CPU-s for all) are stored beside this file by their polynomial: they never change.
# Written by ``python -m tests.fivebar.test_locus``; a slow test recomputes every stored
# case, and a polynomial not stored (a new one, or one whose curve changed) is solved here.
ROOTS = Path(__file__).with_name("line_up_roots_reference.json")


@cache
def _stored_roots() -> dict[str, list[str]]:
    return json.loads(ROOTS.read_text(encoding="utf-8")) if ROOTS.exists() else {}


def _vertical_lines(robot: tuple[Any, ...], sigma: int) -> list[tuple[sp.Rational, sp.Poly]]:
    """(x, S_σ(x, y)) on the lines x = i/4, i = -10 … 19, where it has a degree in y."""
    S = sp.Poly(curve(sigma, *robot), x, y)
    out = []
    for i in range(-10, 20):
        xv = sp.Rational(i, 4)
        py = sp.Poly(S.eval(x, xv), y)
        if py.degree() > 0:
            out.append((xv, py))
    return out


def _roots_key(py: sp.Poly) -> str:
    return str(py.as_expr())


def positive_roots(py: sp.Poly) -> list[str]:
    """``_positive_roots``: stored, or computed when not."""
    rows = _stored_roots().get(_roots_key(py))
    return _positive_roots(py) if rows is None else rows


def _all_root_cases() -> dict[str, sp.Poly]:
    return {
        _roots_key(py): py
        for robot, _ in ARCS
        for sigma in (1, -1)
        for _, py in _vertical_lines(robot, sigma)
    }


@pytest.mark.parametrize(("robot", "owners"), ARCS)
def test_each_line_up_curve_is_made_of_arcs_of_several_working_modes(robot, owners) -> None:  # type: ignore[no-untyped-def]
    """Points of S_σ (y > 0) on vertical lines: exactly one mode is singular at each (apart
    from Type I points, where a leg's two modes meet), and the modes met are 3 or 4."""
    import mpmath

    rb = FiveBar(*(Q(str(p)) for p in robot[:1]), tuple(Q(str(p)) for p in robot[1:]),  # type: ignore[arg-type]
                 (Q(1),) * 4, (Q(1),) * 4, (Q(1, 2),) * 4, Q(0))  # fmt: skip
    modes = ((1, 1), (1, -1), (-1, 1), (-1, -1))
    for sigma, expected in zip((1, -1), owners, strict=True):
        seen = set()
        for xv, py in _vertical_lines(robot, sigma):
            for r in positive_roots(py):
                with mpmath.workdps(60):
                    E = (mpmath.mpf(xv.p) / xv.q, mpmath.mpf(r))
                    sizes = []
                    for m in modes:
                        try:
                            C, D = elbows(rb, E, m)
                        except ValueError:
                            sizes.append(mpmath.inf)
                            continue
                        sizes.append(abs(delta(C, D, E)))
                if all(d == mpmath.inf for d in sizes):
                    continue  # on a reach circle, rounded out of it (a Type I point)
                zero = [m for m, d in zip(modes, sizes, strict=True) if d < 1e-15]  # √ near Type I
                assert len(zero) >= 1, (sigma, xv, r, [mpmath.nstr(d, 5) for d in sizes])
                if len(zero) == 1:
                    seen.add(zero[0])
        assert len(seen) == expected


@pytest.mark.slow  # sympy's nroots at 40 digits on every vertical line of both robots
def test_the_stored_roots_are_the_references() -> None:
    cases = _all_root_cases()
    assert set(cases) == set(_stored_roots())  # every stored case is live
    for key, py in cases.items():
        assert _positive_roots(py) == _stored_roots()[key], key


def _write_roots() -> None:
    table = {key: _positive_roots(py) for key, py in _all_root_cases().items()}
    ROOTS.write_text(json.dumps(table, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    _write_roots()

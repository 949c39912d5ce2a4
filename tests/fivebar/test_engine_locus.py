"""The 5R engine's locus (``rprpr.engine.exact.five_bar``) against the sympy derivation
(locus.py): S₊, S₋, the radical-free parts of δ, the Type I factors and the gradient, as
polynomials in (x, y) and composed with a motion; the norm identity and the factors for
equal and unequal links."""

from __future__ import annotations

from fractions import Fraction as Q
from typing import Any

import flint
import pytest
import sympy as sp
from flint import fmpq, fmpq_poly

from rprpr.engine.exact import five_bar as fb

from .locus import conjugates, curve, curve_at, norm, x, y
from .reference import FiveBar, lined_up
from .standin import q, robot
from .test_dynamics import ROBOT, UNEQUAL

CTX = flint.fmpq_mpoly_ctx.get(("x", "y"), "lex")
EQUAL = FiveBar(Q(1), (Q(1),) * 4, ROBOT.mass, ROBOT.inertia, ROBOT.r, ROBOT.g)
_a, _l2, *_ = lined_up(1, (Q(1, 3), Q(2, 7), Q(3, 4)), Q(1), Q(3, 2), Q(5, 4))
LINED = FiveBar(_a, (Q(1), _l2, Q(3, 2), Q(5, 4)), ROBOT.mass, ROBOT.inertia, ROBOT.r, ROBOT.g)
ROBOTS = [EQUAL, ROBOT, UNEQUAL, LINED]


def _params(rb: FiveBar) -> fb.FiveBarParams:
    return fb.params(robot(rb, (1, 1)), q(rb.g))


def _sym(p: Any) -> sp.Expr:
    """An fmpq_mpoly in x, y as a sympy expression."""
    return sp.Add(
        *(
            sp.Rational(int(c.p), int(c.q)) * x ** int(i) * y ** int(j)
            for (i, j), c in p.to_dict().items()
        )
    )


def _ref(rb: FiveBar) -> tuple[Any, ...]:
    return tuple(sp.Rational(v.numerator, v.denominator) for v in (rb.a, *rb.length))


@pytest.mark.parametrize("rb", ROBOTS, ids=["equal", "a=14/13", "unequal", "lined-up"])
def test_the_curves_and_the_parts_of_delta_are_the_derivations(rb: FiveBar) -> None:
    p = _params(rb)
    X, Y = CTX.gens()
    for sigma in (1, -1):
        assert sp.expand(_sym(fb.curve(p, sigma, X, Y)) - curve(sigma, *_ref(rb))) == 0
        gx, gy = fb.curve_gradient(p, sigma, X, Y)
        S = curve(sigma, *_ref(rb))
        assert sp.expand(_sym(gx) - sp.diff(S, x)) == 0
        assert sp.expand(_sym(gy) - sp.diff(S, y)) == 0
    c = fb.conjugates(p, X, Y)
    ref = conjugates(*_ref(rb))
    for name in ("P0", "P1", "P2", "P3", "D1", "D2", "R1", "R2"):
        assert sp.expand(_sym(getattr(c, name)) - ref[name]) == 0, name
    # the Type I factors: D_i = -(R_i - (lp + ld)²)(R_i - (lp - ld)²)/4
    for leg, D in ((1, "D1"), (2, "D2")):
        stretched, folded = fb.reach(p, leg, X, Y)
        assert sp.expand(-_sym(stretched) * _sym(folded) / 4 - ref[D]) == 0


@pytest.mark.parametrize("rb", [ROBOT, UNEQUAL], ids=["a=14/13", "unequal"])
def test_sixteen_times_the_norm_is_R1_squared_R2_squared_S_plus_S_minus(rb: FiveBar) -> None:
    p = _params(rb)
    X, Y = CTX.gens()
    c = fb.conjugates(p, X, Y)
    engine = c.R1**2 * c.R2**2 * fb.curve(p, 1, X, Y) * fb.curve(p, -1, X, Y)
    assert sp.Poly(_sym(engine), x, y, domain="QQ") == 16 * norm(*_ref(rb))


def test_equal_links_give_a_quartic_and_a_sextic_unequal_links_two_sextics() -> None:
    X, Y = CTX.gens()
    q4 = x**4 - 2 * x**3 + 2 * x**2 * y**2 + x**2 - 2 * x * y**2 + y**4 - 3 * y**2
    p = _params(EQUAL)
    plus, minus = fb.curve(p, 1, X, Y), fb.curve(p, -1, X, Y)
    assert sp.expand(_sym(plus) - q4) == 0
    assert plus.total_degree() == 4 and minus.total_degree() == 6
    for rb in (UNEQUAL, LINED):
        p = _params(rb)
        for sigma in (1, -1):
            S = fb.curve(p, sigma, X, Y)
            assert S.total_degree() == 6
            factors = sp.factor_list(_sym(S), x, y)[1]
            assert len(factors) == 1 and factors[0][1] == 1  # irreducible over Q
    for S in (plus, minus):
        assert len(sp.factor_list(_sym(S), x, y)[1]) == 1


@pytest.mark.parametrize("rb", ROBOTS, ids=["equal", "a=14/13", "unequal", "lined-up"])
def test_the_locus_along_a_motion_is_the_curve_composed_with_it(rb: FiveBar) -> None:
    t = sp.Symbol("t")
    xs = [fmpq(1, 5), fmpq(2), fmpq(-1, 3), fmpq(1, 7)]
    ys = [fmpq(3, 5), fmpq(-1, 2), fmpq(0), fmpq(2, 9)]
    # x(t), y(t) as Polys over QQ: S_σ(x(t), y(t)) is then Poly arithmetic (curve_at, the
    # formula of ``curve``), the same polynomial as curve(σ) with x(t), y(t) substituted
    # and expanded, without expanding a substituted expression of degree 18
    xt, yt = (sp.Poly([sp.Rational(int(c.p), int(c.q)) for c in reversed(cs)], t, domain="QQ")
              for cs in (xs, ys))  # fmt: skip
    plus, minus = fb.FIVE_BAR.locus(_params(rb), fmpq_poly(xs), fmpq_poly(ys))
    for got, sigma in ((plus, 1), (minus, -1)):
        want = sp.Poly(curve_at(sigma, *_ref(rb), xt, yt), t)
        assert [sp.Rational(int(c.p), int(c.q)) for c in got.coeffs()] == want.all_coeffs()[::-1]


def test_the_polynomials_in_x_and_y_are_the_derivations() -> None:
    for rb in (EQUAL, UNEQUAL):
        got = fb.polynomials(_params(rb))
        ref = conjugates(*_ref(rb))
        for sigma, name in ((1, "S+"), (-1, "S-")):
            assert sp.expand(_sym(got[name]) - curve(sigma, *_ref(rb))) == 0
        for name in ("D1", "D2", "R1", "R2"):
            assert sp.expand(_sym(got[name]) - ref[name]) == 0

"""Rigorous balls (engine.balls): every result contains the exact result, checked in exact
rational arithmetic on members drawn from the operands (ends and midpoints)."""

from __future__ import annotations

import math
import operator
from fractions import Fraction

import numpy as np
import pytest
from flint import fmpq
from hypothesis import given, settings
from hypothesis import strategies as st

from rprpr.engine.certified.balls import Ball, hypot, polyval, quiet, two_sum
from rprpr.engine.exact import equations as dyn
from tests.reference import Rational  # exact (gmpy2's rationals, else fractions): the hot loops

# floats over the whole range, subnormals and huge values included
finite = st.floats(allow_nan=False, allow_infinity=False, min_value=-1e300, max_value=1e300)
radius = st.one_of(
    st.just(0.0), st.floats(min_value=0, max_value=1e300, allow_nan=False, allow_infinity=False)
)


def _members(mid: float, rad: float) -> list[Rational]:
    m, r = Rational(mid), Rational(rad)
    return [m - r, m, m + r, m - r / 3]


def _inside(b: Ball, v: Rational) -> bool:
    rad = float(b.rad)
    if not math.isfinite(rad):
        return True  # unbounded: contains everything
    return abs(Rational(float(b.mid)) - v) <= Rational(rad)


EXACT = {"+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv}


@settings(derandomize=True, max_examples=400, deadline=None)
@given(a=finite, ra=radius, b=finite, rb=radius, op=st.sampled_from("+-*/"))
def test_arithmetic_contains_every_exact_result(
    a: float, ra: float, b: float, rb: float, op: str
) -> None:
    # the exact results (None: division by zero), computed once for both shapes
    exact = [
        None if op == "/" and y == 0 else EXACT[op](x, y)
        for x in _members(a, ra)
        for y in _members(b, rb)
    ]
    for shape in ((), (1,)):  # scalars, and arrays (operations done in place)
        A = Ball(np.full(shape, a), np.full(shape, ra))
        B = Ball(np.full(shape, b), np.full(shape, rb))
        with quiet():
            C = {"+": A + B, "-": A - B, "*": A * B, "/": A / B}[op]
        C = Ball(np.ravel(C.mid)[0], np.ravel(C.rad)[0])
        for value in exact:
            if value is None:
                assert not math.isfinite(float(C.rad))
                continue
            assert _inside(C, value), (a, ra, b, rb, op, shape)


@settings(derandomize=True, max_examples=300, deadline=None)
@given(a=st.floats(min_value=0, max_value=1e300), ra=radius)
def test_square_root_contains_every_exact_root(a: float, ra: float) -> None:
    with quiet():
        C = Ball(a, ra).sqrt()
    if not math.isfinite(float(C.rad)):
        return
    m, r = Rational(float(C.mid)), Rational(float(C.rad))
    lo, hi = max(m - r, Rational(0)), m + r
    for x in _members(a, ra):
        if x >= 0:  # √x in [lo, hi] exactly when lo² <= x <= hi²
            assert lo * lo <= x <= hi * hi, (a, ra)


def test_subnormal_and_tiny_values_keep_a_bound() -> None:
    tiny = 5e-324
    with quiet():
        c = Ball(tiny, 0) * Ball(0.5, 0)  # underflows to 0 or η: |error| <= η/2
        assert _inside(c, Fraction(tiny) / 2)
        q = Ball(1e-300, 1e-310) / Ball(1e300, 0)  # underflows
        assert _inside(q, Fraction(1e-300) / Fraction(1e300))
        assert _inside(q, (Fraction(1e-300) + Fraction(1e-310)) / Fraction(1e300))


def test_overflow_and_division_by_zero_are_unbounded_never_wrong() -> None:
    with quiet():
        assert not Ball(1e300, 0).__mul__(Ball(1e300, 0)).bounded()
        assert not (Ball(1.0, 0) / Ball(0.0, 1e-20)).bounded()
        assert not (Ball(1.0, 0) / Ball(1.0, 1.0)).bounded()
        n = (Ball(1.0, 0) / Ball(0.0, 0.0)).normal()
        assert math.isnan(float(n.mid)) and math.isinf(float(n.rad))
        assert Ball(1.0, 0).contains_zero() == np.False_
        assert (Ball(1.0, 0) / Ball(0.0, 0.0)).contains_zero()


def test_rational_constants_become_balls_of_their_rounding() -> None:
    tenth = Ball.of_rational(fmpq(1, 10))
    assert float(tenth.rad) > 0 and _inside(tenth, Fraction(1, 10))
    assert float(Ball.of_rational(fmpq(3, 4)).rad) == 0  # a double: exact
    third = Ball.of_rational(fmpq(-1, 3)) * 3.0
    with quiet():
        assert _inside(third + 1.0, Fraction(0))


def test_two_sum_is_exact() -> None:
    a = np.array([1.0, 1e16, 0.1, -3.0])
    b = np.array([1e-17, 1.0, 0.2, 3.0000000000000004])
    s, e = two_sum(a, b)
    for i in range(len(a)):
        assert Fraction(s[i]) + Fraction(e[i]) == Fraction(a[i]) + Fraction(b[i])


def test_the_paper_formulas_run_unchanged_on_balls() -> None:
    x, y = Ball(np.array([2.0, 3.5]), 0.0), Ball(np.array([-1.0, 0.25]), 0.0)
    one, zero = Ball(1.0, 0.0), Ball(0.0, 0.0)
    with quiet():
        leg = dyn.leg(x, one, zero, y, one, zero, hypot)
    s_exact = [math.sqrt(5), math.sqrt(3.5**2 + 0.0625)]
    for i in range(2):
        assert abs(float(leg.s.mid[i]) - s_exact[i]) <= float(leg.s.rad[i]) + 1e-16
        assert float(leg.s.rad[i]) < 1e-14


def test_hull_contains_its_ends() -> None:
    lo, hi = np.array([0.1, -2.0, 5e-324]), np.array([0.3, 7.0, 1e-300])
    h = Ball.hull(lo, hi)
    for i in range(3):
        assert float(h.lower()[i]) <= lo[i] and hi[i] <= float(h.upper()[i])
        assert abs(Fraction(float(h.mid[i])) - Fraction(lo[i])) <= Fraction(float(h.rad[i]))
        assert abs(Fraction(float(h.mid[i])) - Fraction(hi[i])) <= Fraction(float(h.rad[i]))


@pytest.mark.parametrize("v", [1e-320, 1.0, 3e200])
def test_upper_and_lower_abs_bound_every_member(v: float) -> None:
    b = Ball(v, v / 4)
    for x in _members(v, v / 4):
        assert Fraction(float(b.lower_abs())) <= abs(x) <= Fraction(float(b.upper_abs()))


def test_the_centred_form_encloses_a_polynomial_and_its_derivatives_tightly() -> None:
    """``centred`` over balls: every exact value at exact points of each ball lies inside
    (p, p', p'', p''' of T16(w)/10), and where Horner's rule is wide by cancellation the
    centred enclosure is narrower by orders of magnitude."""
    from flint import fmpq, fmpq_poly

    from rprpr.engine.certified.balls import centred, horner, poly_balls

    t16 = fmpq_poly([1, 0, -128, 0, 2688, 0, -21504, 0, 84480, 0, -180224, 0, 212992, 0,
                     -131072, 0, 32768]) / 10  # fmt: skip
    polys = [t16]
    for _ in range(4):
        polys.append(polys[-1].derivative())
    lo = np.linspace(-1.0, 1.0, 65)[:-1]
    box = Ball.hull(lo, lo + 1 / 32)
    enc = centred([poly_balls(p) for p in polys], box)
    plain = [horner(poly_balls(p), box) for p in polys]
    for k, p in enumerate(polys):
        for j, a in enumerate(lo):
            for f in (0, 0.25, 0.5, 1):  # exact points of the box (dyadic)
                v = Fraction(str(p(fmpq(*float(a).as_integer_ratio()) + fmpq(int(f * 4), 128))))
                assert Fraction(enc[k].lower()[j]) <= v <= Fraction(enc[k].upper()[j]), (k, j, f)
    assert float(np.max(enc[0].rad)) * 10 < float(np.max(plain[0].rad))


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.floats(allow_nan=False, width=64), min_size=1, max_size=9),
    st.lists(st.floats(allow_nan=False, width=64), min_size=1, max_size=5),
)
def test_polyval_gives_numpys_polyval_bit_for_bit(c: list[float], ts: list[float]) -> None:
    """The double-precision guide (sampling the motion's x, the torques' ladders) keeps
    numpy.polynomial's Horner order, so its doubles are numpy's own, infinities and NaN
    included."""
    at = np.array(ts)
    with quiet():
        want = np.polynomial.polynomial.polyval(at, c)
        got = polyval(at, c)
    assert got.tobytes() == want.tobytes()


def _bound(op: str, am, ar, bm, br):  # type: ignore[no-untyped-def]
    """The module docstring's radius, written out in plain numpy expressions (one
    rounding per operation, in the order the docstring states it): the reference the
    operations on broadcast operands must reproduce to the last bit."""
    u, eta, tiny, grow, pad = 2.0**-53, 2.0**-1074, 2.0**-1021, 1.0 + 2.0**-48, 2.0**-1064
    if op == "mul":
        c = am * bm
        prop = (np.abs(am) + ar) * br + ar * np.abs(bm)
        return c, (prop + (u * np.abs(c) + eta)) * grow + pad
    b = np.abs(bm)
    c = am / bm
    prop = (((ar * b + np.abs(am) * br) + tiny) / b + tiny) / (b - br)
    rad = (prop + (u * np.abs(c) + eta)) * grow + pad
    bad = ~(b > br)
    return np.where(bad, np.nan, c), np.where(bad, np.inf, rad)


@pytest.mark.parametrize("op", ["mul", "div"])
@pytest.mark.parametrize(
    "shapes",
    [((2, 9), (2, 9), (9,), (9,)), ((), (), (9,), (9,)), ((2, 1), (2, 1), (2, 9), (2, 9)),
     ((9,), (9,), (), ()), ((9,), (), (9,), (9,)), ((), (9,), (9,), (9,)),
     ((2, 9), (2, 9), (2, 1), (2, 1)), ((9,), (9,), (9,), ())],
)  # fmt: skip
def test_products_and_quotients_of_broadcast_operands_have_the_stated_radius(
    op: str, shapes: tuple[tuple[int, ...], ...]
) -> None:
    """Balls of different shapes (a leg's rows against a shared coordinate, a constant
    against a vector, a radius broadcast over its midpoints): the midpoint and the radius
    are the docstring's, bit for bit, over magnitudes from 1e-300 to 1e300, exact
    operands, unbounded ones and divisors holding 0."""
    rng = np.random.default_rng(23)
    with quiet():
        for k in range(60):

            def draw(s: tuple[int, ...]) -> np.ndarray:
                return np.array(rng.standard_normal(s) * 10.0 ** rng.integers(-300, 300, s))

            am, ar, bm, br = (draw(s) for s in shapes)
            ar, br = np.abs(ar) * (0.0 if k % 5 == 0 else 1.0), np.abs(br)
            if k % 7 == 0:
                ar = ar * np.inf
            if k % 11 == 0:
                bm = bm * 0.0
            got = Ball._of(am, ar) * Ball._of(bm, br) if op == "mul" else (
                Ball._of(am, ar) / Ball._of(bm, br))  # fmt: skip
            mid, rad = _bound(op, am, ar, bm, br)
            assert np.array_equal(np.broadcast_to(got.mid, np.shape(mid)), mid, equal_nan=True)
            assert np.array_equal(np.broadcast_to(got.rad, np.shape(rad)), rad, equal_nan=True)

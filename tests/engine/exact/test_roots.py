"""engine.roots: real_roots_in, the one home of "the real roots of f in [0, t_f]"."""

from __future__ import annotations

import mpmath
from flint import fmpq, fmpq_poly

from rprpr.engine.exact.roots import real_roots_in

T = fmpq_poly([0, 1])


def test_real_roots_in_gives_rational_roots_exactly_and_irrational_ones_as_balls() -> None:
    """(t - 1/2)(t² - 2)(t - 3) t (t - 2) over [0, 2]: 0, 1/2 and 2 exactly (the ends
    of the span count), √2 as balls holding mpmath's √2 at every precision asked; 3
    lies outside, -√2 too."""
    f = (T - fmpq(1, 2)) * (T**2 - 2) * (T - 3) * T * (T - 2)
    got = real_roots_in(f, fmpq(2))
    exact = sorted(r for r, _ in got if r is not None)
    assert exact == [fmpq(0), fmpq(1, 2), fmpq(2)]
    balls = [at for r, at in got if r is None]
    assert len(balls) == 1
    for prec in (64, 256):
        b = balls[0](prec)
        with mpmath.workprec(prec + 64):
            s = mpmath.sqrt(2)
            assert mpmath.mpf(b.lower().str(50, radius=False)) <= s + mpmath.mpf(10) ** -40
            assert mpmath.mpf(b.upper().str(50, radius=False)) >= s - mpmath.mpf(10) ** -40
        assert float(b.rad()) < 2.0 ** (-prec + 8)
    for r, at in got:  # a rational root's ball is the root itself
        if r is not None:
            assert at(64) == r


def test_real_roots_in_a_simple_polynomial_is_isolated_as_it_is() -> None:
    """``simple``: (t² - 2)(t² - 3), square-free without a rational root, isolated
    without factoring: √2 and √3 in (0, 2), in increasing order."""
    f = (T**2 - 2) * (T**2 - 3)
    got = real_roots_in(f, fmpq(2), simple=True)
    assert [r for r, _ in got] == [None, None]
    mids = [float(at(128).mid()) for _, at in got]
    assert mids == [float(mpmath.sqrt(2)), float(mpmath.sqrt(3))]
    assert real_roots_in(fmpq_poly([5]), fmpq(2)) == []  # no root: a constant

"""K(√D1, √D2) (``rprpr.engine.exact.radicals``) against mpmath at 50 digits: products,
inverses and signs agree with the numbers they stand for, and the exact zero test holds
where the representation is not unique (D2 a square in K(√D1), D1 a square in K)."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import mpmath
import pytest
from flint import arb, ctx, fmpq, fmpq_poly

from rprpr.engine.exact.radicals import Rad, Tower
from rprpr.engine.exact.roots import real_roots_in
from rprpr.engine.exact.series import KElem, NumberField


@pytest.fixture(autouse=True)
def _digits() -> Iterator[None]:
    with mpmath.workdps(50):
        yield


def _q_tower(D1: fmpq, D2: fmpq) -> Tower:
    def value(v: Any, prec: int) -> arb:
        with ctx.workprec(prec):
            return arb(v)

    return Tower(D1, D2, value)


def _num(r: Rad, D1: Any, D2: Any) -> Any:
    """The value by mpmath, from the components (rationals)."""
    r1, r2 = mpmath.sqrt(D1), mpmath.sqrt(D2)
    a = [mpmath.mpf(int(v.p)) / int(v.q) for v in r.a]
    return a[0] + a[1] * r1 + a[2] * r2 + a[3] * r1 * r2


def _mpf(q: fmpq) -> Any:
    return mpmath.mpf(int(q.p)) / int(q.q)


ELEMS = [
    (fmpq(1), fmpq(2), fmpq(-3), fmpq(1, 2)),
    (fmpq(-2, 3), fmpq(0), fmpq(5), fmpq(0)),
    (fmpq(0), fmpq(7), fmpq(0), fmpq(-1)),
]


@pytest.mark.parametrize(
    ("D1", "D2"), [(fmpq(2), fmpq(3)), (fmpq(5, 4), fmpq(7)), (fmpq(2), fmpq(8))]
)
def test_products_inverses_and_signs_are_the_numbers(D1: fmpq, D2: fmpq) -> None:
    tw = _q_tower(D1, D2)
    d1, d2 = _mpf(D1), _mpf(D2)
    for a in ELEMS:
        for b in ELEMS:
            x, y = Rad(tw, a), Rad(tw, b)
            assert abs(_num(x * y, d1, d2) - _num(x, d1, d2) * _num(y, d1, d2)) < 1e-40
            assert abs(_num(x - y, d1, d2) - (_num(x, d1, d2) - _num(y, d1, d2))) < 1e-40
        x = Rad(tw, a)
        v = _num(x, d1, d2)
        if abs(v) > 1e-30:
            assert abs(_num(x.inverse(), d1, d2) - 1 / v) < 1e-40
            assert x.sign() == (1 if v > 0 else -1)


def test_zero_where_the_representation_is_not_unique() -> None:
    tw = _q_tower(fmpq(2), fmpq(8))  # r2 = 2 r1
    assert Rad(tw, (fmpq(0), fmpq(-2), fmpq(1), fmpq(0))).is_zero()  # r2 - 2 r1
    assert not Rad(tw, (fmpq(0), fmpq(2), fmpq(1), fmpq(0))).is_zero()  # r2 + 2 r1
    assert Rad(tw, (fmpq(-4), fmpq(0), fmpq(0), fmpq(1))).is_zero()  # r1 r2 - 4
    sq = _q_tower(fmpq(9, 4), fmpq(3))  # r1 = 3/2
    assert Rad(sq, (fmpq(3), fmpq(-2), fmpq(0), fmpq(0))).is_zero()  # 3 - 2 r1
    assert Rad(sq, (fmpq(0), fmpq(0), fmpq(3), fmpq(-2))).is_zero()  # r2 (3 - 2 r1)
    assert not Rad(sq, (fmpq(3), fmpq(2), fmpq(0), fmpq(0))).is_zero()
    assert Rad(sq, (fmpq(3), fmpq(-2), fmpq(1), fmpq(0))) != 0


def test_over_a_number_field() -> None:
    """K = Q[t]/(t³ - t - 1) at its real root ρ, D1 = ρ, D2 = ρ² + 1: arithmetic and signs
    agree with mpmath at ρ; ρ r2 - ρ √(ρ² + 1) = 0 is decided exactly."""
    f = fmpq_poly([-1, -1, 0, 1])
    ((_, at),) = real_roots_in(f, fmpq(2))
    K = NumberField(f, at)
    t = K.elem(fmpq_poly([0, 1]))
    D1, D2 = t, t * t + 1

    def value(v: Any, prec: int) -> arb:
        return K.evaluate(v.p, prec) if isinstance(v, KElem) else arb(v)

    tw = Tower(D1, D2, value)
    rho = mpmath.findroot(lambda s: s**3 - s - 1, 1.3)
    r1, r2 = mpmath.sqrt(rho), mpmath.sqrt(rho**2 + 1)
    x = Rad(tw, (t, K.elem(-1), t * t, K.elem(fmpq(1, 3))))
    y = Rad(tw, (K.elem(2), t, K.elem(0), t))

    def num(r: Rad) -> Any:
        a = [mpmath.polyval([_mpf(c) for c in v.p.coeffs()[::-1]], rho) for v in r.a]
        return a[0] + a[1] * r1 + a[2] * r2 + a[3] * r1 * r2

    assert abs(num(x * y) - num(x) * num(y)) < 1e-40
    assert abs(num(x.inverse()) - 1 / num(x)) < 1e-40
    assert x.sign() == (1 if num(x) > 0 else -1)
    assert not x.is_zero()
    # r1 r2 = √(ρ³ + ρ) = √(2ρ + 1): (r1 r2)² - (2ρ + 1) = 0 exactly
    p = Rad(tw, (K.elem(0), K.elem(0), K.elem(0), K.elem(1)))
    assert (p * p - (t * 2 + 1)).is_zero()

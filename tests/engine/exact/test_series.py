"""Exact truncated series over Q (engine.series.QSeries, flint's fmpq_series) against
closed forms, and the same operations as the Python ``Series``."""

from __future__ import annotations

import random
from math import comb

import pytest
from flint import fmpq

from rprpr.engine.exact.series import QSeries, Series


def _binomial_half(k: int) -> fmpq:
    """The coefficient of ε^k in sqrt(1 + ε): C(1/2, k) = (-1)^(k+1) C(2k, k)/(4^k (2k - 1))."""
    return fmpq((-1) ** (k + 1) * comb(2 * k, k), 4**k * (2 * k - 1))


def test_sqrt_with_matches_the_binomial_series() -> None:
    # sqrt(9 + 9ε) = 3 sqrt(1 + ε), and the other branch -3 sqrt(1 + ε)
    s = QSeries([fmpq(9), fmpq(9)] + [fmpq(0)] * 10)
    for sign in (1, -1):
        assert s.sqrt_with(3 * sign).c == [3 * sign * _binomial_half(k) for k in range(12)]


def test_division_and_truncation_to_the_shorter_operand() -> None:
    one_minus = QSeries([fmpq(1), fmpq(-1), fmpq(0), fmpq(0), fmpq(0)])
    geometric = 1 / one_minus  # 1/(1 - ε) = Σ ε^k
    assert geometric.c == [fmpq(1)] * 5
    short = QSeries([fmpq(2), fmpq(3)])
    assert len(geometric * short) == 2 and (geometric * short).c == [2, 5]
    assert (short - geometric).c == [1, 2] and (-short).c == [-2, -3]
    assert QSeries([fmpq(0), fmpq(0), fmpq(5), fmpq(0)]).valuation() == 2
    assert QSeries([fmpq(0)] * 3).valuation() == 3


def test_the_same_exact_values_as_the_python_series() -> None:
    rng = random.Random(7)

    def rational() -> fmpq:
        return fmpq(rng.randint(-50, 50), rng.randint(1, 30))

    for n in (1, 4, 13, 40):
        a = [fmpq(rng.randint(1, 9))] + [rational() for _ in range(n - 1)]
        b = [fmpq(rng.randint(-9, -1))] + [rational() for _ in range(n - 1)]
        A, B, Aq, Bq = Series(a), Series(b), QSeries(a), QSeries(b)
        q = fmpq(3, 7)
        assert (Aq * Bq).c == (A * B).c
        assert (Aq / Bq).c == (A / B).c
        assert (Aq + Bq * q - 2).c == (A + B * q - 2).c
        assert (q / Aq).c == (q / A).c
        square = Aq * Aq
        assert square.sqrt_with(a[0]).c == Aq.c


def test_mixed_operands_and_division_by_a_series_without_constant_term() -> None:
    q = QSeries([fmpq(1), fmpq(2), fmpq(3)])
    p = Series([fmpq(2), fmpq(1)])
    assert isinstance(p * q, QSeries) and (p * q).c == [2, 5]  # Series on the left
    assert (p - q).c == [1, -1] and (p / q).c == [2, -3]
    for bad in (QSeries([fmpq(0), fmpq(1)]), Series([fmpq(0), fmpq(1)])):
        with pytest.raises(ZeroDivisionError):
            q / bad
    with pytest.raises(ZeroDivisionError):
        1 / QSeries([fmpq(0), fmpq(1)])

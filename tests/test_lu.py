"""The references' linear solve (tests/lu.py) against mpmath's own ``lu_solve``: the same
solution to the last bit, on sparse systems like the references' and dense ones."""

from __future__ import annotations

import random

import mpmath
import pytest

from tests.lu import lu_solve


def _system(rng: random.Random, n: int, density: float) -> tuple[list[list[mpmath.mpf]], list]:
    A = [
        [mpmath.mpf(rng.uniform(-5, 5)) if rng.random() < density else mpmath.mpf(0)
         for _ in range(n)]
        for _ in range(n)
    ]  # fmt: skip
    for i in range(n):
        if not A[i][i]:
            A[i][i] = mpmath.mpf(rng.uniform(1, 3))  # most are regular
    return A, [mpmath.mpf(rng.uniform(-5, 5)) for _ in range(n)]


@pytest.mark.parametrize("density", [0.25, 0.6, 1.0])
def test_the_solve_is_mpmaths_bit_for_bit(density: float) -> None:
    rng = random.Random(int(density * 100))
    solved = singular = 0
    for trial in range(120):
        n = rng.choice([2, 4, 7, 12])
        A, b = _system(rng, n, density)
        with mpmath.workdps(30):
            try:
                want = list(mpmath.lu_solve(mpmath.matrix(A), mpmath.matrix(b)))
            except ZeroDivisionError:
                with pytest.raises(ZeroDivisionError):
                    lu_solve(A, b)
                singular += 1
                continue
            got = lu_solve(A, b)
        assert len(got) == n
        assert all(g == w for g, w in zip(got, want, strict=True)), trial  # exact mpf equality
        solved += 1
    assert solved >= 100


def test_a_column_of_zeros_is_singular_as_in_mpmath() -> None:
    A = [[mpmath.mpf(1), mpmath.mpf(0)], [mpmath.mpf(2), mpmath.mpf(0)]]
    b = [mpmath.mpf(1), mpmath.mpf(1)]
    with pytest.raises(ZeroDivisionError):
        mpmath.lu_solve(mpmath.matrix(A), mpmath.matrix(b))
    with pytest.raises(ZeroDivisionError):
        lu_solve(A, b)

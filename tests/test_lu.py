"""The references' linear solve (tests/lu.py) against mpmath's own ``lu_solve``: the same
solution to the last bit, on sparse systems like the references' and dense ones."""

from __future__ import annotations

import hashlib
import json
import random
from collections.abc import Iterator
from functools import cache
from pathlib import Path
from typing import Any

import mpmath
import pytest

from tests.lu import lu_solve

DENSITIES = [0.25, 0.6, 1.0]
TRIALS = 120


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


def _systems(density: float) -> Iterator[tuple[int, list[list[mpmath.mpf]], list]]:
    """(n, A, b) of every trial, drawn from the density's seed."""
    rng = random.Random(int(density * 100))
    for _ in range(TRIALS):
        n = rng.choice([2, 4, 7, 12])
        yield (n, *_system(rng, n, density))


def _fingerprint(x: list[Any] | None) -> str:
    """A solution's bits (each mpf's sign, mantissa, exponent and bit count) as a SHA-256
    digest, or "singular" for None: equal digests, equal mpf values."""
    if x is None:
        return "singular"
    bits = [tuple(int(p) for p in v._mpf_) for v in x]
    return hashlib.sha256(repr(bits).encode()).hexdigest()[:32]


def _mpmaths(density: float) -> list[str]:
    """The fingerprints of mpmath.lu_solve's solutions of the density's systems at 30
    digits (its matrices: most of this file's time)."""
    out = []
    for _, A, b in _systems(density):
        with mpmath.workdps(30):
            try:
                x = list(mpmath.lu_solve(mpmath.matrix(A), mpmath.matrix(b)))
            except ZeroDivisionError:
                x = None
        out.append(_fingerprint(x))
    return out


# mpmath's solutions of these fixed systems never change: their fingerprints are stored
# beside this file by density (written by ``python -m tests.test_lu``), and a slow test
# recomputes every one from mpmath.lu_solve; a density not stored is computed here.
STORED = Path(__file__).with_name("lu_reference.json")


@cache
def _stored() -> dict[str, list[str]]:
    return json.loads(STORED.read_text(encoding="utf-8")) if STORED.exists() else {}


def mpmaths(density: float) -> list[str]:
    """``_mpmaths``: stored, or computed when not."""
    rows = _stored().get(repr(density))
    return _mpmaths(density) if rows is None else rows


@pytest.mark.parametrize("density", DENSITIES)
def test_the_solve_is_mpmaths_bit_for_bit(density: float) -> None:
    want = mpmaths(density)
    solved = singular = 0
    for trial, (n, A, b) in enumerate(_systems(density)):
        with mpmath.workdps(30):
            if want[trial] == "singular":
                with pytest.raises(ZeroDivisionError):
                    lu_solve(A, b)
                singular += 1
                continue
            got = lu_solve(A, b)
        assert len(got) == n
        assert _fingerprint(got) == want[trial], trial  # exact mpf equality
        solved += 1
    assert solved >= 100


@pytest.mark.slow  # mpmath.lu_solve on every system (mpmath's matrices)
def test_the_stored_solutions_are_mpmaths() -> None:
    assert set(_stored()) == {repr(d) for d in DENSITIES}  # every stored density is live
    for density in DENSITIES:
        assert _mpmaths(density) == _stored()[repr(density)], density


def test_a_column_of_zeros_is_singular_as_in_mpmath() -> None:
    A = [[mpmath.mpf(1), mpmath.mpf(0)], [mpmath.mpf(2), mpmath.mpf(0)]]
    b = [mpmath.mpf(1), mpmath.mpf(1)]
    with pytest.raises(ZeroDivisionError):
        mpmath.lu_solve(mpmath.matrix(A), mpmath.matrix(b))
    with pytest.raises(ZeroDivisionError):
        lu_solve(A, b)


if __name__ == "__main__":
    STORED.write_text(
        json.dumps({repr(d): _mpmaths(d) for d in DENSITIES}, indent=0) + "\n", encoding="utf-8"
    )

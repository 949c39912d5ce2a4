"""``FiveBar``: its parameters checked, and each leg's discriminant D_i against elbows
built by hand.

The reference: rational poses made from Pythagorean triples (C = l1 u, E = C + l3 w with
u, w rational unit vectors), where the elbow is known before any formula is applied.
D_i must be the square of a rational there, and C = (K E + e √D E⊥)/|E|² must give back
the elbow with e = sign(E × C) (docs/five-bar.md §2).
"""

from __future__ import annotations

import itertools
from math import isqrt

import pytest
from flint import fmpq

from rprpr.model.five_bar import FiveBar
from rprpr.model.task import Link

LINK = Link(fmpq(1), fmpq(1, 10), fmpq(1, 2))
LINKS = dict.fromkeys((1, 2, 3, 4), LINK)
# rational unit vectors (3-4-5, 5-12-13, 8-15-17 and their signs)
UNITS = [
    (fmpq(sx * a, c), fmpq(sy * b, c))
    for a, b, c in ((3, 4, 5), (5, 12, 13), (15, 8, 17), (1, 0, 1))
    for sx, sy in itertools.product((1, -1), repeat=2)
]


def _sqrt(q: fmpq) -> fmpq:
    """The rational square root of ``q`` (which must be a square)."""
    a, b = isqrt(int(q.p)), isqrt(int(q.q))
    assert a * a == int(q.p) and b * b == int(q.q), f"{q} is not a rational square"
    return fmpq(a, b)


@pytest.mark.parametrize(("u", "w"), list(itertools.product(UNITS[:8], UNITS)))
def test_the_discriminant_gives_back_an_elbow_built_by_hand(
    u: tuple[fmpq, fmpq], w: tuple[fmpq, fmpq]
) -> None:
    l1, l3 = fmpq(2), fmpq(3, 2)
    c = (l1 * u[0], l1 * u[1])
    e = (c[0] + l3 * w[0], c[1] + l3 * w[1])
    r = e[0] ** 2 + e[1] ** 2
    if r == 0:
        return
    fb = FiveBar(fmpq(1), (l1, fmpq(1), l3, fmpq(1)), (1, 1), LINKS)
    d = fb.discriminant(1, *e)
    assert d >= 0
    root = _sqrt(d)
    k = (l1**2 + r - l3**2) / 2
    cross = e[0] * c[1] - e[1] * c[0]  # E × C
    sign = 1 if cross > 0 else -1
    rebuilt = ((k * e[0] - sign * root * e[1]) / r, (k * e[1] + sign * root * e[0]) / r)
    assert rebuilt == c
    assert (d == 0) == (cross == 0)  # a stretched or folded leg: the modes coincide


def test_leg_2_is_measured_from_b() -> None:
    fb = FiveBar(fmpq(3), (fmpq(1), fmpq(2), fmpq(1), fmpq(2)), (1, -1), LINKS)
    assert fb.leg(2) == (fmpq(3), fmpq(2), fmpq(2))
    assert fb.annulus(2) == (fmpq(0), fmpq(4))
    assert fb.discriminant(2, fmpq(7), fmpq(0)) == 0  # stretched: |E - B| = 4
    assert fb.discriminant(2, fmpq(8), fmpq(0)) < 0  # beyond
    assert fb.discriminant(1, fmpq(2), fmpq(0)) == 0  # leg 1 stretched at |E| = 2
    assert fb.discriminant(1, fmpq(0), fmpq(0)) == 0  # folded at A (l1 = l3)


@pytest.mark.parametrize(
    ("a", "lengths", "modes", "links", "what"),
    [
        (fmpq(0), (fmpq(1),) * 4, (1, 1), LINKS, "a = |AB| must be > 0"),
        (fmpq(1), (fmpq(1), fmpq(1), fmpq(0), fmpq(1)), (1, 1), LINKS, "lengths"),
        (fmpq(1), (fmpq(1),) * 3, (1, 1), LINKS, "lengths"),
        (fmpq(1), (fmpq(1),) * 4, (1, 0), LINKS, "modes"),
        (fmpq(1), (fmpq(1),) * 4, (1, True), LINKS, "modes"),
        (fmpq(1), (fmpq(1),) * 4, (1, -1), dict.fromkeys((2, 3, 4, 5), LINK), "links"),
    ],
)
def test_a_five_bar_out_of_range_is_a_value_error(
    a: fmpq, lengths: tuple[fmpq, ...], modes: tuple[int, ...], links: dict[int, Link], what: str
) -> None:
    with pytest.raises(ValueError, match=what):
        FiveBar(a, lengths, modes, links)  # type: ignore[arg-type]

"""``repair.consistency``: eq. (34) at y = 0 solved for ẍ(t_s), against the three cases of
the closed form worked out by hand (module docstring: (m3 + m5) ẍ = -ẏ² (c1 m3 r3/s1² +
c2 m5 r5/s2²), c1 = sign x, c2 = sign(x - a1))."""

from __future__ import annotations

from fractions import Fraction

import pytest
from flint import fmpq

from rprpr.io.loader import parse_task
from rprpr.repair.consistency import consistent_acceleration
from tests.conftest import task_text

# a1 = 6, m3 = 1, r3 = 1/2 and, heavier, m5 = 2, r5 = 1/2 (the other legs do not enter)
ROBOT = parse_task(
    task_text("x - 3", "timing:\n  duration: 1\n  x: 3 + t\n").replace(
        "5: {mass: 1.0", "5: {mass: 2.0"
    )
).robot


@pytest.mark.parametrize(
    ("x", "by_hand"),
    [
        # case 3, 0 < x < a1 (c1 = 1, c2 = -1): 3 ẍ = ẏ² (2·½/3² - 1·½/3²) = ẏ²/18
        (3, Fraction(1, 54)),
        # case 1, x > a1 (c1 = c2 = 1), s1 = 8, s2 = 2: 3 ẍ = -ẏ² (½/64 + 1/4)
        (8, -(Fraction(1, 128) + Fraction(1, 4)) / 3),
        # case 2, x < 0 (c1 = c2 = -1), s1 = 2, s2 = 8: 3 ẍ = ẏ² (½/4 + 1/64)
        (-2, (Fraction(1, 8) + Fraction(1, 64)) / 3),
    ],
)
def test_the_consistent_acceleration_is_the_closed_form_of_each_case(
    x: int, by_hand: Fraction
) -> None:
    assert ROBOT.links[5].mass == 2 and ROBOT.a1 == 6
    for ydot in (fmpq(1), fmpq(-3, 4)):
        want = by_hand * Fraction(int(ydot.p), int(ydot.q)) ** 2
        assert consistent_acceleration(ROBOT, fmpq(x), ydot) == fmpq(
            want.numerator, want.denominator
        )

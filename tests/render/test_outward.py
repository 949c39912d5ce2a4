"""A printed bound is rounded outward (docs/robust.md, *Output*): an upper bound up, a
lower bound down, from the double's exact binary value (``fractions``, not the code
under test, decides)."""

from __future__ import annotations

import random
from fractions import Fraction

from rprpr.engine.findings import robust_note
from rprpr.engine.robust.windows import Robust
from rprpr.model.numbers import number, outward, with_unit
from rprpr.model.task import Uncertainty
from rprpr.render.phrases import robust_lines

UNITS = {
    "": 1,
    "m": Fraction(1, 10**3),
    "µ": Fraction(1, 10**6),
    "n": Fraction(1, 10**9),
    "p": Fraction(1, 10**12),
}


def _value(text: str, unit: str = "") -> Fraction:
    number_part, _, prefixed = text.partition(" ")
    scale = UNITS[prefixed[: -len(unit)]] if unit else 1
    return Fraction(number_part) * scale


def test_the_reported_case_prints_up() -> None:
    assert number(5000.0049) == "5000"  # the nearest: not a bound
    assert number(5000.0049, toward=1) == "5000.01"
    assert number(-0.0211313, toward=-1) == "-0.0211313"
    assert number(0.00543969930, 3, 1, 3) == "5.44"  # ms, up
    assert with_unit(0.0054396, "s", toward=1) == "5.44 ms"
    assert with_unit(0.0054401, "s", toward=1) == "5.441 ms"
    assert outward(2.4972858744149558, 2.5027255737222736) == ("2.49728", "2.50273")


def test_random_values_print_outward_and_within_one_unit_of_the_last_digit() -> None:
    rng = random.Random(24)
    for _ in range(2000):
        v = rng.uniform(-1, 1) * 10.0 ** rng.randint(-14, 6)
        digits = rng.choice((3, 4, 6))
        up, down = number(v, digits, 1), number(v, digits, -1)
        assert Fraction(down) <= Fraction(v) <= Fraction(up)
        assert Fraction(up) - Fraction(down) <= abs(Fraction(v)) * Fraction(2, 10 ** (digits - 1))
        if v > 0:
            w = with_unit(v, "s", digits, toward=1)
            assert _value(w, "s") >= Fraction(v)
            ms = number(v, digits, 1, 3)
            assert Fraction(ms) / 1000 >= Fraction(v)


def _rep(peak: float) -> dict:
    return {
        "actuation": "prismatic",
        "kinematic_singularities": [],
        "singularities": [
            {
                "t": 2.5,
                "robust": {
                    "residual": [-0.90128849999, 0.90128850001],
                    "window": 0.0036919999999,
                    "joint": 2,
                    "span": [2.498320000001, 2.502029999999],
                },
            }
        ],
        "uncertainty": {"period": 0.01, "peak": [[4999.9, peak], [10.0, 20.000000001]]},
    }


def test_the_robust_lines_print_their_bounds_outward() -> None:
    first, peak = robust_lines(_rep(5000.0049))
    assert "residual [-0.901289, 0.901289] N" in first
    assert "window 3.692 ms" in first and "t = 2.49832 .. 2.50203 s" in first
    assert "|F1| <= 5000.01 N, |F2| <= 20.0001 N" in peak


def test_a_findings_window_is_printed_up() -> None:
    u = Uncertainty({i: (Fraction(0),) * 3 for i in (2, 3, 4, 5)}, Fraction(0), Fraction(1, 1000))
    note = robust_note(Robust((-0.00125, 0.0012500000001), 6.3600000001e-05), u)  # type: ignore[arg-type]
    assert "window is 6.36001e-05 s" in note

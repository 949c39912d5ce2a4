"""``Uncertainty`` from Python checks its values as the task file's reader does
(docs/robust.md): a ValueError naming the value, before any audit."""

from __future__ import annotations

from fractions import Fraction

import pytest
from flint import fmpq

from rprpr import Uncertainty

Q = Fraction
LINKS = {i: (Q(1, 20),) * 3 for i in (2, 3, 4, 5)}


@pytest.mark.parametrize(
    ("links", "a", "period", "says"),
    [
        (LINKS, -0.01, 0.001, "acceleration: expected a number >= 0"),
        (LINKS, 0.01, Q(-1, 1000), "period: expected a number >= 0"),
        ({3: (Q(1), Q(0), Q(0))}, 0, 0.001, "links[3] mass: expected a relative half-width"),
        ({5: (0, 0, 1.5)}, 0, 0.001, "links[5] r: expected a relative half-width >= 0 and < 1"),
        ({4: (0, -0.01, 0)}, 0, 0.001, "links[4] inertia"),
        ({7: (0, 0, 0)}, 0, 0.001, "links[7]: expected a link 2, 3, 4 or 5"),
        ({1: (0, 0, 0)}, 0, 0.001, "links[1]: expected a link"),
        ({3: (0, 0)}, 0, 0.001, "links[3]: expected (mass, inertia, r)"),
        ({3: (0, 0, "5%")}, 0, 0.001, "links[3] r: expected a number"),
        (LINKS, float("nan"), 0.001, "acceleration: expected a finite number"),
    ],
)
def test_a_value_out_of_range_is_a_value_error_naming_it(
    links: dict, a: object, period: object, says: str
) -> None:
    with pytest.raises(ValueError, match=r"^Uncertainty: ") as e:
        Uncertainty(links, a, period)  # type: ignore[arg-type]
    assert says in str(e.value)


def test_the_edges_of_the_ranges_are_accepted() -> None:
    u = Uncertainty({3: (fmpq(0), Q(99, 100), 0.999)}, 0, fmpq(0))  # type: ignore[arg-type]
    assert u.exact().links[3][1] == fmpq(99, 100)

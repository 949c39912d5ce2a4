"""engine.certified.shared: the robot's forms (its constants as balls) shared by every
task of a robot with the same exact parameters, and by no other.

The forms are compared with their definition, the double nearest each rational
(``fractions.Fraction`` to ``float``, correctly rounded: independent of flint and of the
engine's conversion), and with a form made afresh for the robot."""

from __future__ import annotations

import dataclasses
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
from flint import fmpq

from rprpr.engine.certified import shared
from rprpr.engine.certified.balls import Ball
from rprpr.engine.certified.stacked import Stacked, stacked_form
from rprpr.model.task import Link, Robot

TINY = fmpq(1, 10**40)  # far below a double's resolution of the values it is added to


def _robot(**change: Any) -> Robot:
    links = {
        2: Link(fmpq(7, 10), fmpq(122, 1000), fmpq(44, 100)),
        3: Link(fmpq(18, 10), fmpq(35, 1000), fmpq(25, 100)),
        4: Link(fmpq(16, 10), fmpq(52, 1000), fmpq(46, 100)),
        5: Link(fmpq(6, 10), fmpq(26, 1000), fmpq(67, 100)),
    }
    for key in [k for k in change if k.startswith("link")]:
        i, field = int(key[4]), key[6:]
        links[i] = dataclasses.replace(links[i], **{field: change.pop(key)})
    return Robot(**{"a1": fmpq(6), "links": links, "gravity": fmpq(981, 100), **change})


def _nearest(q: fmpq) -> float:
    return float(Fraction(int(q.p), int(q.q)))


@pytest.fixture(autouse=True)
def _empty() -> None:
    shared._BY_KEY.clear()
    shared._LAST.clear()


def test_robots_with_the_same_exact_parameters_share_one_form() -> None:
    a, b = _robot(), _robot()
    assert a is not b
    form = shared.per_robot(a, stacked_form)
    assert shared.per_robot(b, stacked_form) is form
    assert isinstance(form, Stacked)
    # leg 1's m3 = 1.8 and leg 2's m5 = 0.6 as the doubles nearest them
    assert form.m.mid[:, 0].tolist() == [_nearest(fmpq(18, 10)), _nearest(fmpq(6, 10))]


CHANGES = [
    {"a1": fmpq(6) + TINY},
    {"gravity": fmpq(981, 100) + TINY},
    {"actuation": "prismatic"},
    *({f"link{i}_{f}": getattr(_robot().links[i], f) + TINY}
      for i in (2, 3, 4, 5) for f in ("mass", "inertia", "r")),
]  # fmt: skip


@pytest.mark.parametrize("change", CHANGES, ids=[next(iter(c)) for c in CHANGES])
def test_a_robot_differing_in_any_exact_parameter_gets_its_own_form(change: dict[str, Any]) -> None:
    base = shared.per_robot(_robot(), stacked_form)
    other = _robot(**change)
    form = shared.per_robot(other, stacked_form)
    assert form is not base
    assert shared.robot_key(other) != shared.robot_key(_robot())
    fresh = stacked_form(other)
    for name in ("base", "m", "r", "K", "G", "mg", "a1"):
        got, want = getattr(form, name), getattr(fresh, name)
        assert np.array_equal(got.mid, want.mid) and np.array_equal(got.rad, want.rad), name
    assert form.prismatic == (change.get("actuation") == "prismatic")


def test_a_parameter_of_another_type_is_another_key() -> None:
    """2 as an int and as fmpq(2) are equal numbers; the key tells them apart anyway
    (exact by type and value), so a form is never shared on a coincidence of hashes."""
    assert shared.robot_key(_robot(a1=6)) != shared.robot_key(_robot(a1=fmpq(6)))


def test_shared_forms_are_read_only() -> None:
    form = shared.per_robot(_robot(), stacked_form)
    assert isinstance(form, Stacked)
    with pytest.raises(ValueError, match="read-only"):
        form.m.mid[0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        form._consts[0][0] = 1.0
    params = shared.per_robot(_robot(), lambda r: Ball.of_rational(r.a1))
    with pytest.raises(ValueError, match="read-only"):
        params.rad[...] = 1.0


def test_the_cache_is_bounded() -> None:
    forms = [shared.per_robot(_robot(a1=fmpq(6) + k * TINY), stacked_form) for k in range(40)]
    assert len(shared._BY_KEY) == shared.CACHED
    assert len({id(f) for f in forms}) == 40
    # the newest robots' forms are kept, the oldest dropped (made afresh if asked again)
    assert shared.per_robot(_robot(a1=fmpq(6) + 39 * TINY), stacked_form) is forms[39]
    assert shared.per_robot(_robot(a1=fmpq(6)), stacked_form) is not forms[0]

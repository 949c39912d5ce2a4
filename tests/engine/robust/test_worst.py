"""The worst case of each effort over the box at given times (``engine.worst``, the export's
``T1_worst``, ``T2_worst`` columns) against the independent mpmath reference
(``tests/reference.py``) at 50 digits.

The efforts are linear in each link's mass and inertia and affine in the acceleration
error, so with r exact the maximum over the box is the maximum over its corners: the
bound must hold every corner and be within 1e-9 of the largest. With r uncertain the
maximum may sit inside r's interval (T holds m r²): the bound must hold every corner and
every point of a fine grid in r, and stay within 1e-6 of the largest of them.
"""

from __future__ import annotations

import csv
import io
import itertools
from fractions import Fraction
from typing import Any

import numpy as np
import pytest
from flint import fmpq

from rprpr import audit, load_task
from rprpr.engine.robust.worst import worst_efforts
from rprpr.model.task import Link, Task, Uncertainty
from rprpr.render.export import write_csv
from tests.engine.robust.test_windows import (
    P2,
    PRISMATIC,
    _at_corners,
    _evaluate,
    _limited,
    _robots,
    _u,
)

Q = Fraction
TIMES = (Q(1), Q(2), Q(19, 8), Q(13, 4))  # each a double exactly, none the instant 2.5 s


def _ends(v: fmpq, w: Q) -> list[Q]:
    q = Q(int(v.p), int(v.q))
    return sorted({q - abs(q) * w, q + abs(q) * w})


def _links(task: Task, u: Uncertainty, r_grid: int = 0) -> list[dict[int, Link]]:
    """Each link's mass and inertia at the ends of their intervals, r at its ends (and at
    ``r_grid`` points strictly inside), the exact links as they are."""
    axes = []
    for i in (2, 3, 4, 5):
        link = task.robot.links[i]
        wm, wi, wr = u.links[i]
        rs = _ends(link.r, wr)
        if r_grid and wr:
            lo, hi = rs
            rs = [lo + (hi - lo) * Q(k, r_grid + 1) for k in range(r_grid + 2)]
        axes.append(
            [
                (i, m, j, r)
                for m in _ends(link.mass, wm)
                for j in _ends(link.inertia, wi)
                for r in rs
            ]
        )
    return [
        {i: Link(*(fmpq(v.numerator, v.denominator) for v in (m, j, r))) for i, m, j, r in combo}
        for combo in itertools.product(*axes)
    ]


def _reference_max(task: Task, u: Uncertainty, t: Q, r_grid: int = 0) -> tuple[Any, Any]:
    a = u.acceleration
    errors = sorted({(sx * a, sy * a) for sx in (-1, 1) for sy in (-1, 1)})
    best = [0, 0]
    corners = _robots(task, [(links, e) for links in _links(task, u, r_grid) for e in errors])
    for v in _at_corners(task, t, corners):
        for j in (0, 1):
            best[j] = max(best[j], abs(v[f"T{j + 1}"]))
    return best[0], best[1]


def _bounds(task: Task, u: Uncertainty) -> tuple[np.ndarray, np.ndarray]:
    result = audit(task, uncertainty=u)
    return worst_efforts(result.task, result.parts, np.array([float(t) for t in TIMES]))


@pytest.mark.parametrize(
    ("path", "u"),
    [
        (P2, _u({3: (Q(1, 20), Q(1, 20), Q(0)), 5: (Q(1, 20), Q(1, 20), Q(0))}, Q(1, 100))),
        (PRISMATIC, _u({2: (Q(1, 10), Q(1, 10), Q(0)), 4: (Q(1, 10), Q(1, 10), Q(0))}, Q(1, 10))),
    ],
)
def test_with_r_exact_the_bound_is_the_largest_corner(path: str, u: Uncertainty) -> None:
    task = _limited(load_task(path))
    w1, w2 = _bounds(task, u)
    times = TIMES if path == P2 else (Q(1, 8), Q(3, 8))
    if path != P2:
        result = audit(task, uncertainty=u)
        w1, w2 = worst_efforts(result.task, result.parts, np.array([float(t) for t in times]))
    for k, t in enumerate(times):
        largest = _reference_max(task, u, t)
        for j, got in ((0, w1[k]), (1, w2[k])):
            want = largest[j]
            assert float(want) <= got <= float(want) + 1e-9 * (1 + float(want))


def test_with_r_uncertain_the_bound_holds_the_inside_of_r() -> None:
    task = _limited(load_task(P2))
    u = _u({3: (Q(1, 20), Q(1, 20), Q(1, 10))}, Q(1, 100))
    w1, w2 = _bounds(task, u)
    for k, t in enumerate(TIMES[:2]):
        grid = _reference_max(task, u, t, r_grid=20)
        for j, got in ((0, w1[k]), (1, w2[k])):
            assert float(grid[j]) <= got <= float(grid[j]) * (1 + 1e-6) + 1e-9


def test_a_zero_box_gives_the_nominal_efforts() -> None:
    task = _limited(load_task(P2))
    w1, w2 = _bounds(task, _u({}))
    for k, t in enumerate(TIMES):
        v = _evaluate(task, t, (Q(0), Q(0)))
        assert w1[k] == pytest.approx(float(abs(v["T1"])), rel=1e-12, abs=1e-12)
        assert w2[k] == pytest.approx(float(abs(v["T2"])), rel=1e-12, abs=1e-12)
        assert w1[k] >= float(abs(v["T1"])) and w2[k] >= float(abs(v["T2"]))


def test_the_export_has_the_worst_columns_only_with_uncertainty() -> None:
    task = _limited(load_task(P2))
    plain = io.StringIO()
    write_csv(audit(task, samples=5), plain)
    assert "T1_worst" not in plain.getvalue()
    out = io.StringIO()
    u = _u({3: (Q(1, 20),) * 3, 5: (Q(1, 20),) * 3}, Q(1, 100))
    write_csv(audit(task, samples=5, uncertainty=u), out)
    lines = out.getvalue().splitlines()
    rows = list(csv.DictReader(lines[1:]))
    assert list(rows[0])[-3:] == ["T1_worst", "T2_worst", "reason"]
    assert [r["t"] for r in rows] == ["0.0", "1.25", "2.5", "3.75", "5.0"]
    for r in rows:
        if r["t"] == "2.5":  # the instant itself: no finite bound over the box
            assert r["T1_worst"] == "nan"
        else:
            assert float(r["T1_worst"]) >= abs(float(r["T1"]))
            assert float(r["T2_worst"]) >= abs(float(r["T2"]))

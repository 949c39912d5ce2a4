"""The largest effort over the box from the regressor's balls in doubles
(``robust.regressor.form_bounds``) against an exact reference (``fractions``): for
coefficients anywhere in the balls, the exact maximum over the links' box and the
error's corners of |Σ_k π_k (y0_k + e_x yx_k + e_y yy_k)| lies between the lower and the
upper bound, which are close when the balls are narrow; with the default slack and with
the windows' tighter one (``TIGHT_SLACK``)."""

from __future__ import annotations

import itertools
import random

import numpy as np
import pytest
from flint import fmpq

from rprpr.engine.certified.balls import Ball
from rprpr.engine.robust.regressor import BASIS, SLACK, TIGHT_SLACK, form_bounds
from tests.reference import Rational as Q  # exact (gmpy2's rationals, else fractions)


def _box(rng: random.Random) -> dict[int, tuple[tuple[fmpq, fmpq], ...]]:
    out = {}
    for link in (2, 3, 4, 5):
        m, r, i = (
            Q(rng.randint(5, 40), 10),
            Q(rng.randint(-30, 60), 100),
            Q(rng.randint(1, 90), 100),
        )
        w = Q(rng.choice([0, 1, 5, 10]), 100)
        out[link] = tuple((_f(v - abs(v) * w), _f(v + abs(v) * w)) for v in (m, r, i))
    return out


def _f(v: Q) -> fmpq:
    return fmpq(int(v.numerator), int(v.denominator))


_COLUMNS = [
    (BASIS.index((link, "m")) if (link, "m") in BASIS else None,
     BASIS.index((link, "mr")), BASIS.index((link, "J")))
    for link in (2, 3, 4, 5)
]  # fmt: skip


def _exact_max(y: dict[tuple[int, int, int], Q], box: dict, corners: list[tuple[Q, Q]]
               ) -> list[Q]:  # fmt: skip
    """Per effort, max over the corners, both signs and the box of s Σ π_k x_k, exactly:
    for each link the form A m + B m r + C (m r² + I) at m's and I's ends and at r's ends
    and the parabola's vertex where it lies inside. (The box is a product and the form
    m (A + B r + C r²) + C I is a sum of a term in (m, r) and one in I: its maximum is the
    sum of their maxima.)"""
    ends = [tuple((Q(int(a.p), int(a.q)), Q(int(b.p), int(b.q))) for a, b in box[link])
            for link in (2, 3, 4, 5)]  # fmt: skip
    out = []
    for j in (0, 1):
        best = None
        for (ex, ey), s in itertools.product(corners, (1, -1)):
            x = [s * (y[j, k, 0] + ex * y[j, k, 1] + ey * y[j, k, 2]) for k in range(10)]
            total = Q(0)
            for (km, kb, kc), ((ml, mh), (rl, rh), (il, ih)) in zip(_COLUMNS, ends, strict=True):
                A = x[km] if km is not None else Q(0)
                B, C = x[kb], x[kc]
                rs = [rl, rh]
                if C != 0 and rl < -B / (2 * C) < rh:
                    rs.append(-B / (2 * C))
                total += max(m * (A + B * r + C * r * r) for m in (ml, mh) for r in rs)
                total += max(C * il, C * ih)
            best = total if best is None else max(best, total)
        out.append(best)
    return out


@pytest.mark.parametrize("slack", [SLACK, TIGHT_SLACK])
def test_form_bounds_hold_the_exact_maximum_for_coefficients_in_the_balls(slack: float) -> None:
    # (TIGHT_SLACK: the windows' quick proofs; the exact maximum sits much nearer the
    # bounds then, and near the box's vertices of r the rounding counts most)
    rng = random.Random(24 if slack == SLACK else 25)
    for case in range(16 if slack == SLACK else 60):
        box = _box(rng)
        a = Q(rng.choice([0, 1, 10]), 100)
        corners = (
            [(Q(0), Q(0))] if a == 0 else [(sx * a, sy * a) for sx in (-1, 1) for sy in (-1, 1)]
        )
        n = 2
        mid = np.array([[[[rng.uniform(-50, 50) * 10.0 ** rng.randint(-3, 2) for _ in range(n)]
                          for _ in range(3)] for _ in range(10)] for _ in range(2)])  # fmt: skip
        rad = np.abs(mid) * (1e-9 if case % 2 else 0.0)
        Y = Ball(mid, rad)
        fc = [(_f(ex), _f(ey)) for ex, ey in corners]
        up = form_bounds(Y, box, fc, True, slack)
        lo = form_bounds(Y, box, fc, False, slack)
        for col in range(n):
            for pick in (0, 1, -1):  # the balls' middles, and ends
                y = {(j, k, e): Q(float(mid[j, k, e, col])) + pick * Q(float(rad[j, k, e, col]))
                     for j in (0, 1) for k in range(10) for e in range(3)}  # fmt: skip
                exact = _exact_max(y, box, corners)
                for j in (0, 1):
                    assert Q(float(lo[j, col])) <= exact[j] <= Q(float(up[j, col]))
            for j in (0, 1):
                size = max(abs(float(exact[j])), 1.0)
                tol = 1e-6 if case % 2 else 1e-10  # the radii, or the rounding alone
                assert up[j, col] - lo[j, col] <= tol * size


@pytest.mark.parametrize("slack", [SLACK, TIGHT_SLACK])
@pytest.mark.parametrize(("b", "c"), [(1e-162, -1e-163), (1.6e-162, -1.6e-163)])
def test_a_vertex_below_the_doubles_range_of_squares_is_still_bounded(
    b: float, c: float, slack: float
) -> None:
    # efforts of ~1e-162: B² underflows to a subnormal, and the vertex's value A - B²/4C
    # from it is far off; the bounds must hold the exact maximum there too
    mid = np.zeros((2, 10, 3, 1))
    mid[:, BASIS.index((2, "mr")), 0, 0] = b
    mid[:, BASIS.index((2, "J")), 0, 0] = c
    box = {link: ((_f(Q(1)), _f(Q(1))), (_f(Q(4)), _f(Q(6))), (_f(Q(0)), _f(Q(0))))
           for link in (2, 3, 4, 5)}  # fmt: skip
    corners = [(Q(0), Q(0))]
    Y = Ball(mid, np.zeros_like(mid))
    fc = [(_f(ex), _f(ey)) for ex, ey in corners]
    up = form_bounds(Y, box, fc, True, slack)
    lo = form_bounds(Y, box, fc, False, slack)
    y = {(j, k, e): Q(float(mid[j, k, e, 0])) for j in (0, 1) for k in range(10) for e in range(3)}
    exact = _exact_max(y, box, corners)
    for j in (0, 1):
        assert Q(float(lo[j, 0])) <= exact[j] <= Q(float(up[j, 0]))

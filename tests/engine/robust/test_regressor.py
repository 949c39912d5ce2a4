"""The efforts' regressor in closed form (``robust.regressor.regressor_balls``): for link
parameters and an acceleration error, Σ_k Y_k π_k + e_x Y_k^x π_k + e_y Y_k^y π_k must
hold the efforts of the independent mpmath reference (``tests/reference.py``, 50 digits),
under both actuation schemes, at times on both sides of the singular instant."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
import pytest
from flint import fmpq

from rprpr import audit, load_task
from rprpr.engine.certified.balls import Ball
from rprpr.engine.certified.jets import Jet
from rprpr.engine.robust.regressor import BASIS, regressor_balls
from rprpr.model.link import Link
from tests.engine.robust.test_windows import P2, PRISMATIC, _evaluate, _task_with

Q = Fraction


def _pi(links: dict[int, Link]) -> list[Q]:
    """π (``BASIS``) of the links: m r, J = m r² + I, m."""
    out = []
    for link, what in BASIS:
        lk = links[link]
        m, r, i = (Q(int(v.p), int(v.q)) for v in (lk.mass, lk.r, lk.inertia))
        out.append({"m": m, "mr": m * r, "J": m * r * r + i}[what])
    return out


@pytest.mark.parametrize("path", [P2, PRISMATIC])
def test_the_regressor_holds_the_references_efforts(path: str) -> None:
    task = load_task(path)
    base = task.robot.links
    scaled = {  # the links, and every mass, r and inertia moved by +7 %, -4 %, +3 %
        i: Link(lk.mass * fmpq(107, 100), lk.inertia * fmpq(103, 100), lk.r * fmpq(96, 100))
        for i, lk in base.items()
    }
    (part,) = audit(task).parts
    times = [Q(1, 3), Q(12, 5), Q(13, 5), Q(9, 2)]  # t_s = 2.5 on both paths
    kin = part.motion.end_point(Ball.exact(np.array([float(t) for t in times])))
    Y = regressor_balls(task.robot, kin)
    jets = regressor_balls(task.robot, [Jet(k, k * 0.0) for k in kin], jets=True)[0]
    for links, e in itertools.product((base, scaled), ((Q(0), Q(0)), (Q(1, 50), Q(-3, 100)))):
        pi = _pi(links)
        for n, t in enumerate(times):
            v = _evaluate(_task_with(task, links), t, e)
            want = [float(v["T1"]), float(v["T2"])]
            for Yb in (Y, jets):
                for j in (0, 1):
                    got = Ball.exact(0.0)
                    for k, p in enumerate(pi):
                        c = [Ball._of(Yb.mid[j, k, q, n], Yb.rad[j, k, q, n]) for q in range(3)]
                        got = got + (c[0] + c[1] * _b(e[0]) + c[2] * _b(e[1])) * _b(p)
                    assert got.lower() <= want[j] <= got.upper()
                    assert got.rad < 1e-6 * max(1.0, abs(want[j]))


def _b(q: Q) -> Ball:
    return Ball.of_rational(fmpq(q.numerator, q.denominator))

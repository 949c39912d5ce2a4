"""engine.stacked: the two legs stacked in rows, against ``equations`` and the reference.

``Stacked`` restates eqs. (7)-(14), (28)-(33) for both legs at once, because one run of
ball operations over two rows costs about what one leg's run costs (measured: the same
torques through ``equations.leg``/``dynamics``/``efforts`` on balls take 1.3-1.65 times
as long per pass). This test holds the copy and ``equations`` together: on random balls
of both actuation schemes, each encloses the value of the independent mpmath reference
at the balls' centres, and the two enclosures overlap.
"""

from __future__ import annotations

from fractions import Fraction

import mpmath
import numpy as np
import pytest

from rprpr.engine.certified.balls import Ball, hypot, quiet
from rprpr.engine.certified.stacked import Stacked
from rprpr.engine.exact import equations as dyn
from tests.engine.certified.test_motion import _config
from tests.reference import _evaluate


@pytest.mark.parametrize("name", ["paper_path1.rprpr.yaml", "prismatic_crossing.rprpr.yaml"])
def test_stacked_and_equations_enclose_the_reference_on_random_balls(name: str) -> None:
    task = _config(name)
    robot = task.robot
    rng = np.random.default_rng(22)
    n = 40
    mids = [
        rng.uniform(-1.0, 2.0, n), rng.uniform(-2.0, 2.0, n), rng.uniform(-3.0, 3.0, n),
        rng.choice([-1.0, 1.0], n) * rng.uniform(0.05, 1.0, n),  # y away from 0
        rng.uniform(-2.0, 2.0, n), rng.uniform(-3.0, 3.0, n),
    ]  # fmt: skip
    rads = [np.abs(m) * 10.0 ** rng.uniform(-12, -6, n) for m in mids]
    x, xd, xdd, y, yd, ydd = (Ball(m, r) for m, r in zip(mids, rads, strict=True))
    with quiet():
        st = Stacked(robot)
        T_stacked, _ = st.torques(st.legs(x, xd, xdd, y, yd, ydd), y)
        a1 = Ball.of_rational(robot.a1)
        leg1 = dyn.leg(x, xd, xdd, y, yd, ydd, hypot)
        leg2 = dyn.leg(x - a1, xd, xdd, y, yd, ydd, hypot)
        d = dyn.dynamics(leg1, leg2, dyn.Params.of(robot, Ball.of_rational))
        T_eq = dyn.efforts(d, d.mu1 / d.delta, d.mu2 / d.delta)
    for j in range(n):
        with mpmath.workdps(50):
            ref = _evaluate(task, tuple(Fraction(float(m[j])) for m in mids))
        for i, key in enumerate(("T1", "T2")):
            v = float(ref[key])
            a = Ball(T_stacked.mid[i, j], T_stacked.rad[i, j])
            b = Ball(T_eq[i].mid[j], T_eq[i].rad[j])
            assert a.lower() <= v <= a.upper(), (key, j)  # each encloses the reference
            assert b.lower() <= v <= b.upper(), (key, j)
            assert max(a.lower(), b.lower()) <= min(a.upper(), b.upper())
            assert a.rad < 1e-3 * max(abs(v), 1.0)  # and neither is vacuous

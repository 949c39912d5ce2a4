"""T over the hull of the boxes about a bounded instant (``near._over_hull``: λ by the
Lagrange form about t_s, one evaluation over the hull), against the independent
reference (``tests.reference``: mpmath at 60 digits and more, no engine code): the
enclosure holds |T_i| at every reference time of the hull, and a limit check that uses
it decides as the reference says."""

from __future__ import annotations

import numpy as np
import pytest

from rprpr.engine.bounds.boxes import partition
from rprpr.engine.bounds.envelope import Envelope
from tests.engine.certified.test_motion import _config, _motion
from tests.reference import reference


@pytest.mark.parametrize("name", ["paper_path2.rprpr.yaml", "prismatic_crossing.rprpr.yaml"])
def test_the_hull_enclosure_about_a_bounded_instant_holds_the_reference(name: str) -> None:
    task = _config(name)
    env = Envelope(_motion(task))
    lo, hi = partition(env.duration, 512)
    checked = 0
    for k, (s, e) in enumerate(env.motion.instants):
        assert s.torque_bounded
        poor = np.abs(0.5 * lo + 0.5 * hi - e.hi) <= env.tf / 40  # the boxes about t_s
        got = env._over_hull(k, lo, hi, poor, np.inf)
        assert got is not None
        idx, T = got
        h0, h1 = float(lo[idx].min()), float(hi[idx].max())
        assert h0 < e.hi < h1
        for t in np.linspace(h0, h1, 23):
            ref = reference(task, float(t))
            for i, key in enumerate(("T1", "T2")):
                if ref[key] is None:  # exactly at t_s: the limit, within the ball too
                    continue
                v = float(ref[key])
                assert T.lower()[i, 0] <= v <= T.upper()[i, 0], (t, key, v)
        assert env._over_hull(k, lo, hi, poor, 1e-3) is None  # not below a tiny bound
        checked += 1
    assert checked


def test_a_limit_far_above_the_torques_about_a_bounded_instant_needs_no_zone() -> None:
    task = _config("prismatic_crossing.rprpr.yaml")
    env = Envelope(_motion(task))
    t1, t2 = env.limit_violations((300.0, 300.0))
    assert t1.passed is True and t2.passed is True
    assert not env._zones  # decided by the hull enclosure alone
    values = [reference(task, float(t)) for t in np.linspace(0.0, env.tf, 41)]
    peak = max(abs(float(v[key])) for v in values for key in ("T1", "T2") if v[key] is not None)
    assert peak < 300.0  # the reference agrees: the limit is never reached

"""The torques about a pole in one form (``poles.pole_form``: T_i = A_i + S_i/ε^k over a
band) and the band it proves above a limit, against the independent reference
(``tests.reference``: mpmath at 60 digits, no engine code).

* At times t of the band (t ≠ t_s, ε = t - t_s taken exactly), the reference's ε^k T_i(t)
  lies in S_i + ε^k A_i (the balls as exact mpf intervals): the form holds the torques.
* |T_i(t)| >= ``band_floor`` at those times, and the floor is above the limit where the
  band is proven (``pole_bands``).
* The limit check with the bands brackets every crossing about the reference's root.
"""

from __future__ import annotations

from fractions import Fraction
from functools import cache

import mpmath
import numpy as np
import pytest

from rprpr.engine.bounds import limits
from rprpr.engine.bounds.envelope import Envelope
from rprpr.engine.bounds.poles import band_floor, estimate, point_series, pole_bands, pole_form
from rprpr.io.loader import parse_task
from rprpr.model.task import Task
from tests.conftest import CONFIGS as CONFIGS_DIR
from tests.engine.bounds.test_scalars import _exact, _root
from tests.engine.certified.test_motion import _config, _motion
from tests.reference import reference

CONFIGS = ("case1_crossing.rprpr.yaml", "case2_crossing.rprpr.yaml",
           "zero_speed_crossing.rprpr.yaml", "paper_path1.rprpr.yaml")  # fmt: skip


def _interval(ball: object) -> tuple[mpmath.mpf, mpmath.mpf]:
    mid, rad = _exact(ball.mid()), _exact(ball.rad())  # type: ignore[attr-defined]
    return mid - rad, mid + rad


@pytest.mark.parametrize("name", CONFIGS)
@pytest.mark.parametrize("share", [0.5, 0.2, 1e-3])
def test_the_pole_form_holds_the_reference_over_its_band(name: str, share: float) -> None:
    task = _config(name)
    motion = _motion(task)
    env = Envelope(motion)
    tf = float(motion.traj.duration)
    checked = 0
    for k, (s, e) in enumerate(motion.instants):
        if s.torque_bounded:
            continue
        assert e.exact is not None  # the shipped poles are at rational times
        t0, coeffs = env.scalars._origin(e.hi)
        point = point_series(motion, t0, coeffs, k)
        at = pole_form(motion, k, t0, coeffs, e.hi, e.hi, point)
        assert at is not None
        h = share * min(estimate(at, i, 300.0) for i in (0, 1))
        a, z = max(e.hi - h, 0.0), min(e.hi + h, tf)
        form = pole_form(motion, k, t0, coeffs, a, z, point)
        assert form is not None
        order, S, A, hmax = form
        assert order == s.pole_order
        ts = Fraction(int(e.exact.p), int(e.exact.q))
        floors = [band_floor(form, i) for i in (0, 1)]
        for f in np.linspace(0.0, 1.0, 9):
            t = a + float(f) * (z - a)
            if Fraction(t) == ts:
                continue
            ref = reference(task, t)
            eps = Fraction(t) - ts
            assert abs(float(eps)) <= float(_exact(hmax.mid()) + _exact(hmax.rad()))
            with mpmath.workdps(60):
                ek = (mpmath.mpf(eps.numerator) / eps.denominator) ** order
                for i, key in enumerate(("T1", "T2")):
                    s_lo, s_hi = _interval(S[i])
                    a_lo, a_hi = _interval(A[i])
                    rest = sorted((ek * a_lo, ek * a_hi))
                    scaled = ek * ref[key]  # ε^k T_i = S_i + ε^k A_i
                    assert s_lo + rest[0] <= scaled <= s_hi + rest[1], (name, t, key)
                    assert abs(ref[key]) >= floors[i], (name, t, key, floors[i])
            checked += 1
    assert checked >= 8


@pytest.mark.parametrize(("name", "limit"), [("case1_crossing.rprpr.yaml", 300.0),
                                             ("zero_speed_crossing.rprpr.yaml", 300.0),
                                             ("paper_path1.rprpr.yaml", 300.0)])  # fmt: skip
def test_the_bands_are_proven_above_the_limit_and_the_crossings_hold_the_roots(
    name: str, limit: float
) -> None:
    _bands_and_crossings(_config(name), limit)


@cache
def _irrational() -> Task:
    """Case 1 on to x = 9.5: the quintic law reaches x = 8 (y = 0) at an irrational time
    t_s ≈ 1.78502 s, a pole there."""
    text = (CONFIGS_DIR / "case1_crossing.rprpr.yaml").read_text(encoding="utf-8")
    assert "  to: [9, 0.5]\n" in text
    return parse_task(text.replace("  to: [9, 0.5]\n", "  to: [9.5, 0.75]\n"))


@pytest.mark.parametrize("limit", [80.0, 300.0, 1000.0])
def test_the_bands_about_an_irrational_pole_hold_the_reference(limit: float) -> None:
    task = _irrational()
    (s,) = [s for s, _ in _motion(task).instants if not s.torque_bounded]
    assert s.t_exact is None and abs(s.t - 1.78502) < 1e-5
    assert _bands_and_crossings(task, limit) >= 4  # each torque, on each side of the pole


def _bands_and_crossings(task: Task, limit: float) -> int:
    """Each band about a pole has its floor above ``limit`` and below the reference's
    |T_i| at five times across it; each crossing window of the limit check brackets the
    reference's root of |T_i| - limit."""
    env = Envelope(_motion(task))
    got: list[object] = []

    def kept(*args: object) -> object:
        out = pole_bands(*args)  # type: ignore[arg-type]
        got.append(out)
        return out

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(limits, "pole_bands", kept)
        checks = env.limit_violations((limit, limit))
    _, band = got[0]  # type: ignore[misc]
    assert band is not None  # the pieces near each pole were merged and proven
    poles = [s.t for s, _ in env.motion.instants if not s.torque_bounded]
    tf = float(env.motion.traj.duration)
    centres = 0
    for j in range(len(band.lo)):
        if any(band.lo[j] <= t <= band.hi[j] for t in poles):
            # the narrow piece about a pole: open (floors 0), given no pass
            assert band.hi[j] - band.lo[j] <= 1e-9 * tf
            assert (band.floor[:, j] == 0).all() and (band.up[:, j] == np.inf).all()
            centres += 1
            continue
        for t in np.linspace(band.lo[j], band.hi[j], 5):
            ref = reference(task, float(t))
            for i, key in enumerate(("T1", "T2")):
                assert band.floor[i, j] > limit
                assert abs(ref[key]) >= band.floor[i, j], (t, key)
    assert centres == len(poles)
    roots = 0
    for key, c in zip(("T1", "T2"), checks, strict=True):
        assert c.passed is False
        for w in c.windows:
            for lo, hi in ((w.start_lo, w.start_hi), (w.end_lo, w.end_hi)):
                if lo <= 0.0 or hi >= tf:
                    continue
                assert 0 <= hi - lo <= c.resolution
                width = 1000 * c.resolution
                root = _root(task, key, limit, lo - width, hi + width, (lo, hi))
                assert lo <= root <= hi, (key, lo, hi, root)
                roots += 1
    return roots

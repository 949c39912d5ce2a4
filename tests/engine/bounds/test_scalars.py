"""The limit check's arb scalars and the crossings they bracket, against the independent
reference (``tests.reference``: mpmath at 60 digits and more, no engine code).

* ``Scalars.slope`` at a float time: the balls of T1, T2 hold the reference values, and
  the balls of T1', T2' hold the reference's central difference quotient (step 1e-25 s:
  its error, ~1e-50 |T'''|, far below the balls' radii).
* The windows of a limit check bracketed by certified point passes (``limits._bracket``,
  vectorised: cheaper than Newton's method in arb scalars since the compiled kernel):
  each end [lo, hi] is at most the resolution wide and holds the root of |T_i| = limit
  found by bisection on the reference values alone, from a bracket a thousand times
  wider.
"""

from __future__ import annotations

from fractions import Fraction

import mpmath
import pytest

from rprpr.engine.bounds.envelope import Envelope
from rprpr.engine.bounds.scalars import Scalars
from rprpr.model.task import Task
from tests.engine.certified.test_motion import _config, _motion
from tests.reference import reference

CONFIGS = ("case1_crossing.rprpr.yaml", "case2_crossing.rprpr.yaml", "paper_path1.rprpr.yaml",
           "zero_speed_crossing.rprpr.yaml", "touch.rprpr.yaml")  # fmt: skip


def _exact(point: object) -> mpmath.mpf:
    """An arb ball of radius 0 (a midpoint, a radius) as an mpf, exactly."""
    m, e = point.man_exp()  # type: ignore[attr-defined]
    with mpmath.workprec(max(64, int(m).bit_length() + 8)):
        return mpmath.ldexp(mpmath.mpf(int(m)), int(e))


def _contains(ball: object, ref: mpmath.mpf, slack: float = 0.0) -> bool:
    """Whether the arb ball holds the reference value (within ``slack``, relative)."""
    mid, rad = _exact(ball.mid()), _exact(ball.rad())  # type: ignore[attr-defined]
    with mpmath.workdps(60):
        return bool(abs(mid - ref) <= rad * (1 + mpmath.mpf(10) ** -15) + slack * (1 + abs(ref)))


@pytest.mark.parametrize("name", CONFIGS)
def test_the_arb_values_and_slopes_hold_the_reference(name: str) -> None:
    task = _config(name)
    motion = _motion(task)
    S = Scalars(motion)
    tf = float(motion.traj.duration)
    times = [tf * k / 7 + 1e-3 * tf for k in range(7)]
    times += [e.hi + 1e-6 * tf for _, e in motion.instants] + [
        e.hi - 3e-5 for _, e in motion.instants
    ]
    checked = 0
    for t in times:
        if not 0 < t < tf:
            continue
        got = S.slope(t)
        assert got is not None
        ref = reference(task, t)
        h = Fraction(1, 10**25)
        up, down = reference(task, Fraction(t) + h), reference(task, Fraction(t) - h)
        for i, key in enumerate(("T1", "T2")):
            assert _contains(got[0][i], ref[key]), (t, key, got[0][i], ref[key])
            with mpmath.workdps(60):
                slope = (up[key] - down[key]) * mpmath.mpf(10) ** 25 / 2
            assert _contains(got[1][i], slope, 1e-20), (t, key, got[1][i], slope)
            assert got[0][i].rad() < 1e-20 * (1 + abs(got[0][i].mid()))  # tight
        checked += 1
    assert checked >= 7


def _limited(name: str, limit: float) -> tuple[Task, Envelope]:
    task = _config(name)
    return task, Envelope(_motion(task))


def _root(task: Task, key: str, limit: float, a: float, b: float,
          within: tuple[float, float] | None = None) -> mpmath.mpf:  # fmt: skip
    """The root of |T(t)| - limit in [a, b] (one sign change) by bisection on the
    reference alone, 60 halvings. With ``within`` = (lo, hi), the halving stops early
    once the bracket lies inside [lo, hi] or outside it: the root the 60 halvings would
    give lies in every bracket on the way, so whether it is in [lo, hi] is known then
    (and the end returned is on the same side of lo and hi as that root)."""
    lo, hi = Fraction(a), Fraction(b)
    inner = None if within is None else (Fraction(within[0]), Fraction(within[1]))
    f_lo = abs(reference(task, lo)[key]) - limit
    assert f_lo * (abs(reference(task, hi)[key]) - limit) < 0
    for _ in range(60):
        if inner is not None:
            inside = inner[0] <= lo and hi <= inner[1]
            if inside or hi < inner[0] or inner[1] < lo:
                break
        mid = (lo + hi) / 2
        f = abs(reference(task, mid)[key]) - limit
        if (f < 0) == (f_lo < 0):
            lo, f_lo = mid, f
        else:
            hi = mid
    return mpmath.mpf(lo.numerator) / lo.denominator


@pytest.mark.parametrize(
    ("name", "limit"),
    [("case1_crossing.rprpr.yaml", 300.0), ("case2_crossing.rprpr.yaml", 300.0),
     ("zero_speed_crossing.rprpr.yaml", 300.0), ("case1_crossing.rprpr.yaml", 2000.0)],
)  # fmt: skip
def test_point_pass_brackets_hold_the_reference_crossings(name: str, limit: float) -> None:
    task, env = _limited(name, limit)
    checks = env.limit_violations((limit, limit))
    ends = 0
    for key, c in zip(("T1", "T2"), checks, strict=True):
        assert c.passed is False  # a pole: the limit is exceeded about it
        for w in c.windows:
            for lo, hi in ((w.start_lo, w.start_hi), (w.end_lo, w.end_hi)):
                if lo <= 0.0 or hi >= float(env.motion.traj.duration):
                    continue  # a window reaching t = 0 or t_f: no crossing there
                assert 0 <= hi - lo <= c.resolution
                width = 1000 * c.resolution
                root = _root(task, key, limit, lo - width, hi + width, (lo, hi))
                assert lo <= root <= hi, (key, lo, hi, root)
                ends += 1
    assert ends >= 2  # the crossings bracketed


@pytest.mark.parametrize("name", CONFIGS[:2])
def test_at_a_pole_the_arb_scalars_give_nothing_and_beside_it_the_reference(name: str) -> None:
    task = _config(name)
    motion = _motion(task)
    S = Scalars(motion)
    for s, e in motion.instants:
        assert not s.torque_bounded and float(e.exact) == e.hi  # a pole at a float time
        assert S.point(e.hi) is None  # T undefined there: no ball, nothing decided
        t = e.hi + 1e-7
        got = S.point(t)
        assert got is not None
        ref = reference(task, t)
        assert abs(ref["T2"]) > 1e4 or abs(ref["T1"]) > 1e4  # beside the pole
        assert _contains(got[0], ref["T1"]) and _contains(got[1], ref["T2"])

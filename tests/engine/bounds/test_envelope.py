"""Grid-free torque verdicts (engine.envelope) against the independent mpmath reference."""

from __future__ import annotations

import math
from functools import cache

import mpmath
import numpy as np
import pytest

from rprpr.engine.bounds.envelope import Envelope
from rprpr.engine.certified.sampling import grid
from rprpr.engine.certified.zones import make_zone, taylor_at_instant
from rprpr.io.loader import parse_task
from rprpr.model.task import Task
from tests.conftest import task_text
from tests.engine.certified.test_motion import _config, _motion, _task
from tests.reference import delta as reference_delta
from tests.reference import reference


@cache
def _envelope(name: str) -> Envelope:
    return Envelope(_motion(_config(name)))


def _abs_ref(task: Task, t: float, name: str) -> float:
    return abs(float(reference(task, t)[name]))


def test_paper_path2_peak_is_certified_and_grid_free() -> None:
    task = _config("paper_path2.rprpr.yaml")
    peaks = _envelope("paper_path2.rprpr.yaml").torque_peak()
    assert peaks is not None
    for name, p in zip(("T1", "T2"), peaks, strict=True):
        assert p.certified and p.value <= p.upper <= p.value * (1 + 1e-6)
        assert _abs_ref(task, p.t, name) == pytest.approx(p.value, rel=1e-9)  # attained
    assert peaks[0].value == pytest.approx(66.1221, abs=1e-4)
    assert peaks[1].value == pytest.approx(60.5504, abs=1e-4)
    motion = _motion(task)
    for n in (11, 101, 1001, 10001):  # a grid only ever sees less than the peak
        c = motion.sample(grid(task.duration, n))
        for name, p in zip(("T1", "T2"), peaks, strict=True):
            assert np.max(np.abs(c.value[name])) <= p.upper


def test_paper_path2_torque_limit_fails_whatever_the_grid() -> None:
    task = _config("paper_path2.rprpr.yaml")
    t1, t2 = _envelope("paper_path2.rprpr.yaml").limit_violations((66, 61))
    assert t1.passed is False and t2.passed is True and t2.windows == ()
    (w,) = t1.windows
    assert w.start_hi - w.start_lo <= 2 * t1.resolution and w.end_hi - w.end_lo <= 2 * t1.resolution
    assert _abs_ref(task, 0.5 * (w.start_hi + w.end_lo), "T1") > 66
    assert _abs_ref(task, w.start_lo - 1e-6, "T1") < 66 < _abs_ref(task, w.start_hi + 1e-6, "T1")
    assert _abs_ref(task, w.end_hi + 1e-6, "T1") < 66 < _abs_ref(task, w.end_lo - 1e-6, "T1")
    # 11 samples miss the violation entirely: a sampled gate would have passed
    c = _motion(task).sample(grid(task.duration, 11))
    assert np.max(np.abs(c.value["T1"])) < 66


def test_a_limit_touching_the_peak_terminates_undecided_or_failing() -> None:
    env = _envelope("paper_path2.rprpr.yaml")
    peaks = env.torque_peak()
    assert peaks is not None
    t1, _ = env.limit_violations((peaks[0].value, 1000))
    assert t1.passed in (False, None)


def test_saturation_window_around_an_unbounded_instant() -> None:
    task = _config("zero_speed_crossing.rprpr.yaml")
    env = _envelope("zero_speed_crossing.rprpr.yaml")
    peaks = env.torque_peak()
    assert peaks is not None and math.isinf(peaks[0].value) and peaks[0].t == 1.0
    ((s, w1, w2),) = env.saturation_windows((300, 300))
    assert s.t == 1.0 and not s.torque_bounded
    for w, name in ((w1, "T1"), (w2, "T2")):
        assert w is not None and w.pole and w.start_hi < 1.0 < w.end_lo
        assert (
            _abs_ref(task, w.start_lo - 1e-6, name) < 300 < _abs_ref(task, w.start_hi + 1e-6, name)
        )
        assert _abs_ref(task, w.end_hi + 1e-6, name) < 300 < _abs_ref(task, w.end_lo - 1e-6, name)
    assert w1 is not None and w1.start_lo == pytest.approx(0.598678, abs=1e-6)


@pytest.mark.parametrize("name", ["case1_crossing.rprpr.yaml", "zero_speed_crossing.rprpr.yaml"])
@pytest.mark.parametrize("limit", [1e4, 1e6])
def test_crossings_close_to_a_pole_are_bracketed_by_certified_points(
    name: str, limit: float
) -> None:
    # poles of order 1 and 2; |T| reaches these limits within the first box about t_s,
    # where the pieces grow away from the pole: each window's ends are certified points
    # (the reference is below the limit at start_lo and end_hi, above at start_hi and
    # end_lo), within the resolution of each other
    task = _config(name)
    env = Envelope(_motion(task))
    for check, torque in zip(env.limit_violations((limit, limit)), ("T1", "T2"), strict=True):
        (w,) = check.windows
        assert check.passed is False and w.pole
        assert w.start_hi - w.start_lo <= check.resolution
        assert w.end_hi - w.end_lo <= check.resolution
        for t, above in ((w.start_lo, False), (w.start_hi, True), (w.end_lo, True),
                         (w.end_hi, False)):  # fmt: skip
            assert (_abs_ref(task, t, torque) > limit) is above


def test_closest_approach_of_a_near_miss() -> None:
    task = _task("(x - 3)^2 + 1/10000", "2 + t")
    env = Envelope(_motion(task))
    a = env.closest_approach()
    assert a is not None and a.distance == pytest.approx(1e-4, rel=1e-15) and a.t_y == 1.0
    ref = abs(float(reference(task, a.t_delta)["delta"]))
    assert a.delta_lo <= ref <= a.delta_hi * (1 + 1e-12)
    assert a.delta_hi - a.delta_lo <= 1e-6 * a.delta_hi
    assert Envelope(_motion(_config("paper_path2.rprpr.yaml"))).closest_approach() is None


_NEAR_MISSES = {
    # an irrational interior minimum of |δ| (a root of the path's R~ of degree > 1)
    "interior": ("(x - 3)^2/10 + 3/10", "2 + t", "2", "6"),
    # the cubic law ends at E = B: the least |δ| at an end, where x' = 0
    "at an end": ("4/25*x^2 - 19/25*x + 96/25", "2 + 24/25*t^2 - 32/125*t^3", "2.5", "4"),
    # symmetric about x = 3: a rational critical point (a linear factor of R~)
    "rational": ("(x - 3)^2/4 + 1/2", "1 + 2*t", "2", "6"),
    # x(t) turns back at t = 1 (x' = 0 inside): each x is reached twice
    "turning": ("(x - 7/2)^2/10 + 3/10", "2 + 4*t - 2*t^2", "2", "6"),
}


@pytest.mark.parametrize("gap", ["1/10^12", "1/10^30", "1/10^45"])
def test_a_closest_approach_far_below_the_path_scale_stays_exact(gap: str) -> None:
    """E passes AB at 10^-12 ... 10^-45 m: the polynomial's terms cancel there by far more
    than 128 bits; the distance is exact and the bracket of min |δ| non-negative and
    tight (the reference at 60 digits: 6 y/(s1 s2), y = gap at t = 1)."""
    task = _task(f"(x - 3)^2 + {gap}", "2 + t")
    a = Envelope(_motion(task)).closest_approach()
    assert a is not None and a.t_y == 1.0 and a.t_delta == 1.0
    k = int(gap.split("^")[1])
    assert a.distance == 1 / 10**k  # the double nearest 10^-k
    with mpmath.workdps(120):
        g = mpmath.mpf(1) / mpmath.mpf(10) ** k
        true = float(6 * g / (mpmath.sqrt(9 + g * g) * mpmath.sqrt(9 + g * g)))
    assert 0 < a.delta_lo <= true <= a.delta_hi <= a.delta_lo * (1 + 1e-15)


@pytest.mark.parametrize("name", sorted(_NEAR_MISSES))
def test_closest_approach_is_the_least_delta_against_the_reference(name: str) -> None:
    """min |δ| from the critical points: never above |δ| at any of 401 times of the
    60-digit reference (a critical point missed would show), and the reference at the
    reported time inside the bracket."""
    y, x, duration, a1 = _NEAR_MISSES[name]
    task = _task(y, x, duration, a1)
    a = Envelope(_motion(task)).closest_approach()
    assert a is not None and a.delta_lo <= a.delta_hi <= a.delta_lo * (1 + 1e-12)
    tf = float(task.duration)
    grid_min = min(abs(float(reference_delta(task, t))) for t in np.linspace(0, tf, 401))
    assert a.delta_hi <= grid_min * (1 + 1e-12)
    ref = abs(float(reference(task, a.t_delta)["delta"]))
    assert a.delta_lo * (1 - 1e-12) <= ref <= a.delta_hi * (1 + 1e-9)


def test_closest_approach_of_a_motion_without_a_path() -> None:
    """y(t) given directly (pieces): the critical points of δ² in t."""
    text = task_text("x", "timing:\n  duration: 1\n  x: t\n").split("path:")[0] + (
        "motion:\n  pieces:\n    - until: 2\n      x: 2 + t\n      y: 1/2 + (t - 6/5)^2\n"
    )
    task = parse_task(text)
    a = Envelope(_motion(task)).closest_approach()
    assert a is not None

    def delta(t: float) -> float:  # eq. (29) by hand: |δ| = a1 |y|/(s1 s2), 60 digits
        with mpmath.workdps(60):
            t_ = mpmath.mpf(t)
            x, y = 2 + t_, mpmath.mpf(1) / 2 + (t_ - mpmath.mpf(6) / 5) ** 2
            return float(6 * y / (mpmath.hypot(x, y) * mpmath.hypot(x - 6, y)))

    grid_min = min(delta(t) for t in np.linspace(0, 2, 401))
    assert a.delta_lo <= grid_min and a.delta_hi <= grid_min * (1 + 1e-12)
    assert a.delta_lo * (1 - 1e-12) <= delta(a.t_delta) <= a.delta_hi * (1 + 1e-9)
    assert a.delta_hi - a.delta_lo <= 1e-12 * a.delta_hi


def test_through_a_and_b_the_peak_is_the_one_sided_limit() -> None:
    # E at A at t = 0 and at B at t = 2: T is undefined there, bounded on either side;
    # the peak is the supremum, reached as t -> 2- (T1) and t -> 0+ (T2)
    task = _task("x*(x - 6)/10", "3*t")
    peaks = Envelope(_motion(task)).torque_peak()
    assert peaks is not None and all(p.certified for p in peaks)
    assert (peaks[0].t, peaks[1].t) == (2.0, 0.0)
    for p, name, t in ((peaks[0], "T1", 2 - 1e-13), (peaks[1], "T2", 1e-13)):
        ref = _abs_ref(task, t, name)  # within |T'| 1e-13 of the one-sided limit
        assert p.value - 1e-10 <= ref <= p.upper
        assert p.upper <= p.value * (1 + 1e-6)
    assert peaks[0].value == pytest.approx(143.4912707, abs=1e-6)
    c = _motion(task).sample(grid(task.duration, 1001))
    inner = np.abs(c.value["T1"][1:-1])
    assert np.max(inner) <= peaks[0].upper
    t1, _ = Envelope(_motion(task)).limit_violations((100, 1000))
    (w,) = t1.windows
    assert t1.passed is False and w.end_hi == 2.0
    assert _abs_ref(task, w.start_lo - 1e-6, "T1") < 100 < _abs_ref(task, w.start_hi + 1e-6, "T1")


def test_the_peak_beside_an_instant_of_order_60_is_certified() -> None:
    # y = (x - 3)^60, x = 2 + 0.4 t: a touch of order 60 at t = 2.5, bounded; λ = μ/δ
    # loses 30 to 80 digits to cancellation for 0.3 < |t - 2.5| < 1.7, and s1², s2² have
    # complex zeros 2.53 s from the instant: the zone form reaches across that band
    task = _task("(x - 3)^60", "2 + 0.4*t", duration="5")
    motion = _motion(task)
    (s,) = motion.analysis.instants
    assert (s.order, s.t, s.torque_bounded) == (60, 2.5, True)
    zone = make_zone(motion, s, taylor_at_instant(motion, s, 128))
    assert zone is not None and zone.r >= 1.7
    for t in (2.5 - 0.95 * zone.r, 2.5 + 0.5 * zone.r, 2.5 + 0.95 * zone.r):
        ref = reference(task, t)
        for name, ball in zip(("lambda1", "lambda2"), zone.lam(zone.e.eps(np.array([t]))),
                              strict=True):  # fmt: skip
            mid, rad = float(ball.mid[0]), float(ball.rad[0])
            assert abs(mid - float(ref[name])) <= rad and rad <= 1e-8 * (1 + abs(mid))
    peaks = Envelope(motion).torque_peak()
    assert peaks is not None
    for name, p in zip(("T1", "T2"), peaks, strict=True):
        assert p.certified and p.value <= p.upper <= p.value * (1 + 1e-6)
        assert _abs_ref(task, p.t, name) == pytest.approx(p.value, rel=1e-9)  # attained
        for t in np.linspace(0.7, 4.3, 12):  # across the band: below the certified bound
            assert _abs_ref(task, float(t), name) <= p.upper
    assert peaks[0].value == pytest.approx(REF_PEAK_60, rel=1e-9)


REF_PEAK_60 = 3080.84278204547  # |T1(5)| = |T2(0)|, tests/reference.py


@pytest.mark.parametrize(("path", "k"), [("(x - 3)^13", 13), ("(x - 3)^59", 59), ("x - 3", 1)])
def test_zone_form_encloses_the_reference_lambda(path: str, k: int) -> None:
    task = _task(path, "2 + t")
    motion = _motion(task)
    (s,) = motion.analysis.instants
    assert s.order == k
    zone = make_zone(motion, s, taylor_at_instant(motion, s, 128))
    assert zone is not None and zone.r > 0
    for eps in (-0.9 * zone.r, -1e-3 * zone.r, 1e-9, 0.5 * zone.r):
        t = 1.0 + eps
        ref = reference(task, t)
        lam = zone.lam(zone.e.eps(np.array([t])))
        for name, ball in zip(("lambda1", "lambda2"), lam, strict=True):
            mid, rad = float(ball.mid[0]), float(ball.rad[0])
            assert abs(mid - float(ref[name])) <= rad, (name, eps)
            assert rad <= 1e-8 * (1 + abs(mid))


def test_lagrange_form_contains_the_limit_at_a_bounded_instant() -> None:
    from rprpr.engine.certified.zones import taylor_lambda

    task = _config("paper_path2.rprpr.yaml")
    motion = _motion(task)
    (s,) = motion.analysis.instants
    lam = taylor_lambda(motion, s, 2.5 - 1e-3, 2.5 + 1e-3)
    assert lam is not None
    limit = (0.00125, -9.625)  # μ_m/δ_m exactly (engine.certified) and the reference
    for ball, v in zip(lam, limit, strict=True):
        assert abs(float(np.ravel(ball.mid)[0]) - v) <= float(np.ravel(ball.rad)[0])


def test_order_13_bounded_instant_peak_is_certified() -> None:
    # issue 9's table: the float sampler reported torque_peak 840; the true peak is 904
    task = _task("(x - 3)^13", "2 + t")
    peaks = Envelope(_motion(task)).torque_peak()
    assert peaks is not None and all(p.certified for p in peaks)
    assert peaks[0].value == pytest.approx(903.7366, abs=1e-4) and peaks[0].t == 2.0
    assert _abs_ref(task, peaks[0].t, "T1") == pytest.approx(peaks[0].value, rel=1e-9)
    c = _motion(task).sample(grid(task.duration, 1001))
    assert np.max(np.abs(c.value["T1"])) <= peaks[0].upper


def test_the_first_partition_is_cut_finer_where_the_reference_peaks() -> None:
    """The double-precision guess of where |T1| and |T2| peak (``_ladders``) lies within
    5e-5 s of the maxima of the 60-digit reference (path 2: t = 2.74335 s and 0.20245 s
    on a 5e-5 s grid), and the partition's finest boxes (h/64) sit about it."""
    h = 5 / 512
    cuts = np.sort(_envelope("paper_path2.rprpr.yaml")._ladders(h))
    for t_ref in (2.74335, 0.20245):
        assert np.abs(cuts - t_ref).min() <= 5e-5
        near = cuts[np.abs(cuts - t_ref) <= h / 2 - h / 64]  # the core: 32 boxes a side
        assert len(near) >= 32 and np.diff(near).max() <= h / 64 * (1 + 1e-9)

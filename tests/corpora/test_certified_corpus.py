"""The certified sampler (engine.certified) on issue 9's corpus, against tests/reference.py.

Each motion is sampled at t_s ± 10^-k (k = 0 … 13) about each of its instants, at t_s
itself (the float nearest it), and at grid points of N = 11, 1001 and 2001 samples: the
ones nearest the instants and a fixed handful. At every such time every field must be
within 1e-9 (1 + |ref|) of the independent mpmath reference (θ on its continuous branch,
``reference.theta_branch``), carry a radius that certifies it, and be NaN exactly where
the reference says the value is undefined, with the right reason code. The whole grids
are sampled too: every value certified, and the same at a time as when that time is
sampled alone (the value at t never depends on the grid).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rprpr.engine.certified.motion import (
    AT_A,
    AT_B,
    FIELDS,
    OK,
    ON_LINE,
    POLE,
    TOL,
    CertifiedMotion,
)
from rprpr.engine.certified.sampling import grid
from rprpr.engine.exact.singular import analyse
from rprpr.engine.exact.trajectory import trajectory
from rprpr.io.loader import parse_task
from rprpr.model.task import Task
from tests.conftest import CONFIGS, task_text
from tests.corpora import certified_reference as store
from tests.reference import limit, limit_of, reference, theta_branch

SIZES = (11, 1001, 2001)
KS = range(14)  # t_s ± 10^-k
KS_EXTRA = (0, 2, 4, 6, 8, 10, 12, 13)


@dataclass(frozen=True)
class Motion:
    """A task (path y, timing x(t), duration, a1) and its instants of interest: exact
    rationals, or floats near irrational ones (sampled there, never at the instant)."""

    y: str
    x: str
    instants: tuple[Fraction | float, ...]
    duration: str = "2"
    a1: str = "6"
    config: str = ""  # a shipped task file instead (y, x, duration, a1 unused)


ONE = (Fraction(1),)
MICRO = (Fraction(1), 1 + Fraction(1, 10**6))  # 1 s and 1 µs later
ISSUE: dict[str, Motion] = {
    # x - 3 = ±(t - 1)^k on the line y = x - 3: an instant of order k, lacunary series
    **{
        f"lacunary_{k}{name}": Motion("x - 3", f"3 {sign} (t - 1)^{k}", ONE)
        for k in range(2, 14)
        for name, sign in (("+", "+"), ("-", "-"))
    },
    **{f"order_{m}": Motion(f"(x - 3)^{m}", "2 + t", ONE) for m in (9, 13, 59)},
    **{f"pole_{m}": Motion(f"(x - 3)^{m}", "2 + t + t*(t - 1)/4", ONE) for m in (1, 2, 3, 4)},
    "instant_at_0": Motion("x - 2", "2 + t + t^2/3", (Fraction(0),)),
    "bounded_instant_at_0": Motion("(x - 2)^3", "2 + t", (Fraction(0),)),
    "instant_at_tf": Motion("x - 4", "2 + t", (Fraction(2),)),
    "bounded_instant_at_tf": Motion("(x - 4)^5", "2 + t", (Fraction(2),)),
    # t_s within 1e-12 of a grid point: non-dyadic rational; irrational (two of them)
    "rational_near_grid": Motion("x - 3 - 1e-12", "2 + t", (1 + Fraction(1, 10**12),)),
    "irrational_near_grid": Motion("(x - 2)^2 - 1 - 2e-12", "2 + t", (math.sqrt(1 + 2e-12),)),
    "irrational_pair_near_grid": Motion(
        "(x - 2.5)^2 - 2e-24", "2 + t", (0.5 - math.sqrt(2) * 1e-12, 0.5 + math.sqrt(2) * 1e-12)
    ),
    "irrational_pole": Motion("x - 3", "2 + t^2/2", (math.sqrt(2),)),
    # through A and B: at the ends, inside, at a non-dyadic time, of order 3, and E at A
    # a microsecond before a pole (inside that instant's zone)
    "A_and_B_at_the_ends": Motion("x*(x - 6)/10", "3*t", (Fraction(0), Fraction(2))),
    "A_and_B_inside": Motion("x*(x - 6)/10", "4*t - 1", (Fraction(1, 4), Fraction(7, 4))),
    "A_at_a_third": Motion("x*(x - 6)/10", "3*t - 1", (Fraction(1, 3),)),
    "A_order_3": Motion("x^3", "t - 1", ONE),
    "B_on_a_line": Motion("x - 6", "5 + t", ONE),
    "A_inside_a_zone": Motion("x*(x - 1e-6)", "t - 1", (Fraction(1), 1 + Fraction(1, 10**6))),
    "tf_1e-3": Motion("(x - 3)^3", "2 + 2000*t", (Fraction(1, 2000),), duration="0.001"),
    "tf_1000": Motion("x - 3", "2 + t/500", (Fraction(500),), duration="1000"),
    "a1_1000": Motion("(x - 500)^3", "499 + t", ONE, a1="1000"),
    # two instants a microsecond apart, the first bounded, the second a pole
    "two_instants_1e-6": Motion("(x - 3)*(x - 3 - 1e-6)", "2 + t", MICRO),
    "two_instants_1e-6_order_2": Motion("(x - 3)^2*(x - 3 - 1e-6)", "2 + t", MICRO),
}  # fmt: skip
# beyond the issue's list (sampled at fewer t_s ± 10^-k)
EXTRA: dict[str, Motion] = {
    # y = 0 behind A (on leg 1's cut and leg 2's), crossing and touching; beyond B
    "behind_A": Motion("x + 1", "t - 2", ONE),
    "behind_A_touching": Motion("(x + 1)^2", "t - 2", ONE),
    "beyond_B": Motion("x - 7", "6 + t", ONE),
    # a pole behind A a microsecond before E reaches A: both on leg 2's cut, θ2 at A is
    # the limit from the left on the branch the first crossing moved it to
    "A_after_a_pole_behind_it": Motion("x*(x + 1e-6)", "t - 1", (2 - MICRO[1], ONE[0])),
    # irrational instants of order 3 and 5 and on leg 1's cut; near misses (no real
    # instant, complex ones 1e-10 and 1e-15 away)
    "irrational_order_3": Motion("(x^2 - 2)^3", "t", (math.sqrt(2),)),
    "irrational_order_5": Motion("(x^2 - 2)^5", "t", (math.sqrt(2),)),
    "irrational_behind_A": Motion("x^2 - 2", "t - 3", (3 - math.sqrt(2),)),
    "near_miss_1e-20": Motion("(x - 3)^2 + 1e-20", "2 + t", ONE),
    "near_miss_1e-30": Motion("(x - 3)^2 + 1e-30", "2 + t", ONE),
    # on the singular line y = 0 (δ ≡ 0): λ and T undefined; θ2 stays π through A
    "on_the_line": Motion("0", "1 + t", ONE),
    "on_the_line_through_A": Motion("0", "t - 1", ONE),
    "on_the_line_through_B": Motion("0", "5 + t", ONE),
    "pole_at_1e-12": Motion("x - 2 - 1e-12", "2 + t", (Fraction(1, 10**12),)),
    "pole_at_2^-40": Motion("x - 2 - 1/1099511627776", "2 + t", (Fraction(1, 2**40),)),
    "tf_1000_order_5": Motion("(x - 3)^5", "2 + t/500", (Fraction(500),), duration="1000"),
    # the shipped task files (quintic timing for the paper's paths)
    **{
        name: Motion("", "", (Fraction(ts),), duration=tf, config=f"{name}.rprpr.yaml")
        for name, ts, tf in (
            ("paper_path1", "5/2", "5"), ("paper_path2", "5/2", "5"),
            ("case1_crossing", "2", "4"), ("case2_crossing", "2", "4"), ("touch", "2", "4"),
        )
    },
}  # fmt: skip
CORPUS = ISSUE | EXTRA

# -- cached tasks, motions and references -------------------------------------------------

_TASKS: dict[str, Task] = {}
_MOTIONS: dict[str, CertifiedMotion] = {}
_REFS: dict[tuple[str, float], dict[str, Any]] = {}


def _task(name: str) -> Task:
    if name not in _TASKS:
        m = CORPUS[name]
        timing = f"timing:\n  duration: {m.duration}\n  x: {m.x}\n"
        text = (CONFIGS / m.config).read_text() if m.config else task_text(m.y, timing, a1=m.a1)
        _TASKS[name] = parse_task(text)
    return _TASKS[name]


def _motion(name: str) -> CertifiedMotion:
    if name not in _MOTIONS:
        task = _task(name)
        traj = trajectory(task)
        _MOTIONS[name] = CertifiedMotion(traj, task.robot, analyse(traj, task.robot, task.checks))
    return _MOTIONS[name]


def _expected(name: str, t: float) -> dict[str, Any]:
    """The reference's values at t (None: undefined) and the reason code expected: as
    stored (tests/corpora/certified_reference.py), else computed now."""
    key = (name, t)
    if key not in _REFS:
        _REFS[key] = store.lookup(repr(CORPUS[name]), t) or computed(name, t)
    return _REFS[key]


def computed(name: str, t: float) -> dict[str, Any]:
    """``_expected`` from tests/reference.py itself."""
    task = _task(name)
    ref = reference(task, t)
    reason = OK
    if ref["s1"] == 0:
        reason = AT_A
    elif ref["s2"] == 0:
        reason = AT_B
    elif task.path.is_zero():
        reason = ON_LINE
        ref |= {"lambda1": None, "lambda2": None, "T1": None, "T2": None}
    elif ref["y"] == 0:  # at a root of y: λ and T are two-sided limits
        lim = limit(task, Fraction(t))
        if lim is None:
            reason = POLE
            lim = {"lambda1": limit_of(task, Fraction(t), "lambda1")}
            lim |= {"lambda2": None, "T1": None, "T2": None}
        ref = {**ref, **lim}
    ref["theta1"], ref["theta2"] = theta_branch(task, t)
    return {**ref, "reason": reason}


# -- the times ----------------------------------------------------------------------------


def _near_instants(name: str) -> list[float]:
    m = CORPUS[name]
    tf = float(Fraction(m.duration))
    out = []
    for ts in m.instants:
        f = float(ts)
        out.append(f)
        for k in KS if name in ISSUE else KS_EXTRA:
            out += [t for t in (f - 10.0**-k, f + 10.0**-k) if 0 <= t <= tf]
    return out


def _grid_times(name: str, n: int) -> list[float]:
    """The grid points nearest each instant and a fixed handful."""
    g = grid(_task(name).duration, n)
    picks = {0, n - 1, n // 3}
    for ts in CORPUS[name].instants:
        # a stable sort: a tie (t_s on the grid, its neighbours equally near) goes to the
        # earlier point in every numpy
        picks |= {int(i) for i in np.argsort(np.abs(g - float(ts)), kind="stable")[:2]}
    return [float(g[i]) for i in sorted(picks) if i < n]


def _times(name: str) -> list[float]:
    times = set(_near_instants(name))
    for n in SIZES:
        times |= set(_grid_times(name, n))
    return sorted(times)


# -- the checks ---------------------------------------------------------------------------


def _mixed(value: float, ref: Any) -> float:
    """|value - ref| / (1 + |ref|), in mpmath; a float estimate instead when it is at most
    TOL/2 (it is within 1e-15 of the mpmath value then: every comparison with TOL
    decides alike, and the failure messages print the mpmath value)."""
    r = float(ref)
    if math.isfinite(r):
        estimate = abs(value - r) / (1 + abs(r))
        if estimate <= TOL / 2:
            return estimate
    return float(abs(mpmath.mpf(value) - ref) / (1 + abs(ref)))


def _check(name: str, times: list[float]) -> list[str]:
    """Every field at each time against the reference: the failures, as text."""
    c = _motion(name).sample(np.array(times))
    bad = []
    for j, t in enumerate(times):
        ref = _expected(name, t)
        if c.reason[j] != ref["reason"]:
            bad.append(f"t={t!r}: reason {c.reason[j]}, expected {ref['reason']}")
        for f in FIELDS:
            v, r = float(c.value[f][j]), float(c.radius[f][j])
            if ref[f] is None:
                if not math.isnan(v):
                    bad.append(f"t={t!r} {f}: {v!r}, expected NaN")
            elif not math.isfinite(v):
                bad.append(f"t={t!r} {f}: {v!r}, expected {mpmath.nstr(ref[f], 12)}")
            elif _mixed(v, ref[f]) > TOL or not r <= TOL * (1 + abs(v)):
                err = _mixed(v, ref[f])
                bad.append(
                    f"t={t!r} {f}: {v!r} ± {r:.2g}, ref {mpmath.nstr(ref[f], 17)}, err {err:.2g}"
                )
    return bad


@pytest.mark.parametrize("name", sorted(CORPUS))
def test_every_value_matches_the_reference(name: str) -> None:
    bad = _check(name, _times(name))
    assert not bad, "\n".join(bad[:20])


@pytest.mark.parametrize("name", sorted(CORPUS))
def test_whole_grids_are_certified_and_agree_with_the_times_alone(name: str) -> None:
    """The grids of 11 and 2001 samples, sampled whole (the grid of 1001 is every other
    point of 2001's, the same floats: the value at t does not depend on the grid)."""
    motion = _motion(name)
    duration = _task(name).duration
    samples = {n: motion.sample(grid(duration, n)) for n in (11, 2001)}
    assert np.array_equal(grid(duration, 1001), samples[2001].t[::2])
    assert np.array_equal(samples[11].t, samples[2001].t[::200])
    for n, c in samples.items():
        for f in FIELDS:  # every defined value certified; NaN only with a reason
            finite = np.isfinite(c.value[f])
            v, r = c.value[f][finite], c.radius[f][finite]
            assert np.all(r <= TOL * (1 + np.abs(v))), (n, f)
            assert np.all(c.reason[~finite] != OK), (n, f)
    for n in SIZES:
        picked = np.array(_grid_times(name, n))
        alone = motion.sample(picked)
        for c in (samples[2001], samples[11]) if n == 11 else (samples[2001],):
            idx = np.searchsorted(c.t, picked)
            assert np.array_equal(c.t[idx], picked)
            for f in FIELDS:  # the same doubles (NaN for NaN), as assert_array_equal
                got, want = c.value[f][idx], alone.value[f]
                assert np.array_equal(got, want, equal_nan=True), (f, got, want)
            assert np.array_equal(c.reason[idx], alone.reason), (c.reason[idx], alone.reason)


@settings(derandomize=True, database=None, max_examples=30, deadline=None)
@given(
    name=st.sampled_from(sorted(set(CORPUS) - {"order_59"})),
    n=st.integers(2, 300),
    times=st.integers(1, 6),
    i=st.integers(0, 10**6),
    extra=st.lists(st.integers(0, 13), max_size=4),
)
def test_the_value_at_t_is_the_same_on_every_grid_containing_t(
    name: str, n: int, times: int, i: int, extra: list[int]
) -> None:
    """A grid point t of N samples is also a point of the grid of times (N - 1) + 1 (the
    same rational, the same float); its values there, alone and beside times close to
    an instant are the same."""
    motion = _motion(name)
    duration = _task(name).duration
    coarse, fine = grid(duration, n), grid(duration, times * (n - 1) + 1)
    j = i % n
    t = float(coarse[j])
    assert fine[times * j] == t
    ts = float(CORPUS[name].instants[0])
    beside = np.array([t, *(ts + 10.0**-k for k in extra)])
    samples = [motion.sample(coarse), motion.sample(fine), motion.sample(beside)]
    for f in FIELDS:
        got = [c.value[f][k] for c, k in zip(samples, (j, times * j, 0), strict=True)]
        assert np.array_equal(got, [got[0]] * 3, equal_nan=True), (f, got)
    assert len({int(c.reason[k]) for c, k in zip(samples, (j, times * j, 0), strict=True)}) == 1


# -- the stored reference (certified_reference.py) cannot rot ------------------------------


def test_the_store_holds_every_time_the_corpus_samples_and_nothing_else() -> None:
    """Every (motion, time) the tests above read is stored, under the motion's current
    definition; regenerate with ``python -m tests.corpora.certified_reference``."""
    want = {repr(CORPUS[name]): {repr(t) for t in _times(name)} for name in CORPUS}
    have = {motion: set(times) for motion, times in store.stored().items()}
    assert have == want


def _recomputed_time(name: str) -> float:
    """One of the motion's stored times, alternately (by name) the nearest to its first
    instant (where the reference takes limits, and θ its branch) and the middle one."""
    times = _times(name)
    if sorted(CORPUS).index(name) % 2:
        return times[len(times) // 2]
    return min(times, key=lambda t: abs(t - float(CORPUS[name].instants[0])))


@pytest.mark.slow  # the stored reference recomputed at 60 digits and more: it never changes
@pytest.mark.parametrize("name", sorted(CORPUS))
def test_the_stored_reference_is_the_reference_recomputed(name: str) -> None:
    """The stored values are tests/reference.py's, to the digits stored."""
    t = _recomputed_time(name)
    entry, fresh = store.lookup(repr(CORPUS[name]), t), computed(name, t)
    assert entry is not None and entry.keys() == fresh.keys(), t
    assert entry["reason"] == fresh["reason"], t
    for f, v in fresh.items():
        if f == "reason" or v is None:
            assert entry[f] == v, (t, f)
        else:
            assert abs(entry[f] - v) <= mpmath.mpf(2) ** (1 - store.BITS) * abs(v), (t, f)


# -- what the corpus claims of its motions, from the reference alone ----------------------


def _growth(name: str, ts: Fraction, field: str) -> float:
    """d log|field| / d log(1/ε) at t_s + ε, from the reference at ε = 1e-20 and 1e-30."""
    task = _task(name)
    a = reference(task, ts + Fraction(1, 10**20))[field]
    b = reference(task, ts + Fraction(1, 10**30))[field]
    return float(mpmath.log10(abs(b) / abs(a))) / 10


@pytest.mark.parametrize("m", [1, 2, 3, 4])
def test_poles_of_order_1_to_4(m: int) -> None:
    name = f"pole_{m}"
    for field in ("lambda2", "T1", "T2"):  # |λ2|, |T| ~ |ε|^-m
        assert _growth(name, Fraction(1), field) == pytest.approx(m, abs=1e-6)
    assert _expected(name, 1.0)["reason"] == POLE
    (s,) = _motion(name).analysis.instants
    assert s.order == m and not s.torque_bounded


def test_two_instants_a_microsecond_apart_differ_in_boundedness() -> None:
    for name in ("two_instants_1e-6", "two_instants_1e-6_order_2"):
        task = _task(name)
        first, second = CORPUS[name].instants
        assert limit(task, first) is not None and limit(task, second) is None
        assert [s.torque_bounded for s in _motion(name).analysis.instants] == [True, False]
        assert _growth(name, Fraction(second), "lambda2") == pytest.approx(1, abs=1e-6)


# -- issue 9's table, the rows not already in test_certified.py ---------------------------


def test_order_13_at_t0_lambda1_is_the_reference_value() -> None:
    # y = (x - 3)^13, x = 2 + t at t = 0: the issue's T1 = -138.50 is confirmed, its
    # λ1 = 63.80 is not: the reference gives 57.2560 for these links
    ref = _expected("order_13", 0.0)
    assert float(ref["lambda1"]) == pytest.approx(57.25597440, abs=1e-8)
    assert float(ref["T1"]) == pytest.approx(-138.4988102, abs=1e-7)
    c = _motion("order_13").sample(np.array([0.0]))
    assert _mixed(c.value["lambda1"][0], ref["lambda1"]) <= TOL
    assert _mixed(c.value["T1"][0], ref["T1"]) <= TOL


def test_end_point_at_a_inside_a_series_zone_is_undefined() -> None:
    # y = x (x - 1e-6), x = t - 1: E at A at t = 1, a pole a microsecond later; at A the
    # one-sided limits of δ, λ2, T1 and T2 differ (they change sign: s1 does not), so
    # they are undefined there, not finite
    task = _task("A_inside_a_zone")
    eps = Fraction(1, 10**30)
    left, right = (reference(task, 1 + s * eps) for s in (-1, 1))
    for f in ("delta", "lambda2", "T1", "T2"):
        assert left[f] * right[f] < 0 and abs(left[f] - right[f]) > 1e-6, f
    c = _motion("A_inside_a_zone").sample(np.array([1.0 - 1e-13, 1.0, 1.0 + 1e-13]))
    assert list(c.reason) == [OK, AT_A, OK]
    for f in ("theta1", "theta1_dot", "s1_dot", "delta", "lambda1", "lambda2", "T1", "T2"):
        assert np.isnan(c.value[f][1]) and np.all(np.isfinite(c.value[f][[0, 2]])), f


@pytest.mark.parametrize(
    ("name", "legs"),
    [("behind_A", (1, 2)), ("lacunary_3-", (1, 2)), ("irrational_behind_A", (1, 2)),
     ("A_after_a_pole_behind_it", (2,))],
)  # fmt: skip
def test_the_reference_theta_is_continuous(name: str, legs: tuple[int, ...]) -> None:
    """The reference's own θ (``theta_branch``) has no jump on a fine grid of rationals
    (only leg 2 where E passes A: θ1 turns by π there) and starts at atan2's value."""
    task = _task(name)
    tf = Fraction(CORPUS[name].duration)
    ts = [tf * i / 100 for i in range(101)]
    values = [theta_branch(task, t) for t in ts]
    for leg in legs:
        th = [v[leg - 1] for v in values]
        if th[0] is not None and reference(task, 0.0)["y"] != 0:
            assert th[0] == pytest.approx(float(reference(task, 0.0)[f"theta{leg}"]), abs=1e-15)
        steps = [abs(b - a) for a, b in itertools.pairwise(th) if a is not None and b is not None]
        assert max(steps) < 0.5, (leg, max(steps))

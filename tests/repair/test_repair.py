"""``rprpr repair``: values derived here, independently of the engine (closed forms of the
bumps, eq. (34) at y = 0 by hand, tests/reference.py for the torque limit at t_s)."""

from __future__ import annotations

import itertools
import math
import random
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import pytest
from flint import fmpq, fmpq_poly

from rprpr import load_task, parse_task
from rprpr.engine.audit import audit
from rprpr.io.writer import task_text
from rprpr.repair import NoRepair, repair
from tests import reference as R
from tests.conftest import CONFIGS, run_cli

LEGS = """robot:
  a1: 6
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: %s, inertia: 0.05, r: %s}
"""


def _task(body: str, m5: str = "1.0", r5: str = "0.5", name: str = "t") -> str:
    return f"name: {name}\n" + LEGS % (m5, r5) + body


def _piece(task, t):  # type: ignore[no-untyped-def]
    return next(p for p in task.motion if p.start <= t <= p.end)


def _d(p: fmpq_poly, k: int) -> fmpq_poly:
    for _ in range(k):
        p = p.derivative()
    return p


def _ends_kept(old, new) -> None:  # type: ignore[no-untyped-def]
    """Start and end points with their velocities and accelerations unchanged."""
    for t in (fmpq(0), old.duration):
        a, b = _piece(old, t), _piece(new, t)
        for k in range(3):
            assert _d(a.x, k)(t) == _d(b.x, k)(t)
            assert _d(a.y, k)(t) == _d(b.y, k)(t)
    assert new.duration == old.duration


def _round_trip(task):  # type: ignore[no-untyped-def]
    """The repaired task written and read back passes strict."""
    back = parse_task(task_text(task))
    assert audit(back, strict=True).passed
    return back


def test_example_1_becomes_a_first_order_consistent_crossing() -> None:
    old = load_task(CONFIGS / "paper_path1.rprpr.yaml")
    r = repair(old, slope=fmpq(1, 4))
    (s,) = r.after.singularities
    assert r.after.passed and s.order == 1 and s.consistent and s.torque_bounded
    assert s.t_exact == Fraction(5, 2) and abs(s.slope) >= 0.25
    _ends_kept(old, r.task)
    _round_trip(r.task)
    # the bump Δy = b τ (1 - (τ/w)²)³ with b = slope ẋ(t_s): ẋ(5/2) of the quintic 2 + 2 s(t/5)
    # is 2 * 30/16 / 5 = 3/4; its maximum |b| w 7^(-1/2) (6/7)³ at τ = ±w/√7
    (c,) = r.changes
    b, w = Fraction(1, 4) * Fraction(3, 4), Fraction(int(c.window.p), int(c.window.q))
    assert r.path_deviation is not None
    expected = float(b * w) / math.sqrt(7) * (6 / 7) ** 3
    assert r.path_deviation[0] == pytest.approx(expected, rel=1e-12)  # exact maximum
    # independently: the new y(t) minus the old path at the new x(t), on a fine grid
    dev = 0.0
    for k in range(2001):
        t = fmpq(k, 400)
        p = _piece(r.task, t)
        dev = max(dev, abs(float(p.y(t) - old.path(p.x(t)))))  # type: ignore[misc]
    assert dev == pytest.approx(expected, rel=1e-4)


def test_path_2_with_a_heavier_leg_is_repaired_by_its_timing_alone() -> None:
    text = (CONFIGS / "paper_path2.rprpr.yaml").read_text()
    text = text.replace("5: {mass: 1.0", "5: {mass: 2.0")
    old = parse_task(text)
    (s0,) = audit(old).singularities
    assert not s0.consistent and s0.pole_order == 1
    r = repair(old, keep="path")
    assert r.path_kept and r.task.path == old.path
    (s,) = r.after.singularities
    assert s.consistency_residual == 0 and s.torque_bounded and r.after.passed
    # case 3 at x = 3: (m3 + m5) ẍ = ẏ² (m5 r5 / s2² - m3 r3 / s1²), ẏ = p'(3) ẋ = 0.2 * 3/4
    ydot = Fraction(1, 5) * Fraction(3, 4)
    closed = ydot**2 * (2 * Fraction(1, 2) / 9 - Fraction(1, 2) / 9) / 3
    p = _piece(r.task, fmpq(5, 2))
    assert _d(p.x, 2)(fmpq(5, 2)) == fmpq(closed.numerator, closed.denominator)
    assert p.x(fmpq(5, 2)) == 3 and _d(p.x, 1)(fmpq(5, 2)) == fmpq(3, 4)
    _ends_kept(old, r.task)
    _round_trip(r.task)
    # T(t_s) against the independent reference, on the window's polynomial extended
    ref = R.limit(replace(r.task, x_of_t=p.x, pieces=(), law="explicit"), Fraction(5, 2))
    assert ref is not None and s.torque_at_singularity is not None
    assert s.torque_at_singularity[0] == pytest.approx(float(ref["T1"]), rel=1e-9)
    assert s.torque_at_singularity[1] == pytest.approx(float(ref["T2"]), rel=1e-9)
    limit = r.after.torque_peak
    assert limit is not None and max(limit[0].value, limit[1].value) < 300


def test_zero_speed_crossing_gets_a_speed() -> None:
    old = load_task(CONFIGS / "zero_speed_crossing.rprpr.yaml")
    r = repair(old)
    (s,) = r.after.singularities
    assert s.order == 1 and s.speed > 0 and r.after.passed and r.path_kept
    (c,) = r.changes
    assert c.speed[0] == 0 and c.speed[1] > 0
    # legs alike at the midpoint x = 3 = a1/2: eq. (34) needs ẍ(t_s) = 0
    p = _piece(r.task, fmpq(1))
    assert _d(p.x, 2)(fmpq(1)) == 0 and p.x(fmpq(1)) == 3
    _ends_kept(old, r.task)
    _round_trip(r.task)
    with pytest.raises(NoRepair, match="zero speed"):
        repair(old, keep="timing")


def test_a_touch_is_lifted_clear_of_the_line_or_refused_with_the_path_kept() -> None:
    old = load_task(CONFIGS / "touch.rprpr.yaml")
    r = repair(old, clearance=fmpq(1, 20))
    assert r.after.passed and r.after.singularities == []
    p = _piece(r.task, fmpq(2))
    assert p.y(fmpq(2)) == fmpq(1, 20)  # lifted by the clearance at the touch
    assert r.path_deviation is not None and r.path_deviation[0] == pytest.approx(0.05, rel=1e-14)
    _ends_kept(old, r.task)
    _round_trip(r.task)
    with pytest.raises(NoRepair, match="touch"):
        repair(old, keep="path")


TWO = """path:
  y: 1/27*(x - 2)^3*(x - 4)^3
  from: [1, 1]
  to: [5, 1]
timing:
  duration: 4
  x: 1 + t
"""


def test_two_failing_crossings_are_both_repaired() -> None:
    old = parse_task(_task(TWO))
    assert [s.order for s in audit(old).singularities] == [3, 3]
    r = repair(old)
    assert [s.t_exact for s in r.after.singularities] == [1, 3]
    assert all(s.order == 1 and s.torque_bounded for s in r.after.singularities)
    assert r.after.passed and len(r.changes) == 2
    _round_trip(r.task)


def test_a_torque_limit_exceeded_away_from_singular_instants_is_refused() -> None:
    text = (CONFIGS / "paper_path2.rprpr.yaml").read_text()
    old = parse_task(text.replace("[300, 300]", "[20, 20]"))
    with pytest.raises(NoRepair, match=r"RPR202.*not at a singular instant"):
        repair(old)


def test_a_passing_task_is_unchanged() -> None:
    old = load_task(CONFIGS / "paper_path2.rprpr.yaml")
    r = repair(old)
    assert not r.changed and r.task is old and r.changes == ()
    code, out, _ = run_cli("repair", str(CONFIGS / "paper_path2.rprpr.yaml"), "-o", "/nonexistent")
    assert code == 0 and "nothing to repair" in out


REPAIRABLE = ["case1_crossing", "case2_crossing", "paper_path1", "piecewise_timing",
              "touch", "trapezoidal", "zero_speed_crossing"]  # fmt: skip


def test_the_repairable_configs_are_every_shipped_config_that_fails_strict() -> None:
    failing = sorted(
        p.name.removesuffix(".rprpr.yaml")
        for p in CONFIGS.glob("*.rprpr.yaml")
        if load_task(p).robot.mechanism == "rprpr"  # no repair for a 5R in this build
        and not audit(load_task(p), strict=True).passed
    )
    assert failing == REPAIRABLE


@pytest.mark.parametrize("name", REPAIRABLE)
def test_round_trip_of_the_shipped_failing_configs(name: str, tmp_path: Path) -> None:
    src = str(CONFIGS / f"{name}.rprpr.yaml")
    assert run_cli("check", "--strict", src)[0] == 1
    out = str(tmp_path / "r.rprpr.yaml")
    code, text, _ = run_cli("repair", src, "-o", out)
    assert code == 0 and f"checked {out} (strict): pass" in text
    assert run_cli("check", "--strict", out)[0] == 0


def test_keep_path_with_a_zero_slope_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "r.yaml"
    code, _, err = run_cli(
        "repair", str(CONFIGS / "paper_path1.rprpr.yaml"), "--keep", "path", "-o", str(out)
    )
    assert code == 1 and "slope dy/dx = 0" in err and "nothing written" in err
    assert not out.exists()


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_generated_zero_slope_crossings_with_random_legs(seed: int) -> None:
    rng = random.Random(seed)
    xs = Fraction(rng.randint(5, 25), 10)  # the crossing, 0.5 .. 2.5 (case 3, a1 = 6)
    half = Fraction(rng.randint(3, 8), 10)
    m5, r5 = f"{rng.randint(5, 30) / 10}", f"{rng.randint(2, 9) / 10}"
    body = f"""path:
  y: {rng.choice([1, -1]) * rng.randint(1, 9)}/10*(x - {xs})^3
  from: [{xs - half}, {-(half**3)}]
  to: [{xs + half}, {half**3}]
timing:
  duration: 2
  law: quintic
"""
    text = _task(body, m5, r5).replace(f"{-(half**3)}]", "0]").replace(f"{half**3}]", "0]")
    # from/to heights from the path itself
    old = parse_task(_fixed_ends(text))
    assert not audit(old, strict=True).passed
    r = repair(old)
    (s,) = r.after.singularities
    assert s.order == 1 and s.consistency_residual == 0 and r.after.passed
    _ends_kept(old, r.task)
    _round_trip(r.task)


def _fixed_ends(text: str) -> str:
    """path.from/to on the path y(x) (computed with fractions here)."""
    lines = text.splitlines()
    y = next(ln for ln in lines if ln.startswith("  y:")).split(":", 1)[1].strip()
    k, rest = y.split("*(x - ")
    xs = Fraction(rest.split(")")[0])
    coef = Fraction(k)
    out = []
    for ln in lines:
        if ln.startswith(("  from:", "  to:")):
            key, v = ln.split(":", 1)
            x = Fraction(v.strip(" []").split(",")[0])
            ln = f"{key}: [{x}, {coef * (x - xs) ** 3}]"
        out.append(ln)
    return "\n".join(out) + "\n"


def test_the_largest_change_is_the_exact_maximum_of_the_difference() -> None:
    """``roots.max_abs``: the maximum of |p| over [a, b] at an irrational critical point
    (t^3 - 2t on [0, 2]: |p| = 4 at t = 2; on [0, 1]: 4 sqrt(2/3)/3 at t = sqrt(2/3))."""
    from rprpr.engine.exact.roots import max_abs

    p = fmpq_poly([0, -2, 0, 1])
    assert max_abs(p, fmpq(0), fmpq(2)) == (pytest.approx(4.0, rel=1e-15), 2.0)
    m, t = max_abs(p, fmpq(0), fmpq(1))
    true = 4 * math.sqrt(2 / 3) / 3
    assert true <= m <= true * (1 + 1e-14) and t == pytest.approx(math.sqrt(2 / 3), rel=1e-14)
    # a double critical point (p' = 3 (t - 1/2)^2 ...) and a constant
    q = fmpq_poly([0, fmpq(3, 4), fmpq(-3, 2), 1])  # (t - 1/2)^3 + 1/8
    assert max_abs(q, fmpq(0), fmpq(1)) == (pytest.approx(0.25, rel=1e-15), 1.0)
    assert max_abs(fmpq_poly([fmpq(-1, 3)]), fmpq(0), fmpq(1))[0] == pytest.approx(1 / 3, rel=1e-15)


def test_a_trapezoidal_law_is_blended_at_its_knots_into_a_c2_motion() -> None:
    """The trapezoid's C1 knots (acceleration jumps, RPR204 in strict mode) are blended:
    the new x(t) is C2 at every break, keeps its ends, rests and the crossing, and the
    reported largest change is the maximum of |Δx| (checked on a dense rational grid,
    and against the closed form: at the blend about the knot t_b, where x_R - x_L =
    -(a/2)(t - t_b)², Δx = (x_R - x_L) S on the left and (x_R - x_L)(S - 1) on the right)."""
    old = load_task(CONFIGS / "trapezoidal.rprpr.yaml")
    assert not audit(old, strict=True).passed
    r = repair(old)
    assert r.after.passed and r.path_deviation is None and r.task.path == old.path
    assert [n.split(":")[0] for n in r.notes] == ["knot t = 5/3 s", "knot t = 10/3 s"]
    new = r.task.motion
    for p, q in itertools.pairwise(new):  # C2 at every break, exactly
        a, b = p.x, q.x
        for _ in range(3):
            assert a(p.end) == b(p.end)
            a, b = a.derivative(), b.derivative()
    _ends_kept(old, r.task)
    (s,) = r.after.singularities
    assert s.t_exact == Fraction(5, 2) and s.consistent and s.order == 1
    # the largest change: a dense scan of |Δx| (a lower estimate) and the bound reported
    scan = 0.0
    for k in range(20001):
        t = fmpq(5 * k, 20000)
        xn = next(p for p in new if p.start <= t <= p.end).x(t)
        xo = next(p for p in old.motion if p.start <= t <= p.end).x(t)
        scan = max(scan, abs(float(xn - xo)))
    assert r.timing_change is not None
    assert scan <= r.timing_change[0] <= scan * (1 + 1e-6)
    # closed form at the first knot: a = V/t_b = 0.36, blend ±w; |Δx| = (a/2) τ² S(σ)
    w = next(p for p in new if p.start < fmpq(5, 3) < p.end)
    half = (w.end - w.start) / 2
    m = max(
        float(fmpq(9, 50) * (fmpq(k, 4000) * 2 * half - half) ** 2)
        * _smooth(k / 4000 if k <= 2000 else 1 - k / 4000)
        for k in range(4001)
    )
    assert abs(m - r.timing_change[0]) <= 1e-6 * m  # both knots alike, by symmetry


def _smooth(s: float) -> float:
    return s**3 * (10 - 15 * s + 6 * s * s)


def test_the_checks_margins_are_reached_not_only_zeros() -> None:
    """Path 2 with checks.min_speed = 1 m/s and min_slope = 0.5: its crossing (speed
    0.765 m/s, slope 0.2) fails both margins; the repair gives ẋ(t_s) = 5/4 (the first
    short rational at least 11/10 of the margin) and |dy/dx| = 1 (twice the margin), so
    speed √(ẋ² + ẏ²) = 5√2/4 > 1, with x(t_s), the crossing point and the ends kept."""
    text = (CONFIGS / "paper_path2.rprpr.yaml").read_text()
    old = parse_task(text.replace("torque_limit: [300, 300]", "min_speed: 1\n  min_slope: 0.5"))
    assert not audit(old, strict=True).passed
    r = repair(old)
    (c,) = r.changes
    assert set(c.actions) == {"speed", "slope"}
    assert c.speed == (fmpq(3, 4), fmpq(5, 4)) and c.ydot == (fmpq(3, 20), fmpq(5, 4))
    (s,) = r.after.singularities
    assert s.t_exact == Fraction(5, 2) and s.x == 3 and s.consistent
    assert s.slope == pytest.approx(1.0, rel=1e-15)
    assert s.speed == pytest.approx(5 * math.sqrt(2) / 4, rel=1e-15)
    _ends_kept(old, r.task)
    _round_trip(r.task)
    with pytest.raises(NoRepair, match=r"slope dy/dx = 1/5, not above checks.min_slope = 1/2"):
        repair(old, keep="path")


def test_a_prismatic_crossing_is_repaired_by_the_schemes_own_condition() -> None:
    """Linear actuators: the legs' moment balance at y = 0 is linear in ÿ(t_s), not ẍ
    (``test_prismatic``'s hand derivation gives the ÿ* that satisfies it). The shipped
    prismatic crossing with ÿ(t_s) one m/s² off ÿ* fails; with the path kept, ÿ = p' ẍ +
    p'' ẋ² and p' = 3, so the timing bump sets ẍ(t_s) = -1/3; with the timing kept, the
    path bump (t - t_s)² W restores ÿ(t_s) = ÿ* itself. Both pass strict, residual 0."""
    from tests.engine.exact.test_equations_prismatic import _crossing, _prismatic_ydd

    want = _prismatic_ydd(Fraction(4), Fraction(1), Fraction(3))
    assert want == Fraction(-37323, 2450)  # the config's value
    old = _crossing(want + 1, "prismatic")
    assert not audit(old, strict=True).passed
    for keep, path_kept in (("path", True), ("timing", False)):
        r = repair(old, keep=keep)
        (c,) = r.changes
        assert c.yddot is not None and Fraction(str(c.yddot[1])) == want
        assert Fraction(str(c.yddot[0])) == want + 1
        if path_kept:
            assert c.acceleration == (0, fmpq(-1, 3)) and r.path_deviation is None
        else:
            assert c.acceleration == (0, 0) and r.timing_change is None
        (s,) = r.after.singularities
        assert s.consistent and s.consistency_residual == 0 and s.torque_bounded
        assert r.task.robot.actuation == "prismatic"
        _ends_kept(old, r.task)
        _round_trip(r.task)


def test_path_2_on_linear_actuators_is_refused_with_the_reason() -> None:
    """Path 2 crosses slowly upward (ẏ = 0.15 m/s) where the moment balance needs
    ÿ(t_s) = -14.9 m/s² (gravity on the horizontal legs): every local change that gives
    it makes E fall back across AB within tens of ms (new, inconsistent crossings) or
    drives forces far past the limit, so no candidate passes and nothing is claimed."""
    text = (CONFIGS / "paper_path2.rprpr.yaml").read_text()
    old = parse_task(text.replace("robot:\n", "robot:\n  actuation: prismatic\n", 1))
    with pytest.raises(NoRepair, match="no candidate passes the strict check"):
        repair(old, window=fmpq(1, 2))  # one window (each is refused alike): a fast test


def test_crossings_at_irrational_times_are_moved_to_rational_ones_and_repaired(
    tmp_path: Path,
) -> None:
    """y = (x - 5/2)(x - 7/2)/2 under the quintic law crosses AB at x = 5/2 and 7/2 at the
    irrational times 1.79718... and 3.20281... (roots of quintics), inconsistently. The
    repair moves each crossing to the nearest short decimal time (t_r = 1797/1000 and
    3203/1000: x(t_r) set to the crossing point exactly by a timing bump), then meets
    eq. (34) there; the path is kept. The exact task's coefficients outgrow a task
    file's 40-digit numbers, so the command refuses to write it and says why."""
    text = (CONFIGS / "paper_path2.rprpr.yaml").read_text()
    text = text.replace("0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2", "0.5*(x - 2.5)*(x - 3.5)")
    text = text.replace("from: [2, -1]", "from: [2, 0.375]").replace("to: [4, 1]", "to: [4, 0.375]")
    src = tmp_path / "irr.rprpr.yaml"
    src.write_text(text)
    old = load_task(src)
    assert [s.t_rational for s in audit(old).singularities] == [None, None]
    r = repair(old)
    assert r.after.passed and r.path_deviation is None and r.task.path == old.path
    assert [n.split(" moved to ")[1] for n in r.notes] == ["t = 1797/1000 s", "t = 3203/1000 s"]
    new = r.after.singularities
    assert [s.t_exact for s in new] == [Fraction(1797, 1000), Fraction(3203, 1000)]
    for s, x_s in zip(new, (Fraction(5, 2), Fraction(7, 2)), strict=True):
        piece = _piece(r.task, fmpq(s.t_exact.numerator, s.t_exact.denominator))
        assert piece.x(fmpq(s.t_exact.numerator, s.t_exact.denominator)) == fmpq(
            x_s.numerator, x_s.denominator
        )
        assert s.consistent and s.consistency_residual == 0 and s.order == 1
    assert r.timing_change is not None and r.timing_change[0] < 0.01
    _ends_kept(old, r.task)
    out = tmp_path / "out.rprpr.yaml"
    code, _, err = run_cli("repair", str(src), "-o", str(out))
    assert code == 1 and "exceed what a task file holds" in err and not out.exists()


@pytest.mark.parametrize(
    ("value", "says"),
    [("1e99999999", "exponent beyond"), ("abc", "expected a number"), ("0", "positive")],
)
def test_a_bad_window_is_one_usage_line_and_never_a_hang(value: str, says: str) -> None:
    """--window is read by the task file's number rules (capped digits and exponent):
    a huge exponent is refused at once instead of building a 10^99999999 integer."""
    code, _, err = run_cli("repair", str(CONFIGS / "paper_path1.rprpr.yaml"), "--window", value)
    assert code == 2 and says in err and len(err.strip().splitlines()) == 1

"""A repair whose efforts far exceed the original's is a warning; with declared
uncertainty, the repaired motion's worst case is reported.

Path 2 under linear actuators, without a limit: the legs' moment balance needs
ÿ(t_s) = -14.9 m/s², which the repair gives, and the legs' forces reach 64.6 kN where the
original stays within a few kN away from its pole. The numbers are the independent mpmath
reference's (``tests/reference.py``) at the repaired motion's peak time and on the
original's samples outside the changed window.
"""

from __future__ import annotations

from fractions import Fraction
from pathlib import Path

import mpmath
import pytest

from rprpr import parse_task
from rprpr.model.task import Task
from rprpr.repair import repair
from rprpr.repair.effort import RATIO
from tests import reference as R
from tests.conftest import CONFIGS, run_cli

P2 = (CONFIGS / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")
PRISMATIC_NO_LIMIT = P2.replace("robot:\n", "robot:\n  actuation: prismatic\n", 1).replace(
    "checks:\n  torque_limit: [300, 300]   # [N m]\n", ""
)


def _effort(task: Task, t: Fraction, name: str) -> float:
    """The reference's effort at t, the motion's piece holding t evaluated exactly."""
    piece = next(
        p
        for p in task.motion
        if R._fractions(p.x)
        and Fraction(int(p.start.p), int(p.start.q)) <= t <= Fraction(int(p.end.p), int(p.end.q))
    )
    x, xd, xdd = R._poly(R._fractions(piece.x), t)
    y, yd, ydd = R._poly(R._fractions(piece.y), t)
    with mpmath.workdps(50):
        return float(R._evaluate(task, (x, xd, xdd, y, yd, ydd))[name])


# The reference's efforts (F1, F2) [N] of PRISMATIC_NO_LIMIT at each of its 1001 sample
# times but the pole's (t = 2.5 s), stored beside this file: the reference's values never
# change, and a thousand of them at 60 digits cost seconds. Computed by
# ``_reference_efforts`` (tests/reference.py at each float sample time, taken exactly) and
# written by ``python -m tests.repair.test_effort_warning``; a slow test recomputes them.
EFFORTS = Path(__file__).with_name("path2_prismatic_efforts.csv")
POLE = 2.5


def _reference_efforts(task: Task, times: list[float]) -> dict[float, tuple[float, float]]:
    """The reference's (T1, T2) at each of ``times`` (floats, taken exactly)."""
    values = {}
    for v in times:
        q = R.reference(task, Fraction(v))
        values[v] = (float(q["T1"]), float(q["T2"]))
    return values


def _stored_efforts() -> dict[float, tuple[float, float]]:
    """EFFORTS as written: time -> (T1, T2), each float as its repr."""
    rows = EFFORTS.read_text(encoding="utf-8").splitlines()[2:]
    return {float(t): (float(a), float(b)) for t, a, b in (r.split(",") for r in rows)}


def _regular_reference(values: dict[float, tuple[float, float]], t_s: float, half: float) -> float:
    """The original's largest regular |effort| (``repair.effort``, docs/robust.md) from the
    reference's efforts ``values`` (time -> (T1, T2) on the samples but t_s): on the
    samples outside the changed window, each effort less its pole's leading term
    c±/(t - t_s), c± = E (t - t_s) at the sample nearest t_s on each side."""
    out = 0.0
    right = min((v for v in values if v > t_s), key=lambda v: v - t_s)
    left = max(v for v in values if v < t_s)
    for k in (0, 1):
        c = {1: values[right][k] * (right - t_s), -1: values[left][k] * (left - t_s)}
        for v, e in values.items():
            if abs(v - t_s) > half:
                out = max(out, abs(e[k] - c[1 if v > t_s else -1] / (v - t_s)))
    return out


def test_path_2_on_linear_actuators_is_repaired_with_a_warning_naming_the_forces() -> None:
    old = parse_task(PRISMATIC_NO_LIMIT)
    r = repair(old)
    (w,) = r.warnings
    (c,) = r.changes
    peak = r.after.torque_peak
    assert peak is not None
    j = 0 if peak[0].value >= peak[1].value else 1
    at = _effort(r.task, Fraction(peak[j].t), f"T{j + 1}")  # the legs' force there
    assert abs(at) == pytest.approx(peak[j].value, rel=1e-9)
    assert 6.4e4 < peak[j].value < 6.5e4  # the 64.6 kN
    s = r.before.samples
    values = _stored_efforts()  # the reference's, on the same samples
    assert float(c.t) == POLE and list(values) == [float(v) for v in s.t if v != POLE]
    ref = _regular_reference(values, float(c.t), float(c.window))
    (shown,) = [float(x) for x in w.split("outside the changed windows (")[1].split()[:1]]
    assert shown == pytest.approx(ref, rel=1e-5)  # the same samples: the same largest (6 digits)
    assert peak[j].value > RATIO * shown
    assert f"|F{j + 1}| = {peak[j].value:.6g} N" in w and "wider --window" in w


@pytest.mark.slow  # a thousand reference evaluations at 60 digits and more
def test_the_stored_efforts_are_the_references() -> None:
    stored = _stored_efforts()
    assert _reference_efforts(parse_task(PRISMATIC_NO_LIMIT), list(stored)) == stored


def _write_efforts() -> None:
    """EFFORTS from the reference, at the audit's sample times but the pole's."""
    from rprpr import audit

    task = parse_task(PRISMATIC_NO_LIMIT)
    times = [float(v) for v in audit(task).samples.t if v != POLE]
    lines = ["# the reference's efforts of PRISMATIC_NO_LIMIT (test_effort_warning.py)", "t,T1,T2"]
    lines += [f"{t!r},{a!r},{b!r}" for t, (a, b) in _reference_efforts(task, times).items()]
    EFFORTS.write_text("\n".join(lines) + "\n", encoding="utf-8")


def test_a_gentle_repair_warns_of_nothing() -> None:
    r = repair(parse_task((CONFIGS / "paper_path1.rprpr.yaml").read_text(encoding="utf-8")))
    assert r.changed and r.warnings == ()


def test_the_command_prints_the_warning_and_the_worst_case(tmp_path) -> None:  # type: ignore[no-untyped-def]
    f = tmp_path / "p.rprpr.yaml"
    f.write_text(PRISMATIC_NO_LIMIT, encoding="utf-8")
    code, out, err = run_cli("repair", str(f), "-o", str(tmp_path / "out.rprpr.yaml"))
    assert code == 0 and "warning: the repaired motion's forces reach |F" in out + err
    heavier = P2.replace("3: {mass: 1.0,", "3: {mass: 1.5,").replace(
        "timing:", "uncertainty: {links: 5%, acceleration: 0.0001, period: 0.0002}\ntiming:"
    )
    g = tmp_path / "h.rprpr.yaml"
    g.write_text(heavier, encoding="utf-8")
    code, out, err = run_cli("repair", str(g), "-o", str(tmp_path / "h2.rprpr.yaml"))
    assert code == 0 and "over the box at t = 2.5 s: residual [" in out + err
    assert "(strict, RPR201 left to RPR205): pass" in out  # docs/robust.md, *Repair*


@pytest.mark.parametrize(
    ("uncertainty", "keep", "near"),
    [
        # the nominal pole kept at the box's middle: the certified peak is infinite
        ("uncertainty: {links: 1%, acceleration: 0, period: 0.003}\n", None, 4.96e4),
        # the original's pole tail outside a narrow changed window: 3.5 kN, not regular
        ("", "path", 5.06e4),
    ],
)
def test_a_kept_pole_or_the_originals_pole_tail_does_not_silence_the_warning(
    uncertainty: str, keep: str | None, near: float
) -> None:
    text = PRISMATIC_NO_LIMIT
    if uncertainty:
        text = text.replace("timing:", "checks: {torque_limit: [100000, 100000]}\ntiming:")
        text += uncertainty
    r = repair(parse_task(text), keep=keep)
    (w,) = r.warnings
    value = float(w.split("| = ")[1].split()[0])
    at = float(w.split(" at t = ")[1].split()[0])
    assert value == pytest.approx(near, rel=0.01)
    name = w.split("reach |")[1][:2].replace("F", "T")
    assert abs(_effort(r.task, Fraction(at), name)) == pytest.approx(value, rel=1e-5)
    (shown,) = [float(x) for x in w.split("outside the changed windows (")[1].split()[:1]]
    assert 100 < shown < 200 and value > RATIO * shown  # path 2's legs: ~170 N regular


if __name__ == "__main__":
    _write_efforts()

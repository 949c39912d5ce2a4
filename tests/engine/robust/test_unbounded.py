"""The proof that the worst case is unbounded next to E at A or B (``engine.robust.
unbounded``) against the independent mpmath reference (``tests/reference.py``, 50 digits).

A motion through A (or B) with an acceleration tracking error: at times approaching the
passage, the largest |E_j| over the error's corners at the nominal links (one point of
the box, so a value the worst case over the box is at least) must be at least the proven
lower bound a (c / s_i^p - k) there, and that bound must grow past any figure as s_i -> 0;
under both actuation schemes, at A and at B. A motion that passes neither has no proof,
and the worst-case peak of such a passage reports the effort unbounded.
"""

from __future__ import annotations

import dataclasses
from fractions import Fraction
from pathlib import Path

import mpmath
import pytest
from flint import fmpq

from rprpr import audit, load_task
from rprpr.engine.robust.unbounded import poles
from rprpr.engine.robust.windows import Box
from rprpr.model.task import Task, Uncertainty
from tests import reference as ref
from tests.engine.robust.box_reference import errors

Q = Fraction


def _through(tmp_path: Path, base: int, actuation: str, slope: str = "1") -> Task:
    text = f"""name: through
robot:
  a1: 6
  actuation: {actuation}
  links:
    2: {{mass: 2.7, inertia: 0.048, r: 0.69}}
    3: {{mass: 2.3, inertia: 0.023, r: 0.76}}
    4: {{mass: 0.9, inertia: 0.051, r: 0.15}}
    5: {{mass: 2.2, inertia: 0.037, r: 0.88}}
path:
  y: {slope}*(x - {base})
  from: [{base - 1}, {-1 if slope == "1" else "-0.5"}]
  to: [{base + 1}, {1 if slope == "1" else "0.5"}]
timing:
  duration: 2
  law: cubic
checks:
  torque_limit: [300, 300]
"""
    path = tmp_path / "through.rprpr.yaml"
    path.write_text(text, encoding="utf-8")
    return load_task(path)


def _u(a: str = "1/100") -> Uncertainty:
    rel = (fmpq(5, 100),) * 3
    return Uncertainty(dict.fromkeys((2, 3, 4, 5), rel), fmpq(a), fmpq(1, 1000))


def _worst_at_nominal(task: Task, u: Uncertainty, t: Q, effort: int) -> tuple[float, float]:
    """(s_i of the leg through its base at t, max over the error's corners of |E_j|) at
    the nominal links, by the reference."""
    motion = ref._motion(task, t)
    best = mpmath.mpf(0)
    with mpmath.workdps(50):
        for ex, ey in errors(u):
            x, xd, xdd, y, yd, ydd = motion
            v = ref._evaluate(task, (x, xd, xdd + ex, y, yd, ydd + ey))
            best = max(best, abs(v[f"T{effort + 1}"]))
        return v, best


@pytest.mark.parametrize("actuation", ["revolute", "prismatic"])
@pytest.mark.parametrize("base", [0, 6])
def test_bound_holds_and_grows(tmp_path: Path, actuation: str, base: int) -> None:
    task = _through(tmp_path, base, actuation)
    u = _u()
    task = dataclasses.replace(task, uncertainty=u)
    res = audit(task)
    box = Box.of(task.robot, u)
    proofs = poles(task, list(res.parts), box)
    leg = 1 if base == 0 else 2
    # E reaches the base joint at t = 1 s (the cubic law's middle); both sides proven
    assert sorted(p.side for p in proofs) == [-1, 1]
    for p in proofs:
        assert p.leg == leg and abs(p.t - 1.0) < 1e-15
        # the effort whose worst case has the pole: the leg's own torque (revolute), the
        # other leg's force (prismatic: the moment of the passing leg acts across AB)
        assert p.effort == (leg - 1 if actuation == "revolute" else 2 - leg)
        shown = 0
        for j in range(1, 40, 3):
            t = Q(1) + p.side * Q(p.width) * Q(1, 2**j)
            v, worst = _worst_at_nominal(task, u, t, p.effort)
            s = float(v[f"s{leg}"])
            assert s <= p.s_max
            bound = p.lower(s)
            assert worst >= bound  # the proven lower bound holds the reference
            # and it is rounded down: never above a (c / s^p - k) computed exactly
            exact = Q(int(p.a.p), int(p.a.q)) * (Q(p.coef) / Q(s) ** p.order - Q(p.rest))
            assert Q(bound) <= exact
            shown = max(shown, bound)
        assert shown > 1e8  # and it grows past any figure as t -> t_A
        # with the pole's own coefficient: the reference within a few times the bound
        # there (the corners' 1-norm against the bound's 2-norm, the span's extremes)
        assert worst < 6 * bound


def test_peak_reports_unbounded(tmp_path: Path) -> None:
    task = _through(tmp_path, 0, "revolute")
    res = audit(task, peak=True, uncertainty=_u())
    assert res.robust_peak is not None
    (lo1, hi1), (lo2, hi2) = res.robust_peak
    assert lo1 == hi1 == float("inf")
    # T2 is bounded next to A (the error reaches it only through λ, s1 λ -> 0): its
    # certified lower bound holds the reference's at the nominal links, its upper is open
    _, worst = _worst_at_nominal(task, _u(), Q(1, 2), 1)
    assert lo2 >= float(worst) * (1 - 1e-9) and hi2 == float("inf")


def test_no_error_no_proof(tmp_path: Path) -> None:
    task = _through(tmp_path, 0, "revolute")
    u = _u("0")
    task = dataclasses.replace(task, uncertainty=u)
    res = audit(task)
    assert poles(task, list(res.parts), Box.of(task.robot, u)) == []


def test_the_lower_bound_is_rounded_down_at_any_working_precision() -> None:
    """a (c / s^p - k) rounded down to a double, also at 128 bits (poles' own
    precision), where a ball is narrower than a double's rounding: never above the value
    computed exactly with fractions (of either sign)."""
    from flint import ctx, fmpq

    from rprpr.engine.robust.unbounded import Pole

    cases = [
        (2.0856773675275195, 1.573615585199573, 1.2327307663397529),
        (2.320903912357481, 1.7937380314702938, 0.8933009419363618),
        (3.0, 1.0, 1.0), (0.7, 1.0, 0.25), (1.1, 1.3, 0.0),
    ]  # fmt: skip
    old = ctx.prec
    try:
        for prec in (53, 128, 256):
            ctx.prec = prec
            for s, c, k in cases:
                bound = Pole(0, 1, 1.0, 1, 0.1, 1, c, k, 3.0, fmpq(1, 10)).lower(s)
                assert Q(bound) <= Q(1, 10) * (Q(c) / Q(s) - Q(k)), (prec, s)
    finally:
        ctx.prec = old

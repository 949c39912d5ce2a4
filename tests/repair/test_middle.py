"""With declared uncertainty, ``rprpr repair`` aims the acceleration it sets at t_s at the
box's middle (``docs/robust.md``, *Repair*), for both actuation schemes.

The reference is ``tests/engine/robust/box_reference.py`` (mpmath at 50 digits, nothing
from ``rprpr.engine``): the consistency residual at every vertex of the box (multilinear
in the revolute parameters; at the prismatic vertices of m, I and r, where r's interior
vertex cannot be the extreme for these boxes: C > 0), affine in the acceleration z the
repair sets (ẍ revolute, ÿ prismatic). From two values of z per vertex it finds the
middle itself — the z where the largest and the least vertex residual are opposite — and
the nominal consistent z0, and checks the repaired motion against both.
"""

from __future__ import annotations

import dataclasses
from fractions import Fraction
from typing import Any

import mpmath
import pytest
from flint import fmpq

from rprpr import audit, parse_task
from rprpr.model.task import Task, Uncertainty
from rprpr.repair import NoRepair, passes, repair
from tests import reference as R
from tests.conftest import CONFIGS
from tests.engine.exact.test_equations_prismatic import _crossing, _prismatic_ydd
from tests.engine.robust import box_reference as B

Q = Fraction
P2 = (CONFIGS / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")
HEAVY = P2.replace("3: {mass: 1.0,", "3: {mass: 1.5,")  # path 2, inconsistent at t = 2.5 s
NONE = (Q(0), Q(0), Q(0))


def _box(links: dict[int, tuple[Q, Q, Q]], a: Q, period: Q) -> Uncertainty:
    return Uncertainty({i: links.get(i, NONE) for i in (2, 3, 4, 5)}, a, period).exact()  # type: ignore[arg-type]


def _revolute() -> tuple[Task, str]:
    links = {3: (Q(1, 20), Q(0), Q(1, 10)), 5: (Q(1, 20), Q(0), Q(1, 20))}
    u = _box(links, Q(1, 10**4), Q(2, 10**4))
    return dataclasses.replace(parse_task(HEAVY), uncertainty=u), "x"


def _prismatic() -> tuple[Task, str]:
    task = _crossing(_prismatic_ydd(Q(4), Q(1), Q(3)) + 1, "prismatic")  # ÿ(t_s) 1 m/s² off
    u = _box({3: (Q(1, 20), Q(1, 20), Q(1, 10)), 5: (Q(1, 20), Q(1, 20), Q(1, 20))}, Q(1, 100),
             Q(5, 1000))  # fmt: skip
    return dataclasses.replace(task, uncertainty=u), "y"


CASES = {"revolute": _revolute, "prismatic": _prismatic}
_REPAIRS: dict[str, Any] = {}


def _repaired(name: str) -> Any:
    if name not in _REPAIRS:
        task, axis = CASES[name]()
        _REPAIRS[name] = (task, axis, repair(task))
    return _REPAIRS[name]


def _state(task: Task, t: Q) -> B.Motion:
    """x, x', x'', y, y', y'' at t from the piece of the motion that holds t (exactly)."""
    piece = next(p for p in task.motion if Q(str(p.start)) < t < Q(str(p.end)))
    return R._poly(R._fractions(piece.x), t) + R._poly(R._fractions(piece.y), t)


def _affine(task: Task, motion: B.Motion, axis: str) -> list[tuple[Any, Any]]:
    """(K, B) of R = K z + B at every vertex of the box, z the acceleration on ``axis``."""
    k = 2 if axis == "x" else 5
    u = task.uncertainty
    assert u is not None
    corners = B.link_corners(task, u)
    out = []
    for e in B.errors(u):
        at = []
        for z in (Q(0), Q(1)):
            m = list(motion)
            m[k] = z
            v = B.joints(task, tuple(m), e)  # type: ignore[arg-type]
            at.append([B.residual_of(task, links, v) for links in corners])
        with mpmath.workdps(B.DPS):
            out += [(r1 - r0, r0) for r0, r1 in zip(*at, strict=True)]
    return out


def _spread(lines: list[tuple[Any, Any]], z: Any) -> tuple[Any, Any]:
    with mpmath.workdps(B.DPS):
        values = [k * z + b for k, b in lines]
        return min(values), max(values)


def _middle(lines: list[tuple[Any, Any]]) -> Any:
    """The z where min + max of the vertex residuals is 0 (bisection: it is monotone,
    every K of one sign)."""
    with mpmath.workdps(B.DPS):
        assert len({mpmath.sign(k) for k, _ in lines}) == 1
        lo, hi = mpmath.mpf(-1000), mpmath.mpf(1000)
        up = lines[0][0] > 0

        def g(z: Any) -> Any:
            a, b = _spread(lines, z)
            return a + b

        assert (g(lo) < 0 < g(hi)) if up else (g(lo) > 0 > g(hi))
        for _ in range(120):
            mid = (lo + hi) / 2
            if (g(mid) < 0) == up:
                lo = mid
            else:
                hi = mid
        return (lo + hi) / 2


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_repair_centres_the_residual_interval_on_zero(name: str) -> None:
    task, axis, r = _repaired(name)
    (c,) = r.changes
    z_new = c.acceleration[1] if axis == "x" else c.yddot[1]
    t = Q(int(c.t.p), int(c.t.q))
    motion = _state(r.task, t)
    assert motion[3] == 0  # still crossing at t_s
    lines = _affine(task, motion, axis)
    middle = _middle(lines)
    with mpmath.workdps(B.DPS):
        z = mpmath.mpf(int(z_new.p)) / int(z_new.q)
        assert motion[2 if axis == "x" else 5] == Q(int(z_new.p), int(z_new.q))
        lo, hi = _spread(lines, z)
        assert abs(lo + hi) <= 1e-5 * (hi - lo)  # centred on 0
        best = max(_spread(lines, middle)[1], -_spread(lines, middle)[0])
        assert max(hi, -lo) <= best * (1 + 1e-5)  # the least worst-case |R|
        # the nominal consistent value: R(z0) = 0 for the nominal links and no error
        k = 2 if axis == "x" else 5
        nominal = task.robot.links
        v0, v1 = (B.joints(task, (*motion[:k], z, *motion[k + 1 :]), (Q(0), Q(0)))
                  for z in (Q(0), Q(1)))  # fmt: skip
        b0 = B.residual_of(task, nominal, v0)
        z0 = -b0 / (B.residual_of(task, nominal, v1) - b0)
        lo0, hi0 = _spread(lines, z0)
        assert max(hi0, -lo0) > max(hi, -lo) * (1 + 1e-3)  # r uncertain: the middle is not z0
    # the engine's interval over the repaired motion's box holds the vertices, tightly
    rlo, rhi = r.after.robust[0].residual
    assert rlo <= lo and hi <= rhi and abs(rlo - lo) < 1e-9 and abs(rhi - hi) < 1e-9


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_repaired_window_is_within_the_period_and_shorter(name: str) -> None:
    task, _, r = _repaired(name)
    u = task.uncertainty
    before, after = r.before.robust[0], r.after.robust[0]
    assert before.window > float(u.period)  # RPR205 failed the original
    assert "RPR205" in [f.rule for f in r.before.findings]
    assert 0 < after.window <= float(u.period) and after.window < before.window
    assert passes(r.after)  # the nominal model's pole left to RPR205, which passes
    plain = audit(r.task)
    assert plain.verdict == "pass" and [f.rule for f in plain.findings if f.rule == "RPR205"] == []
    (pole,) = [f for f in plain.findings if f.rule == "RPR201"]
    assert pole.severity == "warning" and "RPR205 decides" in pole.message


def test_an_acceleration_error_alone_keeps_the_exact_nominal_consistency() -> None:
    """A box symmetric about the nominal residual (the error alone) has its middle at the
    nominal consistent ẍ: the repair sets it exactly, and the nominal model has no pole."""
    u = _box({}, Q(1, 10**4), Q(2, 10**4))
    task = dataclasses.replace(parse_task(HEAVY), uncertainty=u)
    r = repair(task, window=fmpq(1, 2))
    (c,) = r.changes
    # eq. (34) at (3, 0), case 3: (m3 + m5) ẍ = ẏ² (m5 r5 - m3 r3)/9 with ẏ = 0.15 m/s
    assert c.acceleration[1] == fmpq(3, 20) ** 2 * (fmpq(1, 2) - fmpq(3, 4)) / 9 / fmpq(5, 2)
    (s,) = r.after.singularities
    assert s.consistent and s.torque_bounded and s.consistency_residual == 0
    after = r.after.robust[0]  # K = -(m3 + m5) = -5/2: R in ±2.5e-4 N, centred on 0
    assert after.residual == pytest.approx((-2.5e-4, 2.5e-4), abs=1e-18)
    assert 0 < after.window <= 2e-4 and passes(r.after)


def test_a_window_the_box_itself_makes_is_refused_with_the_reason() -> None:
    """Path 2 is consistent at the box's middle already (symmetric legs); 0.01 m/s² of
    tracking error alone saturates |T1| for 5 ms, which no acceleration at t_s shortens."""
    u = _box({}, Q(1, 100), Q(1, 1000))
    task = dataclasses.replace(parse_task(P2), uncertainty=u)
    with pytest.raises(NoRepair, match="what still fails is the saturation window") as why:
        repair(task, window=fmpq(1, 2))
    assert "track the acceleration more closely" in str(why.value)

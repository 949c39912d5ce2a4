"""Robust verdicts (docs/robust.md) against an independent reference.

The reference is ``tests/reference.py`` (mpmath, the paper's equations, nothing from
``rprpr.engine``) at 50 digits, with the link parameters and the acceleration tracking
error set by hand: the residual of eq. (34) (revolute) or of the legs' moment balance
(prismatic) at every corner of the box, and the efforts at every corner on both sides of
t_s, whose largest |T| gives the brute-force window by bisection.
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Iterator
from fractions import Fraction
from pathlib import Path
from typing import Any

import mpmath
import pytest
from flint import fmpq, fmpq_poly

from rprpr import Motion, audit, load_task, parse_task, with_motion
from rprpr.model.task import Link, Task, Uncertainty
from tests import reference as ref
from tests.engine.robust import box_reference

P2 = "configs/paper_path2.rprpr.yaml"
PRISMATIC = "configs/prismatic_crossing.rprpr.yaml"
ZERO_SPEED = "configs/zero_speed_crossing.rprpr.yaml"
DPS = 50
Q = Fraction


ZERO, MS = Q(0), Q(1, 1000)


def _u(links: dict[int, tuple[Q, Q, Q]], a: Q = ZERO, period: Q = MS) -> Uncertainty:
    full = {i: links.get(i, (Q(0), Q(0), Q(0))) for i in (2, 3, 4, 5)}
    return Uncertainty(full, a, period)  # type: ignore[arg-type]


def _every(rel: Q) -> dict[int, tuple[Q, Q, Q]]:
    return dict.fromkeys((2, 3, 4, 5), (rel, rel, rel))


def _limited(task: Task, limit: int = 300) -> Task:
    checks = dataclasses.replace(task.checks, torque_limit=(fmpq(limit), fmpq(limit)))
    return dataclasses.replace(task, checks=checks)


# -- the reference --------------------------------------------------------------------------


def _corners(task: Task, u: Uncertainty) -> list[tuple[dict[int, Link], tuple[Q, Q]]]:
    """Every corner of the box: each link's (mass, inertia, r) at its ends, and (e_x, e_y)."""
    axes = []
    for i in (2, 3, 4, 5):
        link = task.robot.links[i]
        rel = u.links[i]
        ends = []
        for v, w in zip((link.mass, link.inertia, link.r), rel, strict=True):
            v = Q(int(v.p), int(v.q))
            ends.append(sorted({v - abs(v) * w, v + abs(v) * w}))
        axes.append([(i, m, j, r) for m in ends[0] for j in ends[1] for r in ends[2]])
    a = u.acceleration
    errors = sorted({(sx * a, sy * a) for sx in (-1, 1) for sy in (-1, 1)})
    out = []
    for combo in itertools.product(*axes):
        links = {i: Link(_q(m), _q(j), _q(r)) for i, m, j, r in combo}
        out += [(links, e) for e in errors]
    return out


def _q(v: Q) -> fmpq:
    return fmpq(v.numerator, v.denominator)


def _task_with(task: Task, links: dict[int, Link]) -> Task:
    return dataclasses.replace(task, robot=dataclasses.replace(task.robot, links=links))


def _moved(motion: tuple[Any, ...], e: tuple[Q, Q]) -> tuple[Any, ...]:
    """The motion at one time with the error e added to (x'', y'')."""
    x, xd, xdd, y, yd, ydd = motion
    return x, xd, xdd + e[0], y, yd, ydd + e[1]


def _evaluate(task: Task, t: Q, e: tuple[Q, Q]) -> dict[str, Any]:
    """The reference at t with the error e added to (x'', y'')."""
    with mpmath.workdps(DPS):
        return ref._evaluate(task, _moved(ref._motion(task, t), e))


def _residuals(task: Task, t_s: Q, corners: list[tuple[dict[int, Link], tuple[Q, Q]]]
               ) -> list[Any]:  # fmt: skip
    """The consistency residual at t_s at each corner from the reference's joint values
    (eqs. 7-14): σ(M22 s1'' + N2) + M44 s2'' + N4 (revolute), U1/s1 + σ U2/s2
    (prismatic). The joint values depend on the motion and the error alone: evaluated
    once per error."""
    motion = ref._motion(task, t_s)
    joints: dict[tuple[Q, Q], dict[str, Any]] = {}
    out = []
    for links, e in corners:
        if e not in joints:
            joints[e] = box_reference.joints(task, motion, e)
        out.append(box_reference.residual_of(task, links, joints[e]))
    return out


def _robots(task: Task, corners: list[tuple[dict[int, Link], tuple[Q, Q]]]
            ) -> list[tuple[Any, tuple[Q, Q]]]:  # fmt: skip
    """The robot at each corner of the links' box, beside its error (made once)."""
    return [(_task_with(task, links).robot, e) for links, e in corners]


def _at_corners(task: Task, t: Q, corners: list[tuple[Any, tuple[Q, Q]]]
                ) -> Iterator[dict[str, Any]]:  # fmt: skip
    """The reference at t at each corner (``_robots``: the robot and the error), what
    ``_evaluate`` gives there, one corner at a time. The joint values depend on the motion
    and the error alone (the corners' robots differ in their links): they are evaluated
    once per error and shared by the corners' dynamics."""
    motion = ref._motion(task, t)
    kinematics: dict[tuple[Q, Q], Any] = {}
    for robot, e in corners:
        with mpmath.workdps(DPS):
            if e not in kinematics:
                kinematics[e] = ref._kinematics(task.robot, _moved(motion, e))
            kin, legs = kinematics[e]
            v = kin if legs is None else ref._dynamics(robot, kin, legs)
        yield v


def _above(task: Task, corners: list[tuple[Any, tuple[Q, Q]]], t: Q, bound: Any) -> bool:
    """Whether |T_1(t)| or |T_2(t)| exceeds ``bound`` at some corner of the box (the
    reference's efforts; ``corners``: ``_robots``'s): max over the corners of
    max(|T1|, |T2|) > bound, each corner evaluated once and the search stopped at the
    first corner above, which is moved to the front of ``corners`` (the next time,
    bisected nearby, is most often above there too)."""
    for i, v in enumerate(_at_corners(task, t, corners)):
        if abs(v["T1"]) > bound or abs(v["T2"]) > bound:
            corners.insert(0, corners.pop(i))
            return True
    return False


def _window_end(task: Task, corners: list[Any], t_s: Q, d: int, near: Q, far: Q) -> tuple[Q, Q]:
    """Where on side d (±1) the largest |T| over the corners falls to the limit: times
    (above, at or below) 1e-9 s apart, bisected from t_s + d near (above) and t_s + d far
    (below)."""
    limit = Q(int(task.checks.torque_limit[0].p), int(task.checks.torque_limit[0].q))

    bound = mpmath.mpf(limit.numerator) / limit.denominator  # mpmath 1.3 compares no Fraction
    robots = _robots(task, corners)

    def above(h: Q) -> bool:
        return _above(task, robots, t_s + d * h, bound)

    assert above(near) and not above(far)
    while far - near > Q(1, 10**9):
        mid = Q((near + far) / 2).limit_denominator(10**14)
        near, far = (mid, far) if above(mid) else (near, mid)
    return t_s + d * near, t_s + d * far


# -- the residual over the box -------------------------------------------------------------


@pytest.mark.parametrize(
    ("path", "u"),
    [
        (P2, _u({3: (Q(1, 20),) * 3, 5: (Q(1, 20),) * 3}, Q(1, 100))),
        (P2, _u({3: (Q(1, 50), Q(0), Q(1, 100)), 5: (Q(1, 50), Q(0), Q(0))}, Q(1, 10))),
        (PRISMATIC, _u({3: (Q(1, 20),) * 3, 5: (Q(1, 20),) * 3}, Q(1, 100))),
        (PRISMATIC, _u({2: (Q(1, 10),) * 3, 4: (Q(1, 10),) * 3}, Q(1, 100))),
    ],
)
def test_the_residual_interval_holds_every_corner_and_is_tight(path: str, u: Uncertainty) -> None:
    task = _limited(load_task(path))
    result = audit(task, uncertainty=u)
    (s,) = result.singularities
    lo, hi = result.robust[0].residual
    t_s = Q(s.t_exact)
    values = _residuals(task, t_s, _corners(task, u))
    assert lo <= min(values) and max(values) <= hi
    assert abs(lo - min(values)) < 1e-9 and abs(hi - max(values)) < 1e-9


def test_revolute_residual_moves_only_with_m3_r3_m5_r5_and_ex() -> None:
    task = _limited(load_task(P2))
    # e_y and every other link parameter leave it where it is (0: path 2 is consistent)
    u = _u({2: (Q(1, 10),) * 3, 4: (Q(1, 10),) * 3, 3: (Q(0), Q(1, 10), Q(0))})
    u = dataclasses.replace(u, acceleration=Q(0))
    lo, hi = audit(task, uncertainty=u).robust[0].residual
    assert -1e-40 < lo <= 0 <= hi < 1e-40  # zero, within the balls' rounding
    with_ey = audit(task, uncertainty=dataclasses.replace(u, acceleration=Q(1, 100)))
    # e_x moves it by σ m3 cos θ1 e_x + m5 cos θ2 e_x = (-1 + (-1)) ... at (3, 0): |2 * 0.01|
    assert with_ey.robust[0].residual == pytest.approx((-0.02, 0.02), abs=1e-15)


def test_a_zero_box_reports_the_exact_residual() -> None:
    for path in (P2, "configs/case1_crossing.rprpr.yaml", PRISMATIC):
        task = _limited(load_task(path))
        plain = audit(task)
        zero = audit(task, uncertainty=_u({}))
        for s, r in zip(plain.singularities, zero.robust, strict=True):
            assert r.residual == (s.consistency_residual, s.consistency_residual)


# -- the window -----------------------------------------------------------------------------


WINDOW_CASES = [
    (P2, {3: (Q(1, 20), Q(0), Q(1, 20)), 5: (Q(1, 20), Q(0), Q(1, 20))}, Q(1, 100)),
    (PRISMATIC, {3: (Q(1, 20), Q(0), Q(1, 20)), 5: (Q(1, 20), Q(0), Q(1, 20))}, Q(1, 100)),
]
# The brute-force window of each case, as ``_brute_force`` computes it from the reference
# (left, left_out, right, right_out: each end where the largest |T| over the box's corners
# is above, then at or below, the limit, 1e-9 s apart): the reference's values never
# change, and they cost seconds; the slow test below recomputes them.
BRUTE_FORCE = {
    P2: (
        "88385817770185/35392586695274",
        "497040393832381/199031311555954",
        "126884880790151/50698916538454",
        "405532281425199/162037014630506",
    ),
    PRISMATIC: (
        "4301426857887/17259415719139",
        "5471363528878/21953770472139",
        "21931239950211/87454310830660",
        "23886822362933/95252506790964",
    ),
}


def _brute_force(task: Task, u: Uncertainty, w: float) -> tuple[Q, Q, Q, Q]:
    """Both ends of the brute-force window about the task's singular instant, bisected
    from w/4 (above the limit) and 2w (below) on each side."""
    (s,) = audit(task).singularities
    t_s = Q(s.t_exact)
    corners = _corners(task, u)
    left, left_out = _window_end(task, corners, t_s, -1, Q(w) / 4, Q(w) * 2)
    right, right_out = _window_end(task, corners, t_s, 1, Q(w) / 4, Q(w) * 2)
    return left, left_out, right, right_out


@pytest.mark.parametrize(("path", "links", "a"), WINDOW_CASES)
def test_the_window_holds_the_brute_force_window_and_is_within_a_microsecond(
    path: str, links: dict[int, tuple[Q, Q, Q]], a: Q
) -> None:
    task = _limited(load_task(path))
    u = _u(links, a)
    r = audit(task, uncertainty=u).robust[0]
    assert r.span is not None
    left, left_out, right, right_out = (Q(v) for v in BRUTE_FORCE[path])
    assert r.span[0] <= left and right <= r.span[1]  # the proven span holds the brute force
    assert float(right - left) <= r.window < float(right_out - left_out) + 1e-6


@pytest.mark.slow  # the reference at every corner of the box, bisected to 1e-9 s
@pytest.mark.parametrize(("path", "links", "a"), WINDOW_CASES)
def test_the_stored_brute_force_windows_are_the_references(
    path: str, links: dict[int, tuple[Q, Q, Q]], a: Q
) -> None:
    task, u = _limited(load_task(path)), _u(links, a)
    got = _brute_force(task, u, audit(task, uncertainty=u).robust[0].window)
    want = [Q(v) for v in BRUTE_FORCE[path]]
    assert all(abs(g - v) <= Q(2, 10**9) for g, v in zip(got, want, strict=True)), got  # bisected


def test_path2_numbers_of_the_issue() -> None:
    """±5 % on every link and 0.01 m/s²: 5.44 ms (the union of the errors at each instant);
    the leading-order formula 2 s_i |R| s1 s2/(a1 |ẏ| T_lim) gives 4.0 ms for the error alone
    (R = 0.02 N, s1 = s2 = 3, a1 = 6, ẏ = 0.2 ẋ): the engine's ends lie within 30 % of it."""
    task = _limited(load_task(P2))
    both = audit(task, uncertainty=_u(_every(Q(1, 20)), Q(1, 100))).robust[0]
    assert both.window == pytest.approx(5.44e-3, abs=5e-6)
    assert both.residual == pytest.approx((-0.02113125, 0.02113125), abs=1e-12)
    assert both.joint == 1
    err = audit(task, uncertainty=_u({}, Q(1, 100))).robust[0]
    (s,) = audit(task).singularities
    ydot = 0.2 * s.speed / (1 + 0.2**2) ** 0.5
    leading = 2 * 3 * 0.02 * 3 * 3 / (6 * ydot * 300)
    assert leading == pytest.approx(4.0e-3, rel=0.02)
    assert 0.7 * leading < err.window < 1.3 * leading
    masses = audit(task, uncertainty=_u(_every(Q(1, 20)))).robust[0]
    assert 0 < masses.window < 1e-4  # the masses alone: tens of microseconds
    assert masses.window < err.window < both.window


def test_no_uncertainty_changes_nothing_and_a_zero_box_only_adds_its_records() -> None:
    task = _limited(load_task(P2))
    plain = audit(task).to_dict()
    zero = audit(task, uncertainty=_u({})).to_dict()
    assert "uncertainty" not in plain and "robust" not in plain["singularities"][0]
    assert zero["singularities"][0].pop("robust")["window"] == 0.0
    zero.pop("uncertainty")
    assert zero == plain


# -- verdicts ---------------------------------------------------------------------------------


def _float_planner_task() -> Task:
    """Path 2 written as a planner does: x(t) and y(t) = p(x(t)) as polynomials in t whose
    coefficients are rounded to doubles (one piece from 0 to 5 s)."""
    task = load_task(P2)
    x = task.x_of_t
    y = task.path(x)

    def rounded(p: fmpq_poly, n: int) -> list[float]:
        c = [float(v) for v in p.coeffs()] + [0.0] * (n - p.degree() - 1)
        return c[::-1]  # highest first

    n = y.degree() + 1
    xc, yc = rounded(x, n), rounded(y, n)
    motion = Motion.from_pieces([0.0, 5.0], [[v] for v in xc], [[v] for v in yc], local=False)
    return _limited(with_motion(task, motion))


def test_float_planner_output_passes_with_declared_uncertainty() -> None:
    task = _float_planner_task()
    exact = audit(task)
    (s,) = exact.singularities
    assert not s.consistent and abs(s.consistency_residual) < 1e-12  # rounding only
    assert "RPR201" in [f.rule for f in exact.findings] and exact.verdict == "fail"
    zero = audit(task, uncertainty=_u({}))
    assert zero.verdict == "pass"
    (pole,) = [f for f in zero.findings if f.rule == "RPR201"]
    assert pole.severity == "warning" and "consistent to the input's precision" in pole.message
    assert zero.robust[0].window < 1e-12
    masses = audit(task, uncertainty=_u(_every(Q(1, 20))))
    assert masses.verdict == "pass" and 0 < masses.robust[0].window < 1e-3


def test_a_crossing_at_zero_vertical_speed_fails_on_a_long_window() -> None:
    task = _limited(load_task(ZERO_SPEED))
    result = audit(task, uncertainty=_u(_every(Q(1, 20)), Q(1, 100)))
    assert result.verdict == "fail"
    (f,) = [f for f in result.findings if f.rule == "RPR205"]
    assert "longer than the 1 ms period" in f.message
    assert result.robust[0].window > 0.5


def test_prismatic_window_fails_and_names_the_force() -> None:
    task = _limited(load_task(PRISMATIC))
    result = audit(task, uncertainty=_u(_every(Q(1, 20)), Q(1, 100)))
    (f,) = [f for f in result.findings if f.rule == "RPR205"]
    assert "|F2| > 300 N for at most" in f.message


@pytest.mark.parametrize("knot", ["2.501", "2.5"])
def test_a_knot_inside_the_window_does_not_cut_it_short(knot: str) -> None:
    """Path 2's quintic written as two pieces with a knot at t = 2.501 s, 1 ms after t_s and
    inside the 5.44 ms window of ±5 % and 0.01 m/s²: the window goes on past the knot into
    the second piece, as wide as the one-piece motion's (which the brute force above
    holds), and RPR205 fails it against a 4 ms period."""
    u = _u(_every(Q(1, 20)), Q(1, 100), Q(4, 1000))
    one = audit(_limited(load_task(P2)), uncertainty=u)
    text = (Path(__file__).parent / "path2_split.rprpr.yaml").read_text(encoding="utf-8")
    split = audit(parse_task(text.replace("until: 2.501", f"until: {knot}")))  # or at t_s
    a, b = one.robust[0], split.robust[0]
    assert a.span is not None and b.span is not None
    assert b.window == pytest.approx(a.window, abs=1e-6)
    assert b.window == pytest.approx(5.44e-3, abs=5e-6)
    assert b.span == pytest.approx(a.span, abs=1e-6) and b.span[1] > 2.502
    assert b.window_lo == pytest.approx(a.window_lo, abs=1e-6)
    for result in (one, split):
        assert result.verdict == "fail" and "RPR205" in [f.rule for f in result.findings]

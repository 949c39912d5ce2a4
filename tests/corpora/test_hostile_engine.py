"""Valid but hostile input: the exact analysis never hangs and never crashes (issue 11).

Class 1, valid files that hung: clustered roots with huge coefficients (two instants
7e-331 s apart near t = 1e-30 s), degree 60, sixty irrational instants of one factor.
Each is audited exactly, within seconds, with values derived independently below; a task
that does exceed its work budget is stopped, reported (exit 4, in every format) and the
batch goes on.

Class 4, valid files that crashed on values beyond the double range: coefficients of
1e200 and 1e390, (1000000 x - 3000000)^60, instants at 1e-330 s, masses of 1e30 kg and
1e-30 kg. Each reported quantity is the nearest double (JSON null where that is
infinite), and each one the double does not represent faithfully is listed with its
exact value in ``beyond_double_range`` and printed exactly in every message.
"""

from __future__ import annotations

import json
import math
import os
import signal
import sys
import time
from fractions import Fraction as F
from pathlib import Path

import pytest
from flint import fmpq, fmpz_poly

from rprpr.cli.check import run_checks
from rprpr.cli.main import main
from rprpr.cli.options import CheckOptions
from rprpr.engine import audit as auditing
from rprpr.engine.audit import AuditResult, audit
from rprpr.engine.bounds import envelope as enveloping
from rprpr.engine.exact.singular import ISOLATING
from rprpr.io.loader import parse_task
from rprpr.model.options import AuditOptions
from rprpr.report.exit import ExitCode, run_status
from rprpr.report.records import task_report
from tests.conftest import CONFIGS, reused_runs

LINKS = "".join(
    f"    {i}: {{mass: {m}, inertia: {j}, r: 0.5}}\n"
    for i, m, j in ((2, "M2", "I2"), (3, "M3", "I3"), (4, "M2", "I2"), (5, "M3", "I3"))
)
PATH2 = "0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2"  # the paper's path 2, through (3, 0) at t = 2.5 s
QUINTIC = "  duration: 5\n  law: quintic\n"
SECONDS = 10.0  # CPU seconds: each audit below takes well under one; "hung" was minutes


def text(
    y: str, timing: str, *, ends: tuple[str, str] | None = None, a1: str = "6",
    masses: tuple[str, str] = ("2.0", "1.0"), inertias: tuple[str, str] = ("0.10", "0.05"),
) -> str:  # fmt: skip
    """A task with legs alike (links 2 = 4, 3 = 5)."""
    e = "" if ends is None else f"  from: {ends[0]}\n  to: {ends[1]}\n"
    links = LINKS.replace("M2", masses[0]).replace("M3", masses[1])
    links = links.replace("I2", inertias[0]).replace("I3", inertias[1])
    return (
        f"name: hostile\nrobot:\n  a1: {a1}\n  links:\n{links}path:\n  y: {y}\n{e}timing:\n{timing}"
    )


def audited(source: str) -> tuple[AuditResult, dict, float]:  # type: ignore[type-arg]
    """The audit (default samples), its report as strict JSON data, and its CPU time (not
    wall time: a busy machine must not turn a fast audit into a failure)."""
    start = time.process_time()
    r = audit(parse_task(source))
    seconds = time.process_time() - start
    report = json.loads(json.dumps(task_report(r, "hostile.yaml"), allow_nan=False))
    return r, report, seconds


def beyond(report: dict) -> dict[str, str]:  # type: ignore[type-arg]
    return {b["quantity"]: b["value"] for b in report["beyond_double_range"]}


def sci(v: F) -> str:
    """v with 6 significant digits in scientific form, from exact integers (an independent
    formatter: no float, no arb)."""
    sign, v = ("-" if v < 0 else ""), abs(v)
    e = (
        len(str(v.numerator // v.denominator)) - 1
        if v >= 1
        else -len(str(v.denominator // v.numerator))
    )
    while v / F(10) ** e >= 10:
        e += 1
    while v / F(10) ** e < 1:
        e -= 1
    m = round(v / F(10) ** e * 10**5)
    if m == 10**6:
        m, e = m // 10, e + 1
    digits = str(m).rstrip("0")
    mantissa = digits[0] + ("." + digits[1:] if len(digits) > 1 else "")
    return f"{sign}{mantissa}e{'+' if e >= 0 else '-'}{abs(e):02d}"


# -- class 1: exact root isolation that used to run for minutes -------------------------------


def test_clustered_roots_with_huge_coefficients_are_isolated_in_milliseconds() -> None:
    # y = x^20 - 2 (1e30 x - 1)^2, x = t: two roots at 1e-30 -+ (1e-30)^10/(sqrt 2 1e30),
    # 7e-331 s apart, where 1e30 x - 1 = -+x^10/sqrt 2; there dy/dx = 20 x^19 - 4e30 (1e30 x - 1)
    # = +-2 sqrt 2 1e-270 (to 1e-269 relative): the lower root first. δ' = -a1 y'/(s1 s2)
    # with s1 = 1e-30, s2 = 6 - 1e-30: -+2 sqrt 2 1e-240
    r, report, seconds = audited(text("x^20 - 2*(1e30*x - 1)^2", "  duration: 2e-30\n  x: t\n"))
    assert seconds < SECONDS
    assert [(s.order, s.kind, s.case.number, s.t_exact) for s in r.singularities] == [
        (1, "crossing", 3, None),
        (1, "crossing", 3, None),
    ]
    assert [s.t for s in r.singularities] == [1e-30, 1e-30]  # apart by far less than a double
    root2 = 2 * math.sqrt(2)
    assert [s.slope for s in r.singularities] == pytest.approx([root2 * 1e-270, -root2 * 1e-270])
    assert [s.delta_derivatives[1] for s in r.singularities] == pytest.approx(
        [-root2 * 1e-240, root2 * 1e-240]
    )
    # inconsistent, by a residual (eq. 34) below the double range: printed exactly
    assert [s.consistent for s in r.singularities] == [False, False]
    got = beyond(report)
    assert set(got) == {f"singularities[{i}].consistency_residual" for i in (0, 1)}
    for i, s in enumerate(r.singularities):
        assert (
            s.consistency_residual == 0.0 and got[f"singularities[{i}].consistency_residual"] != "0"
        )
        assert f"residual {got[f'singularities[{i}].consistency_residual']} N" in " ".join(
            f.message for f in r.findings
        )


def test_the_same_cluster_at_degree_60_reports_slopes_beyond_the_double_range() -> None:
    # x^60 - 2 (1e30 x - 1)^2: the roots are (1e-30)^30/(sqrt 2 1e30) apart and the slopes
    # +-4e30 (1e-30)^30/sqrt 2 = +-2 sqrt 2 1e-870 underflow, as do δ' = -+2 sqrt 2 1e-840:
    # 0 as doubles, exact in the list
    r, report, seconds = audited(text("x^60 - 2*(1e30*x - 1)^2", "  duration: 2e-30\n  x: t\n"))
    assert seconds < SECONDS
    assert [(s.order, s.t) for s in r.singularities] == [(1, 1e-30), (1, 1e-30)]
    assert [s.slope for s in r.singularities] == [0.0, 0.0]
    got = beyond(report)
    assert {k: v for k, v in got.items() if "residual" not in k} == {
        "singularities[0].delta_derivatives[1]": "-2.82843e-840",
        "singularities[0].slope": "2.82843e-870",
        "singularities[1].delta_derivatives[1]": "2.82843e-840",
        "singularities[1].slope": "-2.82843e-870",
    }
    # every message prints the exact value, never the misleading 0
    assert [s.slope_principle.reason for s in r.singularities] == [
        "dy/dx = 2.82843e-870 is nonzero",
        "dy/dx = -2.82843e-870 is nonzero",
    ]


def test_order_60_with_360_digit_coefficients() -> None:
    # (1e6 x - 3e6)^60 = 1e360 (x - 3)^60, x = t + 1: t_s = 2 exactly, order 60 (a touch);
    # δ = -a1 y/(s1 s2) with s1 = s2 = 3: δ^(60)(t_s) = -6 1e360 60!/9, far beyond doubles
    r, report, seconds = audited(text("(1000000*x - 3000000)^60", "  duration: 5\n  x: t + 1\n"))
    assert seconds < SECONDS
    (s,) = r.singularities
    assert (s.t_rational, s.order, s.kind, s.case.number) == (fmpq(2), 60, "touch", 3)
    assert s.slope_principle.passed is False and s.torque_bounded
    d60 = -F(6, 9) * 10**360 * math.factorial(60)
    assert beyond(report) == {"singularities[0].delta_derivatives[60]": sci(d60)}
    assert report["singularities"][0]["delta_derivatives"][60] is None  # -inf as a double
    assert report["verdict"] == "fail"


def test_sixty_irrational_instants_of_one_degree_60_factor() -> None:
    # T60(x) + 1/7 (Chebyshev) on x = t - 1: T60(cos a) = cos(60 a) = -1/7 at 60 angles
    t60 = fmpz_poly.chebyshev_t(60)
    y = " + ".join(f"({c})*x^{i}" for i, c in enumerate(t60.coeffs()) if c != 0) + " + 1/7"
    r, _, seconds = audited(text(y, "  duration: 2\n  x: t - 1\n"))
    assert seconds < SECONDS
    a = math.acos(-1 / 7)
    roots = sorted(1 + math.cos((s * a + 2 * math.pi * k) / 60) for k in range(60) for s in (1, -1))
    want = sorted({round(v, 12) for v in roots})  # the 60 distinct roots of T60(x) = -1/7
    assert len(want) == 60
    assert [s.order for s in r.singularities] == [1] * 60
    assert [s.t for s in r.singularities] == pytest.approx(want, abs=1e-11)
    assert all(s.t_exact is None for s in r.singularities)


# -- the work budget ---------------------------------------------------------------------------


def _deaf() -> None:
    """One long wait that nothing but SIGKILL ends: every signal that can be blocked is
    blocked (the worker's own mask: it is a forked process), so no handler runs and no
    default action stops it, and the wait is one C call that needs no CPU. It ends after a
    minute with no result, which the run would report as an error, not as the budget: so
    a test fails, rather than hangs, if the budget does not stop it."""
    signal.pthread_sigmask(signal.SIG_BLOCK, signal.valid_signals())
    time.sleep(60)


def _deaf_audit(task, options=None, *, on_stage):  # type: ignore[no-untyped-def]
    """An audit that enters root isolation and stays there, deaf (``_deaf``)."""
    on_stage(ISOLATING)
    _deaf()


@pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="the patch reaches workers by fork"
)
def test_a_task_over_budget_is_stopped_at_its_stage_and_the_batch_goes_on(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    slow = tmp_path / "slow.yaml"
    source = (CONFIGS / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")
    slow.write_text(source.replace("name: Example 2 of the paper, path 2", "name: slow"))
    real = auditing.audit

    def audit_or_hang(task, **kw):  # type: ignore[no-untyped-def]
        return _deaf_audit(task, **kw) if task.name == "slow" else real(task, **kw)

    monkeypatch.setattr(auditing, "audit", audit_or_hang)
    files = [
        str(slow),
        str(CONFIGS / "paper_path1.rprpr.yaml"),
        str(CONFIGS / "paper_path2.rprpr.yaml"),
    ]
    # 1 s: a thousand times what the exact analysis of the other tasks costs, so that a
    # busy machine cannot push them over it too
    run = run_checks(files, CheckOptions(AuditOptions(samples=101), budget=1.0))
    assert [kind for kind, _, _ in run.entries()] == ["budget", "report", "report"]
    (error,) = run.budget_errors
    assert error["task"] == str(slow) and error["stage"] == ISOLATING
    assert error["message"] == (
        "the exact analysis exceeded its budget of 1 s at the isolation of the real roots of y(t)"
    )
    assert [r["verdict"] for r in run.reports] == ["fail", "pass"]
    assert run_status(run) == ExitCode.BUDGET == 4
    assert run.summary() == {"tasks": 3, "passed": 1, "failed": 1, "errors": 1}


@pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="the patch reaches workers by fork"
)
def test_with_two_workers_a_stopped_task_and_a_dead_worker_keep_the_task_order(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    source = (CONFIGS / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")
    files = []
    for name in ("slow", "fine", "dies", "fine2"):
        p = tmp_path / f"{name}.rprpr.yaml"
        p.write_text(source.replace("name: Example 2 of the paper, path 2", f"name: {name}"))
        files.append(str(p))
    real = auditing.audit

    def audit_or_not(task, **kw):  # type: ignore[no-untyped-def]
        if task.name == "dies":  # a crash in C, or the out-of-memory killer
            os.kill(os.getpid(), signal.SIGKILL)
        return _deaf_audit(task, **kw) if task.name == "slow" else real(task, **kw)

    monkeypatch.setattr(auditing, "audit", audit_or_not)
    run = run_checks(files, CheckOptions(AuditOptions(samples=101), budget=1.0, jobs=2))
    assert [(kind, item["task"]) for kind, item, _ in run.entries()] == [
        ("budget", files[0]), ("report", files[1]), ("internal", files[2]), ("report", files[3]),
    ]  # fmt: skip
    assert "the worker process auditing it died (exit code -9)" in run.internal_errors[0]["message"]
    assert run_status(run) == ExitCode.BUDGET


def _deaf_envelope(self, rel=None):  # type: ignore[no-untyped-def]
    """A torque peak that never ends, deaf (``_deaf``)."""
    _deaf()


@pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="the patch reaches workers by fork"
)
def test_budget_exceeded_is_reported_in_every_format_with_exit_4(
    capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    # the real audit of path 1, whose torque envelope (the last stage but the findings)
    # never ends: the budget stops it there, whatever the exact analysis before it cost
    monkeypatch.setattr(enveloping.Envelope, "torque_peak", _deaf_envelope)
    path1, path2 = str(CONFIGS / "paper_path1.rprpr.yaml"), str(CONFIGS / "paper_path2.rprpr.yaml")
    common = ["check", "--peak", "--budget", "1", path1]  # far above the exact analysis
    message = "the exact analysis exceeded its budget of 1 s at the torque envelope"
    outputs = {}
    with reused_runs():  # one audit stopped by its budget, rendered in every format
        for fmt in ("json", "junit", "github", "text"):
            with pytest.raises(SystemExit) as e:
                main([*common, "--format", fmt])
            assert e.value.code == 4
            outputs[fmt] = capsys.readouterr()
    doc = json.loads(outputs["json"].out)
    assert doc["summary"] == {"tasks": 1, "passed": 0, "failed": 0, "errors": 1}
    assert [(b["task"], b["stage"], b["message"]) for b in doc["budget_errors"]] == [
        (path1, auditing.ENVELOPE, message)
    ]
    assert 'type="budget-exceeded"' in outputs["junit"].out and message in outputs["junit"].out
    assert outputs["github"].out.endswith(f",title=rprpr budget exceeded::{message}\n")
    assert message in outputs["text"].err
    # a task with a budget it fits in: audited as usual
    monkeypatch.undo()
    with pytest.raises(SystemExit) as e:
        main(["check", "--format", "json", "--budget", "60", path2])
    assert e.value.code == 0
    assert json.loads(capsys.readouterr().out)["budget_errors"] == []


# -- class 4: values beyond the double range ---------------------------------------------------


def test_coefficients_of_1e200_give_doubles_where_they_fit() -> None:
    # y = 1e200 (x - 3), x = t + 1: t_s = 2, slope 1e200; speed = sqrt(1 + 1e400) ~ 1e200
    # fits although its square does not; δ' = -a1 y'/(s1 s2) = -6e200/9
    r, report, _ = audited(text("(x - 3)*(1e30)^6*1e20", "  duration: 5\n  x: t + 1\n"))
    (s,) = r.singularities
    assert (s.t_rational, s.order) == (fmpq(2), 1)
    assert s.slope == 1e200 and s.speed == pytest.approx(1e200, rel=1e-15)
    assert s.delta_derivatives[1] == pytest.approx(-6e200 / 9, rel=1e-15)
    assert report["beyond_double_range"] == []


def test_coefficients_of_1e390_are_null_with_their_exact_values() -> None:
    r, report, _ = audited(text("(x - 3)*(1e30)^13", "  duration: 5\n  x: t + 1\n"))
    (s,) = r.singularities
    assert (s.t_rational, s.order, s.slope_principle.passed) == (fmpq(2), 1, True)
    rec = report["singularities"][0]
    assert (rec["slope"], rec["speed"], rec["delta_derivatives"][1]) == (None, None, None)
    got = beyond(report)
    assert got["singularities[0].slope"] == "1e+390"
    assert got["singularities[0].speed"] == "1e+390"  # sqrt(1 + 1e780)
    assert got["singularities[0].delta_derivatives[1]"] == sci(-F(6, 9) * 10**390)
    assert s.velocity_principle.reason == "speed 1e+390 m/s is nonzero"


def test_an_instant_at_1e_330_s_keeps_its_exact_time() -> None:
    # x = 1e330 t + 2 over 1e-30 s crosses x = 3 at t = 1e-330: below the smallest double
    r, report, _ = audited(text("x - 3", "  duration: 1e-30\n  x: (1e30)^11*t + 2\n"))
    (s,) = r.singularities
    assert s.t_rational == fmpq(1, 10**330) and s.t == 0.0
    got = beyond(report)
    assert got["singularities[0].t"] == "1e-330"
    assert got["singularities[0].speed"] == "1.41421e+330"  # |(1e330, 1e330)|
    assert report["singularities"][0]["speed"] is None and report["verdict"] == "pass"


def test_a_motion_of_1e_30_s_by_the_quintic_law() -> None:
    # the quintic law's peak speed is 15/8 (x1 - x0)/t_f at t_f/2, here along dy/dx = 1
    r, report, _ = audited(
        text(PATH2.replace("0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2", "x - 3"),
             "  duration: 1e-30\n  law: quintic\n", ends=("[2, -1]", "[4, 1]"))
    )  # fmt: skip
    (s,) = r.singularities
    assert s.t_rational == fmpq(1, 2 * 10**30)
    assert s.speed == pytest.approx(15 / 8 * 2 / 1e-30 * math.sqrt(2), rel=1e-15)
    assert report["beyond_double_range"] == []


@pytest.mark.parametrize("scale", ["1e30", "1e-30"])
def test_masses_of_1e30_and_1e_30_kg_scale_the_torques(scale: str) -> None:
    # eq. (28) is linear in the masses and inertias (gravity included): the paper's path 2
    # with every mass and inertia times k has k times its torques, (63.225, -5.445) N m
    k = float(scale)
    r, report, _ = audited(
        text(PATH2, QUINTIC, ends=("[2, -1]", "[4, 1]"),
             masses=(f"2{scale[1:]}", f"1{scale[1:]}"),
             inertias=(f"0.1{scale[1:]}", f"0.05{scale[1:]}"))
    )  # fmt: skip
    (s,) = r.singularities
    assert s.torque_at_singularity == pytest.approx((63.225 * k, -5.445 * k), rel=1e-12)
    assert report["beyond_double_range"] == []


@pytest.mark.parametrize(
    ("a1", "case", "delta1"),
    [
        ("1e-30", 1, -F(1, 10**30) / (3 * (3 - F(1, 10**30)))),
        ("1" + "0" * 39, 3, -F(10**39) / (3 * (10**39 - 3))),
    ],
)
def test_robots_of_1e_30_and_1e39_metres(a1: str, case: int, delta1: F) -> None:
    # y = x - 3, x = t + 1: t_s = 2 at (3, 0), beyond B (case 1) or between A and B (case 3);
    # δ' = -a1 y'/(s1 s2) with s1 = 3, s2 = |3 - a1|
    r, report, _ = audited(text("x - 3", "  duration: 5\n  x: t + 1\n", a1=a1))
    (s,) = r.singularities
    assert (s.t_rational, s.order, s.case.number) == (fmpq(2), 1, case)
    assert s.delta_derivatives[1] == pytest.approx(float(delta1), rel=1e-15)
    assert report["beyond_double_range"] == []


def test_a_gravity_of_1e39_gives_the_torques_eq_28_is_linear_in() -> None:
    # at constant velocity the torques at t_s are affine in g: T(g) = T(0) + g (T(1) - T(0))
    def torque(g: str) -> tuple[float, float]:
        source = text("x - 3", "  duration: 5\n  x: t + 1\n")
        (s,) = audit(
            parse_task(source.replace("  links:", f"  gravity: {g}\n  links:"))
        ).singularities
        assert s.torque_at_singularity is not None
        return s.torque_at_singularity

    t0, t1, big = torque("0"), torque("1"), torque("1" + "0" * 39)
    assert big == pytest.approx(
        [a + 1e39 * (b - a) for a, b in zip(t0, t1, strict=True)], rel=1e-14
    )


def test_the_end_point_at_a_at_1e_90_s() -> None:
    # x = t - 1e-90 passes A (x = 0) at t = 1e-90 on y = 1e270 x: an inverse-kinematic
    # singularity of leg 1, no Type II instant
    r, report, _ = audited(text("x*(1e30)^9", "  duration: 1\n  x: t - 1/(1e30)^3\n"))
    assert r.singularities == []
    assert [(k.t, k.leg) for k in r.kinematic_singularities] == [(1e-90, 1)]
    assert [f.rule for f in r.findings] == ["RPR103"] and report["verdict"] == "fail"


def test_an_irrational_instant_at_1_4e_200_s() -> None:
    # y = x^2 - 2e-400, x = t: t_s = sqrt 2 1e-200 (irrational), slope 2 t_s
    r, report, _ = audited(text("x^2 - 2/((1e30)^13*1e10)", "  duration: 1\n  x: t\n"))
    (s,) = r.singularities
    assert s.t_exact is None and s.order == 1
    assert s.t == pytest.approx(math.sqrt(2) * 1e-200, rel=1e-15) and s.x == s.t
    assert s.slope == pytest.approx(2 * math.sqrt(2) * 1e-200, rel=1e-15)
    assert report["beyond_double_range"] == []


def test_an_inconsistency_of_1e600_newton_is_printed_exactly() -> None:
    # y = 1e300 (x^2 - 2), x = t: an irrational instant at sqrt 2 whose eq. (34) residual
    # is beyond the double range: -inf as a double, exact in the finding's message
    r, report, _ = audited(text("(x^2 - 2)*(1e30)^10", "  duration: 5\n  x: t\n"))
    (s,) = r.singularities
    assert s.t == pytest.approx(math.sqrt(2), rel=1e-15) and s.t_exact is None
    assert not s.consistent and s.consistency_residual == -math.inf
    residual = beyond(report)["singularities[0].consistency_residual"]
    assert residual.startswith("-") and residual.endswith("e+600")
    (finding,) = [f for f in r.findings if f.rule == "RPR201"]
    assert f"residual {residual} N" in finding.message
    assert all("inf" not in f.message for f in r.findings)


def test_a_torque_limit_of_1e_30_and_margins_of_1e39() -> None:
    margins = "checks:\n  min_slope: 1" + "0" * 39 + "\n  min_speed: 0.1e-29\n"
    margins += "  torque_limit: [1e-30, 1e-30]\n"
    r, _, _ = audited(text(PATH2, QUINTIC, ends=("[2, -1]", "[4, 1]")) + margins)
    (s,) = r.singularities
    assert s.slope_principle.reason == (
        "|dy/dx| = 0.2 does not exceed the margin checks.min_slope = 1e+39"
    )
    assert s.velocity_principle.reason == "speed 0.764853 m/s exceeds checks.min_speed = 1e-30 m/s"
    assert [f.rule for f in r.findings] == ["RPR101", "RPR202", "RPR202"]
    assert r.verdict == "fail"


def test_hostile_files_through_the_command_line_give_strict_json(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    files = []
    for i, (y, timing) in enumerate(
        [
            ("(x - 3)*(1e30)^13", "  duration: 5\n  x: t + 1\n"),
            ("(1000000*x - 3000000)^60", "  duration: 5\n  x: t + 1\n"),
            ("x^20 - 2*(1e30*x - 1)^2", "  duration: 2e-30\n  x: t\n"),
            ("x - 3", "  duration: 1e-30\n  x: (1e30)^11*t + 2\n"),
        ]
    ):
        p = tmp_path / f"hostile{i}.rprpr.yaml"
        p.write_text(text(y, timing), encoding="utf-8")
        files.append(str(p))
    with pytest.raises(SystemExit) as e:
        main(["check", "--format", "json", *files])
    # the order-60 touch fails its slope principle, the two crossings 1e-30 s from the
    # start have unbounded torques (RPR201 fails by default); no error
    assert e.value.code == 1
    out = capsys.readouterr().out
    doc = json.loads(out, parse_constant=lambda c: pytest.fail(f"not strict JSON: {c}"))
    assert doc["summary"] == {"tasks": 4, "passed": 2, "failed": 2, "errors": 0}
    assert [r["task"] for r in doc["reports"]] == files
    assert [len(r["beyond_double_range"]) for r in doc["reports"]] == [5, 1, 2, 5]

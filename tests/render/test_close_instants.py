"""Two singular instants 10⁻⁶ s apart read apart in every format (and so do a torque peak
and the limit it just exceeds).

y = (x - 3)(x - 3.000001) with x = 2 + t crosses y = 0 at t = 1 and t = 1.000001. The
instants are told apart once, over all the instants of the task (``numbers.labels``), and
every format names them the same way: the text table and verdict line, the JSON records,
the JUnit system-out and failures, the GitHub annotations and the findings themselves.
Six significant digits alone would print both as ``t = 1 s``.
"""

from __future__ import annotations

import io
import json
import re
import xml.etree.ElementTree as ET
from typing import Any

from rich.console import Console

from rprpr.engine.audit import audit
from rprpr.io.loader import parse_task
from rprpr.render.github import render as github
from rprpr.render.json import render as json_report
from rprpr.render.junit import render as junit
from rprpr.render.text import render as text
from rprpr.report.records import task_report
from rprpr.report.run import REPORT, Run
from tests.conftest import CLOSE_INSTANTS, task_text

PATH = "close.yaml"
CLOSE = CLOSE_INSTANTS
# both instants then break the slope principle (|dy/dx| = 1e-6): a finding at each
SHALLOW = CLOSE + "checks:\n  min_slope: 0.01\n"

WHERE = "(x, y) = (3, 0), case 3, order 1"
UNBOUNDED = (
    f"t = 1.000001 s, {WHERE}: torques unbounded (pole of order 1):"
    " inconsistent: eq. (34) residual 7.40741e-20 N ≠ 0"
)


def slope_fails(t: str) -> str:
    return (
        f"t = {t} s, {WHERE}: slope principle fails: |dy/dx| = 1e-06 does not exceed"
        " the margin checks.min_slope = 0.01"
    )


def report(source: str, strict: bool | None = None) -> dict[str, Any]:
    return task_report(audit(parse_task(source, PATH), strict=strict), PATH)


def run_of(rep: dict[str, Any]) -> Run:
    r = Run()
    r.add(REPORT, rep)
    return r


def text_lines(rep: dict[str, Any]) -> list[str]:
    out = io.StringIO()
    console = Console(file=out, width=160, color_system=None)
    text(run_of(rep), console, console)
    return out.getvalue().splitlines()


def test_findings_name_each_instant_apart() -> None:
    assert [(f.rule, f.message, f.t) for f in audit(parse_task(CLOSE)).findings] == [
        ("RPR201", UNBOUNDED, 1.000001)
    ]
    assert [(f.rule, f.message) for f in audit(parse_task(SHALLOW)).findings] == [
        ("RPR101", slope_fails("1")),
        ("RPR101", slope_fails("1.000001")),
        ("RPR201", UNBOUNDED),
    ]


def test_json_records_hold_both_times() -> None:
    doc = json.loads(json_report(run_of(report(CLOSE))))
    (rep,) = doc["reports"]
    assert [s["t"] for s in rep["singularities"]] == [1.0, 1.000001]
    assert [s["torque_bounded"] for s in rep["singularities"]] == [True, False]
    assert [(f["message"], f["t"]) for f in rep["findings"]] == [(UNBOUNDED, 1.000001)]


def test_text_table_names_both_instants_apart() -> None:
    rows = [ln.split("│") for ln in text_lines(report(CLOSE)) if ln.startswith("│")]
    assert [r[1].strip() for r in rows] == ["1", "1.000001"]
    assert [r[-2].strip() for r in rows] == ["38.93, -38.94", "unbounded"]


def test_text_verdict_line_names_the_pole_with_its_digits() -> None:
    verdict = [ln for ln in text_lines(report(CLOSE)) if ln.startswith("  verdict:")]
    assert verdict == [
        "  verdict: FAIL — 2 singular instants, 0 high-order; torques unbounded at t = 1.000001 s"
    ]


def test_junit_names_both_instants_apart() -> None:
    root = ET.fromstring(junit(run_of(report(SHALLOW, strict=True))))
    (case,) = root.iter("testcase")
    assert (case.findtext("system-out") or "").splitlines() == [
        f"t = 1 s: {WHERE} crossing; slope principle fail, velocity principle pass; torque bounded",
        f"t = 1.000001 s: {WHERE} crossing; slope principle fail, velocity principle pass;"
        " torque unbounded (pole of order 1)",
        "verdict: fail (strict), 2 singular instants; torques unbounded at t = 1.000001 s",
    ]
    assert [f.get("message") for f in case.iter("failure")] == [
        f"RPR101 slope-principle: {slope_fails('1')}",
        f"RPR101 slope-principle: {slope_fails('1.000001')}",
        f"RPR201 unbounded-torque: {UNBOUNDED}",
    ]


def test_github_annotations_name_both_instants_apart() -> None:
    assert github(run_of(report(SHALLOW))).splitlines() == [
        f"::error file={PATH},line=10,title=RPR101 slope-principle::{slope_fails('1')}",
        f"::error file={PATH},line=10,title=RPR101 slope-principle::{slope_fails('1.000001')}",
        f"::error file={PATH},line=4,title=RPR201 unbounded-torque::{UNBOUNDED}",
    ]


def test_a_peak_just_beyond_the_torque_limit_reads_apart_from_the_limit() -> None:
    # y = 1, x = 2 + t: |T1| peaks at 60.4347834699... N m at t = 2 s (the end), just
    # beyond the limit; with six digits both would read 60.4348
    level = task_text("1", "timing:\n  duration: 2\n  x: 2 + t\n")
    task = parse_task(level + "checks:\n  torque_limit: [60.4347834, 1000]\n")
    ((rule, message),) = [(f.rule, f.message) for f in audit(task, peak=True).findings]
    assert rule == "RPR202" and message.startswith(
        "|T1| reaches 60.43478347 N m at t = 2 s, beyond the limit 60.4347834 N m:"
        " above it from t = "
    )
    # the crossing, by bisection on the 60-digit reference: t = 1.99999999735 s; the
    # message's time (10 digits) within the bracket's 1e-9 t_f of it
    start = float(re.search(r"above it from t = ([0-9.]+) s", message).group(1))  # type: ignore[union-attr]
    assert abs(start - 1.99999999735) <= 2e-9 + 5e-10
    assert message.endswith(f"(t = {start:.10g} .. 2 s)")

"""The report formats of ``rprpr check``: JSON, JUnit XML, GitHub workflow commands, text.

Stable rule ids in every format; GitHub's escaping exactly as the Actions toolkit's;
JUnit parsed back and held to the element/attribute structure of the common JUnit
schema (Jenkins ``junit-10.xsd``) with counts consistent with the children.
"""

from __future__ import annotations

import copy
import json
import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path
from unittest import mock

import pytest

from rprpr.cli.check import check_one
from rprpr.cli.options import CheckOptions
from rprpr.io.loader import parse_task
from rprpr.model.errors import TaskFileError
from rprpr.model.options import AuditOptions
from rprpr.model.rules import RULES
from rprpr.render.github import annotation_path, command, escape_data, escape_property
from rprpr.render.github import render as github
from rprpr.render.junit import render as junit
from rprpr.render.junit import xml_text
from rprpr.report.run import Run
from tests.conftest import BAD_A1, FAST, ROOT, run_cli

P1 = "configs/paper_path1.rprpr.yaml"  # fails RPR101 (slope) and RPR201 (unbounded)
P2 = "configs/paper_path2.rprpr.yaml"  # passes, no finding
ZERO = "configs/zero_speed_crossing.rprpr.yaml"  # fails RPR102 (velocity) and RPR201
TRICKY = "50% done: a, b\r\nnext line"


@pytest.fixture(autouse=True)
def _in_repo(monkeypatch: pytest.MonkeyPatch) -> None:
    """Run from the repository root, so that task paths are the relative ones CI uses."""
    monkeypatch.chdir(ROOT)


def line_of(path: str, prefix: str) -> int:
    """1-based line of the first line of ``path`` starting with ``prefix``."""
    lines = (ROOT / path).read_text(encoding="utf-8").splitlines()
    return next(i for i, ln in enumerate(lines, 1) if ln.startswith(prefix))


def make_run(
    *paths: str, samples: int = 101, strict: bool | None = None, warn_unbounded: bool = False
) -> Run:
    r = Run()
    verdicts = AuditOptions(samples=samples, strict=strict, warn_unbounded=warn_unbounded)
    options = CheckOptions(verdicts)
    for p in paths:
        r.add(*check_one(p, options))
    return r


P1_UNBOUNDED = (
    "t = 2.5 s, (x, y) = (3, 0), case 3, order 3: torques unbounded (pole of order 2):"
    " consistent (eq. 34), but only 1 of 3 boundedness conditions hold"
)
ZERO_UNBOUNDED = (
    "t = 1 s, (x, y) = (3, 0), case 3, order 3: torques unbounded (pole of order 2):"
    " consistent (eq. 34), but only 1 of 3 boundedness conditions hold"
)


@pytest.fixture
def bad_file(tmp_path: Path) -> str:
    p = tmp_path / "bad.yaml"
    p.write_text(BAD_A1, encoding="utf-8")
    return str(p)


# -- JSON ------------------------------------------------------------------------------------
def test_json_document_summary_and_input_errors(bad_file: str, tmp_path: Path) -> None:
    missing = str(tmp_path / "missing.yaml")
    code, out, _ = run_cli("check", "--format", "json", *FAST, P1, P2, bad_file, missing)
    assert code == 2
    doc = json.loads(out)
    assert list(doc) == [
        "rprpr",
        "reports",
        "summary",
        "input_errors",
        "internal_errors",
        "budget_errors",
    ]
    assert doc["summary"] == {"tasks": 4, "passed": 1, "failed": 1, "errors": 2}
    assert [r["task"] for r in doc["reports"]] == [P1, P2]
    assert [r["verdict"] for r in doc["reports"]] == ["fail", "pass"]
    bad, gone = doc["input_errors"]
    assert {k: bad[k] for k in ("task", "line", "column", "key", "rule")} == {
        "task": bad_file, "line": 3, "column": 7, "key": "robot.a1", "rule": "RPR001",
    }  # fmt: skip
    assert bad["message"].startswith("expected a number > 0")
    assert bad["message"].endswith("found -1")
    # unknown location and key are null, not a made-up line 0
    assert {k: gone[k] for k in ("task", "line", "column", "key", "message")} == {
        "task": missing, "line": None, "column": None, "key": None, "message": "no such file",
    }  # fmt: skip
    assert doc["internal_errors"] == []


def test_json_findings_carry_rule_ids_keys_and_lines() -> None:
    _, out, _ = run_cli("check", "--format", "json", *FAST, P1, ZERO)
    p1, zero = json.loads(out)["reports"]
    assert [(f["rule"], f["name"], f["severity"], f["key"], f["line"]) for f in p1["findings"]] == [
        ("RPR101", "slope-principle", "error", "path.y", line_of(P1, "  y:")),
        ("RPR201", "unbounded-torque", "error", "robot.links", line_of(P1, "  links:")),
    ]
    assert [(f["rule"], f["key"], f["line"]) for f in zero["findings"]] == [
        ("RPR102", "timing", line_of(ZERO, "timing:")),
        ("RPR201", "robot.links", line_of(ZERO, "  links:")),
    ]
    assert [f["message"] for f in p1["findings"]][1] == P1_UNBOUNDED
    _, out, _ = run_cli("check", "--format", "json", "--warn-unbounded", *FAST, P1)
    (p1,) = json.loads(out)["reports"]
    assert [f["severity"] for f in p1["findings"]] == ["error", "warning"]


def test_json_leaves_out_the_times_so_runs_are_reproducible() -> None:
    a = run_cli("check", "--format", "json", *FAST, P1, P2)
    b = run_cli("check", "--format", "json", *FAST, P1, P2)
    assert a == b
    assert '"time"' not in a[1]


# -- GitHub ----------------------------------------------------------------------------------
def test_github_escaping_is_the_actions_toolkit_one() -> None:
    assert escape_data(TRICKY) == "50%25 done: a, b%0D%0Anext line"
    assert escape_property(TRICKY) == "50%25 done%3A a%2C b%0D%0Anext line"
    # % first, so an escape is never escaped twice
    assert escape_data("%0A") == "%250A"
    assert escape_property("a:%2C") == "a%3A%252C"
    assert command("warning", {"file": "a,b:c.yaml", "line": 4, "col": None}, TRICKY) == (
        "::warning file=a%2Cb%3Ac.yaml,line=4::50%25 done: a, b%0D%0Anext line"
    )
    assert command("error", {}, "plain") == "::error::plain"


def test_github_one_line_per_finding(bad_file: str) -> None:
    code, out, err = run_cli("check", "--format", "github", *FAST, P1, P2, ZERO, bad_file)
    assert code == 2
    y1, links1 = line_of(P1, "  y:"), line_of(P1, "  links:")
    timing, links0 = line_of(ZERO, "timing:"), line_of(ZERO, "  links:")
    assert out.splitlines() == [
        f"::error file={P1},line={y1},title=RPR101 slope-principle::t = 2.5 s, (x, y) = (3, 0),"
        " case 3, order 3: slope principle fails: the path is horizontal here (dy/dx = 0, eq."
        " 48): a high-order singularity",
        f"::error file={P1},line={links1},title=RPR201 unbounded-torque::{P1_UNBOUNDED}",
        f"::error file={ZERO},line={timing},title=RPR102 velocity-principle::t = 1 s,"
        " (x, y) = (3, 0), case 3, order 3: velocity principle fails: the end point is at rest"
        " here (speed 0, eq. 47): a high-order singularity",
        f"::error file={ZERO},line={links0},title=RPR201 unbounded-torque::{ZERO_UNBOUNDED}",
        f"::error file={escape_property(annotation_path(bad_file))},line=3,col=7,"
        f"title=RPR001 invalid-task::robot.a1: {bad_message()}",
    ]
    assert err.startswith(f"{bad_file}:3:7: robot.a1: ")  # the log line, on stderr


def bad_message() -> str:
    """The loader's message for BAD_A1."""
    with pytest.raises(TaskFileError) as e:
        parse_task(BAD_A1)
    return e.value.message


def test_github_escapes_a_tricky_message_and_path() -> None:
    r = make_run(P1)
    rep = r.reports[0]
    rep["task"] = "odd,dir:x/50%.yaml"
    rep["findings"][0]["message"] = TRICKY
    lines = github(r).splitlines()
    assert lines[0] == (
        f"::error file=odd%2Cdir%3Ax/50%25.yaml,line={line_of(P1, '  y:')},"
        "title=RPR101 slope-principle::50%25 done: a, b%0D%0Anext line"
    )
    assert len(lines) == 2  # the newline in the message did not make a line of its own


def test_github_escapes_a_tricky_file_name_end_to_end(tmp_path: Path) -> None:
    odd = tmp_path / "plan 50%,v2:final\nb.yaml"
    odd.write_text(BAD_A1, encoding="utf-8")
    code, out, _ = run_cli("check", "--format", "github", str(odd))
    assert code == 2
    [line] = out.splitlines()
    file = str(odd).replace("%", "%25").replace("\n", "%0A").replace(":", "%3A").replace(",", "%2C")
    assert line.startswith(
        f"::error file={file},line=3,col=7,title=RPR001 invalid-task::robot.a1: "
    )


def test_github_paths_are_workspace_relative(tmp_path: Path) -> None:
    assert annotation_path("./configs/a.yaml") == "configs/a.yaml"
    assert annotation_path(str(tmp_path / "x" / "a.yaml"), root=str(tmp_path)) == "x/a.yaml"
    assert annotation_path("/elsewhere/a.yaml", root=str(tmp_path)) == "/elsewhere/a.yaml"


def test_github_passing_tasks_print_nothing() -> None:
    assert run_cli("check", "--format", "github", *FAST, P2) == (0, "", "")


def test_github_strict_findings_are_errors_in_strict_mode() -> None:
    out = github(make_run(P1, warn_unbounded=True))
    assert [ln.split("::")[1].split(" ")[0] for ln in out.splitlines()] == ["error", "warning"]
    out = github(make_run(P1, strict=True, warn_unbounded=True))
    assert [ln.split("::")[1].split(" ")[0] for ln in out.splitlines()] == ["error", "error"]


# -- JUnit -----------------------------------------------------------------------------------
# The element/attribute structure of the Jenkins xunit plugin's junit-10.xsd, the schema
# GitHub/GitLab/Jenkins readers accept (transcribed: allowed attributes, required ones,
# allowed children), plus ``file`` on testcase, which GitLab reads and rprpr documents.
SUREFIRE_TIME = re.compile(r"(([0-9]{0,3},)*[0-9]{3}|[0-9]{0,3})*(\.[0-9]*)?")
LEAVES = ("failure", "error", "skipped")
SCHEMA: dict[str, tuple[set[str], set[str], set[str]]] = {
    # tag: (allowed attributes, required attributes, allowed children)
    "testsuites": ({"name", "time", "tests", "failures", "errors"}, set(), {"testsuite"}),
    "testsuite": (
        {
            "name",
            "tests",
            "failures",
            "errors",
            "group",
            "time",
            "skipped",
            "timestamp",
            "hostname",
            "id",
            "package",
            "file",
            "log",
            "url",
        },
        {"name", "tests", "failures", "errors"},
        {"testsuite", "properties", "testcase", "system-out", "system-err"},
    ),
    "testcase": (
        {"name", "time", "classname", "group", "file"},
        {"name"},
        {"skipped", "error", "failure", "system-out", "system-err"},
    ),
    "failure": ({"type", "message"}, set(), set()),
    "error": ({"type", "message"}, set(), set()),
    "skipped": ({"type", "message"}, set(), set()),
    "properties": (set(), set(), {"property"}),
    "property": ({"name", "value"}, {"name", "value"}, set()),
    "system-out": (set(), set(), set()),
    "system-err": (set(), set(), set()),
}


def validate_junit(xml: str) -> ET.Element:
    """Parse ``xml`` and check it against SCHEMA and the counting rules; the root."""
    assert xml.startswith('<?xml version="1.0" encoding="UTF-8"?>\n')
    root = ET.fromstring(xml.encode("utf-8"))
    assert root.tag == "testsuites"

    def check(e: ET.Element) -> None:
        allowed, required, children = SCHEMA[e.tag]
        assert set(e.attrib) <= allowed, (e.tag, set(e.attrib) - allowed)
        assert required <= set(e.attrib), (e.tag, required - set(e.attrib))
        for c in e:
            assert c.tag in children, (e.tag, c.tag)
            check(c)
        if e.tag in ("testsuites", "testsuite") and "time" in e.attrib:
            assert SUREFIRE_TIME.fullmatch(e.attrib["time"]), e.attrib["time"]
        if e.tag == "testcase" and "time" in e.attrib:
            float(e.attrib["time"])

    check(root)
    for suite in [root, *root.iter("testsuite")]:
        cases = list(suite.iter("testcase"))
        assert int(suite.attrib["tests"]) == len(cases)
        assert int(suite.attrib["failures"]) == sum(c.find("failure") is not None for c in cases)
        assert int(suite.attrib["errors"]) == sum(c.find("error") is not None for c in cases)
        if "skipped" in suite.attrib:
            assert int(suite.attrib["skipped"]) == sum(c.find("skipped") is not None for c in cases)
    return root


def test_junit_structure_counts_and_cases(bad_file: str) -> None:
    code, out, _ = run_cli("check", "--peak", "--format", "junit", *FAST, P1, P2, ZERO, bad_file)
    assert code == 2
    root = validate_junit(out)
    [suite] = root.findall("testsuite")  # one testsuite per run
    assert suite.attrib["name"] == "rprpr check"
    assert {k: suite.attrib[k] for k in ("tests", "failures", "errors", "skipped")} == {
        "tests": "4", "failures": "2", "errors": "1", "skipped": "0",
    }  # fmt: skip
    cases = suite.findall("testcase")
    assert [(c.attrib["classname"], c.attrib["name"], c.attrib["file"]) for c in cases] == [
        (P1, "Example 1 of the paper, path 1", P1),
        (P2, "Example 2 of the paper, path 2", P2),
        (ZERO, "Crossing at zero speed", ZERO),
        (bad_file, bad_file, bad_file),
    ]
    times = [float(c.attrib["time"]) for c in cases]
    assert all(t >= 0 for t in times)
    assert float(suite.attrib["time"]) == pytest.approx(sum(times), abs=0.003)

    # one failure per failing finding: the rule id in type, the reason in the message
    f1, unbounded = cases[0].findall("failure")
    assert unbounded.attrib["message"] == f"RPR201 unbounded-torque: {P1_UNBOUNDED}"
    assert f1.attrib["type"] == "RPR101"
    assert f1.attrib["message"] == (
        "RPR101 slope-principle: t = 2.5 s, (x, y) = (3, 0), case 3, order 3: slope principle"
        " fails: the path is horizontal here (dy/dx = 0, eq. 48): a high-order singularity"
    )
    assert f1.text is not None
    assert f1.text.startswith(f"{P1}:{line_of(P1, '  y:')}: path.y: RPR101 slope-principle: ")
    assert cases[1].findall("failure") == [] and cases[1].findall("error") == []
    f3, _ = cases[2].findall("failure")
    assert f3.attrib["type"] == "RPR102"
    assert "velocity principle fails: the end point is at rest" in f3.attrib["message"]

    out1 = cases[0].findtext("system-out")
    assert out1 is not None
    assert "t = 2.5 s: (x, y) = (3, 0), case 3, order 3 crossing; slope principle fail" in out1
    assert out1.splitlines()[-1] == (
        "verdict: fail, 1 singular instant; torques unbounded at t = 2.5 s"
    )
    out2 = cases[1].findtext("system-out")
    assert out2 is not None  # the certified peaks and their times (tests/cli/test_output.py)
    assert out2.splitlines()[-1] == (
        "verdict: pass, 1 singular instant; peak |T1| 66.1221 N m at t = 2.743 s,"
        " |T2| 60.5504 N m at t = 0.2024 s"
    )

    # the unreadable task file: an error naming the rule, line and key
    [err] = cases[3].findall("error")
    assert err.attrib["type"] == "RPR001"
    assert err.attrib["message"].startswith(
        f"RPR001 invalid-task: {bad_file}:3: robot.a1: expected"
    )
    assert err.text is not None
    assert err.text.startswith(f"{bad_file}:3:7: robot.a1: expected")


def test_junit_lists_an_accepted_unbounded_torque_as_a_warning() -> None:
    root = validate_junit(junit(make_run(P1, warn_unbounded=True)))
    [case] = root.iter("testcase")
    assert [f.attrib["type"] for f in case.findall("failure")] == ["RPR101"]
    out = case.findtext("system-out")
    assert out is not None
    warnings = [ln for ln in out.splitlines() if ln.startswith("warning: ")]
    assert warnings == [
        f"warning: {P1}:{line_of(P1, '  links:')}: robot.links: RPR201 unbounded-torque:"
        f" {P1_UNBOUNDED} (fails only with --strict)"
    ]


def test_junit_strict_mode_gives_a_failure_per_finding() -> None:
    root = validate_junit(junit(make_run(P1, strict=True, warn_unbounded=True)))
    [case] = root.iter("testcase")
    assert [f.attrib["type"] for f in case.findall("failure")] == ["RPR101", "RPR201"]
    assert root.attrib["failures"] == "1"  # one failed testcase, two failures in it


def test_junit_internal_error_is_an_error_with_the_traceback() -> None:
    r = Run()
    try:
        raise ValueError("boom")
    except ValueError as e:
        from rprpr.report.records import internal_error

        r.add("internal", internal_error(e, "t.yaml"), 0.25)
    root = validate_junit(junit(r))
    [err] = root.iter("error")
    assert err.attrib["type"] == "internal-error"
    assert err.attrib["message"].startswith("t.yaml: internal error (ValueError: boom)")
    assert err.text is not None and "Traceback" in err.text
    assert root.attrib["errors"] == "1" and root.attrib["time"] == "0.250"


def test_junit_escapes_markup_newlines_and_forbidden_characters() -> None:
    r = make_run(P1)
    rep = r.reports[0]
    rep["name"] = 'a <b> & "c"\nd\x07e'
    rep["task"] = "dir/<&>.yaml"
    rep["findings"][0]["message"] = TRICKY + " <&>\x00"
    root = validate_junit(junit(r))
    [case] = root.iter("testcase")
    assert case.attrib["name"] == 'a <b> & "c"\nd\\x07e'
    assert case.attrib["classname"] == case.attrib["file"] == "dir/<&>.yaml"
    f, _ = case.findall("failure")  # RPR101, RPR201
    # XML normalises a literal \r\n in text to \n; the attribute keeps both (as &#13;&#10;)
    assert f.attrib["message"] == "RPR101 slope-principle: 50% done: a, b\r\nnext line <&>\\x00"
    assert xml_text("ok\x01\ud800\ufffe\t\n") == "ok\\x01\\ud800\\ufffe\t\n"


def test_junit_lists_every_task_even_when_quiet() -> None:
    _, out, _ = run_cli("check", "--format", "junit", "-q", *FAST, P1, P2)
    assert len(validate_junit(out).findall("testsuite/testcase")) == 2


# -- rule ids in every format ---------------------------------------------------------------
@pytest.mark.parametrize("fmt", ["text", "json", "junit", "github"])
def test_rule_ids_appear_in_every_format(fmt: str, bad_file: str) -> None:
    _, out, err = run_cli("check", "--format", fmt, *FAST, P1, ZERO, bad_file)
    both = out + err
    for rule in ("RPR101", "RPR102", "RPR201", "RPR001"):
        assert rule in both, (fmt, rule)
    if fmt == "text":  # FILE:LINE:COL: RPRnnn [severity] name: message
        for rule in ("RPR101", "RPR102", "RPR201"):
            assert f"{rule} [error] {RULES[rule].name}: " in out, (fmt, rule)
    elif fmt != "json":
        for rule in ("RPR101", "RPR102", "RPR201"):
            assert RULES[rule].title in out, (fmt, rule)


def test_text_marks_strict_only_findings_as_warnings() -> None:
    y = line_of(P1, "  y:")
    wide = {**os.environ, "COLUMNS": "400"}  # one line per finding
    with mock.patch.dict(os.environ, wide):
        _, out, _ = run_cli("check", *FAST, P1)
    lines = [ln for ln in out.splitlines() if ln.startswith(f"{P1}:")]
    assert lines[0].startswith(f"{P1}:{y}:1: RPR101 [error] slope-principle: t = 2.5 s")
    assert lines[1].endswith(f":1: RPR201 [error] unbounded-torque: {P1_UNBOUNDED}")
    with mock.patch.dict(os.environ, wide):
        _, out, _ = run_cli("check", "--warn-unbounded", *FAST, P1)
    lines = [ln for ln in out.splitlines() if ln.startswith(f"{P1}:")]
    assert lines[1].endswith(f":1: RPR201 [warning] unbounded-torque: {P1_UNBOUNDED}")
    with mock.patch.dict(os.environ, wide):
        _, out, _ = run_cli("check", "--strict", "--warn-unbounded", *FAST, P1)
    assert f"RPR201 [error] unbounded-torque: {P1_UNBOUNDED}" in out


def test_renderers_do_not_change_the_run() -> None:
    r = make_run(P1, P2)
    before = copy.deepcopy(r)
    github(r)
    junit(r)
    assert r == before

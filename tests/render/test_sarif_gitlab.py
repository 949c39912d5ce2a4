"""``--output-format sarif`` validates against the OASIS SARIF 2.1.0 schema (vendored in
tests/render/sarif/) and ``gitlab`` has the fields GitLab's Code Quality report requires; both
locate each finding at the task file's line, as the JSON report does."""

from __future__ import annotations

import json
from pathlib import Path

import jsonschema
import pytest

from rprpr.model.rules import RULES
from rprpr.render.sarif import OPT_IN
from tests.conftest import BAD_A1, CONFIGS, FAST, reused_runs, run_cli

SCHEMA = json.loads((Path(__file__).parent / "sarif" / "sarif-schema-2.1.0.json").read_text())
P1 = "configs/paper_path1.rprpr.yaml"


def _sarif(*args: str) -> tuple[int, dict]:  # type: ignore[type-arg]
    with reused_runs():  # the tasks audited once for every format of this file
        code, out, _ = run_cli("check", "--output-format", "sarif", *FAST, *args)
    return code, json.loads(out)


def _shared(*args: str) -> tuple[int, str, str]:
    """``rprpr check ARGS``, audited once for every format this file prints."""
    with reused_runs():
        return run_cli("check", *args)


def test_the_vendored_schema_is_the_official_one() -> None:
    assert SCHEMA["title"] == "Static Analysis Results Format (SARIF) Version 2.1.0 JSON Schema"
    assert SCHEMA["id"].startswith("https://docs.oasis-open.org/sarif/sarif/v2.1.0/")


@pytest.mark.parametrize("tasks", [[P1], [str(CONFIGS)], ["configs/paper_path2.rprpr.yaml"]])
def test_sarif_is_valid_sarif_2_1_0(tasks: list[str]) -> None:
    _, doc = _sarif(*tasks)
    jsonschema.Draft4Validator(SCHEMA).validate(doc)
    assert doc["version"] == "2.1.0"
    [run] = doc["runs"]
    # the rules only declared uncertainty raises are listed with it (render.sarif.OPT_IN)
    assert [r["id"] for r in run["tool"]["driver"]["rules"]] == [
        r for r in RULES if r not in OPT_IN
    ]


def test_sarif_results_agree_with_the_json_report() -> None:
    code, doc = _sarif(P1)
    _, out, _ = run_cli("check", "--format", "json", *FAST, P1)
    findings = json.loads(out)["reports"][0]["findings"]
    results = doc["runs"][0]["results"]
    assert code == 1
    assert [(r["ruleId"], r["level"], r["message"]["text"]) for r in results] == [
        (f["rule"], f["severity"], f["message"]) for f in findings
    ]
    # RPR101 points at path.y: line 19 of the shipped file (the paper's eq. 50)
    loc = results[0]["locations"][0]["physicalLocation"]
    assert loc == {"artifactLocation": {"uri": P1}, "region": {"startLine": 19}}
    for r in results:
        assert doc["runs"][0]["tool"]["driver"]["rules"][r["ruleIndex"]]["id"] == r["ruleId"]


def test_sarif_reports_a_bad_file_at_its_line_and_column(write_task) -> None:  # type: ignore[no-untyped-def]
    bad = write_task(BAD_A1, "bad.rprpr.yaml")
    code, doc = _sarif(str(bad))
    jsonschema.Draft4Validator(SCHEMA).validate(doc)
    [result] = doc["runs"][0]["results"]
    assert code == 2 and result["ruleId"] == "RPR001"
    assert result["locations"][0]["physicalLocation"]["region"] == {
        "startLine": 3,
        "startColumn": 7,
    }
    assert result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"].startswith(
        "file://"
    )


def test_gitlab_code_quality_has_the_required_fields() -> None:
    code, out, _ = _shared("--output-format", "gitlab", *FAST, str(CONFIGS))
    issues = json.loads(out)
    assert code == 1 and issues
    for issue in issues:
        assert {"description", "check_name", "fingerprint", "severity", "location"} <= set(issue)
        assert issue["severity"] in ("info", "minor", "major", "critical", "blocker")
        assert isinstance(issue["location"]["lines"]["begin"], int)
        assert not issue["location"]["path"].startswith("/")
    assert len({i["fingerprint"] for i in issues}) == len(issues)
    # a run of its own: fingerprints depend on nothing a run measures
    again = json.loads(run_cli("check", "--output-format", "gitlab", *FAST, str(CONFIGS))[1])
    assert [i["fingerprint"] for i in again] == [i["fingerprint"] for i in issues]  # stable
    p1 = [i for i in issues if i["location"]["path"] == P1]
    assert [(i["check_name"], i["severity"], i["location"]["lines"]["begin"]) for i in p1] == [
        ("RPR101", "major", 19), ("RPR201", "major", 13),
    ]  # fmt: skip


def test_statistics_count_findings_per_rule_as_the_json_report_does() -> None:
    _, out, _ = _shared("--format", "json", *FAST, str(CONFIGS))
    found: dict[str, int] = {}
    for r in json.loads(out)["reports"]:
        for f in r["findings"]:
            found[f["rule"]] = found.get(f["rule"], 0) + 1
    code, out, _ = _shared("--statistics", "--format", "json", *FAST, str(CONFIGS))
    assert code == 1
    assert {d["code"]: d["count"] for d in json.loads(out)} == found
    _, text, _ = _shared("--statistics", *FAST, str(CONFIGS))
    assert text.splitlines()[0] == f"{max(found.values())}  RPR201  unbounded-torque"

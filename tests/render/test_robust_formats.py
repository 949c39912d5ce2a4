"""With declared uncertainty every format carries RPR205 and the robust analysis
(docs/robust.md, *Output*): the paper's path 2 with ±5 % on every link, 0.01 m/s² of
tracking error and a 1 ms period (README's robust.rprpr.yaml). The window, 5.44 ms, is
the reference's (``tests/engine/robust/test_windows.py``: the brute force at the box's
corners in mpmath); here each format is held to the same words, one audit rendered four
ways."""

from __future__ import annotations

import io
import json
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest
from rich.console import Console

from rprpr.render.github import render as github
from rprpr.render.gitlab import render as gitlab
from rprpr.render.junit import render as junit
from rprpr.render.text import render as text
from rprpr.report.run import Run
from tests.conftest import ROOT
from tests.render.test_formats import make_run

MESSAGE = (
    "for every mass, inertia and r within ±5 % and tracking error ≤ 0.01 m/s², |T1| > 300 N m"
    " for at most 5.44 ms around t = 2.5 s (t = 2.49728 .. 2.50273 s): longer than the 1 ms"
    " period"
)
ROBUST = (
    "robust t = 2.5 s: residual [-0.0211313, 0.0211313] N, window 5.44 ms (|T1|,"
    " t = 2.49728 .. 2.50273 s), period 1 ms"
)
NAME = "robust.rprpr.yaml"


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Run, int]:
    p2 = (ROOT / "configs" / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")
    where = tmp_path_factory.mktemp("robust")
    (where / NAME).write_text(
        p2 + "uncertainty:\n  links: 5%\n  acceleration: 0.01\n  period: 0.001\n", "utf-8"
    )
    line = len(p2.splitlines()) + 1  # the uncertainty key's
    with pytest.MonkeyPatch.context() as m:
        m.chdir(where)
        return make_run(NAME), line


def test_text_has_the_finding_and_the_robust_line(run: tuple[Run, int]) -> None:
    r, line = run
    out, err = io.StringIO(), io.StringIO()
    text(r, Console(file=out, width=400), Console(file=err, width=400))
    lines = out.getvalue().splitlines()
    assert f"{NAME}:{line}:1: RPR205 [error] saturation-window: {MESSAGE}" in lines
    assert f"  {ROBUST}" in lines
    assert any(v.startswith("  verdict: FAIL") for v in lines)


def test_github_annotates_the_finding(run: tuple[Run, int]) -> None:
    r, line = run
    out = github(r).splitlines()
    assert out == [
        f"::error file={NAME},line={line},title=RPR205 saturation-window::"
        + MESSAGE.replace("%", "%25")
    ]


def test_junit_fails_the_case_and_shows_the_robust_line(run: tuple[Run, int]) -> None:
    r, line = run
    root = ET.fromstring(junit(r))
    (case,) = root.iter("testcase")
    (failure,) = case.findall("failure")
    assert failure.get("type") == "RPR205"
    assert failure.get("message") == f"RPR205 saturation-window: {MESSAGE}"
    assert failure.text == f"{NAME}:{line}: uncertainty: RPR205 saturation-window: {MESSAGE}"
    out = case.findtext("system-out") or ""
    assert ROBUST in out.splitlines()
    assert root.get("failures") == "1"


def test_gitlab_has_one_issue_at_the_uncertainty_key(run: tuple[Run, int]) -> None:
    r, line = run
    (issue,) = json.loads(gitlab(r))
    assert issue["check_name"] == "RPR205"
    assert issue["description"] == f"RPR205 saturation-window: {MESSAGE}"
    assert issue["location"] == {"path": NAME, "lines": {"begin": line}}
    assert issue["severity"] == "major"


def test_the_fixture_is_the_readme_example() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert MESSAGE in readme and ROBUST in readme
    assert Path(ROOT / "configs" / "paper_path2.rprpr.yaml").exists()

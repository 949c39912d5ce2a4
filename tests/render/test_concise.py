"""``rprpr check --output-format concise``: the findings alone, one line each,
``FILE:LINE:COL: RPRnnn [severity] message`` (the bytes are pinned by the golden files)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from rprpr.render.concise import render
from tests.conftest import BAD_A1, FAST, ROOT, run_cli
from tests.render.test_formats import P1, P2, make_run

LINE = re.compile(r"^(?P<file>[^:]+):(?P<line>\d+):(?P<col>\d+): (?P<rule>RPR\d{3}) "
                  r"\[(?P<severity>error|warning)\] (?P<message>.+)$")  # fmt: skip


@pytest.fixture(autouse=True)
def _in_repo(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


def test_a_finding_per_line_with_its_location_rule_severity_and_whole_message() -> None:
    code, out, err = run_cli("check", "--output-format", "concise", *FAST, P1, P2)
    assert (code, err) == (1, "")
    lines = out.splitlines()
    assert [LINE.match(ln)["rule"] for ln in lines] == ["RPR101", "RPR201"]  # type: ignore[index]
    assert lines[0] == (
        "configs/paper_path1.rprpr.yaml:19:1: RPR101 [error] t = 2.5 s, (x, y) = (3, 0),"
        " case 3, order 3: slope principle fails: the path is horizontal here (dy/dx = 0,"
        " eq. 48): a high-order singularity"
    )


def test_the_same_findings_as_the_text_report_without_the_rule_names() -> None:
    tasks = [str(p.relative_to(ROOT)) for p in sorted((ROOT / "configs").glob("*.yaml"))]
    _, text, _ = run_cli("check", *FAST, *tasks)
    _, concise, _ = run_cli("check", "--format", "concise", *FAST, *tasks)
    named = re.compile(r"^(\S+:\d+:1: RPR\d{3} \[\w+\]) [a-z-]+: (.*)$")
    from_text = [named.sub(r"\1 \2", ln) for ln in text.splitlines() if named.match(ln)]
    assert len(from_text) >= 8 and concise.splitlines() == from_text


def test_strict_makes_the_warnings_errors_and_quiet_leaves_warnings_out() -> None:
    task = "configs/piecewise_timing.rprpr.yaml"  # two RPR204 torque jumps: warnings
    _, out, _ = run_cli("check", "--format", "concise", *FAST, task)
    assert [LINE.match(ln)["severity"] for ln in out.splitlines()] == ["warning"] * 2  # type: ignore[index]
    _, strict, _ = run_cli("check", "--format", "concise", "--strict", *FAST, task)
    assert strict == out.replace("[warning]", "[error]")
    code, quiet, _ = run_cli("check", "--format", "concise", "-q", *FAST, task)
    assert (code, quiet) == (0, "")


def test_a_passing_run_prints_nothing() -> None:
    assert run_cli("check", "--format", "concise", *FAST, P2) == (0, "", "")


def test_a_bad_task_file_is_one_rpr001_line_per_error_at_its_line_and_column(
    tmp_path: Path,
) -> None:
    bad = tmp_path / "bad.yaml"
    bad.write_text(BAD_A1, encoding="utf-8")
    code, out, err = run_cli("check", "--format", "concise", str(bad))
    assert code == 2
    assert (
        out == f"{bad}:3:7: RPR001 [error] robot.a1: expected a number > 0 (|AB| [m]), found -1\n"
    )
    assert err.startswith(f"{bad}:3:7: robot.a1:")  # the log says it too, as every format


def test_control_characters_never_break_a_line() -> None:
    run = make_run(P1)
    [(_, item, _)] = run.entries()
    item = {**item, "task": "evil\nname\x1b[31m.yaml"}
    item["findings"] = [{**f, "message": f["message"] + "\r\nforged:1:1: RPR999"}
                        for f in item["findings"]]  # fmt: skip
    run.reports[0] = item
    lines = render(run).splitlines()
    assert len(lines) == 2
    assert all(ln.startswith("evil\\nname\\x1b[31m.yaml:") for ln in lines)
    assert all("\\r\\nforged" in ln for ln in lines)


def test_the_configuration_may_choose_it(tmp_path: Path) -> None:
    (tmp_path / "rprpr.toml").write_text('format = "concise"\n', encoding="utf-8")
    task = tmp_path / "p1.rprpr.yaml"
    task.write_text((ROOT / P1).read_text(encoding="utf-8"), encoding="utf-8")
    code, out, _ = run_cli("check", "--config", str(tmp_path / "rprpr.toml"), *FAST, str(task))
    assert code == 1 and [ln.split(": ")[1].split()[0] for ln in out.splitlines()] == [
        "RPR101",
        "RPR201",
    ]

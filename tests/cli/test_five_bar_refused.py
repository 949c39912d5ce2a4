"""A 5R task is read and validated, but this build has no 5R audit: the audit refuses it
(``engine.audit.refuse_unaudited``) rather than audit it as an RPRPR. Every command that
audits says so in one located line and exits 2; the Python API raises ``TaskFileError``.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from rprpr import audit
from rprpr.io.loader import load_task
from rprpr.model.errors import TaskFileError
from tests.conftest import run_cli

DEXTAR = Path(__file__).resolve().parents[1] / "io" / "data" / "five_bar_dextar.rprpr.yaml"
LINE = next(
    i for i, ln in enumerate(DEXTAR.read_text().splitlines(), 1) if ln.startswith("  mechanism:")
)
MESSAGE = (
    "robot.mechanism: the 5R audit is not available in this build (it audits mechanism: rprpr only)"
)


def test_the_audit_refuses_a_5r_task() -> None:
    task = load_task(DEXTAR)
    with pytest.raises(TaskFileError) as info:
        audit(task)
    e = info.value
    assert (e.file, e.line, e.key) == (str(DEXTAR), LINE, "robot.mechanism")
    assert str(e) == f"{DEXTAR}:{LINE}: {MESSAGE}"


@pytest.mark.parametrize("form", ["concise", "text"])
def test_check_refuses_a_5r_task_in_one_line_with_status_2(form: str) -> None:
    code, out, err = run_cli("check", "--format", form, str(DEXTAR))
    assert code == 2
    # concise: the finding on standard output; every format: the input error on standard error
    assert err == f"{DEXTAR}:{LINE}: {MESSAGE} [RPR001]\n"
    if form == "concise":
        assert out == f"{DEXTAR}:{LINE}:1: RPR001 [error] {MESSAGE}\n"
    else:
        assert out == ""


@pytest.mark.parametrize(
    "command", [("export", "-o", "{tmp}/x.csv"), ("plot", "-o", "{tmp}/x.png")]
)
def test_export_and_plot_refuse_a_5r_task_too(command: tuple[str, ...], tmp_path: Path) -> None:
    args = [a.format(tmp=tmp_path) for a in command]
    code, _, err = run_cli(args[0], str(DEXTAR), *args[1:])
    assert code == 2
    assert err == f"rprpr: {DEXTAR}:{LINE}: {MESSAGE}\n"
    assert not list(tmp_path.iterdir())  # nothing written


def test_an_rprpr_task_is_audited_as_before() -> None:
    config = Path(__file__).resolve().parents[2] / "configs" / "paper_path2.rprpr.yaml"
    result = audit(load_task(config))
    assert result.task.robot.mechanism == "rprpr"
    assert result.verdict == "pass"

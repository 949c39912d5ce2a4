"""What this build cannot audit of a 5R task is refused in one located line, exit 2.

``rprpr check`` audits a 5R task's exact verdicts (tests/fivebar/test_check.py); the
certified layers are not available for a 5R yet (``engine.five_bar_audit.refuse``): a
torque limit, the torque peak (``--peak``, ``checks.peak``), declared uncertainty, and
the commands that need certified samples (``export``, ``repair``; ``plot`` draws a 5R:
tests/render/test_sheet_five_bar.py). The Python API raises ``TaskFileError`` at the same
key.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from rprpr import audit
from rprpr.io.loader import load_task
from rprpr.model.errors import TaskFileError
from tests.conftest import run_cli

DEXTAR = Path(__file__).resolve().parents[1] / "io" / "data" / "five_bar_dextar.rprpr.yaml"
TEXT = DEXTAR.read_text()
LIMIT = "  torque_limit: [5, 5]       # |T1|, |T2| [N m]\n"
YET = "not available for a 5R yet"


def _line(text: str, start: str) -> int:
    return next(i for i, ln in enumerate(text.splitlines(), 1) if ln.startswith(start))


LIMIT_LINE = _line(TEXT, "  torque_limit:")
MECHANISM_LINE = _line(TEXT, "  mechanism:")
LIMIT_MESSAGE = (
    f"checks.torque_limit: the certified torque limit check is {YET} (remove checks.torque_limit)"
)


def _without_limit(folder: Path, extra: str = "") -> Path:
    assert LIMIT in TEXT
    path = folder / "dextar.rprpr.yaml"
    path.write_text(TEXT.replace(LIMIT, "  strict: false\n") + extra)
    return path


def test_the_audit_refuses_a_5r_task_with_a_torque_limit() -> None:
    with pytest.raises(TaskFileError) as info:
        audit(load_task(DEXTAR))
    e = info.value
    assert (e.file, e.line, e.key) == (str(DEXTAR), LIMIT_LINE, "checks.torque_limit")
    assert str(e) == f"{DEXTAR}:{LIMIT_LINE}: {LIMIT_MESSAGE}"


@pytest.mark.parametrize("form", ["concise", "text"])
def test_check_refuses_a_torque_limit_in_one_line_with_status_2(form: str) -> None:
    code, out, err = run_cli("check", "--format", form, str(DEXTAR))
    assert code == 2
    assert err == f"{DEXTAR}:{LIMIT_LINE}: {LIMIT_MESSAGE} [RPR001]\n"
    if form == "concise":
        assert out == f"{DEXTAR}:{LIMIT_LINE}:1: RPR001 [error] {LIMIT_MESSAGE}\n"
    else:
        assert out == ""


def test_check_audits_the_same_task_without_the_limit(tmp_path: Path) -> None:
    code, out, err = run_cli("check", str(_without_limit(tmp_path)))
    assert (code, err) == (0, "")
    assert "no Type II singular instant in [0, t_f]" in out
    assert out.splitlines()[-1] == "  verdict: PASS — 0 singular instants, 0 high-order"


def test_check_refuses_the_peak_of_a_5r(tmp_path: Path) -> None:
    path = _without_limit(tmp_path)
    code, _, err = run_cli("check", "--peak", str(path))
    assert code == 2
    line = _line(path.read_text(), "checks:")
    assert err == (
        f"{path}:{line}: checks.peak: the certified torque peak (--peak, checks.peak) is {YET}"
        " [RPR001]\n"
    )


def test_check_refuses_declared_uncertainty_on_a_5r(tmp_path: Path) -> None:
    path = tmp_path / "dextar.rprpr.yaml"
    path.write_text(TEXT + "uncertainty: {links: 5%, acceleration: 0, period: 0.001}\n")
    code, _, err = run_cli("check", str(path))
    assert code == 2
    line = _line(path.read_text(), "uncertainty:")
    # the task file's reader refuses it already (the robust audit is the RPRPR's)
    assert err.startswith(f"{path}:{line}:14: uncertainty: uncertainty is for mechanism: rprpr")
    assert err.endswith(" [RPR001]\n") and err.count("\n") == 1


@pytest.mark.parametrize(
    "command",
    [
        ("export", "-o", "{tmp}/x.csv"),
        ("repair", "-o", "{tmp}/r.yaml"),
    ],
)
def test_export_and_repair_refuse_a_5r_task(command: tuple[str, ...], tmp_path: Path) -> None:
    args = [a.format(tmp=tmp_path) for a in command]
    source = _without_limit(tmp_path)
    code, _, err = run_cli(args[0], str(source), *args[1:])
    assert code == 2
    assert err == (
        f"rprpr: {source}:{MECHANISM_LINE}: robot.mechanism: rprpr {args[0]} is {YET}"
        " (rprpr check audits it)\n"
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dextar.rprpr.yaml"]  # nothing written


def test_an_rprpr_task_is_audited_as_before() -> None:
    config = Path(__file__).resolve().parents[2] / "configs" / "paper_path2.rprpr.yaml"
    result = audit(load_task(config))
    assert result.task.robot.mechanism == "rprpr"
    assert result.verdict == "pass"

"""The command line where the world misbehaves: closed pipes, full disks, an output file
that is also a task, control characters smuggled in through YAML escapes, bugs."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

from tests.conftest import CLOSE_INSTANTS, CONFIGS, run_cli, run_cli_to, stdout_on

RPRPR = [sys.executable, "-m", "rprpr"]


def test_output_file_that_is_a_task_is_refused_and_left_intact(tmp_path: Path) -> None:
    task = tmp_path / "plan.rprpr.yaml"  # a task file by the naming convention
    shutil.copy(CONFIGS / "paper_path2.rprpr.yaml", task)
    before = task.read_bytes()
    code, out, err = run_cli("check", "-o", str(task), str(tmp_path))
    assert code == 2 and out == ""
    assert err.strip().splitlines() == [
        f"rprpr: usage error: the output file {task} is also a task file: it would be overwritten"
    ]
    assert task.read_bytes() == before


def test_dash_is_standard_output(tmp_path: Path) -> None:
    path2 = str(CONFIGS / "paper_path2.rprpr.yaml")
    code, out, _ = run_cli("check", "--format", "json", "-o", "-", "--samples", "11", path2)
    assert code == 0 and out.startswith("{") and '"verdict": "pass"' in out


@pytest.mark.parametrize(
    ("config", "status"), [("paper_path2.rprpr.yaml", 0), ("paper_path1.rprpr.yaml", 1)]
)
@pytest.mark.parametrize("fmt", ["text", "json"])
def test_a_closed_pipe_keeps_the_verdicts_exit_status(config: str, status: int, fmt: str) -> None:
    args = ["check", "--format", fmt, "--samples", "11", str(CONFIGS / config)]
    returncode, err = into_a_closed_pipe(args, real=(fmt, status) == ("text", 1))
    assert returncode == status, err
    assert b"Traceback" not in err
    assert b"Exception ignored" not in err  # the interpreter's last flush did not fail


def into_a_closed_pipe(args: list[str], real: bool) -> tuple[int, bytes]:
    """``rprpr ARGS`` writing into a pipe whose reader went away before anything was
    written: (exit status, stderr). In a real process (``real``: the interpreter's last
    flush at exit included), else in this process on the stream Python would make for
    the pipe (``run_cli_to``)."""
    if real:
        proc = subprocess.Popen([*RPRPR, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        assert proc.stdout is not None
        proc.stdout.close()  # the reader goes away before anything is written
        _, err = proc.communicate()
        return proc.returncode, err
    read, write = os.pipe()
    os.close(read)
    code, text = run_cli_to(stdout_on(write), *args)
    return code, text.encode("utf-8")


def test_schema_into_a_closed_pipe_exits_0() -> None:
    returncode, err = into_a_closed_pipe(["schema"], real=False)
    assert returncode == 0, err
    assert b"Traceback" not in err


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_full_disk_is_one_line_and_exit_2() -> None:
    code, _, err = run_cli("check", "-o", "/dev/full", str(CONFIGS / "paper_path2.rprpr.yaml"))
    assert code == 2
    assert err.strip().splitlines()[0] == (
        "rprpr: cannot write the report to /dev/full: No space left on device"
    )


@pytest.mark.parametrize("escape", ["\\e[8m", "\\x07", "\\r", "\\uFFFE", "\\0"])
def test_control_characters_written_as_yaml_escapes_are_rejected(
    escape: str, tmp_path: Path
) -> None:
    text = (CONFIGS / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")
    text = text.replace("name: Example 2 of the paper, path 2", f'name: "ok{escape} hidden"')
    task = tmp_path / "esc.yaml"
    task.write_text(text, encoding="utf-8")
    code, out, err = run_cli("check", str(task))
    assert code == 2 and out == ""
    [line] = err.strip().splitlines()
    assert line.startswith(f"{task}:") and " name: control character U+" in line
    assert "\x1b" not in err


@pytest.mark.parametrize("command", ["export", "plot"])
def test_plot_and_export_name_the_task_in_an_internal_error(
    command: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import rprpr.engine.audit

    def broken(*a: Any, **k: Any) -> Any:
        raise RuntimeError("simulated bug")

    monkeypatch.setattr(rprpr.engine.audit, "audit", broken)
    monkeypatch.chdir(tmp_path)
    task = str(CONFIGS / "paper_path2.rprpr.yaml")
    code, _, err = run_cli(command, task)
    assert code == 3
    [line] = err.strip().splitlines()
    assert line.startswith(f"rprpr: {task}: internal error (RuntimeError: simulated bug)")


def test_text_report_tells_close_instants_apart(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    task = tmp_path / "close.yaml"
    task.write_text(CLOSE_INSTANTS, encoding="utf-8")
    monkeypatch.setenv("COLUMNS", "160")  # wide enough for the table's t column in full
    code, out, _ = run_cli("check", "--samples", "11", str(task))
    assert code == 1  # two first-order crossings; the inconsistency: unbounded torques
    rows = [ln for ln in out.splitlines() if ln.startswith("│")]
    assert [r.split("│")[1].strip() for r in rows] == ["1", "1.000001"]
    findings = [ln for ln in out.splitlines() if "RPR201" in ln]
    # t = 1 (x = a1/2, x" = 0) is consistent; t = 1.000001 is not, and says which it is
    assert [f.split("t = ")[1].split(" s,")[0] for f in findings] == ["1.000001"]


def test_a_crowded_sheet_keeps_markers_and_drops_per_instant_labels(tmp_path: Path) -> None:
    """16 singular instants (T_16 of x - 3 along x = 2 + t): every instant keeps its
    marker, the one-by-one labels give way, and drawing warns of nothing."""
    from flint import fmpq_poly, fmpz_poly

    from rprpr.engine.audit import audit
    from rprpr.io.expression import poly_text
    from rprpr.io.loader import parse_task
    from rprpr.render import sheet as P
    from tests.conftest import task_text
    from tests.sheets import drawn

    t16 = fmpq_poly([int(c) for c in fmpz_poly.chebyshev_t(16).coeffs()])(fmpq_poly([-3, 1]))
    task = parse_task(task_text(poly_text(t16, "x"), "timing:\n  duration: 2\n  x: 2 + t\n"))
    m = P.motion(audit(task, samples=201), "t16.yaml")
    assert len(m.result.singularities) == 16 > P.MAX_LABELS
    fig = P.render([m])
    drawn(fig)  # a draw, unpainted (no pixel is read): filterwarnings = error
    gids = [a.get_gid() or "" for ax in fig.get_axes() for a in ax.get_children()]
    assert sum(g.startswith("delta-singular-0-") for g in gids) == 16
    assert not any(g.startswith("delta-label-") for g in gids)
    texts = [t.get_text() for ax in fig.get_axes() for t in ax.texts]
    assert not any("order 1" in t for t in texts)

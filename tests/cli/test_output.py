"""Every output file is written whole or not at all, never onto an input of the run, and
a disk that cannot take it is one line and exit 2 (issue 11, classes 6, 9, 10 and 13).

``check -o``, ``plot`` (-o, the default sheet, --animate), ``export -o`` write a temporary
file beside the target and rename it into place (``cli.output.AtomicFile``); a target
that is a device (``/dev/null``, ``/dev/full``) is written in place.
"""

from __future__ import annotations

import errno
import io
import json
import math
import os
import shutil
import stat
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from rprpr.cli.output import AtomicFile, refuse_overwriting_inputs
from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.render import export as E
from rprpr.render.json import render as json_report
from rprpr.report.records import task_report
from rprpr.report.run import Run
from tests.cli.forked import Forked, rprpr_main
from tests.conftest import (
    CONFIGS,
    PATH2_FILE,
    ROOT,
    run_cli,
    run_cli_to,
    stdout_on,
    task_text,
)

RPRPR = [sys.executable, "-m", "rprpr"]
FULL = Path("/dev/full")
needs_full = pytest.mark.skipif(not FULL.exists(), reason="needs /dev/full")


def listing(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


# -- 6. atomic outputs ---------------------------------------------------------------------
def test_a_failed_check_report_keeps_the_previous_one(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A bug while writing the report: exit 3, the old report as it was, no temporary."""
    report = tmp_path / "report.json"
    report.write_text("old report\n")
    import rprpr.render.json

    def broken(*a: Any, **k: Any) -> str:
        raise RuntimeError("simulated bug while rendering")

    monkeypatch.setattr(rprpr.render.json, "render", broken)
    code, _, err = run_cli("check", "--format", "json", "-o", str(report), PATH2_FILE)
    assert code == 3 and "simulated bug" in err
    assert report.read_text() == "old report\n"
    assert listing(tmp_path) == ["report.json"]


def test_check_o_replaces_the_report_only_when_complete(tmp_path: Path) -> None:
    report = tmp_path / "report.json"
    report.write_text("old report\n")
    os.chmod(report, 0o640)
    code, _, _ = run_cli("check", "--format", "json", "-o", str(report), PATH2_FILE)
    assert code == 0
    assert json.loads(report.read_text())["summary"]["passed"] == 1
    assert stat.S_IMODE(report.stat().st_mode) == 0o640  # the file's mode is kept
    assert listing(tmp_path) == ["report.json"]


def test_a_new_output_gets_the_umask_mode_not_mkstemps_0600(tmp_path: Path) -> None:
    mask = os.umask(0o022)
    try:
        run_cli("check", "--format", "json", "-o", str(tmp_path / "r.json"), PATH2_FILE)
    finally:
        os.umask(mask)
    assert stat.S_IMODE((tmp_path / "r.json").stat().st_mode) == 0o644


def test_an_output_through_a_symbolic_link_writes_the_file_and_keeps_the_link(
    tmp_path: Path,
) -> None:
    (tmp_path / "reports").mkdir()
    real = tmp_path / "reports" / "latest.json"
    real.write_text("old\n")
    link = tmp_path / "report.json"
    link.symlink_to(real)
    code, _, _ = run_cli("check", "--format", "json", "-o", str(link), PATH2_FILE)
    assert code == 0 and link.is_symlink()
    assert json.loads(real.read_text())["summary"]["tasks"] == 1
    assert listing(tmp_path / "reports") == ["latest.json"]


def test_dev_null_as_output_is_written_in_place_never_replaced() -> None:
    before = os.stat(os.devnull)
    code, out, _ = run_cli("check", "--format", "json", "-o", os.devnull, PATH2_FILE)
    after = os.stat(os.devnull)
    assert code == 0 and out == ""
    assert stat.S_ISCHR(after.st_mode) and (after.st_ino, after.st_rdev) == (
        before.st_ino,
        before.st_rdev,
    )


@pytest.mark.skipif(not Path("/dev/stdout").exists(), reason="needs /dev/stdout")
@pytest.mark.real_workers  # rprpr as a process does it: its check audits in a worker of its own
def test_dev_stdout_on_a_pipe_is_written_in_place() -> None:
    # /dev/stdout links to /proc/self/fd/1, whose target on a pipe ("pipe:[n]") no path
    # reaches: the report goes through the name given, as to any device
    # (rprpr in a process forked from this one, its descriptor 1 a pipe: tests/cli/forked.py)
    args = ["check", "--format", "json", PATH2_FILE]
    proc = Forked(lambda: rprpr_main(*args, "-o", "/dev/stdout"), cwd=ROOT)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 0 and stdout.decode() == run_cli(*args)[1]
    assert stderr.decode().endswith("json report written to /dev/stdout\n")


def test_atomic_file_removes_its_temporary_on_a_failed_write(tmp_path: Path) -> None:
    target = tmp_path / "out.csv"
    target.write_text("previous\n")
    out = AtomicFile(str(target))
    tmp = out.create()
    assert Path(tmp).parent == tmp_path and Path(tmp).name.startswith(".out.csv.")
    Path(tmp).write_text("half")
    out.discard()
    assert listing(tmp_path) == ["out.csv"] and target.read_text() == "previous\n"


@pytest.mark.parametrize("command", ["export", "plot"])
def test_a_disk_that_fills_while_writing_is_exit_2_and_keeps_the_old_file(
    command: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """ENOSPC half-way through the file: one line, exit 2, the previous file intact."""
    name = "m.csv" if command == "export" else "m.png"
    target = tmp_path / name
    target.write_text("previous\n")

    def full_disk(path: str) -> None:
        with open(path, "w", encoding="utf-8") as f:
            f.write("half")
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    if command == "export":
        monkeypatch.setattr(E, "write", lambda result, out, *a, **k: full_disk(out.name))
    else:
        import rprpr.render.sheet

        monkeypatch.setattr(rprpr.render.sheet, "save", lambda fig, path, *a, **k: full_disk(path))
    # what is drawn does not matter here (its writer is the full disk), only what is kept
    drawing = ["--panels", "delta"] if command == "plot" else []
    code, _, err = run_cli(command, PATH2_FILE, "-o", str(target), "--samples", "21", *drawing)
    what = "samples" if command == "export" else "sheet"
    assert code == 2
    assert err.splitlines() == [
        f"rprpr: cannot write the {what} to {target}: No space left on device"
    ]
    assert target.read_text() == "previous\n" and listing(tmp_path) == [name]


# -- 10. full disks and closed streams --------------------------------------------------------
@needs_full
@pytest.mark.parametrize(
    ("args", "what"),
    [
        (["check", "--format", "text", PATH2_FILE], "report"),
        (["check", "--format", "json", PATH2_FILE], "report"),
        (["check", "--format", "junit", PATH2_FILE], "report"),
        (["check", "--format", "github", str(CONFIGS / "paper_path1.rprpr.yaml")], "report"),
        (["export", PATH2_FILE, "--format", "json"], "samples"),
        (["schema"], "schema"),
    ],
)
def test_standard_output_on_a_full_disk_is_exit_2_and_one_line(args: list[str], what: str) -> None:
    done = on_full_stdout(args, real=args[:3] == ["check", "--format", "text"])
    assert done.returncode == 2
    assert done.stderr.splitlines() == [
        f"rprpr: cannot write the {what} to standard output: No space left on device"
    ]


def on_full_stdout(args: list[str], real: bool) -> subprocess.CompletedProcess[str]:
    """``rprpr ARGS`` with standard output on /dev/full: in a real process (``real``: the
    interpreter's last flush at exit included), else in this process on the stream
    Python would make for it (``run_cli_to``)."""
    if real:
        with FULL.open("w") as full:
            return subprocess.run([*RPRPR, *args], stdout=full, stderr=subprocess.PIPE, text=True)
    code, err = run_cli_to(stdout_on(os.open(FULL, os.O_WRONLY)), *args)
    return subprocess.CompletedProcess(args, code, None, err)


def with_closed_stdout(
    args: list[str], real: bool, cwd: Path | None = None
) -> subprocess.CompletedProcess[str]:
    """``rprpr ARGS`` started with standard output closed (``>&-``): in a real process
    (``real``), else in this process as Python starts then (``sys.stdout`` is None)."""
    if real:
        return subprocess.run(
            ["sh", "-c", 'exec "$@" >&-', "sh", *RPRPR, *args], capture_output=True, text=True,
            cwd=cwd,
        )  # fmt: skip
    code, err = run_cli_to(None, *args)
    return subprocess.CompletedProcess(args, code, None, err)


@needs_full
@pytest.mark.parametrize("args", [["--help"], ["--version"], ["plot", "--help"]])
def test_help_and_version_on_a_full_disk_are_exit_2(args: list[str]) -> None:
    done = on_full_stdout(args, real=args == ["--help"])
    assert (done.returncode, done.stderr) == (
        2,
        "rprpr: cannot write the output: No space left on device\n",
    )


@needs_full
@pytest.mark.parametrize(
    ("command", "name", "what"),
    [("check", "r.json", "report"), ("export", "m.csv", "samples"), ("plot", "s.png", "sheet")],
)
def test_an_output_file_linked_to_a_full_device_is_exit_2(
    command: str, name: str, what: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / name).symlink_to(FULL)
    args = [command, PATH2_FILE, "-o", name] + (["--format", "json"] if command == "check" else [])
    if command == "plot":  # what is drawn does not matter here, only where it goes
        args += ["--dpi", "50", "--samples", "21", "--panels", "delta"]
    monkeypatch.chdir(tmp_path)  # the output is named relative to the working directory
    code, _, err = run_cli(*args)
    assert code == 2
    assert (
        err.splitlines()[0] == f"rprpr: cannot write the {what} to {name}: No space left on device"
    )
    assert (tmp_path / name).is_symlink() and listing(tmp_path) == [name]


@pytest.mark.parametrize(
    ("args", "what"),
    [
        (["schema"], "schema"),
        (["check", PATH2_FILE], "report"),
        (["export", PATH2_FILE], "samples"),
    ],
)
def test_a_closed_standard_output_is_a_failed_write(args: list[str], what: str) -> None:
    """Started with standard output closed (``>&-``): exit 2, never a crash, never a
    silent success."""
    done = with_closed_stdout(args, real=args[0] == "check")
    assert (done.returncode, done.stderr) == (
        2,
        f"rprpr: cannot write the {what} to standard output: standard output is closed\n",
    )


def test_a_closed_standard_output_does_not_stop_a_report_to_a_file(tmp_path: Path) -> None:
    done = subprocess.run(
        ["sh", "-c", 'exec "$@" >&-', "sh", *RPRPR, "check", "--format", "json", "-o", "r.json",
         PATH2_FILE],
        capture_output=True, text=True, cwd=tmp_path,
    )  # fmt: skip
    assert done.returncode == 0
    assert json.loads((tmp_path / "r.json").read_text())["summary"]["passed"] == 1


# -- 9. outputs never overwrite inputs -----------------------------------------------------------
def _task(folder: Path, name: str) -> Path:
    task = folder / name
    shutil.copy(PATH2_FILE, task)
    return task


def _refused(err: str, output: str) -> bool:
    return err.startswith(f"rprpr: usage error: the output file {output} is also a task file")


def test_export_onto_its_own_task_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    task = _task(tmp_path, "plan.json")  # JSON is YAML: a valid task file
    before = task.read_bytes()
    code, _, err = run_cli("export", "plan.json", "-o", "plan.json")
    assert code == 2 and _refused(err, "plan.json")
    assert task.read_bytes() == before


def test_export_o_dash_is_standard_output_and_writes_no_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    task = _task(tmp_path, "plan.json")
    code, out, _ = run_cli("export", "plan.json", "--samples", "3", "--format", "csv", "-o", "-")
    assert code == 0 and listing(tmp_path) == ["plan.json"]  # no file named "-"
    code, same, _ = run_cli("export", "plan.json", "--samples", "3", "--format", "csv")
    assert out == same and len(out.splitlines()) == 2 + 3  # the comment, the columns, 3 rows
    assert task.exists()


def test_plot_whose_default_sheet_is_its_own_task_is_refused(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    task = _task(tmp_path, "sheet.png")  # default output: sheet.png, the task itself
    before = task.read_bytes()
    code, _, err = run_cli("plot", "sheet.png")
    assert code == 2 and _refused(err, "sheet.png")
    assert task.read_bytes() == before


@pytest.mark.parametrize("option", ["-o", "--animate"])
def test_plot_outputs_onto_a_task_are_refused(option: str, tmp_path: Path) -> None:
    name = "a.png" if option == "-o" else "a.gif"
    task = _task(tmp_path, name)
    other = _task(tmp_path, "b.yaml")
    code, _, err = run_cli("plot", str(other), str(task), option, str(task))
    assert code == 2 and _refused(err, str(task))
    assert task.read_bytes() == Path(PATH2_FILE).read_bytes()


@pytest.mark.parametrize("alias", ["hard link", "symbolic link", "dot slash", "dot dot"])
def test_check_o_onto_a_task_under_another_name_is_refused(
    alias: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "sub").mkdir()
    task = _task(tmp_path, "t.yaml")
    monkeypatch.chdir(tmp_path / "sub")
    out = {
        "hard link": "h.yaml",
        "symbolic link": "s.yaml",
        "dot slash": "./../t.yaml",
        "dot dot": "../sub/../t.yaml",
    }[alias]
    if alias == "hard link":
        os.link(task, "h.yaml")
    elif alias == "symbolic link":
        os.symlink(task, "s.yaml")
    code, _, err = run_cli("check", "-o", out, "../t.yaml")
    assert code == 2 and _refused(err, out)
    assert task.read_bytes() == Path(PATH2_FILE).read_bytes()


def test_refusal_compares_identity_not_names(tmp_path: Path) -> None:
    a = _task(tmp_path, "a.yaml")
    b = _task(tmp_path, "b.yaml")  # same content, another file: not an input
    refuse_overwriting_inputs([str(b), None, str(tmp_path / "new.json")], [str(a)])
    with pytest.raises(Exception, match="is also a task file"):
        refuse_overwriting_inputs([str(tmp_path / "." / "a.yaml")], [str(a)])


# -- 13. non-finite values: nan in CSV, null in JSON --------------------------------------------
def test_every_non_finite_value_is_nan_in_csv_and_null_in_json(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    result = audit(load_task(PATH2_FILE), samples=3)
    table = result.samples.rows().copy()
    table[0, 15], table[1, 16], table[2, 17] = math.inf, -math.inf, math.nan
    monkeypatch.setattr(E, "rows", lambda r: table)
    csv_text, json_text = io.StringIO(), io.StringIO()
    E.write(result, csv_text, "csv")
    E.write(result, json_text, "json")
    body = csv_text.getvalue().splitlines()[2:]
    assert body[0].split(",")[15] == body[1].split(",")[16] == body[2].split(",")[17] == "nan"
    assert "inf" not in csv_text.getvalue().lower().replace("infinite", "")
    doc = json.loads(json_text.getvalue(), parse_constant=lambda c: pytest.fail(c))
    assert (doc["rows"][0][15], doc["rows"][1][16], doc["rows"][2][17]) == (None, None, None)


def test_a_motion_beyond_double_range_exports_nan_never_inf(tmp_path: Path) -> None:
    """x up to 1e30 m and y = x^12 + 1: y overflows the double range."""
    task = tmp_path / "huge.yaml"
    task.write_text(task_text("x^12 + 1", "timing:\n  x: 1e30*t + 2\n  duration: 1\n"))
    code, out, _ = run_cli("export", str(task), "--samples", "5")
    assert code == 0
    values = [v for line in out.splitlines()[2:] for v in line.split(",")]
    assert "nan" in values and not any("inf" in v for v in values)
    assert all(v == "nan" or math.isfinite(float(v)) for v in values)


def test_the_check_json_report_is_strict_json_whatever_the_records_hold() -> None:
    run_ = Run()
    report = task_report(audit(load_task(PATH2_FILE), samples=11), PATH2_FILE)
    report["singularities"][0]["t"] = math.inf  # as an overflowing engine value would be
    report["torque_peak"] = [math.nan, -math.inf]
    run_.add("report", report)
    doc = json.loads(json_report(run_), parse_constant=lambda c: pytest.fail(c))
    assert doc["reports"][0]["singularities"][0]["t"] is None
    assert doc["reports"][0]["torque_peak"] == [None, None]


def test_rows_helper_is_the_engines_table() -> None:
    result = audit(load_task(PATH2_FILE), samples=3)
    assert np.array_equal(E.rows(result), result.samples.rows(), equal_nan=True)

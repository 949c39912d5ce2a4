"""``rprpr repair``: a reviewable change (only the keys it must change), ``--diff`` and
``--in-place``, and the modeline of a new file."""

from __future__ import annotations

import os
import shutil
import stat
from pathlib import Path

import pytest

from rprpr.cli.repair import unified_diff
from rprpr.model.defaults import SCHEMA_MODELINE
from tests.conftest import CONFIGS, run_cli

TRAPEZOIDAL = CONFIGS / "trapezoidal.rprpr.yaml"  # RPR204 torque jumps: strict fails


@pytest.fixture
def task(tmp_path: Path) -> Path:
    """A copy of the trapezoidal config, mode 0640."""
    p = tmp_path / "plan.rprpr.yaml"
    shutil.copyfile(TRAPEZOIDAL, p)
    os.chmod(p, 0o640)
    return p


def test_diff_prints_what_in_place_would_write_and_exits_1(task: Path) -> None:
    before = task.read_bytes()
    code, out, err = run_cli("repair", "--diff", str(task))
    assert code == 1
    assert task.read_bytes() == before and sorted(os.listdir(task.parent)) == [task.name]
    lines = out.splitlines()
    assert lines[:2] == [f"--- {task}", f"+++ {task}"]
    assert [ln for ln in lines if ln.startswith("-") and not ln.startswith("---")] == [
        "-  law: trapezoidal           # accelerate, cruise, decelerate, in x from path.from"
        " to path.to",
        "-  cruise_speed: 0.6          # |dx/dt| while cruising [m/s], in (D/t_f, 2D/t_f] ="
        " (0.4, 0.8]",
    ]
    assert "+  x:" in lines
    assert "timing: max |Δx(t)|" in err  # the account goes to standard error

    code, _, _ = run_cli("repair", "--in-place", str(task))
    assert code == 0
    assert task.read_text(encoding="utf-8") == _patched(before.decode(), out)


def _patched(old: str, diff: str) -> str:
    """``old`` with the one-hunk unified ``diff`` applied (enough for this test)."""
    body = diff.split("\n@@", 1)[1].split("\n", 1)[1].splitlines()
    start = int(diff.split("@@ -", 1)[1].split(",")[0]) - 1
    lines = old.splitlines()
    new = lines[:start]
    i = start
    for d in body:
        if d.startswith(" "):
            new.append(lines[i])
            i += 1
        elif d.startswith("-"):
            i += 1
        else:
            new.append(d[1:])
    return "\n".join(new + lines[i:]) + "\n"


def test_in_place_keeps_the_permissions_and_then_nothing_is_left_to_do(task: Path) -> None:
    code, out, err = run_cli("repair", "-i", str(task))
    assert code == 0 and f"checked {task} (strict): pass" in out
    assert err == f"rprpr: wrote {task}\n"
    assert stat.S_IMODE(task.stat().st_mode) == 0o640
    assert sorted(os.listdir(task.parent)) == [task.name]  # no temporary file left
    text = task.read_text(encoding="utf-8")
    assert text.startswith(TRAPEZOIDAL.read_text(encoding="utf-8").split("timing:")[0])
    assert "(repaired)" not in text  # in place, the task keeps its name
    assert run_cli("repair", "--diff", str(task)) == (
        0,
        "",
        f"rprpr: {task}: passes the strict check: nothing to repair, nothing written\n",
    )
    assert run_cli("check", "--strict", str(task))[0] == 0


def test_a_new_file_keeps_the_comments_and_names_its_origin(tmp_path: Path) -> None:
    src = tmp_path / "p1.rprpr.yaml"
    shutil.copyfile(CONFIGS / "paper_path1.rprpr.yaml", src)
    code, _, _ = run_cli("repair", str(src))
    assert code == 0
    out = (tmp_path / "p1.repaired.rprpr.yaml").read_text(encoding="utf-8")
    old = src.read_text(encoding="utf-8")
    lines = out.splitlines()
    # the task's own modeline still points at the same file from the same folder
    assert lines[0] == old.splitlines()[0]
    origin = "# Example 1 of the paper, path 1, repaired by rprpr repair from p1.rprpr.yaml"
    assert lines[1] == origin
    comments = [ln for ln in old.splitlines() if ln.startswith("#")][1:]
    assert lines[2 : 2 + len(comments)] == comments
    assert "name: Example 1 of the paper, path 1 (repaired)" in lines
    assert "    3: {mass: 1.0, inertia: 0.05, r: 0.5}   # r3 = |EG3|" in lines


def test_a_new_file_elsewhere_gets_the_modeline_of_init(tmp_path: Path) -> None:
    out = tmp_path / "r.rprpr.yaml"
    code, _, _ = run_cli("repair", str(CONFIGS / "paper_path1.rprpr.yaml"), "-o", str(out))
    assert code == 0
    assert out.read_text(encoding="utf-8").splitlines()[0] == SCHEMA_MODELINE
    from rprpr.cli.init import TEMPLATE

    assert TEMPLATE.splitlines()[0] == SCHEMA_MODELINE


def test_a_task_without_a_modeline_gets_the_modeline_of_init(tmp_path: Path) -> None:
    src = tmp_path / "t.yaml"
    body = (CONFIGS / "zero_speed_crossing.rprpr.yaml").read_text(encoding="utf-8")
    src.write_text(body.split("\n", 1)[1], encoding="utf-8")  # without its modeline
    code, _, _ = run_cli("repair", str(src))
    assert code == 0
    lines = (tmp_path / "t.repaired.rprpr.yaml").read_text(encoding="utf-8").splitlines()
    assert lines[0] == SCHEMA_MODELINE and lines[1].endswith("repaired by rprpr repair from t.yaml")


def test_a_form_that_cannot_be_edited_is_written_whole_and_says_so(tmp_path: Path) -> None:
    src = tmp_path / "t.yaml"
    text = (CONFIGS / "zero_speed_crossing.rprpr.yaml").read_text(encoding="utf-8")
    text = text.replace("    2: {mass: 2.0", "    2: &leg {mass: 2.0", 1)
    text = text.replace("    4: {mass: 2.0, inertia: 0.10, r: 0.5}", "    4: *leg")  # an alias
    src.write_text(text, encoding="utf-8")
    code, _, err = run_cli("repair", str(src), "-o", str(tmp_path / "o.rprpr.yaml"))
    assert code == 0
    assert "cannot be edited key by key; the repaired task is written whole" in err
    assert run_cli("check", "--strict", str(tmp_path / "o.rprpr.yaml"))[0] == 0


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["--diff", "--in-place"], "--in-place and --diff cannot go together"),
        (["-i", "-o", "x.yaml"], "-o and --in-place cannot go together"),
        (["--diff", "-o", "x.yaml"], "-o and --diff cannot go together"),
        (["--diff", "--plot", "x.png"], "--diff writes nothing"),
    ],
)
def test_options_that_cannot_go_together(task: Path, args: list[str], says: str) -> None:
    code, out, err = run_cli("repair", str(task), *args)
    assert (code, out) == (2, "") and says in err and len(err.splitlines()) == 1


def test_in_place_needs_a_file() -> None:
    code, _, err = run_cli("repair", "-", "--in-place")
    assert code == 2 and "--in-place needs a task file" in err


def test_no_repair_with_diff_is_exit_1_and_no_diff(tmp_path: Path) -> None:
    code, out, err = run_cli(
        "repair", "--diff", "--keep", "path", str(CONFIGS / "paper_path1.rprpr.yaml")
    )
    assert (code, out) == (1, "") and "no repair" in err


def test_unified_diff_marks_a_missing_last_line_break() -> None:
    assert unified_diff("a\nb", "a\nc", "f") == (
        "--- f\n+++ f\n@@ -1,2 +1,2 @@\n a\n-b\n\\ No newline at end of file\n+c\n"
        "\\ No newline at end of file\n"
    )
    assert unified_diff("a\n", "a\n", "f") == ""


def test_a_task_on_standard_input_is_diffed_too(monkeypatch: pytest.MonkeyPatch) -> None:
    import io

    data = TRAPEZOIDAL.read_bytes()
    monkeypatch.setattr("sys.stdin", io.TextIOWrapper(io.BytesIO(data), encoding="utf-8"))
    code, out, _ = run_cli("repair", "--diff", "-")
    assert code == 1
    assert out.splitlines()[:2] == ["--- -", "+++ -"] and "-  law: trapezoidal" in out

"""``io.edit``: a task file edited where the repaired task differs, and nowhere else."""

from __future__ import annotations

import difflib

import pytest

from rprpr.io.edit import edit, modeline, same_motion
from rprpr.io.loader import load_task, parse_task
from rprpr.model.task import Task
from rprpr.repair import repair
from tests.conftest import CONFIGS, LINKS_ALIKE, task_text

REPAIRABLE = ["case1_crossing", "case2_crossing", "paper_path1", "piecewise_timing",
              "touch", "trapezoidal", "zero_speed_crossing"]  # fmt: skip


def _repaired(text: str) -> tuple[Task, Task]:
    old = parse_task(text, "t.yaml", directory=str(CONFIGS))
    return old, repair(old).task


def _changed_lines(old: str, new: str) -> tuple[list[str], list[str]]:
    """The lines ``new`` removed from ``old``, and those it added."""
    removed, added = [], []
    for line in difflib.ndiff(old.splitlines(), new.splitlines()):
        if line.startswith("- "):
            removed.append(line[2:])
        elif line.startswith("+ "):
            added.append(line[2:])
    return removed, added


@pytest.mark.parametrize("name", REPAIRABLE)
def test_the_edit_reads_back_as_the_repaired_motion_and_keeps_every_other_line(
    name: str,
) -> None:
    text = (CONFIGS / f"{name}.rprpr.yaml").read_text(encoding="utf-8")
    old, new = _repaired(text)
    edited = edit(text, old, new)
    assert edited is not None
    back = parse_task(edited, "t.yaml", directory=str(CONFIGS))
    assert same_motion(back, new) and not same_motion(back, old)
    assert back.robot == old.robot and back.checks == old.checks and back.name == old.name
    removed, _ = _changed_lines(text, edited)
    # what goes is the motion's lines alone: never a comment line, the robot or checks
    kept = [ln for ln in text.splitlines() if ln not in removed]
    outside = ("#", "name:", "robot:", "  a1:", "  gravity:", "  links:", "    ")
    for line in text.splitlines():
        if line.startswith(outside) and not line.startswith("    - {until"):  # not timing.x
            assert line in kept, line
    assert edited.splitlines()[0] == text.splitlines()[0]  # the modeline, as it was


def test_only_the_timing_law_gives_way_when_the_path_is_kept() -> None:
    text = (CONFIGS / "trapezoidal.rprpr.yaml").read_text(encoding="utf-8")
    old, new = _repaired(text)
    edited = edit(text, old, new)
    assert edited is not None
    removed, added = _changed_lines(text, edited)
    assert [ln.split("#")[0].strip() for ln in removed] == [
        "law: trapezoidal",
        "cruise_speed: 0.6",
    ]
    assert added[0] == "  x:" and all(a.startswith(("  - until: ", "    x: ")) for a in added[1:])
    assert "  duration: 5                # t_f [s]" in edited.splitlines()  # as written


def test_number_spelling_and_flow_style_outside_the_change_are_the_files() -> None:
    text = (CONFIGS / "paper_path1.rprpr.yaml").read_text(encoding="utf-8")
    old, new = _repaired(text)
    edited = edit(text, old, new)
    assert edited is not None
    assert "    2: {mass: 2.0, inertia: 0.10, r: 0.5}   # r2 = |AG2|" in edited.splitlines()
    assert "path:" not in edited and "timing:" not in edited  # given way to motion.pieces
    assert edited.count("\nmotion:\n  pieces:\n") == 1


def test_rename_rewrites_the_name_plainly_and_nothing_else_more() -> None:
    text = (CONFIGS / "paper_path1.rprpr.yaml").read_text(encoding="utf-8")
    old, new = _repaired(text)
    plain, renamed = edit(text, old, new), edit(text, old, new, rename=True)
    assert plain is not None and renamed is not None
    assert new.name == "Example 1 of the paper, path 1 (repaired)"
    assert renamed == plain.replace("name: Example 1 of the paper, path 1\n", f"name: {new.name}\n")


def test_crlf_line_endings_are_kept() -> None:
    text = (CONFIGS / "zero_speed_crossing.rprpr.yaml").read_text(encoding="utf-8")
    crlf = text.replace("\n", "\r\n")
    old, new = _repaired(crlf)
    edited = edit(crlf, old, new)
    assert edited is not None and "\n" not in edited.replace("\r\n", "")
    assert edited.replace("\r\n", "\n") == edit(text, *_repaired(text))


ZERO_SPEED = task_text(
    "x^3 - 9*x^2 + 27*x - 27 + 0.2*(x - 3)\n  from: 2\n  to: 4",
    "timing:\n  duration: 2\n  x: 3 + (t - 1)^3\n",
)


def test_a_point_given_as_x_alone_stays_so_and_a_quoted_polynomial_is_replaced() -> None:
    text = ZERO_SPEED.replace("  x: 3 + (t - 1)^3", '  x: "3 + (t - 1)^3"  # stops at t = 1')
    old, new = _repaired(text)
    edited = edit(text, old, new)
    assert edited is not None
    assert "  from: 2\n  to: 4\n" in edited and "stops at t = 1" not in edited
    assert same_motion(parse_task(edited), new)


def test_a_flow_timing_is_replaced_whole_and_still_reads_back() -> None:
    text = ZERO_SPEED.replace(
        "timing:\n  duration: 2\n  x: 3 + (t - 1)^3\n", "timing: {duration: 2, x: 3 + (t - 1)^3}\n"
    )
    old, new = _repaired(text)
    edited = edit(text, old, new)
    assert edited is not None and same_motion(parse_task(edited), new)
    assert edited.startswith(text.split("path:")[0])  # name and robot untouched


def test_anchors_are_not_edited() -> None:
    links = LINKS_ALIKE.replace("2: {mass", "2: &leg {mass").replace(
        "4: {mass: 2.0, inertia: 0.10, r: 0.5}", "4: *leg"
    )
    text = task_text(
        "x^3 - 9*x^2 + 27*x - 27 + 0.2*(x - 3)\n  from: 2\n  to: 4",
        "timing:\n  duration: 2\n  x: 3 + (t - 1)^3\n",
        links=links,
    )
    old, new = _repaired(text)
    assert edit(text, old, new) is None  # the caller writes the task whole


def test_an_unchanged_motion_is_no_edit() -> None:
    text = (CONFIGS / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")
    task = load_task(CONFIGS / "paper_path2.rprpr.yaml")
    assert edit(text, task, task) == text


def test_modeline() -> None:
    assert modeline("# yaml-language-server: $schema=https://x/s.json\nname: a\n") == (
        "https://x/s.json"
    )
    assert modeline("#yaml-language-server: $schema=../s.json\r\n") == "../s.json"
    assert modeline("name: a\n# yaml-language-server: $schema=x\n") is None


def test_a_task_without_a_name_is_edited_all_the_same() -> None:
    text = ZERO_SPEED.replace("name: test\n", "# unnamed: the file's stem names it\n")
    old, new = _repaired(text)
    edited = edit(text, old, new, rename=True)
    assert edited is not None and "name:" not in edited
    assert edited.startswith("# unnamed: the file's stem names it\nrobot:\n")

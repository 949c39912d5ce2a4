"""Every independent error of a bad task file in one run, each with its line and column;
one error only where it makes the rest meaningless (YAML syntax, encoding)."""

from __future__ import annotations

import json
from pathlib import PurePath

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rprpr.io.build import stem
from rprpr.io.loader import parse_task
from rprpr.model.errors import TaskFileError
from tests.conftest import run_cli
from tests.golden import MANY_ERRORS

WANT = [
    (3, 7, "robot.a1", "expected a number > 0 (|AB| [m]), found -6"),
    (6, 15, "robot.links.3.mass", "expected a number >= 0 (m3 [kg]), found -1.0"),
    (14, 13, "timing.duration", "expected a number (t_f [s]), found the text 'five'"),
    (15, 3, "timing.lwa", "unknown key 'lwa'; did you mean 'law'?"),
]


def _errors(text: str) -> list[tuple[int, int, str, str]]:
    with pytest.raises(TaskFileError) as e:
        parse_task(text, "t.yaml")
    assert e.value.errors[0] is e.value
    return [(x.line, x.column, x.key, x.message) for x in e.value.errors]


def test_four_mistakes_are_four_errors_in_file_order() -> None:
    assert _errors(MANY_ERRORS) == WANT


def test_a_misspelt_key_is_not_also_missing() -> None:
    messages = [m for *_, m in _errors(MANY_ERRORS.replace("timing:", "timming:"))]
    assert messages[-1] == "unknown key 'timming'; did you mean 'timing'?"
    assert not any("missing" in m for m in messages)


def test_a_yaml_syntax_error_stops_the_reading() -> None:
    text = MANY_ERRORS.replace("  to: 4\n", "  to: [4, 1\n")
    ((_, _, key, message),) = _errors(text)
    assert message.startswith("YAML syntax error") and key == ""


def test_every_format_carries_every_error(
    tmp_path: object, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)  # type: ignore[arg-type]
    with open("many.yaml", "w", encoding="utf-8") as fh:
        fh.write(MANY_ERRORS)
    code, out, err = run_cli("check", "many.yaml")
    assert code == 2 and out == ""
    assert err.splitlines() == [f"many.yaml:{ln}:{c}: {k}: {m} [RPR001]" for ln, c, k, m in WANT]
    code, out, _ = run_cli("check", "--format", "json", "many.yaml")
    (entry,) = json.loads(out)["input_errors"]
    assert [(e["line"], e["column"], e["key"], e["message"]) for e in entry["errors"]] == WANT
    code, out, _ = run_cli("check", "--format", "github", "many.yaml")
    assert [line.split("::")[1] for line in out.splitlines()] == [
        f"error file=many.yaml,line={ln},col={c},title=RPR001 invalid-task" for ln, c, _, _ in WANT
    ]
    code, out, _ = run_cli("check", "--format", "junit", "many.yaml")
    assert out.count("<error ") == 1 and "(and 3 more errors)" in out
    assert all(f"many.yaml:{ln}:{c}: {k}: " in out for ln, c, k, _ in WANT)


def test_a_missing_timing_law_names_every_law_and_x() -> None:
    from rprpr.model.timing import LAWS
    from tests.conftest import PATH2_YAML, task_text

    with pytest.raises(TaskFileError) as info:
        parse_task(task_text(PATH2_YAML, "timing:\n  duration: 5\n"), "t.yaml")
    assert info.value.message == (
        "missing timing law: give law (quintic, cubic, or trapezoidal with cruise_speed)"
        " or x (a polynomial in t, or pieces {until, x})"
    )
    assert all(law in info.value.message for law in LAWS)


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet="ab./\\:-_ ", max_size=12))
def test_a_task_without_a_name_is_named_by_its_files_stem_as_pathlib_says(file: str) -> None:
    assert stem(file) == PurePath(file).stem
    assert stem("configs/paper_path2.rprpr.yaml") == "paper_path2.rprpr"

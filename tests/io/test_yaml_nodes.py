"""A YAML indentation error says so, located, as yamllint would ("wrong indentation:
expected 4 but found 3"), instead of libyaml's raw "did not find expected key"."""

from __future__ import annotations

from pathlib import Path

import pytest

from rprpr.io.loader import TaskFileError, load_task
from tests.conftest import CONFIGS

BASE = (CONFIGS / "paper_path1.rprpr.yaml").read_text()


@pytest.mark.parametrize(
    ("old", "new", "line", "message"),
    [
        (
            "    4: {",
            "   4: {",
            16,
            "wrong indentation: expected 4 (as line 15) or 2 (as line 13) but found 3 spaces",
        ),
        (
            "  gravity:",
            "    gravity:",
            12,
            "wrong indentation: expected 2 (as line 11) but found 4 spaces",
        ),
        (
            "\npath:",
            "\n path:",
            18,
            "wrong indentation: expected 2 (as line 13) or 0 (as line 10) but found 1 space",
        ),
    ],
    ids=["a-link-one-short", "a-key-too-deep", "a-top-level-key"],
)
def test_an_indentation_mismatch_is_named_at_its_line(
    tmp_path: Path, old: str, new: str, line: int, message: str
) -> None:
    assert BASE.count(old) == 1
    bad = tmp_path / "bad.yaml"
    bad.write_text(BASE.replace(old, new))
    with pytest.raises(TaskFileError) as e:
        load_task(str(bad))
    err = e.value
    found = len(new) - len(new.lstrip("\n").lstrip(" ")) - new.startswith("\n")
    assert (err.line, err.column) == (line, found + 1)
    assert f"YAML syntax error: {message} (YAML says: " in str(err), str(err)
    assert BASE.replace(old, new).splitlines()[line - 1].startswith(" " * found + new.strip()[0])


def test_other_syntax_errors_keep_yamls_words(tmp_path: Path) -> None:
    """An unclosed flow list is not an indentation problem: no indentation hint."""
    bad = tmp_path / "bad.yaml"
    bad.write_text(BASE.replace("[2, -1]", "[2, -1"))
    with pytest.raises(TaskFileError) as e:
        load_task(str(bad))
    assert "indentation" not in str(e.value)
    assert "did not find expected ',' or ']'" in str(e.value)

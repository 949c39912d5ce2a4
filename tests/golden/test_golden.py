"""Every rendered report against its golden file, byte for byte (tests/golden/README.md).

A mismatch prints a unified diff per file; when the change is intended, regenerate with
``.venv/bin/python -m tests.golden`` and review ``git diff tests/golden`` like code."""

from __future__ import annotations

import difflib
import re

import pytest

from tests.conftest import CONFIGS, run_cli
from tests.golden import CASES, GOLDEN, REGENERATE, VARIANTS, Case, case_dir, render


def _diff(case: Case, name: str, text: str) -> str | None:
    """A unified diff from the golden file to ``text``; None when they are equal."""
    path = case_dir(case) / name
    want = path.read_bytes() if path.exists() else None
    if want == text.encode("utf-8"):
        return None
    old = "" if want is None else want.decode("utf-8", errors="replace")
    golden = f"tests/golden/{case.name}/{name}" if want is not None else "/dev/null"
    lines = difflib.unified_diff(
        old.splitlines(keepends=True),
        text.splitlines(keepends=True),
        fromfile=golden,
        tofile=f"{name} as rprpr prints it now",
    )
    return "".join(
        ln if ln.endswith("\n") else ln + "\n\\ No newline at end of file\n" for ln in lines
    )


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_reports_match_their_golden_files_byte_for_byte(case: Case) -> None:
    files = render(case)
    diffs = [d for name, text in files.items() if (d := _diff(case, name, text)) is not None]
    stale = sorted(p.name for p in case_dir(case).glob("*") if p.name not in files)
    diffs += [f"tests/golden/{case.name}/{name}: no longer produced\n" for name in stale]
    if diffs:
        pytest.fail("".join(diffs) + f"\nIf the change is intended: {REGENERATE}", pytrace=False)


def test_every_golden_folder_belongs_to_a_case() -> None:
    folders = {p.name for p in GOLDEN.iterdir() if p.is_dir() and p.name != "__pycache__"}
    assert folders == {c.name for c in CASES}


def test_golden_cases_cover_every_shipped_config_and_format() -> None:
    singles = {c.tasks for c in CASES if len(c.tasks) == 1}
    assert {(f"configs/{p.name}",) for p in CONFIGS.glob("*.yaml")} <= singles
    # the formats `rprpr check --format` offers, as its usage error lists them
    _, _, err = run_cli("check", "--format", "?", "configs")
    offered = set(re.findall(r"'(\w+)'", err.split("is not one of", 1)[1]))
    assert offered == {"text", "concise", "json", "junit", "github", "sarif", "gitlab", "html"}
    formats = {v.args[1] if v.args else "text" for v in VARIANTS}
    assert formats == offered

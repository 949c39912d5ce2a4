"""Shared fixtures: task files written from text, and the repository's configs."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = ROOT / "configs"

LINKS_ALIKE = """\
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
"""


def task_text(
    y: str, timing: str, *, a1: str = "6", links: str = LINKS_ALIKE, extra: str = ""
) -> str:
    """A task file's text with the given path, timing block and links."""
    return f"name: test\nrobot:\n  a1: {a1}\n{links}path:\n  y: {y}\n{timing}{extra}"


@pytest.fixture
def write_task(tmp_path: Path):  # type: ignore[no-untyped-def]
    """Write a task file and return its path."""
    count = [0]

    def write(text: str, name: str | None = None) -> Path:
        count[0] += 1
        p = tmp_path / (name or f"task{count[0]}.yaml")
        p.write_text(text, encoding="utf-8")
        return p

    return write

"""README's ```console examples print what rprpr prints (``tests/readme_examples.py``)."""

from __future__ import annotations

import pytest

from .readme_examples import BLOCK, README, examples, run

EXAMPLES = [e for m in BLOCK.finditer(README.read_text(encoding="utf-8")) for e in examples(m[1])]


def test_the_readme_has_console_examples() -> None:
    assert len(EXAMPLES) >= 3
    assert any(e.command.startswith("rprpr check") for e in EXAMPLES)


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda e: e.command)
def test_a_readme_example_prints_what_rprpr_prints(example) -> None:  # type: ignore[no-untyped-def]
    got = run(example.command)
    assert got == example.output, (
        f"README example `{example.command}` is stale; after an intended change run "
        ".venv/bin/python -m tests.readme_examples"
    )

"""The assertions of every test function: ``assert`` statements and ``pytest.raises`` calls,
counted in the source (AST) per function (``path::name``) of the files under ``tests/`` of
this clone (or of the folder given). A change that makes the suite cheaper keeps every
count: compare two revisions with

    python .ci/assert_counts.py > after.json
    git archive main | tar -x -C /tmp/main && python .ci/assert_counts.py /tmp/main > before.json
    python .ci/assert_counts.py --compare before.json after.json

(--compare prints each function whose count went down, and exits 1 if any did)."""

from __future__ import annotations

import ast
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def _is_raises(node: ast.AST) -> bool:
    return (
        isinstance(node, ast.Call)
        and isinstance(node.func, ast.Attribute)
        and node.func.attr == "raises"
        and isinstance(node.func.value, ast.Name)
        and node.func.value.id == "pytest"
    )


def counts(root: Path = ROOT) -> dict[str, int]:
    """``path::function`` -> asserts + pytest.raises inside it, for every function of
    the test tree (helpers and fixtures too: a test's assertions may live there)."""
    out: dict[str, int] = {}
    for path in sorted((root / "tests").rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        rel = path.relative_to(root).as_posix()
        for node in ast.walk(tree):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                n = sum(isinstance(sub, ast.Assert) or _is_raises(sub) for sub in ast.walk(node))
                key = f"{rel}::{node.name}"
                while key in out:  # a nested or repeated name: keep each
                    key += "'"
                out[key] = n
    return out


def compare(before: dict[str, int], after: dict[str, int]) -> list[str]:
    """Each function whose count went down (or that is gone) from ``before`` to ``after``."""
    return [
        f"{name}: {n} -> {after.get(name, 0)}"
        for name, n in sorted(before.items())
        if n and after.get(name, 0) < n
    ]


if __name__ == "__main__":
    if sys.argv[1:2] == ["--compare"]:
        old, new = (json.loads(Path(p).read_text()) for p in sys.argv[2:4])
        lost = compare(old, new)
        print("\n".join(lost) if lost else "no assertion lost")
        print(f"total: {sum(old.values())} -> {sum(new.values())}")
        sys.exit(1 if lost else 0)
    json.dump(
        counts(Path(sys.argv[1]) if sys.argv[1:] else ROOT), sys.stdout, indent=1, sort_keys=True
    )
    print()

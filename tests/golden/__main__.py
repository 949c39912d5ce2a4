"""Regenerate the golden files from the current code: ``.venv/bin/python -m tests.golden``.

Writes tests/golden/CASE/* for every case, removes files no case produces any more, and
lists what changed. Review the diff (``git diff tests/golden``) like code before committing.
"""

from __future__ import annotations

import shutil

from . import CASES, GOLDEN, case_dir, render


def main() -> None:
    changed: list[str] = []
    keep = {case_dir(c) for c in CASES}
    for stale in sorted(p for p in GOLDEN.iterdir() if p.is_dir() and p not in keep):
        if stale.name != "__pycache__":
            shutil.rmtree(stale)
            changed.append(f"removed {stale.relative_to(GOLDEN)}/")
    for case in CASES:
        folder = case_dir(case)
        folder.mkdir(exist_ok=True)
        files = render(case)
        for old in sorted(folder.iterdir()):
            if old.name not in files:
                old.unlink()
                changed.append(f"removed {old.relative_to(GOLDEN)}")
        for name, text in files.items():
            path = folder / name
            data = text.encode("utf-8")
            if not path.exists() or path.read_bytes() != data:
                path.write_bytes(data)
                changed.append(f"wrote {path.relative_to(GOLDEN)}")
    print("\n".join(changed) if changed else "golden files: unchanged")


if __name__ == "__main__":
    main()

"""The former import name ``rprpr_cli`` keeps working: the same API and ``python -m``."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from .cli.forked import run_rprpr
from .conftest import CONFIGS

BAD = Path(__file__).parent / "corpora" / "bad_tasks" / "missing_a1.yaml"


def test_the_old_import_name_offers_the_same_api() -> None:
    import rprpr
    import rprpr_cli

    assert rprpr_cli.audit is rprpr.audit and rprpr_cli.load_task is rprpr.load_task
    result = rprpr_cli.audit(rprpr_cli.load_task(CONFIGS / "paper_path1.rprpr.yaml"))
    assert result.verdict == "fail" and result.singularities[0].order == 3


def test_python_m_with_the_old_name_runs_the_command_line() -> None:
    """``python -m rprpr_cli`` in a new interpreter (what a real ``-m`` finds and runs)
    does what ``python -m rprpr`` does (a new interpreter's ``-m rprpr``: test_bad_tasks'
    process test; here it runs in a process forked from this one, ``tests/cli/forked.py``)."""
    runs = [
        run_rprpr(["check", str(BAD)], Path.cwd()),
        subprocess.run(
            [sys.executable, "-m", "rprpr_cli", "check", str(BAD)], capture_output=True, text=True
        ),
    ]
    assert [r.returncode for r in runs] == [2, 2]
    assert runs[0].stderr == runs[1].stderr
    assert "robot.a1: missing required key 'a1'" in runs[1].stderr

"""cli.main: the ``rprpr`` program asks OpenBLAS for one thread unless the user chose.

rprpr does no linear algebra; numpy's OpenBLAS otherwise starts a pool of threads in every
process that imports it, which costs CPU at each start."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from rprpr.cli import main

# ``run`` with ``main`` replaced by a report of what it would find
PROBE = (
    "import os, sys; from rprpr.cli import main as m; "
    "m.main = lambda: (print(os.environ.get('OPENBLAS_NUM_THREADS'), 'numpy' in sys.modules), "
    "sys.exit(0)); m.run()"
)


def _env(**set_: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in main.BLAS_THREADS}
    return {**env, **set_}


def test_one_thread_when_the_environment_says_nothing(monkeypatch: pytest.MonkeyPatch) -> None:
    env = _env()
    monkeypatch.setattr(os, "environ", env)  # this process's own is left as it is
    main._one_blas_thread()
    assert env["OPENBLAS_NUM_THREADS"] == "1"


@pytest.mark.parametrize("name", main.BLAS_THREADS)
def test_the_users_choice_is_kept(monkeypatch: pytest.MonkeyPatch, name: str) -> None:
    env = _env(**{name: "3"})
    monkeypatch.setattr(os, "environ", env)
    main._one_blas_thread()
    assert env[name] == "3"
    assert env.get("OPENBLAS_NUM_THREADS") == ("3" if name == "OPENBLAS_NUM_THREADS" else None)


def test_the_program_sets_it_before_numpy_is_imported() -> None:
    """``run`` (the console script) sets it first, when numpy is not imported yet, so
    that numpy's import in the command (or in a worker, which inherits it) reads it."""
    done = subprocess.run([sys.executable, "-c", PROBE], env=_env(), capture_output=True,
                          text=True, check=True)  # fmt: skip
    assert done.stdout.split() == ["1", "False"]
    done = subprocess.run([sys.executable, "-c", PROBE], env=_env(OMP_NUM_THREADS="2"),
                          capture_output=True, text=True, check=True)  # fmt: skip
    assert done.stdout.split() == ["None", "False"]

"""``cli.collector``: the program holds the garbage collector off only through its
start-up; every audit runs with it on, and ``main`` called from Python leaves it alone."""

from __future__ import annotations

import gc
import subprocess

import click
import pytest

from rprpr.cli import collector
from rprpr.cli.main import main, main_group

from ..conftest import ROOT
from .forked import fresh_probe

# a start-up probe (``tests.cli.forked.fresh_probe``): the program in a fresh process
fresh_probe(
    "test_collector program",
    "numpy, flint, yaml, click, rich.console",
    "import gc, os, sys\n"
    "from rprpr.cli import check, main\n"
    "real = check.check_one\n"
    "def spy(*args, **kw):\n"
    "    os.write(2, f'GC={gc.isenabled()} FROZEN={gc.get_freeze_count() > 0}\\n'.encode())\n"
    "    return real(*args, **kw)\n"
    "check.check_one = spy\n"
    "sys.argv = ['rprpr', 'check', 'configs/case1_crossing.rprpr.yaml',"
    " 'configs/paper_path2.rprpr.yaml']\n"
    "main.run()\n",
    ROOT,
)


def test_the_audit_of_the_program_runs_with_the_collector_on_and_the_start_up_frozen(
    fresh: dict[str, tuple[int, str, str]],
) -> None:
    done = subprocess.CompletedProcess("probe", *fresh["test_collector program"])
    assert done.returncode == 1, done.stderr  # case 1's unbounded torques fail
    assert done.stderr.splitlines() == ["GC=True FROZEN=True"] * 2, done.stderr


@pytest.mark.parametrize("name", ["rule", "schema", "init", "export", "plot", "repair"])
def test_every_other_command_has_the_collector_back_once_its_module_is_imported(
    name: str,
) -> None:
    collector.hold()
    try:
        assert not gc.isenabled()
        main_group.get_command(click.Context(main_group), name)
        assert gc.isenabled()
    finally:
        collector.release()


def test_main_called_from_python_leaves_the_collector_as_it_was(
    capsys: pytest.CaptureFixture[str],
) -> None:
    for enabled in (False, True):
        (gc.enable if enabled else gc.disable)()
        try:
            with pytest.raises(SystemExit):
                main(
                    [
                        "check",
                        "--format",
                        "json",
                        "-q",
                        str(ROOT / "configs/paper_path2.rprpr.yaml"),
                    ]
                )
            assert gc.isenabled() == enabled
        finally:
            gc.enable()
    capsys.readouterr()

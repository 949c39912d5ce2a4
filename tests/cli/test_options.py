"""The light install (``pip install rprpr``, without the extra ``rprpr[plot]``): every
command but the sheet works without matplotlib, and the sheet says how to get it.

matplotlib's absence is simulated in a subprocess: ``sys.modules['matplotlib'] = None``
(and Pillow's, ``PIL``) makes every import of them fail as on a machine without them.
The same run, in a virtual environment really without matplotlib, is stated in README
("Quick start").
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest

from rprpr.cli.options import PLOT_EXTRA
from tests.cli.forked import fresh_probe
from tests.conftest import PATH1_FILE, PATH2_FILE, ROOT

# several commands in one Python without matplotlib and Pillow (COMMANDS: each command's
# folder and arguments), each on its own UTF-8 pipe-like streams: each one's folder and
# (exit status, stdout, stderr), as JSON on the real standard output
LIGHT_BATCH = (
    "import io, json, sys\n"
    "sys.modules['matplotlib'] = None\n"
    "sys.modules['PIL'] = None\n"
    "from contextlib import redirect_stderr, redirect_stdout\n"
    "from rprpr.cli.main import main\n"
    "done = []\n"
    "for _, argv in COMMANDS:\n"
    "    out, err = (io.TextIOWrapper(io.BytesIO(), encoding='utf-8', newline='',\n"
    "                                 write_through=True) for _ in 'oe')\n"
    "    with redirect_stdout(out), redirect_stderr(err):\n"
    "        try:\n"
    "            main(argv)\n"
    "        except SystemExit as e:\n"
    "            code = e.code if isinstance(e.code, int) else int(e.code is not None)\n"
    "    done.append([code, *(s.buffer.getvalue().decode() for s in (out, err))])\n"
    "print(json.dumps([[f, d] for (f, _), d in zip(COMMANDS, done)]))\n"
)


fresh_probe(
    "test_options shim",
    "",
    "import sys\nsys.modules['matplotlib'] = None\nimport matplotlib.pyplot\n",
)


def test_the_shim_really_hides_matplotlib(fresh: dict[str, tuple[int, str, str]]) -> None:
    done = subprocess.CompletedProcess("probe", *fresh["test_options shim"])
    assert done.returncode == 1
    assert "ModuleNotFoundError" in done.stderr


# the commands the tests below run without matplotlib, all in one such Python
# (``light_runs``): those that work, and those that draw a sheet ({tmp}: a folder each)
WORKING = {
    "check": ["check", "--samples", "101", PATH2_FILE, PATH1_FILE],
    "export": ["export", "--samples", "11", "-o", "{tmp}/m.csv", PATH2_FILE],
    "repair": ["repair", PATH1_FILE, "-o", "{tmp}/fixed.rprpr.yaml"],
    "init": ["init", "{tmp}/new.rprpr.yaml"],
    "rule": ["rule", "RPR101"],
    "schema": ["schema"],
}
SHEETS = [
    (["plot", PATH2_FILE, "-o", "{tmp}/sheet.png"], "plot"),
    (["plot", PATH2_FILE, "--show"], "plot"),
    (["repair", PATH1_FILE, "-o", "{tmp}/r.rprpr.yaml", "--plot", "{tmp}/r.png"],
     "repair --plot"),
]  # fmt: skip


def _light_batch(folder: Path) -> str:
    """The code that runs each command of WORKING and SHEETS (by name, or by ``what`` and
    index; {tmp}: a new folder of its own in ``folder``) and ``plot --help`` (its folder:
    ROOT) in one Python without matplotlib (LIGHT_BATCH)."""
    commands = dict(WORKING)
    commands |= {f"{what} {i}": args for i, (args, what) in enumerate(SHEETS)}
    runs = {}
    for i, (name, args) in enumerate(commands.items()):
        tmp = folder / f"{i}"
        tmp.mkdir()
        runs[name] = (str(tmp), [a.format(tmp=tmp) for a in args])
    runs["plot --help"] = (str(ROOT), ["plot", "--help"])
    return f"COMMANDS = {list(runs.values())!r}\n{LIGHT_BATCH}"


# a start-up probe (``tests.cli.forked.fresh_probe``): one fresh process, from rprpr's
# dependencies but matplotlib and Pillow, in ROOT (the commands' folders are their own)
fresh_probe("test_options light", "numpy, flint, yaml, click, rich.console", _light_batch, ROOT)
LIGHT_NAMES = [*WORKING, *(f"{what} {i}" for i, (_, what) in enumerate(SHEETS)), "plot --help"]


@pytest.fixture
def light_runs(
    fresh: dict[str, tuple[int, str, str]],
) -> dict[str, tuple[Path, subprocess.CompletedProcess[str]]]:
    """Each command of WORKING and SHEETS (by name, or by ``what`` and index) and ``plot
    --help``, run in one Python without matplotlib: (its folder, what it did)."""
    status, stdout, stderr = fresh["test_options light"]
    assert status == 0, stderr
    ran = json.loads(stdout)
    return {
        name: (Path(folder), subprocess.CompletedProcess(name, *done))
        for name, (folder, done) in zip(LIGHT_NAMES, ran, strict=True)
    }


def test_check_export_repair_init_rule_and_schema_work_without_matplotlib(
    light_runs: dict[str, tuple[Path, subprocess.CompletedProcess[str]]],
) -> None:
    checked, exported, repaired, initialised, ruled, schema = (
        light_runs[name][1] for name in WORKING
    )
    csv = light_runs["export"][0] / "m.csv"
    out = light_runs["repair"][0] / "fixed.rprpr.yaml"
    new = light_runs["init"][0] / "new.rprpr.yaml"
    done = checked
    assert done.returncode == 1, done.stderr  # path 1 fails: the audit ran
    assert "RPR101" in done.stdout and "PASS" in done.stdout and "FAIL" in done.stdout
    assert done.stderr == ""

    done = exported
    assert done.returncode == 0, done.stderr
    rows = [r for r in csv.read_text().splitlines() if not r.startswith("#")]
    assert len(rows) == 12  # the column names and 11 samples

    done = repaired
    assert done.returncode == 0, done.stderr
    assert "checked" in done.stdout and out.is_file()

    done = initialised
    assert done.returncode == 0, done.stderr
    assert new.is_file()

    done = ruled
    assert (done.returncode, done.stdout.splitlines()[0]) == (0, "RPR101 slope-principle")

    done = schema
    assert done.returncode == 0 and '"$schema"' in done.stdout


@pytest.mark.parametrize("index", range(len(SHEETS)), ids=[what for _, what in SHEETS])
def test_the_sheet_without_matplotlib_says_how_to_install_it(
    index: int, light_runs: dict[str, tuple[Path, subprocess.CompletedProcess[str]]]
) -> None:
    what = SHEETS[index][1]
    tmp_path, done = light_runs[f"{what} {index}"]
    assert done.returncode == 2
    assert done.stdout == ""
    assert done.stderr == (
        f"rprpr: {what} draws with matplotlib, which is not installed: {PLOT_EXTRA}\n"
    )
    assert list(tmp_path.iterdir()) == []  # nothing written, not even the repaired task


def test_plot_help_needs_no_matplotlib(
    light_runs: dict[str, tuple[Path, subprocess.CompletedProcess[str]]],
) -> None:
    _, done = light_runs["plot --help"]
    assert done.returncode == 0 and "Usage: rprpr plot" in done.stdout


def test_the_extra_is_named_in_the_package_metadata() -> None:
    import tomllib

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    needs = " ".join(project["dependencies"]).lower()
    assert "matplotlib" not in needs and "pillow" not in needs
    extras = project["optional-dependencies"]
    assert any(d.startswith("matplotlib") for d in extras["plot"])
    assert any(d.startswith("pillow") for d in extras["plot"])
    assert "rprpr[plot]" in extras["test"]  # the suite draws sheets
    assert PLOT_EXTRA == "pip install 'rprpr[plot]'"

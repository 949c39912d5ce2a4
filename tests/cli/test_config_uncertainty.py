"""The configuration's ``uncertainty`` default (``cli.uncertainty``) and the rule that an
uncertainty needs a torque limit, the task's or the configuration's, checked once the
configuration is applied.

The numbers: path 2 with ±5 % on every link and 0.01 m/s² has a 5.44 ms window
(``tests/engine/robust/test_windows.py``: against the mpmath reference), longer than a 1 ms period.
"""

from __future__ import annotations

import json
import re
from contextlib import chdir
from pathlib import Path

import pytest
from flint import fmpq

from rprpr.cli.config import TaskDefaults, configure, load_settings
from rprpr.cli.errors import InputError
from rprpr.io.loader import parse_task
from rprpr.model.errors import TaskFileError
from tests.conftest import CONFIGS, run_cli

P2 = (CONFIGS / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")
NO_LIMIT = P2.replace("checks:\n  torque_limit: [300, 300]   # [N m]\n", "")
OWN = "uncertainty: {links: 0%, acceleration: 0, period: 0.001}\n"
CONFIG = 'uncertainty = {links = "5%", acceleration = 0.01, period = 0.001}\n'


def _check(folder: Path, name: str) -> tuple[int, dict, str]:  # type: ignore[type-arg]
    with chdir(folder):
        code, out, err = run_cli("check", "--format", "json", "--samples", "101", name)
    return code, json.loads(out) if out.startswith("{") else {}, out + err


def _write(folder: Path, name: str, text: str) -> None:
    (folder / name).write_text(text, encoding="utf-8")


def test_no_limit_check_of_its_own_when_there_is_uncertainty() -> None:
    assert "checks" not in NO_LIMIT and "torque_limit" in P2  # the fixture is what it says
    assert parse_task(NO_LIMIT + OWN).uncertainty is not None  # the limit may come later


def test_the_configuration_declares_the_uncertainty_of_a_task_without_one(tmp_path: Path) -> None:
    _write(tmp_path, "rprpr.toml", CONFIG)
    _write(tmp_path, "p2.rprpr.yaml", P2)
    code, doc, _ = _check(tmp_path, "p2.rprpr.yaml")
    (report,) = doc["reports"]
    assert report["uncertainty"]["acceleration"] == 0.01
    assert report["uncertainty"]["period"] == 0.001
    assert set(report["uncertainty"]["links"]) == {"2", "3", "4", "5"}
    (sing,) = report["singularities"]
    assert sing["robust"]["window"] == pytest.approx(5.44e-3, abs=5e-6)
    assert code == 1 and "RPR205" in {f["rule"] for f in report["findings"]}


def test_the_tasks_own_uncertainty_wins_whole(tmp_path: Path) -> None:
    _write(tmp_path, "rprpr.toml", CONFIG)
    _write(tmp_path, "p2.rprpr.yaml", P2 + OWN)  # the exact model: path 2 is consistent
    code, doc, _ = _check(tmp_path, "p2.rprpr.yaml")
    (report,) = doc["reports"]
    assert report["uncertainty"]["acceleration"] == 0
    (sing,) = report["singularities"]
    assert sing["robust"]["window"] == 0 and sing["robust"]["residual"] == [0, 0]
    assert code == 0


def test_a_task_takes_its_limit_from_the_configuration(tmp_path: Path) -> None:
    _write(tmp_path, "rprpr.toml", "torque_limit = [300, 300]\n")
    _write(tmp_path, "p2.rprpr.yaml", NO_LIMIT + OWN)
    code, doc, _ = _check(tmp_path, "p2.rprpr.yaml")
    assert code == 0 and doc["reports"][0]["singularities"][0]["robust"]["window"] == 0


def test_no_limit_anywhere_is_one_located_line_at_the_tasks_key(tmp_path: Path) -> None:
    _write(tmp_path, "p2.rprpr.yaml", NO_LIMIT + OWN)
    line = (NO_LIMIT + OWN).splitlines().index(OWN.strip()) + 1
    with chdir(tmp_path):
        code, out, err = run_cli("check", "--isolated", "p2.rprpr.yaml")
    assert code == 2
    (located,) = [ln for ln in (out + err).splitlines() if ln.startswith("p2.rprpr.yaml:")]
    assert located.startswith(f"p2.rprpr.yaml:{line}:14: uncertainty: uncertainty needs")
    assert "checks.torque_limit" in located and "configuration" in located


def test_the_configurations_uncertainty_without_a_limit_names_the_configuration(
    tmp_path: Path,
) -> None:
    _write(tmp_path, "pyproject.toml", "[project]\nname = 'x'\n\n[tool.rprpr]\n" + CONFIG)
    _write(tmp_path, "p2.rprpr.yaml", NO_LIMIT)
    code, _doc, text = _check(tmp_path, "p2.rprpr.yaml")
    assert code == 2
    assert re.search(r"uncertainty of the configuration \(\S*pyproject\.toml:5\)", text)


def test_other_commands_need_the_tasks_own_limit(tmp_path: Path) -> None:
    _write(tmp_path, "p2.rprpr.yaml", NO_LIMIT + OWN)
    with chdir(tmp_path):
        code, out, err = run_cli("export", "p2.rprpr.yaml", "-o", "out.csv")
    assert code == 2 and "uncertainty needs checks.torque_limit" in out + err


@pytest.mark.parametrize(
    ("toml", "needle"),
    [
        ('uncertainty = {links = "100%"}', "uncertainty.links: expected a percentage"),
        ("uncertainty = {links = 0.05}", "(write the percentage with %)"),
        ('uncertainty = {links = {3 = {mass = "2%", m = "1%"}}}', "unknown key 'm'"),
        ('uncertainty = {links = {6 = {mass = "2%"}}}', "unknown link '6'"),
        ("uncertainty = {acceleration = -1}", "uncertainty.acceleration: expected a number >= 0"),
        ('uncertainty = {window = "1"}', "unknown key 'window'"),
        ('uncertainty = "5%"', "expected a table {links, acceleration, period}"),
        ('uncertainty = {links = "5%"}', "missing required key 'period' (the controller's"),
    ],
)
def test_a_bad_configured_uncertainty_names_the_file_line_and_key(
    tmp_path: Path, toml: str, needle: str
) -> None:
    _write(tmp_path, "rprpr.toml", "jobs = 1\n" + toml + "\n")
    with pytest.raises(InputError) as e:
        load_settings(cwd=str(tmp_path))
    assert str(e.value).startswith(f"{tmp_path / 'rprpr.toml'}:2: uncertainty")
    assert needle in str(e.value)


def test_per_link_values_exactly_and_show_settings(tmp_path: Path) -> None:
    from fractions import Fraction as F

    _write(
        tmp_path,
        "rprpr.toml",
        'uncertainty = {links = {3 = {mass = "2%", r = "1.5%"}}, period = 0}\n',
    )
    u = load_settings(cwd=str(tmp_path))["uncertainty"]
    assert u.links[3] == (F(1, 50), F(0), F(3, 200)) and u.links[2] == (0, 0, 0)
    assert u.acceleration == 0 and u.period == 0
    task = configure(parse_task(P2), TaskDefaults(uncertainty=u))
    assert task.uncertainty is not None and task.uncertainty.links[3][2] == fmpq(3, 200)
    with chdir(tmp_path):
        _code, out, _ = run_cli("check", "--show-settings")
    assert re.search(r"^uncertainty\s+= \{links = \{3 = \{mass = \"2%\".*rprpr\.toml", out, re.M)
    with pytest.raises(TaskFileError):
        configure(parse_task(NO_LIMIT), TaskDefaults(uncertainty=u))

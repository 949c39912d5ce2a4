"""The repository's configuration: discovery, keys, rule levels, precedence (command line >
task file > configuration > defaults), per-task suppression, and the errors that name a
bad key or rule. The verdicts asserted rest on the paper: path 2 (eq. 51) crosses y = 0
with slope 0.2 at (3, 0); path 1 (eq. 50) is horizontal there (RPR101)."""

from __future__ import annotations

import json
import os
import shutil
from contextlib import chdir
from pathlib import Path

import pytest

from rprpr.cli.config import find_config, load_settings
from rprpr.cli.errors import InputError
from rprpr.model.rules import Finding, SelectorError, levels, with_levels
from tests.conftest import CONFIGS, run_cli

P1 = CONFIGS / "paper_path1.rprpr.yaml"  # fails RPR101 (horizontal) and RPR201
P2 = CONFIGS / "paper_path2.rprpr.yaml"  # passes: slope 0.2, first order, bounded


@pytest.fixture
def repo(tmp_path: Path) -> Path:
    """A repository with tasks/ (paths 1 and 2), a docker-compose.yml, a nested folder."""
    (tmp_path / "tasks").mkdir()
    shutil.copy(P1, tmp_path / "tasks" / "p1.rprpr.yaml")
    shutil.copy(P2, tmp_path / "tasks" / "p2.rprpr.yaml")
    (tmp_path / "docker-compose.yml").write_text("services: {}\n", encoding="utf-8")
    (tmp_path / "sub" / "deeper").mkdir(parents=True)
    return tmp_path


def _check(repo: Path, *args: str, cwd: Path | None = None) -> tuple[int, dict, str]:  # type: ignore[type-arg]
    with chdir(cwd or repo):
        code, out, err = run_cli("check", "--format", "json", "--samples", "101", *args)
    return code, json.loads(out) if out else {}, err


def _rules(doc: dict) -> list[list[tuple[str, str]]]:  # type: ignore[type-arg]
    return [[(f["rule"], f["severity"]) for f in r["findings"]] for r in doc["reports"]]


# -- discovery -------------------------------------------------------------------------------
def test_the_nearest_configuration_upward_wins(repo: Path) -> None:
    (repo / "pyproject.toml").write_text("[tool.rprpr]\njobs = 2\n", encoding="utf-8")
    (repo / "sub" / "pyproject.toml").write_text("[project]\nname = 'x'\n", encoding="utf-8")
    assert find_config(str(repo / "sub" / "deeper")) == str(repo / "pyproject.toml")
    (repo / "sub" / "rprpr.toml").write_text("jobs = 3\n", encoding="utf-8")
    assert find_config(str(repo / "sub" / "deeper")) == str(repo / "sub" / "rprpr.toml")
    settings = load_settings(cwd=str(repo / "sub" / "deeper"))
    assert settings["jobs"] == 3 and settings.sources["jobs"] == str(repo / "sub" / "rprpr.toml")
    assert load_settings(isolated=True, cwd=str(repo / "sub"))["jobs"] == 1


def test_check_with_no_path_checks_the_configured_paths_task_files_only(repo: Path) -> None:
    (repo / "pyproject.toml").write_text('[tool.rprpr]\npaths = ["tasks"]\n', encoding="utf-8")
    code, doc, _ = _check(repo, cwd=repo / "sub" / "deeper")  # paths: relative to the root
    assert code == 1
    assert [Path(r["task"]).name for r in doc["reports"]] == ["p1.rprpr.yaml", "p2.rprpr.yaml"]
    code, doc, _ = _check(repo, "--isolated")  # the working directory, task files only
    assert code == 1 and doc["summary"]["tasks"] == 2  # docker-compose.yml never read


def test_include_and_exclude_choose_the_task_files(repo: Path) -> None:
    shutil.copy(P2, repo / "tasks" / "plain.yaml")
    (repo / "rprpr.toml").write_text(
        'include = ["tasks/*.yaml"]\nexclude = ["p1.rprpr.yaml"]\n', encoding="utf-8"
    )
    code, doc, _ = _check(repo)
    assert code == 0
    assert sorted(Path(r["task"]).name for r in doc["reports"]) == ["p2.rprpr.yaml", "plain.yaml"]


# -- levels ----------------------------------------------------------------------------------
def test_selectors_resolve_as_ruff_does() -> None:
    assert levels() == {}
    assert levels(ignore=["RPR1"], warn=["RPR201"]) == {
        "RPR101": "ignore", "RPR102": "ignore", "RPR103": "ignore", "RPR104": "ignore",
        "RPR201": "warn",
    }  # fmt: skip
    assert levels(select=["RPR101"])["RPR102"] == "ignore"  # not selected
    assert "RPR101" not in levels(select=["RPR101"], ignore=["RPR1"])  # the longer wins
    assert levels(select=["RPR1"], ignore=["RPR1"])["RPR101"] == "ignore"  # a tie: ignore
    assert levels(warn=["RPR2"], error=["RPR202"]) == {
        "RPR201": "warn", "RPR202": "error", "RPR203": "warn", "RPR204": "warn", "RPR205": "warn",
    }  # fmt: skip
    with pytest.raises(SelectorError, match="both in warn and in error"):
        levels(warn=["RPR202"], error=["RPR202"])
    with pytest.raises(SelectorError, match="did you mean RPR201"):
        levels(ignore=["RPR2011"])
    with pytest.raises(SelectorError, match="never audited"):
        levels(ignore=["RPR001"])


def test_levels_drop_downgrade_and_promote_findings() -> None:
    found = [Finding("RPR101", "a", 1.0), Finding("RPR202", "b"), Finding("RPR201", "c", 1.0)]
    out = with_levels(found, {"RPR101": "ignore", "RPR202": "error", "RPR201": "warn"})
    assert [f.rule for f in out] == ["RPR202", "RPR201"]
    assert out[0].fails(strict=False)  # promoted: fails outside strict mode
    assert not out[1].fails(strict=False) and out[1].fails(strict=True)  # a warning


def test_configured_levels_change_the_verdict(repo: Path) -> None:
    (repo / "rprpr.toml").write_text('warn = ["RPR201"]\nignore = ["RPR101"]\n', "utf-8")
    code, doc, _ = _check(repo, "tasks/p1.rprpr.yaml")
    assert code == 0 and _rules(doc) == [[("RPR201", "warning")]]
    code, doc, _ = _check(repo, "--strict", "tasks/p1.rprpr.yaml")
    assert code == 1 and _rules(doc) == [[("RPR201", "error")]]


def test_a_task_silences_a_rule_with_a_reason_and_wins_over_the_configuration(
    repo: Path,
) -> None:
    task = repo / "tasks" / "p1.rprpr.yaml"
    task.write_text(
        task.read_text(encoding="utf-8")
        + "checks:\n  ignore:\n    RPR101: accepted in a test\n  warn:\n    RPR201: also\n",
        encoding="utf-8",
    )
    (repo / "rprpr.toml").write_text('error = ["RPR201"]\n', encoding="utf-8")
    code, doc, _ = _check(repo, str(task))
    assert code == 0 and _rules(doc) == [[("RPR201", "warning")]]
    code, doc, _ = _check(repo, "--isolated", str(task))  # the Python API reads it too
    assert code == 0 and _rules(doc) == [[("RPR201", "warning")]]


def test_a_task_without_a_reason_is_rejected(write_task) -> None:  # type: ignore[no-untyped-def]
    p = write_task(P2.read_text(encoding="utf-8") + "  ignore:\n    RPR101:\n")
    code, _out, err = run_cli("check", "--isolated", str(p))
    assert code == 2 and "checks.ignore.RPR101" in err and "found null" in err


def test_task_checks_win_over_configured_defaults(repo: Path) -> None:
    # path 2's slope at (3, 0) is 0.2 (paper, eq. 51): a margin of 0.3 fails it, 0.1 not
    (repo / "rprpr.toml").write_text("min_slope = 0.3\n", encoding="utf-8")
    code, doc, _ = _check(repo, "tasks/p2.rprpr.yaml")
    assert code == 1 and _rules(doc) == [[("RPR101", "error")]]
    task = repo / "tasks" / "p2.rprpr.yaml"
    task.write_text(task.read_text(encoding="utf-8") + "  min_slope: 0.1\n", encoding="utf-8")
    code, doc, _ = _check(repo, "tasks/p2.rprpr.yaml")
    assert code == 0 and _rules(doc) == [[]]


def test_a_configured_torque_limit_applies_where_a_task_has_none(repo: Path) -> None:
    # path 1 has no limit of its own, and unbounded torques at t = 2.5 s: beyond any limit
    (repo / "rprpr.toml").write_text("torque_limit = [300, 300]\nerror = ['RPR202']\n", "utf-8")
    _code, doc, _ = _check(repo, "tasks/p1.rprpr.yaml")
    assert ("RPR202", "error") in _rules(doc)[0]
    assert doc["reports"][0]["torque_limit"][0]["limit"] == 300


def test_the_peak_is_computed_when_the_command_line_the_task_or_the_configuration_asks(
    repo: Path,
) -> None:
    # path 2's |T1| peaks at 66.1221 N m (tests/report: against the reference)
    def peak(*args: str) -> object:
        code, doc, _ = _check(repo, *args, "tasks/p2.rprpr.yaml")
        assert code == 0
        (rep,) = doc["reports"]
        return rep["torque_peak"] and round(rep["torque_peak"][0], 4)

    assert peak() is None  # not asked: "torque_peak_computed": false
    assert peak("--peak") == 66.1221
    (repo / "rprpr.toml").write_text("peak = true\n", encoding="utf-8")
    assert peak() == 66.1221
    task = repo / "tasks" / "p2.rprpr.yaml"
    task.write_text(task.read_text(encoding="utf-8") + "  peak: false\n", encoding="utf-8")
    assert peak() is None  # the task's own key wins over the configuration
    assert peak("--peak") == 66.1221  # the command line over both
    with chdir(repo):
        _, out, _ = run_cli("check", "--show-settings")
    assert "peak         = true  # " + str(repo / "rprpr.toml") in out.splitlines()


def test_warn_unbounded_and_the_task_key_still_work(repo: Path) -> None:
    code, doc, _ = _check(
        repo, "--isolated", "--warn-unbounded", str(CONFIGS / "case1_crossing.rprpr.yaml")
    )
    assert code == 0 and _rules(doc) == [[("RPR201", "warning")]]


# -- errors that name what is wrong -------------------------------------------------------
@pytest.mark.parametrize(
    ("toml", "needle"),
    [
        (
            "min-slope = 0.1\n",
            "unknown key 'min-slope' in the configuration (did you mean 'min_slope'?)",
        ),
        ('ignore = ["RPR2011"]\n', "ignore: unknown rule 'RPR2011' (did you mean RPR201?)"),
        ('warn = ["RPR202"]\nerror = ["RPR202"]\n', "RPR202 is both in warn and in error"),
        ("jobs = -1\n", "jobs: expected an integer from 0 to 256"),
        ("torque_limit = [300]\n", "torque_limit: expected [|T1| limit, |T2| limit]"),
        ('format = "xml"\n', "format: expected one of text, concise, json, junit, github"),
        ("strict = 1\n", "strict: expected true or false, found 1"),
        ("jobs = \n", "invalid TOML"),
    ],
)
def test_a_bad_configuration_is_an_error_naming_it(repo: Path, toml: str, needle: str) -> None:
    (repo / "rprpr.toml").write_text(toml, encoding="utf-8")
    with chdir(repo):
        code, out, err = run_cli("check", "tasks")
    assert code == 2 and out == ""
    assert needle in err and str(repo / "rprpr.toml") in err
    assert len(err.strip().splitlines()) == 1


def test_a_bad_key_in_pyproject_names_the_table(repo: Path) -> None:
    (repo / "pyproject.toml").write_text("[tool.rprpr]\nselekt = []\n", encoding="utf-8")
    with pytest.raises(InputError, match=r"unknown key 'selekt' in \[tool.rprpr\]"):
        load_settings(cwd=str(repo))


def test_show_settings_says_where_each_value_comes_from(repo: Path) -> None:
    (repo / "pyproject.toml").write_text(
        '[tool.rprpr]\npaths = ["tasks"]\nwarn = ["RPR201"]\n', encoding="utf-8"
    )
    with chdir(repo):
        code, out, err = run_cli("check", "--show-settings", "-j", "2")
    cfg = str(repo / "pyproject.toml")
    assert code == 0 and err == ""
    lines = out.splitlines()
    assert lines[0] == f"# configuration: {cfg}"
    assert f'paths        = ["tasks"]  # {cfg}' in lines
    assert "jobs         = 2  # command line" in lines
    assert "samples      = 1001  # default" in lines
    assert "RPR201 unbounded-torque       warn" in lines


def test_settings_paths_are_relative_to_the_root_not_the_working_directory(repo: Path) -> None:
    (repo / "rprpr.toml").write_text('paths = ["tasks"]\n', encoding="utf-8")
    with chdir(repo / "sub"):
        settings = load_settings()
    assert [os.path.abspath(os.path.join(repo / "sub", p)) for p in settings["paths"]] == [
        str(repo / "tasks")
    ]


# -- rules on the command line, and rule names wherever ids go -------------------------------
def test_the_command_line_selects_and_ignores_with_the_configurations_semantics(
    repo: Path,
) -> None:
    p1 = "tasks/p1.rprpr.yaml"  # RPR101 and RPR201, both errors
    assert _rules(_check(repo, "--ignore", "RPR201", p1)[1]) == [[("RPR101", "error")]]
    assert _rules(_check(repo, "--select", "RPR2", p1)[1]) == [[("RPR201", "error")]]
    # the most specific selector wins, as in the configuration: RPR201 over RPR2
    code, doc, _ = _check(repo, "--select", "RPR1", "--extend-select", "RPR201", p1)
    assert code == 1 and _rules(doc) == [[("RPR101", "error"), ("RPR201", "error")]]
    code, doc, _ = _check(repo, "--ignore", "RPR2", "--extend-select", "RPR201", p1)
    assert _rules(doc) == [[("RPR101", "error"), ("RPR201", "error")]]
    # comma-separated, repeated, and by name
    code, doc, _ = _check(repo, "--ignore", "slope-principle,RPR104", "--ignore", "RPR201", p1)
    assert (code, _rules(doc)) == (0, [[]])


def test_command_line_ignore_adds_to_the_configuration_and_select_starts_afresh(
    repo: Path,
) -> None:
    (repo / "rprpr.toml").write_text('ignore = ["RPR101"]\n', encoding="utf-8")
    p1 = "tasks/p1.rprpr.yaml"
    assert _rules(_check(repo, p1)[1]) == [[("RPR201", "error")]]
    assert _rules(_check(repo, "--ignore", "RPR201", p1)[1]) == [[]]
    # --select replaces the configuration's select and its ignore, as ruff's does
    assert _rules(_check(repo, "--select", "ALL", p1)[1]) == [
        [("RPR101", "error"), ("RPR201", "error")]
    ]
    with chdir(repo):
        code, out, _ = run_cli("check", "--ignore", "RPR202", "--show-settings")
    assert code == 0
    assert f'ignore       = ["RPR101", "RPR202"]  # {repo / "rprpr.toml"} + command line' in out


def test_an_unknown_rule_on_the_command_line_is_one_line_naming_the_option(repo: Path) -> None:
    with chdir(repo):
        code, out, err = run_cli("check", "--extend-select", "unbounded-torq", "tasks")
    assert (code, out) == (2, "")
    assert err == (
        "rprpr: --extend-select: unknown rule 'unbounded-torq' (did you mean unbounded-torque?);"
        " `rprpr rule` lists the rules\n"
    )
    with chdir(repo):
        code, _, err = run_cli("check", "--select", "RPR001", "tasks")
    assert code == 2 and err.startswith("rprpr: --select: RPR001 (invalid-task) cannot be")


def test_rule_names_are_selectors_in_the_configuration() -> None:
    assert levels(select=["ALL"], ignore=["unbounded-torque"]) == {"RPR201": "ignore"}
    assert levels(select=["ALL"], warn=["RPR2"], error=["torque-limit"])["RPR202"] == "error"
    assert levels(select=["ALL"], ignore=["rpr201"]) == {"RPR201": "ignore"}
    with pytest.raises(SelectorError, match="did you mean slope-principle"):
        levels(ignore=["slope-principl"])
    with pytest.raises(SelectorError, match="cannot be selected"):
        levels(ignore=["invalid-task"])


def test_a_task_ignores_or_warns_a_rule_by_its_name(write_task) -> None:  # type: ignore[no-untyped-def]
    p = write_task(
        P1.read_text(encoding="utf-8")
        + "checks:\n  ignore:\n    slope-principle: a test rig\n"
        + "  warn:\n    unbounded-torque: accepted here\n"
    )
    code, out, err = run_cli("check", "--isolated", "--format", "json", str(p))
    assert (code, err) == (0, "")
    assert _rules(json.loads(out)) == [[("RPR201", "warning")]]


def test_a_missing_reason_says_a_reason_is_required(write_task) -> None:  # type: ignore[no-untyped-def]
    p = write_task(P2.read_text(encoding="utf-8") + "  ignore:\n    unbounded-torque:\n")
    code, _, err = run_cli("check", "--isolated", str(p))
    assert code == 2 and len(err.splitlines()) == 1
    assert "expected text: why this task may break the rule (a reason is required)" in err
    assert "a name for reports" not in err

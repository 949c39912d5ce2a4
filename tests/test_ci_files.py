"""The CI integration files: the pre-commit hook, the composite GitHub Action, and the
README's CI section."""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

import pytest
import yaml

from rprpr.model.rules import RULES

from .cli.forked import run_served
from .conftest import CONFIGS, ROOT

HOOKS = ROOT / ".pre-commit-hooks.yaml"
ACTION = ROOT / "action.yml"
DOC = ROOT / "README.md"
BIN = Path(sys.executable).parent  # where pip put the rprpr console script


def load(path: Path) -> Any:
    return yaml.safe_load(path.read_text(encoding="utf-8"))


def env_without_colour(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR")}
    env["PATH"] = f"{BIN}{os.pathsep}{env.get('PATH', '')}"
    env.update(extra)
    return env


# -- .pre-commit-hooks.yaml -------------------------------------------------------------------
@pytest.fixture(scope="module")
def hook() -> dict[str, Any]:
    hooks = load(HOOKS)
    assert isinstance(hooks, list)
    [h] = hooks
    return h  # type: ignore[no-any-return]


def test_pre_commit_hook_has_the_required_keys(hook: dict[str, Any]) -> None:
    assert {"id", "name", "entry", "language"} <= set(hook)
    assert hook["id"] == "rprpr-check"
    assert hook["language"] == "python"
    assert hook["types"] == ["yaml"]
    assert "files" not in hook  # every YAML file: rprpr itself keeps the task files
    entry = shlex.split(hook["entry"])
    assert entry[:2] == ["rprpr", "check"]
    assert "--force-exclude" in entry
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"][
        "scripts"
    ]
    assert scripts["rprpr"] == "rprpr.cli.main:run"  # what `language: python` installs
    assert hook.get("pass_filenames", True) is True


def _selected(hook: dict[str, Any], files: list[str]) -> list[str]:
    """The files pre-commit would pass: ``files`` matches (default: any), of type yaml
    (identify: by suffix), and ``exclude`` does not."""
    inc, exc = re.compile(hook.get("files", "")), re.compile(hook.get("exclude", "^$"))
    yaml_type = "yaml" in hook.get("types", ["yaml"])
    return [
        f
        for f in files
        if inc.search(f) and not exc.search(f) and (not yaml_type or f.endswith((".yaml", ".yml")))
    ]


def test_pre_commit_hook_passes_yaml_files_not_hidden_configs(hook: dict[str, Any]) -> None:
    files = [
        "tasks/a.rprpr.yaml", "tasks/sub/b.yml", "tasks/c.json", "README.md", "tasks/yaml",
        ".pre-commit-config.yaml", ".github/workflows/ci.yml", "tasks/.draft.yaml",
        ".gitlab-ci.yml", "docker-compose.yml",
    ]  # fmt: skip
    assert _selected(hook, files) == ["tasks/a.rprpr.yaml", "tasks/sub/b.yml", "docker-compose.yml"]


def _run_hook(
    hook: dict[str, Any], repo: Path, staged: list[str], *, real: bool = False
) -> subprocess.CompletedProcess[str]:
    """The hook's command line on the files pre-commit would pass it, in ``repo``: the
    console script pip installed (``real``: its interpreter's start-up included), else an
    ``rprpr`` whose runs are forked from this process (``tests.cli.forked.run_served``)."""
    args = [*shlex.split(hook["entry"]), *hook.get("args", []), *_selected(hook, staged)]
    if not real:
        return run_served([*args, "--samples", "101"], cwd=repo, env=env_without_colour())
    return subprocess.run(
        [str(BIN / args[0]), *args[1:], "--samples", "101"],
        cwd=repo, capture_output=True, text=True, env=env_without_colour(), check=False,
    )  # fmt: skip


@pytest.mark.slow  # the hook's command line, run as pre-commit runs it
def test_pre_commit_hook_never_audits_other_yaml_files(
    hook: dict[str, Any], tmp_path: Path
) -> None:
    """The trap of a docker-compose.yml (``unknown key 'services'``, exit 2) is gone: a
    commit that changes only YAML files that are not tasks passes, and prints nothing."""
    (tmp_path / "docker-compose.yml").write_text("services: {}\n", encoding="utf-8")
    (tmp_path / "mkdocs.yaml").write_text("site_name: x\n", encoding="utf-8")
    p = _run_hook(hook, tmp_path, ["docker-compose.yml", "mkdocs.yaml"])
    assert (p.returncode, p.stdout, p.stderr) == (0, "", "")


@pytest.mark.slow  # the hook's command line, run as pre-commit runs it
def test_pre_commit_hook_follows_the_configured_include(
    hook: dict[str, Any], tmp_path: Path
) -> None:
    (tmp_path / "plans").mkdir()
    shutil.copy(CONFIGS / "paper_path1.rprpr.yaml", tmp_path / "plans" / "p1.yaml")
    (tmp_path / "compose.yaml").write_text("services: {}\n", encoding="utf-8")
    (tmp_path / "rprpr.toml").write_text('include = ["plans/*.yaml"]\n', encoding="utf-8")
    p = _run_hook(hook, tmp_path, ["plans/p1.yaml", "compose.yaml"])
    assert p.returncode == 1  # the plan fails (RPR101); compose.yaml was never read
    assert "plans/p1.yaml" in p.stdout and "compose" not in p.stdout + p.stderr


@pytest.mark.slow  # the hook's command line, run as pre-commit runs it
def test_pre_commit_hook_entry_checks_the_files_it_is_given(
    hook: dict[str, Any], tmp_path: Path
) -> None:
    repo = tmp_path / "repo"
    (repo / "tasks").mkdir(parents=True)
    (repo / ".github" / "workflows").mkdir(parents=True)
    shutil.copy(CONFIGS / "paper_path2.rprpr.yaml", repo / "tasks" / "good.rprpr.yaml")
    shutil.copy(CONFIGS / "paper_path1.rprpr.yaml", repo / "tasks" / "bad_plan.rprpr.yml")
    (repo / ".pre-commit-config.yaml").write_text("repos: []\n", encoding="utf-8")
    (repo / ".github" / "workflows" / "ci.yml").write_text("on: push\n", encoding="utf-8")
    (repo / "docker-compose.yml").write_text("services: {}\n", encoding="utf-8")
    staged = [
        "tasks/good.rprpr.yaml",
        "tasks/bad_plan.rprpr.yml",
        ".pre-commit-config.yaml",
        ".github/workflows/ci.yml",
        "docker-compose.yml",
    ]
    p = _run_hook(hook, repo, staged, real=True)  # the console script, as pre-commit runs it
    assert p.returncode == 1
    assert p.stderr == ""
    assert "tasks/bad_plan.rprpr.yml — Example 1 of the paper, path 1" in p.stdout
    assert "tasks/good.rprpr.yaml" not in p.stdout  # --quiet: only what fails
    assert p.stdout.splitlines()[-1] == "2 tasks: 1 passed, 1 failed, 0 errors"


# -- action.yml -------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def action() -> dict[str, Any]:
    a = load(ACTION)
    assert isinstance(a, dict)
    return a


def test_action_has_the_required_keys_and_inputs(action: dict[str, Any]) -> None:
    assert {"name", "description", "inputs", "runs"} <= set(action)
    inputs = action["inputs"]
    assert set(inputs) == {"paths", "strict", "args", "python-version"}
    assert all("description" in v for v in inputs.values())
    assert {k: v["default"] for k, v in inputs.items()} == {
        "paths": "", "strict": "false", "args": "", "python-version": "3.11",
    }  # fmt: skip
    runs = action["runs"]
    assert runs["using"] == "composite"
    steps = runs["steps"]
    assert all("shell" in s for s in steps if "run" in s)  # composite run steps need a shell
    setup, install, check = steps
    assert setup["uses"].startswith("actions/setup-python@")
    assert setup["with"]["python-version"] == "${{ inputs.python-version }}"
    assert install["env"]["RPRPR_SOURCE"] == "${{ github.action_path }}"
    assert "pip install" in install["run"] and '"$RPRPR_SOURCE"' in install["run"]
    assert "rprpr check --format github" in check["run"]
    # inputs reach the script through the environment, never pasted into it
    assert "${{" not in check["run"] and "${{" not in install["run"]


def test_the_action_and_the_hook_install_the_light_form(
    action: dict[str, Any], hook: dict[str, Any]
) -> None:
    """Neither the Action nor the pre-commit hook installs matplotlib: the package's
    dependencies leave it out, and neither asks for the extra rprpr[plot]."""
    install = action["runs"]["steps"][1]["run"]
    assert "[plot]" not in install and "matplotlib" not in install
    assert not any(
        "matplotlib" in d or "plot" in d for d in hook.get("additional_dependencies", [])
    )
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert not any(d.lower().startswith(("matplotlib", "pillow")) for d in project["dependencies"])


def _run_check_step(
    action: dict[str, Any], cwd: Path = ROOT, *, real: bool = False, **inputs: str
) -> subprocess.CompletedProcess[str]:
    """The Action's check step, run by bash as Actions runs it, with ``inputs``: its
    ``rprpr`` the console script pip installed (``real``: its interpreter's start-up
    included), else one whose runs are forked from this process (``run_served``)."""
    bash = shutil.which("bash")
    if bash is None:
        pytest.skip("bash is not installed")
    script = action["runs"]["steps"][2]["run"]
    env = env_without_colour(**{f"INPUT_{k.upper()}": v for k, v in inputs.items()})
    command = [bash, "--noprofile", "--norc", "-eo", "pipefail", "-c", script]
    if not real:
        return run_served(command, cwd=cwd, env=env)
    return subprocess.run(command, cwd=cwd, capture_output=True, text=True, env=env, check=False)


@pytest.mark.slow  # the Action's script, run by bash as Actions runs it
def test_action_by_default_checks_the_task_files_of_the_repository_only(
    action: dict[str, Any], tmp_path: Path
) -> None:
    (tmp_path / "docker-compose.yml").write_text("services: {}\n", encoding="utf-8")
    (tmp_path / "tasks").mkdir()
    shutil.copy(CONFIGS / "paper_path1.rprpr.yaml", tmp_path / "tasks" / "p1.rprpr.yaml")
    p = _run_check_step(action, tmp_path, real=True, paths="", strict="false", args="--samples 101")
    assert p.returncode == 1  # the task fails; docker-compose.yml is never read
    assert p.stdout.startswith("::error file=tasks/p1.rprpr.yaml,line=19,")
    assert "docker-compose" not in p.stdout + p.stderr


@pytest.mark.slow  # the Action's script, run by bash as Actions runs it
def test_action_check_step_annotates_and_fails_like_rprpr(action: dict[str, Any]) -> None:
    # newline- and space-separated
    paths = "configs/paper_path2.rprpr.yaml\n  configs/case1_crossing.rprpr.yaml"
    p = _run_check_step(action, paths=paths, strict="false", args="--samples 101")
    assert p.returncode == 1  # unbounded torques fail by default
    assert p.stdout.startswith("::error file=configs/case1_crossing.rprpr.yaml,line=")
    assert "title=RPR201 unbounded-torque::" in p.stdout
    assert len(p.stdout.splitlines()) == 1
    p = _run_check_step(action, paths=paths, strict="false", args="--warn-unbounded")
    assert p.returncode == 0
    assert p.stdout.startswith("::warning file=configs/case1_crossing.rprpr.yaml,line=")
    p = _run_check_step(action, paths=paths, strict="true", args="--warn-unbounded")
    assert p.returncode == 1
    assert p.stdout.startswith("::error file=configs/case1_crossing.rprpr.yaml,line=")


@pytest.mark.slow  # the Action's script, run by bash as Actions runs it
def test_action_check_step_rejects_a_bad_strict_and_never_globs(action: dict[str, Any]) -> None:
    p = _run_check_step(action, paths="configs", strict="maybe", args="")
    assert p.returncode == 2
    assert (
        p.stdout == "::error title=rprpr check::input strict must be true or false, not 'maybe'\n"
    )
    p = _run_check_step(action, paths="configs/*.yaml", strict="false", args="--samples 101")
    assert p.returncode == 2  # the literal name "configs/*.yaml": no such file
    assert p.stdout.startswith(
        "::error file=configs/*.yaml,title=RPR001 invalid-task::no such file"
    )


# -- README: rprpr in CI ------------------------------------------------------------
@pytest.fixture(scope="module")
def doc() -> str:
    return DOC.read_text(encoding="utf-8")


def test_doc_rule_table_lists_exactly_the_rules(doc: str) -> None:
    rows = re.findall(r"^\| `(RPR\d{3}) ([a-z-]+)` \| (always|strict) \|", doc, flags=re.M)
    assert [r[0] for r in rows] == list(RULES)
    for rid, name, fails in rows:
        assert name == RULES[rid].name
        assert (fails == "strict") is RULES[rid].strict_only
    assert set(re.findall(r"\bRPR\d{3}\b", doc)) == set(RULES)  # no stale id anywhere


def _yaml_blocks(doc: str) -> list[Any]:
    return [yaml.safe_load(b) for b in re.findall(r"```yaml\n(.*?)```", doc, flags=re.S)]


def test_doc_examples_are_valid_and_agree_with_the_files(
    doc: str, action: dict[str, Any], hook: dict[str, Any]
) -> None:
    blocks = [b for b in _yaml_blocks(doc) if isinstance(b, dict)]
    [workflow] = [b for b in blocks if "jobs" in b]
    [precommit] = [b for b in blocks if "repos" in b]
    [gitlab] = [b for b in blocks if "rprpr" in b]
    steps = workflow["jobs"]["rprpr"]["steps"]
    [uses] = [s for s in steps if s.get("uses", "").startswith("OWNER/rprpr@")]
    assert set(uses["with"]) <= set(action["inputs"])
    [repo] = precommit["repos"]
    assert [h["id"] for h in repo["hooks"]] == [hook["id"]]
    assert set(repo["hooks"][0]) == {"id"}  # the hook's own defaults select the task files
    job = gitlab["rprpr"]
    [check] = [c for c in job["script"] if c.startswith("rprpr check")]
    out = shlex.split(check)[shlex.split(check).index("-o") + 1]
    assert "--format junit" in check
    assert job["artifacts"]["reports"]["junit"] == out
    assert job["artifacts"]["when"] == "always"


# -- .ci/run and .pre-commit-config.yaml: CI runs what a contributor runs ---------------------
CI_RUN = ROOT / ".ci" / "run"
PRE_COMMIT_CONFIG = ROOT / ".pre-commit-config.yaml"
LINTERS = {"ruff check", "ruff format", "mypy"}


def _readme_test_command(doc: str) -> str:
    [command] = re.findall(r"^# set up and run the whole test suite.*\n(.+)$", doc, flags=re.M)
    return command  # type: ignore[no-any-return]


def _tool(argv: list[str]) -> str:
    """The linter an argument vector runs: ``ruff check``, ``ruff format`` or ``mypy``."""
    name = Path(argv[0]).name
    return f"{name} {argv[1]}" if name == "ruff" else name


def _ci_linters() -> dict[str, list[str]]:
    lines = CI_RUN.read_text(encoding="utf-8").splitlines()
    runs = [
        shlex.split(ln)
        for ln in lines
        if ln.startswith(".venv/bin/") and not ln.startswith(".venv/bin/python")
    ]
    return {_tool(argv): argv for argv in runs}


def test_ci_runs_the_readmes_test_command_verbatim_then_every_linter(doc: str) -> None:
    command = _readme_test_command(doc)
    assert ".[dev]" in command  # the linters come with the test set-up
    assert command.endswith('.venv/bin/python -m pytest -n auto -m "not slow"')
    lines = CI_RUN.read_text(encoding="utf-8").splitlines()
    assert command in lines
    # then the slow tests the README's command leaves out, and the lowest versions
    assert lines[lines.index(command) + 1] == ".venv/bin/python -m pytest -n auto -m slow"
    assert any("-c .ci/lowest.txt" in ln for ln in lines)
    linters = _ci_linters()
    assert set(linters) == LINTERS
    assert "--check" in linters["ruff format"]  # CI never rewrites a file
    assert linters["mypy"][-2:] == ["rprpr", "rprpr_cli"]


def test_pre_commit_runs_the_linters_ci_runs_from_the_venv() -> None:
    config = load(PRE_COMMIT_CONFIG)
    [repo] = config["repos"]
    assert repo["repo"] == "local"  # nothing to fetch: the hooks use .venv's pinned tools
    hooks = {h["id"]: h for h in repo["hooks"]}
    assert all(h["language"] == "system" for h in hooks.values())
    entries = {_tool(shlex.split(h["entry"])): shlex.split(h["entry"]) for h in hooks.values()}
    assert set(entries) == LINTERS
    assert all(argv[0].startswith(".venv/bin/") for argv in entries.values())
    ci = _ci_linters()
    # the same targets as CI: ruff on the files pre-commit passes, mypy on the packages
    assert [a for a in entries["mypy"] if not a.startswith("-")][1:] == ["rprpr", "rprpr_cli"]
    assert [a for a in ci["mypy"] if not a.startswith("-")][1:] == ["rprpr", "rprpr_cli"]
    assert hooks["mypy"]["pass_filenames"] is False


def test_the_license_file_is_the_mit_license_pyproject_names() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert project["license"] == {"text": "MIT"}
    text = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License\n\nCopyright (c) ")
    assert "the rprpr authors" in text.splitlines()[2]
    assert 'THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND' in text

"""README's examples, kept true: every block of README.md is executed, in the order a
reader meets them, in one fresh working directory that holds a copy of ``configs/`` (and
``tasks/``, ``more/plan.yaml``, the placeholder names of the CI examples, as copies of
passing shipped tasks):

* ```` ```console ````: ``$ rprpr ...`` commands, each followed by what it prints
  (standard output, then standard error), run with a plain terminal
  (``conftest.run_cli``); the output must match;
* ```` ```sh ````: every command line (``\\`` continues a line) must exit 0, or the status a
  trailing comment names (``# ... exit 1 ...``); an ``rprpr`` command without shell syntax
  runs in this process, anything else in ``bash`` with the virtual environment's ``bin``
  first on PATH. ``SKIP`` lists the few commands that are not run, each with why;
* ```` ```python ````: executed as a module of its own;
* ```` ```toml ````: a configuration file, named by its first line's comment, in a folder of
  its own: ``rprpr check --show-settings`` must take every key from it;
* ```` ```yaml ````: a task example (top-level keys among a task's) is read with
  ``parse_task``; a fragment is first put in place of the same keys of ``rprpr init``'s
  task (``motion`` replaces ``path`` and ``timing``). A block whose first line is
  ``# FILE, ...`` with FILE a task file of the working directory is an edit: its keys
  replace FILE's, as an editor would. Any other YAML (a CI file) must load.

Rewrite the console blocks after an intended change, and review the diff::

    .venv/bin/python -m tests.readme_examples
"""

from __future__ import annotations

import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import tomllib
import traceback
from collections.abc import Iterator
from contextlib import chdir
from dataclasses import dataclass, field
from pathlib import Path

import yaml

from .conftest import CONFIGS, ROOT, plain_terminal, run_cli

README = ROOT / "README.md"
BLOCK = re.compile(r"^```console\n(.*?)^```\n", re.S | re.M)
FENCE = re.compile(r"^( *)```(\w*)\n(.*?)^\1```\n", re.S | re.M)
TASK_KEYS = {"name", "robot", "path", "timing", "motion", "checks"}
EDIT = re.compile(r"# (\S+\.rprpr\.ya?ml),")
BIN = Path(sys.executable).parent  # where pip put the rprpr console script

# Commands of README's ```sh blocks that a test does not run, and why.
SKIP: dict[str, str] = {
    "python3 -m venv .venv && .venv/bin/pip install -q . && .venv/bin/rprpr check "
    "configs/paper_path2.rprpr.yaml": "installs from the network into a new virtual "
    "environment (the tests run in the one it made; its last step, rprpr check, is the "
    "tour's)",
    "python3 -m venv .venv && .venv/bin/pip install -q -e '.[dev]' && .venv/bin/python -m "
    'pytest -n auto -m "not slow"': "installs from the network, then runs the whole suite, "
    "this test with it; .ci/run runs it verbatim (tests/test_ci_files.py)",
    "python3 -m venv .venv && .venv/bin/pip install -q -e '.[dev]'": "installs from the network",
    '.venv/bin/python -m pytest -n auto -m "not slow"': "the whole suite, this test with it",
    ".venv/bin/python -m pytest -n auto -m slow": "the slow end-to-end tests (.ci/run runs them)",
    ".venv/bin/ruff check . && .venv/bin/ruff format --check .": "the linters of .ci/run "
    "(tests/test_ci_files.py pins them); lint is CI's job, not a test's",
    ".venv/bin/mypy rprpr rprpr_cli": "the type check of .ci/run (tests/test_ci_files.py "
    "pins it); minutes of work, CI's job",
    ".venv/bin/python -m tests.golden": "rewrites the golden files of the repository; "
    "tests/golden checks them",
    ".venv/bin/python benchmarks/bench_check.py": "measures wall-clock time, which no test asserts",
}


@dataclass(frozen=True)
class Example:
    command: str  # what follows "$ "
    output: str  # the lines after it, up to the next command or the block's end


@dataclass(frozen=True)
class Block:
    lang: str
    body: str  # dedented
    line: int  # of the opening fence, 1-based
    start: int  # offsets of the whole fenced block in README
    end: int

    @property
    def id(self) -> str:
        return f"README.md:{self.line} {self.lang or 'plain'}"


@dataclass
class Outcome:
    """What running a block gave: problems (empty: as documented), and for a console
    block each example as it runs now."""

    problems: list[str] = field(default_factory=list)
    fresh: list[Example] = field(default_factory=list)
    skipped: list[tuple[str, str]] = field(default_factory=list)


def blocks(text: str) -> list[Block]:
    out = []
    for m in FENCE.finditer(text):
        indent = len(m[1])
        body = "".join(ln[indent:] for ln in m[3].splitlines(keepends=True))
        out.append(Block(m[2], body, text.count("\n", 0, m.start()) + 1, m.start(), m.end()))
    return out


def examples(block: str) -> list[Example]:
    """The commands of a console block, each with its output."""
    out: list[Example] = []
    for line in block.splitlines(keepends=True):
        if line.startswith("$ "):
            out.append(Example(line[2:].rstrip("\n"), ""))
        elif out:
            out[-1] = Example(out[-1].command, out[-1].output + line)
    return out


def commands(block: str) -> list[str]:
    """The command lines of a sh block (continuations joined, comment lines left out)."""
    out: list[str] = []
    pending = ""
    for line in block.splitlines():
        if pending:
            line = pending + " " + line.strip()
            pending = ""
        if line.endswith("\\"):
            pending = line[:-1].rstrip()
        elif line.strip() and not line.lstrip().startswith("#"):
            out.append(line.strip())
    return out


def expected_status(command: str) -> int:
    comment = re.search(r"\s#.*\bexit (\d+)\b", command)
    return int(comment[1]) if comment else 0


def without_comment(command: str) -> str:
    return re.sub(r"\s+#[^'\"]*$", "", command)


def run(command: str) -> tuple[int, str]:
    """``command``'s exit status and what it printed (stdout, then stderr), from the
    working directory: an rprpr command line in this process, anything else in bash."""
    argv = shlex.split(command, comments=True)
    if argv and argv[0] == "rprpr" and not set(argv) & {"|", "&&", ";", ">", "<", "||"}:
        with plain_terminal():
            status, out, err = run_cli(*argv[1:])
        return status, out + err
    env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR")}
    env["PATH"] = f"{BIN}{os.pathsep}{env.get('PATH', '')}"
    p = subprocess.run(
        ["bash", "-c", command], capture_output=True, text=True, env=env, check=False
    )
    return p.returncode, p.stdout + p.stderr


def top_level(text: str) -> dict[str, tuple[int, int]]:
    """Each top-level key of a YAML mapping's text: its lines [start, end), trailing blank
    and comment lines left to the next key."""
    lines = text.splitlines(keepends=True)
    keys = [(i, m[1]) for i, ln in enumerate(lines) if (m := re.match(r"([A-Za-z_][\w-]*):", ln))]
    spans = {}
    for n, (i, key) in enumerate(keys):
        end = keys[n + 1][0] if n + 1 < len(keys) else len(lines)
        while end > i + 1 and (not lines[end - 1].strip() or lines[end - 1].startswith("#")):
            end -= 1
        spans[key] = (i, end)
    return spans


def replace_keys(base: str, fragment: str) -> str:
    """``base`` (a task's text) with the top-level keys of ``fragment`` in place of its own;
    a key ``base`` lacks is added at the end, ``motion`` drops ``path`` and ``timing``."""
    new = top_level(fragment)
    frag = fragment.splitlines(keepends=True)
    lines = base.splitlines(keepends=True)
    old = top_level(base)
    drop = {"path", "timing"} if "motion" in new else set()
    edits = []
    for key, (i, j) in old.items():
        if key in new:
            a, b = new[key]
            edits.append((i, j, frag[a:b]))
        elif key in drop:
            edits.append((i, j, []))
    for i, j, repl in sorted(edits, reverse=True):
        lines[i:j] = repl
    for key, (a, b) in new.items():
        if key not in old:
            lines += ["\n", *frag[a:b]]
    return "".join(lines)


def run_yaml(block: Block, here: Path) -> list[str]:
    from rprpr import TaskFileError, parse_task
    from rprpr.cli.init import TEMPLATE

    edit = EDIT.match(block.body)
    if edit and (here / edit[1]).is_file():
        target = here / edit[1]
        target.write_text(replace_keys(target.read_text("utf-8"), block.body), "utf-8")
        text, name = target.read_text("utf-8"), edit[1]
    else:
        doc = yaml.safe_load(block.body)
        if not (isinstance(doc, dict) and set(doc) <= TASK_KEYS):
            return [] if doc is not None else ["an empty YAML block"]
        text = block.body if {"robot", "path", "timing"} <= set(doc) else None
        text = text or replace_keys(TEMPLATE, block.body)
        name = "README-example.rprpr.yaml"
    try:
        parse_task(text, file=str(here / name))
    except TaskFileError as e:
        return [f"not a valid task: {e}"]
    return []


def run_toml(block: Block, here: Path) -> list[str]:
    """A configuration example, as its first line names it, in a folder of its own:
    ``rprpr check --show-settings`` takes every key from it."""
    name = block.body.split("\n", 1)[0].removeprefix("# ").strip()
    folder = here / f"toml-{block.line}"
    folder.mkdir()
    (folder / name).write_text(block.body, encoding="utf-8")
    doc = tomllib.loads(block.body)
    keys = doc["tool"]["rprpr"] if name == "pyproject.toml" else doc
    with chdir(folder):
        status, printed = run("rprpr check --show-settings")
    if status != 0:
        return [f"rprpr check --show-settings exited {status}:\n{printed}"]
    taken = re.findall(rf"^(\w+) += .*  # {re.escape(str(folder / name))}$", printed, re.M)
    return [] if taken == list(keys) else [f"{name}: keys {list(keys)}, taken {taken}"]


def run_block(block: Block, here: Path) -> Outcome:
    got = Outcome()
    try:
        if block.lang == "console":
            for e in examples(block.body):
                argv = shlex.split(e.command)
                assert argv[0] == "rprpr", f"not an rprpr command: {e.command}"
                _, printed = run(e.command)
                if printed and not printed.endswith("\n"):
                    printed += "\n"  # a block's lines end: a missing last newline is shown
                got.fresh.append(Example(e.command, printed))
                if printed != e.output:
                    got.problems.append(f"`{e.command}` prints otherwise now")
        elif block.lang == "sh":
            for command in commands(block.body):
                if without_comment(command) in SKIP:
                    got.skipped.append((without_comment(command), SKIP[without_comment(command)]))
                    continue
                status, printed = run(without_comment(command))
                if status != expected_status(command):
                    got.problems.append(f"`{command}` exited {status}:\n{printed}")
        elif block.lang == "python":
            code = compile(block.body, f"README.md:{block.line}", "exec")
            exec(code, {"__name__": "__readme__"})
        elif block.lang == "yaml":
            got.problems += run_yaml(block, here)
        elif block.lang == "toml":
            got.problems += run_toml(block, here)
    except Exception:
        got.problems.append(traceback.format_exc())
    return got


def workspace(here: Path) -> None:
    """A fresh clone's view: configs/, and the CI examples' placeholder paths."""
    shutil.copytree(CONFIGS, here / "configs")
    (here / "tasks").mkdir()
    (here / "more").mkdir()
    for name in ("paper_path2.rprpr.yaml", "waypoints.rprpr.yaml"):
        shutil.copy(CONFIGS / name, here / "tasks" / name)
    shutil.copy(CONFIGS / "paper_path2.rprpr.yaml", here / "more" / "plan.yaml")


def session(text: str, here: Path) -> Iterator[tuple[Block, Outcome]]:
    """Every block of ``text`` run in order in the empty directory ``here``."""
    workspace(here)
    with chdir(here):
        for block in blocks(text):
            yield block, run_block(block, here)


def regenerate() -> bool:
    """Rewrite every console block with what rprpr prints now; whether anything changed."""
    text = README.read_text(encoding="utf-8")
    with tempfile.TemporaryDirectory() as tmp:
        done = [(b, o) for b, o in session(text, Path(tmp)) if b.lang == "console"]
    new = text
    for block, outcome in reversed(done):
        body = "".join(f"$ {e.command}\n{e.output}" for e in outcome.fresh)
        new = new[: block.start] + f"```console\n{body}```\n" + new[block.end :]
    if new != text:
        README.write_text(new, encoding="utf-8")
    return new != text


if __name__ == "__main__":
    print("README.md rewritten" if regenerate() else "README.md examples are up to date")

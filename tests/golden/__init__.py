"""Golden files: what ``rprpr check`` prints, byte for byte, in every output format.

Each case is one ``rprpr check`` command line (a shipped config, the configs/ directory at
once, a run with bad task files, two close singular instants). Each is run once per
variant: the text report at 80 and at 160 columns (no colour: standard output is not a
terminal), the concise findings, JSON, JUnit (its measured ``time=`` attributes zeroed),
GitHub annotations, SARIF, GitLab Code Quality and the HTML page (without its sheets).
``tests/golden/CASE/VARIANT.EXT`` holds the standard output, ``tests/golden/CASE/runs.txt``
the command lines, exit statuses and standard error.

Regenerate every file after an intended change, and review the diff like code::

    .venv/bin/python -m tests.golden
"""

from __future__ import annotations

import re
import tempfile
from collections.abc import Iterator
from contextlib import chdir, contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from ..conftest import CLOSE_INSTANTS, CONFIGS, ROOT, plain_terminal, reused_runs, run_cli

GOLDEN = Path(__file__).resolve().parent
REGENERATE = ".venv/bin/python -m tests.golden"


@dataclass(frozen=True)
class Variant:
    """One output format: ``check``'s extra arguments, the environment, the file suffix."""

    name: str
    args: tuple[str, ...]
    env: dict[str, str] = field(default_factory=dict)
    suffix: str = "txt"

    @property
    def file(self) -> str:
        return f"{self.name}.{self.suffix}"


# every format with --peak (the certified torque peak computed: these files are byte for
# byte what rprpr printed before the peak became a thing asked for), then the default
# run, in which the peak is not computed (no verdict needs it), in the formats that
# print it (text, JSON, JUnit; the others print findings only)
VARIANTS = (
    Variant("text-60", ("--format", "text", "--peak"), {"COLUMNS": "60"}),
    Variant("text-80", ("--format", "text", "--peak"), {"COLUMNS": "80"}),
    Variant("text-120", ("--format", "text", "--peak"), {"COLUMNS": "120"}),
    Variant("text-160", ("--format", "text", "--peak"), {"COLUMNS": "160"}),
    Variant("json", ("--format", "json", "--peak"), suffix="json"),
    Variant("junit", ("--format", "junit", "--peak"), suffix="xml"),
    Variant("github", ("--format", "github", "--peak")),
    Variant("concise", ("--output-format", "concise")),
    Variant("sarif", ("--format", "sarif", "--peak"), suffix="json"),
    Variant("gitlab", ("--format", "gitlab", "--peak"), suffix="json"),
    Variant("default-text-80", (), {"COLUMNS": "80"}),
    Variant("default-json", ("--format", "json"), suffix="json"),
    Variant("default-junit", ("--format", "junit"), suffix="xml"),
    Variant("default-github", ("--format", "github")),
    # the page without its sheets: matplotlib's SVG is not the same bytes from one
    # matplotlib to the next (tests/render/test_html.py checks the sheets' structure)
    Variant("html", ("--format", "html", "--no-sheets"), suffix="html"),
)


@dataclass(frozen=True)
class Case:
    """``rprpr check TASKS``, run from the repository's root, or from a fresh temporary
    directory holding ``files`` (name: text) when there are any."""

    name: str
    tasks: tuple[str, ...]
    files: dict[str, str] = field(default_factory=dict)


# four independent mistakes in one file (a1 < 0, a negative mass, a text for a number, a
# misspelt key): every one is reported, in the order of the file, in one run
MANY_ERRORS = """\
name: four mistakes
robot:
  a1: -6
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: -1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
path:
  y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2
  from: [2, -1]
  to: 4
timing:
  duration: five
  lwa: quintic
"""

CASES = (
    *(Case(p.name.split(".")[0], (f"configs/{p.name}",)) for p in sorted(CONFIGS.glob("*.yaml"))),
    Case("configs_directory", ("configs",)),
    Case(
        "bad_tasks",
        (
            "configs/paper_path2.rprpr.yaml",
            "tests/corpora/bad_tasks/a1_negative.yaml",
            "tests/corpora/bad_tasks/syntax_unclosed_flow.yaml",
        ),
    ),
    Case("close_instants", ("close_instants.yaml",), {"close_instants.yaml": CLOSE_INSTANTS}),
    Case("many_errors", ("many_errors.yaml",), {"many_errors.yaml": MANY_ERRORS}),
)


def untimed(junit: str) -> str:
    """JUnit XML with its measured times zeroed (the only part that differs run to run)."""
    return re.sub(r' time="[0-9.]+"', ' time="0"', junit)


@contextmanager
def _working_directory(case: Case) -> Iterator[None]:
    """The repository's root, or a temporary directory holding the case's files."""
    if not case.files:
        with chdir(ROOT):
            yield
        return
    with tempfile.TemporaryDirectory() as tmp, chdir(tmp):
        for name, text in case.files.items():
            Path(name).write_text(text, encoding="utf-8")
        yield


def _command(case: Case, variant: Variant) -> str:
    env = "".join(f"{k}={v} " for k, v in variant.env.items())
    return " ".join([f"$ {env}rprpr check", *variant.args, *case.tasks])


def render(case: Case) -> dict[str, str]:
    """The golden files of ``case``: file name -> text, as rprpr prints them today (the
    tasks audited once, printed in every variant)."""
    files: dict[str, str] = {}
    runs: list[str] = []
    with _working_directory(case), reused_runs():
        for variant in VARIANTS:
            with plain_terminal(**variant.env):
                code, out, err = run_cli("check", *variant.args, *case.tasks)
            files[variant.file] = untimed(out) if variant.name.endswith("junit") else out
            runs.append(f"{_command(case, variant)}\nexit status {code}\n{err}")
    files["runs.txt"] = "\n".join(runs)
    return files


def case_dir(case: Case) -> Path:
    return GOLDEN / case.name

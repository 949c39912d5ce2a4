"""The conventions of a command-line tool: -V, a --help that lists every command without
importing it, ``rprpr rule``, ``rprpr init``, ``-`` for standard input."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
from pathlib import Path

import click
import pytest

from rprpr._version import __version__
from rprpr.cli.main import COMMANDS, main_group, run
from rprpr.cli.rule import explain
from rprpr.model.rules import RULES
from tests.cli.forked import fresh_probe
from tests.conftest import PATH2_FILE, ROOT, run_cli


def test_short_version_flag() -> None:
    assert run_cli("-V") == (0, f"rprpr, version {__version__}\n", "")


def test_help_lists_every_command_with_its_own_help() -> None:
    code, out, _ = run_cli("--help")
    assert code == 0
    for name, summary in COMMANDS.items():
        cmd = main_group.get_command(click.Context(main_group), name)
        assert cmd is not None and cmd.help is not None
        assert " ".join(cmd.help.split()).startswith(summary), name
        assert f"  {name}" in out and summary in out


def test_version_and_help_import_no_command_module(
    probed: dict[str, tuple[int, str, str]],
) -> None:
    _, _, stderr = probed["help"]
    loaded = eval(stderr.strip().splitlines()[-1])
    assert not set(loaded) & {f"rprpr.cli.{c}" for c in COMMANDS}


def test_rule_lists_and_explains_every_rule() -> None:
    code, out, _ = run_cli("rule")
    assert code == 0 and [ln.split()[0] for ln in out.splitlines()] == list(RULES)
    for rule in RULES.values():
        code, out, _ = run_cli("rule", rule.id.lower())
        assert code == 0 and out == "\n".join(explain(rule)) + "\n"
        assert out.startswith(f"{rule.id} {rule.name}\n")
        assert rule.fix in out and rule.meaning in out
    _, out, _ = run_cli("rule", "unbounded-torque")
    assert "Paper: eqs. (30)-(36)" in out and "RPR201: <why" in out
    assert "checks.unbounded_torque: warn" in out


def test_an_unknown_rule_is_a_usage_error_with_the_closest() -> None:
    code, out, err = run_cli("rule", "RPR2011")
    assert code == 2 and out == ""
    assert err.strip() == (
        "rprpr: usage error: unknown rule 'RPR2011' (did you mean RPR201?); `rprpr rule` lists them"
    )


def test_init_writes_the_papers_example_2_which_passes(tmp_path: Path) -> None:
    target = tmp_path / "task.rprpr.yaml"
    code, out, err = run_cli("init", str(tmp_path))
    assert code == 0 and out == "" and f"wrote {target}" in err
    text = target.read_text(encoding="utf-8")
    assert text.startswith("# yaml-language-server: $schema=")
    assert "0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2" in text  # eq. (51)
    code, out, _ = run_cli("check", "--isolated", "--format", "json", str(tmp_path))
    [report] = json.loads(out)["reports"]
    assert code == 0 and report["verdict"] == "pass"
    [s] = report["singularities"]
    assert (s["t"], s["x"], s["order"], s["slope"]) == (2.5, 3.0, 1, pytest.approx(0.2))


def test_init_never_overwrites(tmp_path: Path) -> None:
    target = tmp_path / "mine.rprpr.yaml"
    target.write_text("keep me\n", encoding="utf-8")
    code, _out, err = run_cli("init", str(target))
    assert code == 2 and err.strip() == f"rprpr: {target} already exists: not overwritten"
    assert target.read_text(encoding="utf-8") == "keep me\n"


def test_init_to_standard_output() -> None:
    from rprpr.cli.init import TEMPLATE

    assert run_cli("init", "-") == (0, TEMPLATE, "")


def test_a_task_on_standard_input(monkeypatch: pytest.MonkeyPatch) -> None:
    data = Path(PATH2_FILE).read_bytes()
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data)))
    code, out, _ = run_cli("check", "--format", "json", "--stdin-filename", "p2.rprpr.yaml", "-")
    [report] = json.loads(out)["reports"]
    assert code == 0 and report["task"] == "p2.rprpr.yaml" and report["verdict"] == "pass"
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"robot: [\n")))
    code, out, err = run_cli("check", "-")
    assert code == 2 and err.startswith("-:")


def test_a_missing_library_is_named_not_an_internal_error(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "flint" else real(name, *a)
    )
    code, out, err = run_cli("check", PATH2_FILE)
    assert code == 2 and out == ""
    assert err.startswith("rprpr: python-flint not installed for ")
    assert "internal error" not in err


PROGRAM = "import atexit, sys\natexit.register(lambda: print('teardown ran', file=sys.stderr))\n"
ENDS = [
    (
        ["check", "--format", "json", PATH2_FILE, str(ROOT / "configs/case1_crossing.rprpr.yaml")],
        1,
    ),
    (["check", "--format", "github", PATH2_FILE], 0),
    (["rule", "RPR9"], 2),
]


# Fresh processes, each forked from the suite's one prober (``tests.cli.forked.fresh_probe``,
# read through the session fixture ``fresh``): ``--help`` from a bare start, and the program
# (``run``) on each of ENDS once the prober has imported rprpr's dependencies (their
# start-up paid once).
fresh_probe(
    "test_main help",
    "",
    "import sys\nfrom rprpr.cli.main import main\n"
    "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
    "print(sorted(m for m in sys.modules if m.startswith('rprpr.cli.')), file=sys.stderr)",
    ROOT,
)
for _args, _ in ENDS:
    fresh_probe(
        f"test_main {_args!r}",
        "numpy, flint, yaml, click, rich.console",
        PROGRAM + f"from rprpr.cli.main import run\nsys.argv = ['rprpr', *{_args!r}]\nrun()\n",
        ROOT,
    )


@pytest.fixture
def probed(fresh: dict[str, tuple[int, str, str]]) -> dict[str, tuple[int, str, str]]:
    """The probes above: (exit status, standard output, standard error) by name here."""
    return {k.removeprefix("test_main "): v for k, v in fresh.items()}


@pytest.mark.parametrize(("args", "status"), ENDS)
def test_the_program_ends_once_its_output_is_out_with_mains_status_and_bytes(
    args: list[str], status: int, probed: dict[str, tuple[int, str, str]]
) -> None:
    """``run`` (the console script, ``python -m rprpr``) flushes the standard streams and
    ends the process without the interpreter's teardown (an atexit hook never runs);
    what it wrote and its status are ``main``'s in this process."""
    returncode, stdout, stderr = probed[repr(args)]
    assert (returncode, stdout, stderr) == run_cli(*args)
    assert "teardown ran" not in stderr


fresh_probe(
    "test_main multiprocessing",
    "",
    PROGRAM + "import multiprocessing\nfrom rprpr.cli.main import run\n"
    "sys.argv = ['rprpr', 'rule', 'RPR101']\nrun()\n",
    ROOT,
)


def test_with_multiprocessing_loaded_the_program_takes_the_ordinary_exit(
    probed: dict[str, tuple[int, str, str]],
) -> None:
    """Where the workers are spawned by multiprocessing (off Linux), its shared memory may
    live in a temporary folder that its exit handler removes: ``run`` then leaves the
    process to the ordinary exit, and the handlers run."""
    done = subprocess.CompletedProcess("probe", *probed["multiprocessing"])
    assert (done.returncode, done.stdout) == run_cli("rule", "RPR101")[:2]
    assert "teardown ran" in done.stderr


def test_a_failed_flush_at_the_end_takes_the_ordinary_exit(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Standard output that cannot be flushed when the command is done: ``run`` leaves the
    process to the ordinary exit (which reports the failed flush), with main's status."""

    class Full(io.StringIO):
        def flush(self) -> None:
            raise OSError(28, "No space left on device")

    ended: list[int] = []
    monkeypatch.setattr(os, "_exit", ended.append)
    monkeypatch.setattr(sys, "argv", ["rprpr", "rule", "RPR101"])
    monkeypatch.setattr(sys, "stdout", Full())
    with pytest.raises(SystemExit) as e:
        run()
    assert ended == [] and e.value.code == 2

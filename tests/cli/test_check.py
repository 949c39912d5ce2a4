"""``rprpr check`` as CI runs it: many tasks, bad files among them, exit codes, -j, -q,
--exit-zero, -o, the progress bar and colour."""

from __future__ import annotations

import functools
import importlib.util
import json
import os
import pty
import re
import select
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

from rprpr.cli.check import PROGRESS_MIN_TASKS, want_progress
from rprpr.cli.output import color_enabled, make_console
from rprpr.cli.tasks import collect_tasks
from tests.cli.forked import Forked, rprpr_main
from tests.conftest import (
    BAD_A1,
    CONFIGS,
    FAST,
    PATH1_YAML,
    PATH2_YAML,
    QUINTIC,
    ROOT,
    reused_runs,
    run_cli,
    task_text,
)

ANSI = "\x1b["


@pytest.fixture
def mixed(tmp_path: Path) -> Path:
    """A folder of tasks: the configs, a bad file, a nested .yml, hidden files and dirs."""
    root = tmp_path / "tasks"
    shutil.copytree(CONFIGS, root / "configs")
    (root / "b_bad.rprpr.yaml").write_text(BAD_A1, encoding="utf-8")
    (root / "docker-compose.yml").write_text("services: {}\n", encoding="utf-8")  # no task
    (root / "nested" / "deeper").mkdir(parents=True)
    (root / "nested" / "deeper" / "p2.rprpr.yml").write_text(
        task_text(PATH2_YAML, QUINTIC), encoding="utf-8"
    )
    (root / "nested" / "notes.txt").write_text("not a task", encoding="utf-8")
    (root / ".hidden").mkdir()
    (root / ".hidden" / "x.rprpr.yaml").write_text(BAD_A1, encoding="utf-8")
    (root / ".gitlab-ci.yml").write_text("stages: [test]\n", encoding="utf-8")
    return root


# -- discovery -------------------------------------------------------------------------
def test_directories_are_searched_recursively_sorted_skipping_hidden(mixed: Path) -> None:
    found = [Path(f).relative_to(mixed).as_posix() for f in collect_tasks([str(mixed)])]
    configs = sorted(p.name for p in CONFIGS.glob("*.yaml"))
    assert found == [
        "b_bad.rprpr.yaml",
        *(f"configs/{c}" for c in configs),
        "nested/deeper/p2.rprpr.yml",
    ]


def test_files_keep_their_order_and_are_checked_once(mixed: Path) -> None:
    p2 = str(mixed / "configs" / "paper_path2.rprpr.yaml")
    files = collect_tasks([p2, str(mixed / "configs"), "./" + os.path.relpath(p2)])
    assert files[0] == p2
    assert len(files) == len(collect_tasks([str(mixed / "configs")]))
    assert files.count(p2) == 1


def test_an_explicit_file_is_checked_whatever_its_suffix(tmp_path: Path) -> None:
    p = tmp_path / "task.txt"
    p.write_text(task_text(PATH2_YAML, QUINTIC), encoding="utf-8")
    assert collect_tasks([str(p)]) == [str(p)]


def test_no_task_found_is_a_usage_error(tmp_path: Path) -> None:
    (tmp_path / "readme.txt").write_text("x", encoding="utf-8")
    code, out, err = run_cli("check", str(tmp_path))
    assert code == 2
    assert out == ""
    assert err.strip() == (
        f"rprpr: usage error: no task files (*.rprpr.yaml, *.rprpr.yml) found in {tmp_path}"
    )
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["check", "--isolated", "tests/golden"], "no task files"),
        (["check", "--format", "xml", "configs"], "'xml' is not one of"),
        (["check", "-j", "-1", "configs"], "-1 is not in the range"),
        (["check", "--samples", "1", "configs"], "1 is not in the range"),
    ],
)
def test_bad_invocations_exit_2_with_one_line(args: list[str], needle: str) -> None:
    code, out, err = run_cli(*args)
    assert code == 2
    assert out == ""
    assert err.startswith("rprpr: usage error: ")
    assert needle in err
    assert len(err.strip().splitlines()) == 1


def test_an_unwritable_output_file_is_a_usage_error_before_auditing(tmp_path: Path) -> None:
    target = tmp_path / "missing" / "report.json"
    code, out, err = run_cli("check", "-o", str(target), str(CONFIGS / "paper_path2.rprpr.yaml"))
    assert code == 2
    assert out == ""
    assert err.strip() == (
        f"rprpr: usage error: cannot write the output file {target}: No such file or directory"
    )


# -- one bad file never stops the others; the highest status wins ------------------------
def test_a_bad_file_is_reported_and_the_others_still_run(mixed: Path) -> None:
    code, out, err = run_cli("check", "--format", "json", *FAST, str(mixed))
    assert code == 2  # input error (2) beats the failing tasks (1)
    doc = json.loads(out)
    n_configs = len(list(CONFIGS.glob("*.yaml")))
    assert doc["summary"]["tasks"] == n_configs + 2
    assert doc["summary"]["errors"] == 1
    assert doc["summary"]["passed"] + doc["summary"]["failed"] == n_configs + 1
    assert len(doc["reports"]) == n_configs + 1
    [bad] = doc["input_errors"]
    assert bad["task"] == str(mixed / "b_bad.rprpr.yaml")
    assert (bad["line"], bad["column"], bad["key"], bad["rule"]) == (3, 7, "robot.a1", "RPR001")
    # the one-line error also reaches stderr for the log, naming file, line and key
    assert err == f"{mixed / 'b_bad.rprpr.yaml'}:3:7: robot.a1: {bad['message']} [RPR001]\n"


def _write(tmp_path: Path, **files: str) -> list[str]:
    out = []
    for name, text in files.items():
        p = tmp_path / f"{name}.yaml"
        p.write_text(text, encoding="utf-8")
        out.append(str(p))
    return out


@pytest.mark.parametrize(
    ("kinds", "expected"),
    [
        (("pass",), 0),
        (("pass", "fail"), 1),
        (("fail", "bad", "pass"), 2),
        (("bad",), 2),
    ],
)
def test_exit_status_is_the_highest_that_applies(
    tmp_path: Path, kinds: tuple[str, ...], expected: int
) -> None:
    texts = {
        "pass": task_text(PATH2_YAML, QUINTIC),
        "fail": task_text(PATH1_YAML, QUINTIC),
        "bad": BAD_A1,
    }
    files = _write(tmp_path, **{f"{i}_{k}": texts[k] for i, k in enumerate(kinds)})
    for fmt in ("text", "json", "junit", "github"):
        code, _, _ = run_cli("check", "--format", fmt, *FAST, *files)
        assert code == expected, fmt


def test_an_internal_error_exits_3_and_the_other_tasks_still_run(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    import rprpr.engine.audit

    real = rprpr.engine.audit.audit

    def flaky(task: Any, **kw: Any) -> Any:
        if task.name == "boom":
            raise RuntimeError("simulated bug")
        return real(task, **kw)

    monkeypatch.setattr(rprpr.engine.audit, "audit", flaky)
    boom = task_text(PATH2_YAML, QUINTIC).replace("name: test", "name: boom")
    files = _write(tmp_path, a=boom, b=task_text(PATH1_YAML, QUINTIC), c=BAD_A1)
    code, out, err = run_cli("check", "--format", "json", *FAST, *files)
    assert code == 3
    doc = json.loads(out)
    assert doc["summary"] == {"tasks": 3, "passed": 0, "failed": 1, "errors": 2}
    [internal] = doc["internal_errors"]
    assert internal["task"] == files[0]
    assert internal["message"] == "RuntimeError: simulated bug"
    assert "Traceback" in internal["traceback"]
    assert err.splitlines()[-1].startswith(
        f"{files[0]}: internal error (RuntimeError: simulated bug)"
    )
    assert "Traceback" not in err
    monkeypatch.setenv("RPRPR_DEBUG", "1")  # the traceback, for a bug report
    _, _, err = run_cli("check", "--format", "json", *FAST, *files)
    assert "Traceback (most recent call last)" in err
    assert "RuntimeError: simulated bug" in err


def test_exit_zero_hides_failures_but_not_errors(tmp_path: Path) -> None:
    [fail] = _write(tmp_path, fail=task_text(PATH1_YAML, QUINTIC))
    assert run_cli("check", *FAST, fail)[0] == 1
    code, out, _ = run_cli("check", "--exit-zero", *FAST, fail)
    assert code == 0
    assert "verdict: FAIL" in out  # still reported
    [bad] = _write(tmp_path, bad=BAD_A1)
    assert run_cli("check", "--exit-zero", *FAST, fail, bad)[0] == 2


def test_unbounded_torque_fails_unless_accepted_and_strict_fails_it_again(tmp_path: Path) -> None:
    case1 = str(CONFIGS / "case1_crossing.rprpr.yaml")  # inconsistent crossing: RPR201
    code, out, _ = run_cli("check", "--format", "github", *FAST, case1)
    assert code == 1
    assert out.startswith("::error file=")
    assert "title=RPR201 unbounded-torque::" in out
    code, out, _ = run_cli("check", "--format", "github", "--warn-unbounded", *FAST, case1)
    assert code == 0
    assert out.startswith("::warning file=")
    code, out, _ = run_cli("check", "--format", "github", "--strict", "--warn-unbounded", case1)
    assert code == 1
    assert out.startswith("::error file=")
    # the task file's own key accepts it too; the flag wins over "fail"
    text = (CONFIGS / "case1_crossing.rprpr.yaml").read_text(encoding="utf-8")
    warn, fail = tmp_path / "warn.yaml", tmp_path / "fail.yaml"
    warn.write_text(text + "checks:\n  unbounded_torque: warn\n", encoding="utf-8")
    fail.write_text(text + "checks:\n  unbounded_torque: fail\n", encoding="utf-8")
    assert run_cli("check", "--format", "github", str(warn))[0] == 0
    assert run_cli("check", "--format", "github", str(fail))[0] == 1
    assert run_cli("check", "--format", "github", "--warn-unbounded", str(fail))[0] == 0


# -- -q/--quiet --------------------------------------------------------------------------
def test_quiet_text_shows_only_failures_and_errors(tmp_path: Path) -> None:
    files = _write(
        tmp_path,
        a_pass=task_text(PATH2_YAML, QUINTIC),
        b_fail=task_text(PATH1_YAML, QUINTIC),
        c_bad=BAD_A1,
    )
    code, out, err = run_cli("check", "-q", *FAST, *files)
    assert code == 2
    assert files[0] not in out
    assert f"{files[1]} — test" in out
    assert out.count("verdict:") == 1
    assert out.splitlines()[-1] == "3 tasks: 1 passed, 1 failed, 1 error"
    assert err == f"{files[2]}:3:7: robot.a1: {_bad_message()} [RPR001]\n"


def _bad_message() -> str:
    from rprpr.io.loader import parse_task
    from rprpr.model.errors import TaskFileError

    with pytest.raises(TaskFileError) as e:
        parse_task(BAD_A1)
    return e.value.message


def test_quiet_with_everything_passing_prints_nothing(tmp_path: Path) -> None:
    files = _write(tmp_path, a=task_text(PATH2_YAML, QUINTIC), b=task_text(PATH2_YAML, QUINTIC))
    assert run_cli("check", "-q", *FAST, *files) == (0, "", "")
    assert run_cli("check", "-q", "--format", "github", *FAST, *files) == (0, "", "")


def test_quiet_json_keeps_the_counts_of_every_task(tmp_path: Path) -> None:
    files = _write(tmp_path, a=task_text(PATH2_YAML, QUINTIC), b=task_text(PATH1_YAML, QUINTIC))
    code, out, _ = run_cli("check", "-q", "--format", "json", *FAST, *files)
    doc = json.loads(out)
    assert code == 1
    assert [r["task"] for r in doc["reports"]] == [files[1]]
    assert doc["summary"] == {"tasks": 2, "passed": 1, "failed": 1, "errors": 0}


def test_quiet_github_drops_warnings_only() -> None:
    p1 = str(CONFIGS / "paper_path1.rprpr.yaml")  # RPR101 error + RPR201 accepted: a warning
    _, out, _ = run_cli("check", "--format", "github", "--warn-unbounded", p1)
    assert [line.split(" ", 1)[0] for line in out.splitlines()] == ["::error", "::warning"]
    _, out, _ = run_cli("check", "-q", "--format", "github", "--warn-unbounded", p1)
    assert [line.split(" ", 1)[0] for line in out.splitlines()] == ["::error"]


# -- -o/--output-file ----------------------------------------------------------------------
@pytest.mark.parametrize("fmt", ["text", "json", "junit", "github"])
def test_output_file_holds_what_stdout_would(tmp_path: Path, fmt: str) -> None:
    files = [str(CONFIGS / "paper_path1.rprpr.yaml"), str(CONFIGS / "paper_path2.rprpr.yaml")]
    code, out, err = run_cli("check", "--format", fmt, *FAST, *files)
    target = tmp_path / f"report.{fmt}"
    code2, out2, err2 = run_cli("check", "--format", fmt, "-o", str(target), *FAST, *files)
    assert (code, code2) == (1, 1)
    assert (out2, err) == ("", "")
    summary = f"rprpr: 2 tasks: 1 passed, 1 failed, 0 errors; {fmt} report written to {target}"
    assert err2 == summary + "\n"
    assert _untimed(target.read_text(encoding="utf-8")) == _untimed(out)


def test_text_output_file_also_lists_bad_files(tmp_path: Path) -> None:
    files = _write(tmp_path, a=task_text(PATH2_YAML, QUINTIC), b=BAD_A1)
    target = tmp_path / "report.txt"
    code, out, err = run_cli("check", "-o", str(target), *FAST, *files)
    line = f"{files[1]}:3:7: robot.a1: {_bad_message()} [RPR001]"
    assert code == 2
    assert out == ""
    assert err.splitlines() == [
        line,
        f"rprpr: 2 tasks: 1 passed, 0 failed, 1 error; text report written to {target}",
    ]
    report = target.read_text(encoding="utf-8").splitlines()
    assert line in report
    assert report[-1] == "2 tasks: 1 passed, 0 failed, 1 error"
    assert ANSI not in target.read_text(encoding="utf-8")


# -- -j: the same report whatever the number of workers --------------------------------------
def _untimed(text: str) -> str:
    """JUnit with its measured times zeroed (the only part that may differ)."""
    return re.sub(r'time="[0-9.]+"', 'time="0"', text)


def _bench() -> ModuleType:
    spec = importlib.util.spec_from_file_location(
        "bench_many", ROOT / "benchmarks" / "bench_many.py"
    )
    assert spec and spec.loader
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def varied(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """48 varied task files from the benchmark's generator (all kinds, a bad one too)."""
    folder = tmp_path_factory.mktemp("varied")
    counts = _bench().generate(folder, 48, seed=7)
    assert len(counts) >= 8  # many kinds of task
    (folder / "zz_bad.rprpr.yaml").write_text(BAD_A1, encoding="utf-8")
    return folder


@pytest.mark.parametrize("fmt", ["json", "junit", "github", "text"])
def test_parallel_output_is_byte_for_byte_the_serial_output(varied: Path, fmt: str) -> None:
    # one serial and one parallel run of the tasks, each printed in every format
    with reused_runs():
        serial = run_cli("check", "--format", fmt, *FAST, "-j", "1", str(varied))
        parallel = run_cli("check", "--format", fmt, *FAST, "-j", "2", str(varied))
    assert serial[0] == parallel[0] == 2
    assert serial[2] == parallel[2]
    if fmt == "junit":  # the measured times differ; everything else must not
        assert _untimed(parallel[1]) == _untimed(serial[1])
        assert len(re.findall(r'time="', serial[1])) == 2 + 49
    else:
        assert parallel[1] == serial[1]
    assert len(serial[1]) > 1000


def test_jobs_zero_means_one_worker_per_cpu() -> None:
    a = run_cli("check", "--format", "json", *FAST, str(CONFIGS))
    b = run_cli("check", "--format", "json", *FAST, "-j", "0", str(CONFIGS))
    assert a == b


# -- colour and the progress bar -------------------------------------------------------------
class _Stream:
    def __init__(self, tty: bool) -> None:
        self.tty = tty

    def isatty(self) -> bool:
        return self.tty


@pytest.mark.parametrize(
    ("color", "env", "tty", "expected"),
    [
        ("auto", {}, True, True),
        ("auto", {}, False, False),
        ("auto", {"NO_COLOR": "1"}, True, False),
        ("auto", {"NO_COLOR": ""}, True, True),  # empty means unset (no-color.org)
        ("auto", {"FORCE_COLOR": "1"}, False, True),
        ("auto", {"FORCE_COLOR": "1", "NO_COLOR": "1"}, False, False),
        ("auto", {"TERM": "dumb"}, True, False),
        ("always", {"NO_COLOR": "1"}, False, True),
        ("never", {"FORCE_COLOR": "1"}, True, False),
    ],
)
def test_color_policy(color: str, env: dict[str, str], tty: bool, expected: bool) -> None:
    assert color_enabled(color, _Stream(tty), env) is expected


def test_console_without_colour_writes_no_escape_codes() -> None:
    import io

    from rich.text import Text

    buf = io.StringIO()
    make_console(buf, False, {}).print(Text("FAIL", style="bold red"))
    assert buf.getvalue() == "FAIL\n"
    buf = io.StringIO()
    make_console(buf, True, {}).print(Text("FAIL", style="bold red"))
    assert buf.getvalue() == "\x1b[1;31mFAIL\x1b[0m\n"


@pytest.mark.parametrize(
    ("env", "args", "colored"),
    [
        ({}, [], False),  # stdout is not a terminal here
        ({"FORCE_COLOR": "1"}, [], True),
        ({"FORCE_COLOR": "1", "NO_COLOR": "1"}, [], False),
        ({"NO_COLOR": "1"}, ["--color", "always"], True),
        ({"FORCE_COLOR": "1"}, ["--color", "never"], False),
    ],
)
def test_text_report_colour_follows_the_environment(
    monkeypatch: pytest.MonkeyPatch,
    env: dict[str, str],
    args: list[str],
    colored: bool,
) -> None:
    for k, v in env.items():
        monkeypatch.setenv(k, v)
    code, out, _ = run_cli("check", *args, *FAST, str(CONFIGS / "paper_path1.rprpr.yaml"))
    assert code == 1
    assert (ANSI in out) is colored
    assert "verdict: FAIL" in re.sub(r"\x1b\[[0-9;]*m", "", out)


def test_progress_only_on_a_terminal_for_more_than_a_handful() -> None:
    n = PROGRESS_MIN_TASKS
    assert want_progress(n + 1, _Stream(True), quiet=False)
    assert not want_progress(n, _Stream(True), quiet=False)
    assert not want_progress(n + 1, _Stream(False), quiet=False)
    assert not want_progress(n + 1, _Stream(True), quiet=True)


def _run_with_ptys(
    args: list[str], *, stdout_tty: bool, stderr_tty: bool, env: dict[str, str], fresh: bool
) -> tuple[int, bytes, bytes]:
    """Run ``python -m rprpr ARGS`` with stdout/stderr on pseudo-terminals as asked: in a
    new interpreter (``fresh``), else in a process forked from this one and set up as a
    fresh one (``tests/cli/forked.py``)."""
    fds: dict[str, tuple[int, int]] = {}
    for name, tty in (("out", stdout_tty), ("err", stderr_tty)):
        fds[name] = pty.openpty() if tty else os.pipe()
    proc: subprocess.Popen[bytes] | Forked
    if fresh:
        proc = subprocess.Popen(
            [sys.executable, "-m", "rprpr", *args],
            stdout=fds["out"][1],
            stderr=fds["err"][1],
            cwd=ROOT,
            env=env,
        )
    else:
        proc = Forked(
            lambda: rprpr_main(*args),
            cwd=ROOT, new_session=False, out=fds["out"][1], err=fds["err"][1], env=env,
        )  # fmt: skip
    for _, w in fds.values():
        os.close(w)
    data = dict.fromkeys(fds, b"")
    readers = {r: name for name, (r, _) in fds.items()}
    while readers:
        ready, _, _ = select.select(list(readers), [], [], 30)
        assert ready, "rprpr hung"
        for r in ready:
            try:
                chunk = os.read(r, 65536)
            except OSError:  # a pty's reader gets EIO once the child has closed it
                chunk = b""
            if chunk:
                data[readers[r]] += chunk
            else:
                os.close(r)
                del readers[r]
    return proc.wait(timeout=30), data["out"], data["err"]


def _env(**extra: str) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("NO_COLOR", "FORCE_COLOR", "COLUMNS")}
    env.update(TERM="xterm-256color", **extra)
    return env


@pytest.mark.slow  # processes on pseudo-terminals (forked: see _run_with_ptys)
@pytest.mark.real_workers  # the forked rprpr forks its workers, as rprpr does
def test_progress_bar_goes_to_a_terminal_stderr_never_to_stdout(varied: Path) -> None:
    args = ["check", "--format", "json", *FAST, str(varied)]
    ptys = functools.partial(_run_with_ptys, fresh=False)
    code, out, err = ptys(args, stdout_tty=False, stderr_tty=True, env=_env())
    assert code == 2
    assert b"checking" in err  # the bar, drawn on the terminal (and erased: transient)
    assert b"checking" not in out
    assert ANSI.encode() not in out
    code2, out2, err2 = ptys(args, stdout_tty=False, stderr_tty=False, env=_env())
    assert (code2, out2) == (code, out)  # stdout is the same with or without the bar
    assert b"checking" not in err2
    # a handful of tasks: no bar even on a terminal
    small = ["check", *FAST, str(CONFIGS / "paper_path2.rprpr.yaml")]
    _, _, err3 = ptys(small, stdout_tty=False, stderr_tty=True, env=_env())
    assert err3 == b""


@pytest.mark.slow  # real processes on pseudo-terminals
def test_colour_on_a_terminal_stdout_and_no_colour_with_no_color() -> None:
    args = ["check", *FAST, str(CONFIGS / "paper_path1.rprpr.yaml")]
    ptys = functools.partial(_run_with_ptys, fresh=True)
    code, out, _ = ptys(args, stdout_tty=True, stderr_tty=False, env=_env())
    assert code == 1
    assert ANSI.encode() in out
    code, out, _ = ptys(args, stdout_tty=True, stderr_tty=False, env=_env(NO_COLOR="1"))
    assert code == 1
    assert ANSI.encode() not in out
    assert b"verdict: FAIL" in out

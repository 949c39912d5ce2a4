"""A hostile corpus for the command line: file names, task names and environments that
broke rprpr (issue 11, classes 5, 10, 11, 12 and 14), each with the answer it must get.

* names: a newline, ANSI escapes, a bell, a carriage return, a backspace, a bidi
  override, bytes that are not UTF-8, ``%``/``:``/``,`` for the GitHub annotations;
  task names that forge lines; nothing reaches a terminal raw, every line stays one line;
* environments: a standard output in cp1252, ASCII or Latin-1, a C locale without UTF-8
  mode (ASCII fallbacks, never a crash; JUnit well-formed on any stream), a deleted
  working directory, a closed or full standard error;
* the files of a run: unreadable files and directories (named or found: one error for
  that task, the batch goes on), the same file under several names (audited once),
  a FIFO, a symbolic-link loop.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest

from rprpr.render.escape import ascii_fallback, printable
from tests.cli.forked import Forked, rprpr_main
from tests.conftest import PATH1_FILE, PATH2_FILE, run_cli, run_cli_encoded

RPRPR = [sys.executable, "-m", "rprpr"]
ESC = "\x1b"


@pytest.fixture(autouse=True)
def _wide(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "400")  # a long name's header line on one line


def copy_as(folder: Path, name: str | bytes, source: str = PATH2_FILE) -> str:
    """The task ``source`` copied under ``name`` (bytes: a name that is not UTF-8)."""
    target = os.path.join(os.fsencode(folder), name) if isinstance(name, bytes) else folder / name
    shutil.copyfile(source, target)
    return os.fsdecode(target)


def with_name(folder: Path, yaml_name: str, source: str = PATH1_FILE) -> str:
    """``source`` with its ``name:`` line replaced by ``yaml_name`` (YAML text)."""
    text = Path(source).read_text(encoding="utf-8")
    first = next(line for line in text.splitlines() if line.startswith("name:"))
    task = folder / "named.yaml"
    task.write_text(text.replace(first, f"name: {yaml_name}"), encoding="utf-8")
    return str(task)


def no_raw_controls(text: str) -> bool:
    """No control character but newline (and the ESC of no colour: none asked for)."""
    return all(c == "\n" or c.isprintable() or c == " " for c in text)


# -- 11. file names and task names that would act on the terminal ---------------------------
HOSTILE_NAMES = {
    "newline": "a\nverdict: PASS.yaml",
    "ansi clear screen": f"x{ESC}[2Jy.yaml",
    "ansi colour": f"{ESC}[31mred{ESC}[0m.yaml",
    "bell": "ring\x07.yaml",
    "carriage return": "over\rwritten.yaml",
    "backspace": "back\x08space.yaml",
    "bidi override": "evil\u202elmay.yaml",
    "C1 control": "csi\x9b2J.yaml",
}


@pytest.mark.parametrize("name", HOSTILE_NAMES.values(), ids=HOSTILE_NAMES.keys())
def test_a_hostile_file_name_is_escaped_in_the_text_report(name: str, tmp_path: Path) -> None:
    path = copy_as(tmp_path, name)
    code, out, err = run_cli("check", "--color", "never", path)
    assert code == 0 and err == ""
    assert out.splitlines()[0] == f"{printable(path)} — Example 2 of the paper, path 2"
    assert no_raw_controls(out)
    assert "verdict: PASS" not in out.splitlines()[1]


@pytest.mark.parametrize("name", HOSTILE_NAMES.values(), ids=HOSTILE_NAMES.keys())
def test_a_hostile_missing_file_name_is_one_escaped_error_line(name: str, tmp_path: Path) -> None:
    missing = str(tmp_path / name)
    code, out, err = run_cli("check", "--format", "json", missing, PATH2_FILE)
    assert code == 2
    assert err.splitlines() == [f"{printable(missing)}: no such file [RPR001]"]
    doc = json.loads(out)  # the machine-readable report keeps the true name
    assert doc["input_errors"][0]["task"] == missing and doc["summary"]["passed"] == 1


def test_a_file_name_that_is_not_utf8_is_shown_by_its_bytes(tmp_path: Path) -> None:
    path = copy_as(tmp_path, b"caf\xe9.yaml")  # Latin-1: not UTF-8
    code, out, _ = run_cli("check", path)
    assert code == 0 and out.splitlines()[0].startswith(f"{tmp_path}/caf\\xe9.yaml — ")
    code, out, _ = run_cli("check", "--format", "json", path)
    assert json.loads(out)["reports"][0]["verdict"] == "pass"
    code, out, _ = run_cli("export", path, "--samples", "3", "--format", "json")
    assert code == 0 and json.loads(out)["task"] == "Example 2 of the paper, path 2"
    code, out, _ = run_cli("export", path, "--samples", "3")
    assert code == 0 and "caf\\xe9.yaml" in out.splitlines()[0]


def test_a_task_name_cannot_forge_a_verdict_line(tmp_path: Path) -> None:
    task = with_name(tmp_path, '"x\\n  verdict: PASS\\u2028  verdict: PASS"')
    code, out, _ = run_cli("check", "--color", "never", task)
    assert code == 1
    verdicts = [line for line in out.splitlines() if line.strip().startswith("verdict:")]
    assert verdicts == [verdicts[0]] and verdicts[0].startswith("  verdict: FAIL")
    assert f"{task} — x\\n  verdict: PASS\\u2028  verdict: PASS" in out.splitlines()


def test_junit_with_a_hostile_task_name_is_well_formed(tmp_path: Path) -> None:
    task = with_name(tmp_path, '"<x> & \\u202e \\u2028 \\t"')
    path = copy_as(tmp_path, f"{ESC}[2J.yaml")
    code, out, _ = run_cli("check", "--format", "junit", task, path)
    assert code == 1
    root = ET.fromstring(out.encode("utf-8"))
    names = [c.attrib["name"] for c in root.iter("testcase")]
    assert names[0] == "<x> & \\u202e \\u2028 \t"
    assert [c.attrib["classname"] for c in root.iter("testcase")][1].endswith("\\x1b[2J.yaml")


def test_github_annotations_escape_property_values_and_keep_one_line_each(tmp_path: Path) -> None:
    path = copy_as(tmp_path, "50%,a:b.yaml", PATH1_FILE)
    code, out, _ = run_cli("check", "--format", "github", path)
    assert code == 1
    lines = out.splitlines()
    assert len(lines) == 2 and all(line.startswith(("::error ", "::warning ")) for line in lines)
    assert "50%25%2Ca%3Ab.yaml" in lines[0]


def test_github_messages_escape_controls_from_a_hostile_file_name(tmp_path: Path) -> None:
    missing = str(tmp_path / f"no{ESC}[2Jne\u202e.yaml")
    code, out, _ = run_cli("check", "--format", "github", missing)
    assert code == 2
    [line] = out.splitlines()
    assert ESC not in line and "\u202e" not in line and "\\x1b[2J" in line


def test_printable_escapes_each_class_once() -> None:
    assert printable("a\nb\r\t\x00\x1b\x7f\x85\u2028\u202e\ud800\udcff\ufffe ok é δ") == (
        "a\\nb\\r\\t\\x00\\x1b\\x7f\\x85\\u2028\\u202e\\ud800\\xff\\ufffe ok é δ"
    )
    assert printable("line\nnext\x1b", keep="\n") == "line\nnext\\x1b"


def test_ascii_fallbacks_name_the_greek_letters_and_symbols() -> None:
    assert [ascii_fallback(c) for c in "δσςψθλμΣ→—−…±≡×é☃"] == [
        "delta", "sigma", "sigma", "psi", "theta", "lambda", "mu", "Sigma",
        "->", "--", "-", "...", "+/-", "==", "x", "e", "\\u2603",
    ]  # fmt: skip


# -- 10. standard output that is not UTF-8 ------------------------------------------------
def rprpr_in(env: dict[str, str], *args: str, cwd: Path | None = None) -> Any:
    return subprocess.run(
        [*RPRPR, *args], capture_output=True, env={**os.environ, **env}, cwd=cwd, timeout=120
    )


CP1252 = {"PYTHONIOENCODING": "cp1252"}
ASCII = {"PYTHONIOENCODING": "ascii"}
C_LOCALE = {"LC_ALL": "C", "LANG": "C", "PYTHONUTF8": "0", "PYTHONCOERCECLOCALE": "0"}


class Done:
    """What a run left: its exit status and its standard output and error as bytes."""

    def __init__(self, returncode: int, stdout: bytes, stderr: bytes) -> None:
        self.returncode, self.stdout, self.stderr = returncode, stdout, stderr


def rprpr_encoded(env: dict[str, str], *args: str) -> Done:
    """``rprpr ARGS`` with ``env``'s standard streams: in this process for an encoding
    given by PYTHONIOENCODING (the streams Python would make for it), in a real process
    for a locale (Python's start-up decides those, tested as such)."""
    if set(env) == {"PYTHONIOENCODING"}:
        return Done(*run_cli_encoded(env["PYTHONIOENCODING"], *args))
    done = rprpr_in(env, *args)
    return Done(done.returncode, done.stdout, done.stderr)


@pytest.mark.parametrize("env", [CP1252, ASCII, C_LOCALE], ids=["cp1252", "ascii", "C"])
def test_the_text_report_on_a_non_utf8_stream_uses_ascii_fallbacks(
    env: dict[str, str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("COLUMNS", "200")
    done = rprpr_encoded(env, "check", PATH1_FILE)
    assert done.returncode == 1, done.stderr
    out = done.stdout.decode("latin-1")
    assert "case sigma psi" in out and "verdict: FAIL" in out
    assert all(ord(c) < 128 or c == "\x97" for c in out)  # cp1252 has the em dash
    assert done.stderr == b""


def test_cp1252_keeps_the_characters_cp1252_has(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("COLUMNS", "200")
    done = rprpr_encoded(CP1252, "check", PATH1_FILE)
    assert " \x97 " in done.stdout.decode("latin-1")  # the em dash, in cp1252's own byte


@pytest.mark.parametrize("env", [CP1252, ASCII], ids=["cp1252", "ascii"])
@pytest.mark.parametrize("fmt", ["json", "junit", "github"])
def test_machine_formats_on_a_non_utf8_stream(env: dict[str, str], fmt: str) -> None:
    done = rprpr_encoded(env, "check", "--format", fmt, PATH1_FILE, "missing\u03b4.yaml")
    assert done.returncode == 2, done.stderr
    assert done.stderr == b"missingdelta.yaml: no such file [RPR001]\n"
    if fmt == "json":
        assert json.loads(done.stdout)["summary"] == {
            "tasks": 2, "passed": 0, "failed": 1, "errors": 1
        }  # fmt: skip
    elif fmt == "junit":  # declared UTF-8 and true to it: non-ASCII as character references
        root = ET.fromstring(done.stdout)
        assert root.attrib["errors"] == "1" and done.stdout.isascii()
    else:
        assert done.stdout.decode("ascii").count("::error ") == 3  # RPR101, RPR201, RPR001


@pytest.mark.parametrize(
    "env", [CP1252, ASCII, {"PYTHONIOENCODING": "latin-1"}, C_LOCALE],
    ids=["cp1252", "ascii", "latin-1", "C"],
)  # fmt: skip
@pytest.mark.parametrize("command", ["plot", "export", "check"])
def test_help_on_a_non_utf8_stream(env: dict[str, str], command: str) -> None:
    done = rprpr_encoded(env, command, "--help")
    assert done.returncode == 0 and done.stderr == b""
    assert b"Usage: rprpr " + command.encode() in done.stdout


def test_export_json_on_a_non_utf8_stream_is_the_same_document(tmp_path: Path) -> None:
    task = with_name(tmp_path, "δ-path ψ", PATH2_FILE)
    utf8 = rprpr_encoded({"PYTHONIOENCODING": "utf-8"}, "export", task, "--format", "json",
                         "--samples", "3")  # fmt: skip
    ascii_ = rprpr_encoded(ASCII, "export", task, "--format", "json", "--samples", "3")
    assert utf8.returncode == ascii_.returncode == 0
    assert utf8.stdout == ascii_.stdout and json.loads(utf8.stdout)["task"] == "δ-path ψ"


# -- 12. a working directory deleted under the run -----------------------------------------
def _check_in_a_deleted_directory(
    fmt: str, gone: Path, real: bool, monkeypatch: pytest.MonkeyPatch
) -> subprocess.CompletedProcess[str]:
    """``rprpr check --format FMT`` on path 1 with ``gone`` as the working directory,
    deleted before the run: in a real process started there (``real``: Python's start-up
    meets the missing directory too), else in this process."""
    if real:
        return subprocess.run(
            ["sh", "-c", 'cd "$1" && rmdir "$1" && shift && exec "$@"', "sh", str(gone), *RPRPR,
             "check", "--format", fmt, PATH1_FILE],
            capture_output=True, text=True, timeout=120,
        )  # fmt: skip
    monkeypatch.chdir(gone)
    gone.rmdir()
    code, out, err = run_cli("check", "--format", fmt, PATH1_FILE)
    return subprocess.CompletedProcess([], code, out, err)


@pytest.mark.parametrize(
    ("fmt", "real"), [("github", True), ("text", False), ("json", False), ("junit", False)]
)
def test_a_deleted_working_directory_still_gives_the_report(
    fmt: str, real: bool, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    gone = tmp_path / "gone"
    gone.mkdir()
    done = _check_in_a_deleted_directory(fmt, gone, real, monkeypatch)
    assert done.returncode == 1, done.stderr
    assert done.stderr == ""
    if fmt == "github":
        assert done.stdout.splitlines()[0].startswith(
            f"::error file={PATH1_FILE},line=19,title=RPR101 slope-principle::"
        )


# -- 10. standard error closed or full ---------------------------------------------------------
@pytest.mark.parametrize("redirect", ["2>&-", "2>/dev/full"])
def test_a_lost_standard_error_keeps_the_exit_status(redirect: str) -> None:
    """Standard error closed (a new interpreter: Python starts without ``sys.stderr``), or
    on a full device (a process forked from this one, its descriptor 2 on /dev/full, set
    up as a fresh one: ``tests/cli/forked.py``)."""
    if redirect.endswith("full"):
        if not Path("/dev/full").exists():
            pytest.skip("needs /dev/full")
        full = os.open("/dev/full", os.O_WRONLY)
        try:
            args = ["check", "missing.yaml", PATH2_FILE]
            proc = Forked(lambda: rprpr_main(*args), cwd=os.getcwd(), err=full)
        finally:
            os.close(full)
        stdout, _ = proc.communicate(timeout=120)
        done = subprocess.CompletedProcess(args, proc.returncode, stdout)
    else:
        done = subprocess.run(
            ["sh", "-c", f'exec "$@" {redirect}', "sh", *RPRPR, "check", "missing.yaml",
             PATH2_FILE], capture_output=True, timeout=120,
        )  # fmt: skip
    assert done.returncode == 2 and b"Example 2" in done.stdout


# -- 5. unreadable files and directories: that task's error, the batch goes on ----------------
def _unreadable(path: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Make ``path`` unreadable: by its mode, or (as root, whom modes do not stop) by
    answering as the system would."""
    if os.geteuid() != 0:
        os.chmod(path, 0)
        return
    import builtins

    import rprpr.io.reading

    real_access, real_open = os.access, builtins.open
    real_scandir, real_listdir = os.scandir, os.listdir

    def denied(p: Any) -> OSError:
        return PermissionError(13, "Permission denied", p)

    def is_it(p: Any) -> bool:
        return isinstance(p, str | bytes | os.PathLike) and os.fsdecode(p) == path

    monkeypatch.setattr(os, "access", lambda p, m, **k: False if is_it(p) else real_access(p, m))

    def fake_open(p: Any, *a: Any, **k: Any) -> Any:
        if is_it(p):
            raise denied(p)
        return real_open(p, *a, **k)

    def fake_scandir(p: Any = ".") -> Any:
        if is_it(p):
            raise denied(p)
        return real_scandir(p)

    def fake_listdir(p: Any = ".") -> Any:
        if is_it(p):
            raise denied(p)
        return real_listdir(p)

    monkeypatch.setattr(rprpr.io.reading, "open", fake_open, raising=False)
    monkeypatch.setattr(os, "scandir", fake_scandir)
    monkeypatch.setattr(os, "listdir", fake_listdir)


def test_an_unreadable_file_named_on_the_command_line_is_that_tasks_error(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    locked = copy_as(tmp_path, "locked.yaml")
    _unreadable(locked, monkeypatch)
    code, out, err = run_cli("check", "--format", "json", locked, PATH2_FILE)
    assert code == 2
    assert err.splitlines() == [f"{locked}: cannot read the file: Permission denied [RPR001]"]
    assert json.loads(out)["summary"] == {"tasks": 2, "passed": 1, "failed": 0, "errors": 1}


@pytest.mark.parametrize("named", [True, False], ids=["named", "found-in-a-directory"])
def test_an_unreadable_directory_is_that_entrys_error(
    named: bool, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    top = tmp_path / "tasks"
    (top / "locked").mkdir(parents=True)
    copy_as(top / "locked", "hidden.rprpr.yaml")
    ok = copy_as(top, "z.rprpr.yaml")
    locked = str(top / "locked")
    _unreadable(locked, monkeypatch)
    args = [locked, ok] if named else [str(top)]
    code, out, err = run_cli("check", "--format", "json", *args)
    assert code == 2
    assert err.splitlines() == [f"{locked}: cannot read the directory: Permission denied [RPR001]"]
    doc = json.loads(out)
    assert [r["task"] for r in doc["reports"]] == [ok] and doc["summary"]["errors"] == 1


def test_a_fifo_named_on_the_command_line_does_not_hang(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.yaml"
    os.mkfifo(fifo)
    code, _, err = run_cli("check", str(fifo), PATH2_FILE)
    assert code == 2 and err.startswith(f"{fifo}: not a regular file")


def test_a_symbolic_link_loop_in_a_task_directory_does_not_hang(tmp_path: Path) -> None:
    copy_as(tmp_path, "t.rprpr.yaml")
    (tmp_path / "loop").symlink_to(tmp_path)
    (tmp_path / "self.rprpr.yaml").symlink_to(tmp_path / "self.rprpr.yaml")
    code, out, err = run_cli("check", "--format", "json", str(tmp_path))
    doc = json.loads(out)
    assert [r["task"] for r in doc["reports"]] == [str(tmp_path / "t.rprpr.yaml")]
    assert code == 2 and "self.rprpr.yaml" in err


# -- 14. one file, several names: audited once, by its identity ------------------------------
def test_the_same_file_under_other_names_is_audited_once(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    copy_as(tmp_path, "t.yaml")
    os.symlink("t.yaml", "soft.yaml")
    os.link("t.yaml", "hard.yaml")
    (tmp_path / "sub").mkdir()
    names = ["t.yaml", "./t.yaml", "soft.yaml", "hard.yaml", "sub/../t.yaml",
             str(tmp_path / "t.yaml"), "."]  # fmt: skip
    code, out, _ = run_cli("check", "--format", "json", *names)
    assert code == 0
    doc = json.loads(out)
    assert doc["summary"]["tasks"] == 1 and doc["reports"][0]["task"] == "t.yaml"


def test_a_missing_file_named_twice_is_one_error() -> None:
    code, out, err = run_cli("check", "--format", "json", "nope.yaml", "./nope.yaml")
    assert code == 2 and json.loads(out)["summary"]["errors"] == 1
    assert err.splitlines() == ["nope.yaml: no such file [RPR001]"]


def test_two_files_with_the_same_content_are_two_tasks(tmp_path: Path) -> None:
    a, b = copy_as(tmp_path, "a.yaml"), copy_as(tmp_path, "b.yaml")
    code, out, _ = run_cli("check", "--format", "json", a, b)
    assert code == 0 and json.loads(out)["summary"]["tasks"] == 2


# -- odd but valid names ------------------------------------------------------------------------
@pytest.mark.parametrize(
    "name", ["-dash.yaml", " spaced name .yaml", "δ-path.yaml", "x" * 250 + ".yaml"]
)
def test_odd_but_valid_names_are_audited(
    name: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    copy_as(tmp_path, name)
    code, out, _ = run_cli("check", "--format", "json", "--", name)
    assert code == 0 and json.loads(out)["reports"][0]["task"] == name

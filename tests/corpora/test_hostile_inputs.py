"""A hostile corpus for the surfaces added in 0.2 (standard input, the configuration, the
waypoint CSV, the six report formats), each test with the promise of README's Guarantees
it pins:

* C1 standard input is read through the capped reader: an endless or stalled pipe is a
  "file too large ... 1 MiB" line and exit 2 as soon as it passes the cap, never a hang;
* C2 a bad configuration is one located line and exit 2, never a hang or a crash (the
  task file's number rules, TOML's own limits, a FIFO, a folder without permission);
* C3 inputs are never overwritten: the waypoint CSV a task reads and the configuration
  are inputs of the run, and two outputs cannot be one file;
* C4 a waypoint CSV resolves inside its task file's folder, and no report quotes a file
  the task was not allowed to read (a folder search does not follow a link out either);
* C5 every name the OS can give is shown, as escapes, in every report (exit 3 only for
  bugs);
* C6 usage errors are decided before any work or write;
* C7 the text report costs what it prints: a 3,000-instant report without rich's
  per-row layout (work counted, never timed);
* C8 no line of any report can start a CI runner's command.

Every random input is drawn from a fixed seed: the same cases on every run.
"""

from __future__ import annotations

import faulthandler
import json
import os
import random
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from contextlib import chdir, contextmanager
from pathlib import Path

import pytest

from rprpr.cli.config import load_settings
from rprpr.cli.errors import InputError
from rprpr.model.errors import TaskFileError
from rprpr.report.records import input_error
from rprpr.report.run import INPUT, Run
from tests.conftest import CONFIGS, LINKS_ALIKE, PATH1_FILE, run_cli

RPRPR = [sys.executable, "-m", "rprpr"]
FORMATS = ("text", "json", "junit", "github", "sarif", "gitlab")
HANG_GUARD = 120  # seconds: only so that a regression fails instead of hanging the suite
SECRET = "s3cr3t-0f-the-m4chine"

WAYPOINT_TASK = f"name: waypoints\nrobot:\n  a1: 6\n{LINKS_ALIKE}motion:\n  waypoints: plan.csv\n"
PLAN = "t,x,y\n0,2,-1\n1,3,0.5\n2,4,1\n"


def one_error_line(err: str) -> str:
    """The one line standard error holds (and no traceback)."""
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, lines
    return lines[0]


@pytest.fixture
def waypoint_task(tmp_path: Path) -> Path:
    """A task reading its waypoints from plan.csv beside it."""
    (tmp_path / "plan.csv").write_text(PLAN, encoding="utf-8")
    task = tmp_path / "t.rprpr.yaml"
    task.write_text(WAYPOINT_TASK, encoding="utf-8")
    return task


# -- C1: standard input, capped ---------------------------------------------------------
ENDLESS = "import sys\nwhile True:\n    sys.stdout.write('a: 1\\n' * 4096)\n"
# 3 MB, then the pipe stays open and silent: no end of file will ever come
STALLED = (
    "import sys, time\nsys.stdout.write('a: 1\\n' * 600_000)\nsys.stdout.flush()\n"
    "time.sleep(3600)\n"
)


@contextmanager
def writer(program: str) -> Iterator[subprocess.Popen[bytes]]:
    """A process writing ``program``'s output into a pipe (ended after the block)."""
    proc = subprocess.Popen([sys.executable, "-c", program], stdout=subprocess.PIPE)
    try:
        yield proc
    finally:
        proc.kill()
        proc.wait()
        assert proc.stdout is not None
        proc.stdout.close()


@pytest.mark.parametrize("source", [ENDLESS, STALLED], ids=["endless", "stalled"])
@pytest.mark.parametrize("command", ["check", "plot", "export"])
def test_standard_input_past_the_cap_stops_at_once(
    source: str, command: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Promise: never a hang, bounded work; standard input past 1 MiB is one line, exit 2,
    as soon as the cap is passed (the writer is still writing, or holding the pipe open
    without an end). ``check`` on the stalled pipe runs as a real process; the others
    (the same reader) in this process, on the stream Python makes for a piped standard
    input."""
    with writer(source) as gen:
        assert gen.stdout is not None
        if command == "check" and source is STALLED:
            done = subprocess.run(
                [*RPRPR, command, "-"], stdin=gen.stdout, capture_output=True, text=True,
                cwd=tmp_path, timeout=HANG_GUARD,
            )  # fmt: skip
        else:
            piped = os.fdopen(os.dup(gen.stdout.fileno()), "r", encoding="utf-8")
            monkeypatch.setattr(sys, "stdin", piped)
            monkeypatch.chdir(tmp_path)
            faulthandler.dump_traceback_later(HANG_GUARD, exit=True)  # a hang ends the run
            try:
                code, out, err = run_cli(command, "-")
            finally:
                faulthandler.cancel_dump_traceback_later()
                piped.close()
            done = subprocess.CompletedProcess([command, "-"], code, out, err)
        assert gen.poll() is None or source is ENDLESS  # the stalled pipe never ended
    assert done.returncode == 2
    line = one_error_line(done.stderr)
    assert "-: file too large: more than 1048576 bytes" in line and "(1 MiB)" in line
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_the_capped_reader_reads_no_further_than_the_cap() -> None:
    """Promise: bounded work: an endless stream is read cap + 1 bytes far, no further."""
    from rprpr.io.reading import ReadProblem, read_stream

    class Endless:
        given = 0

        def read(self, n: int) -> bytes:
            self.given += n
            return b"x" * n

    stream = Endless()
    with pytest.raises(ReadProblem, match=r"more than 4096 bytes, the cap is 4096 bytes \(4 KiB\)"):
        read_stream(stream, 4096)  # type: ignore[arg-type]
    assert stream.given == 4097


# -- C2: the configuration, one located line -----------------------------------------------
BEYOND = "has an exponent beyond ±30"
BAD_CONFIGS = {
    "huge exponent": ("min_slope = 1e999999999\n", f"1: min_slope: number '1e999999999' {BEYOND}"),
    "tiny budget": ("budget = 1e-999999999\n", f"1: budget: number '1e-999999999' {BEYOND}"),
    "tiny margin": ("jobs = 1\nmin_speed = 1e-9999\n", f"2: min_speed: number '1e-9999' {BEYOND}"),
    "5,000 digits": (
        "jobs = 1\n\nsamples = 1" + "0" * 5000 + "\n",
        "3: invalid TOML: an integer with more than 4300 digits",
    ),
    "41 digits": ("torque_limit = [1" + "0" * 40 + ", 3]\n", "...' has more than 40 digits"),
    "deep nesting": (
        "paths = " + "[" * 3000 + "]" * 3000 + "\n",
        "1: invalid TOML: arrays or tables nested too deeply",
    ),
    "inf": ("min_slope = inf\n", "1: min_slope: expected a number, found 'inf'"),
    "float as a path": ("paths = [1.5]\n", "1: paths: expected a list of strings, found [1.5]"),
    "not UTF-8": ("# caf\udce9\n", "1: cannot read the configuration: not UTF-8 text"),
}  # fmt: skip


@pytest.mark.parametrize(("toml", "expected"), BAD_CONFIGS.values(), ids=BAD_CONFIGS.keys())
def test_a_bad_configuration_found_upward_is_one_located_line(
    toml: str, expected: str, tmp_path: Path
) -> None:
    """Promise: a bad configuration is one line naming the file, its line and key, exit 2,
    before any task; never a hang (1e999999999 took no answer in 20 s) or exit 3."""
    config = tmp_path / ".rprpr.toml"
    config.write_bytes(toml.encode("utf-8", "surrogateescape"))
    shutil.copyfile(PATH1_FILE, tmp_path / "t.rprpr.yaml")
    with chdir(tmp_path):
        code, out, err = run_cli("check", "t.rprpr.yaml")
    assert code == 2 and out == ""
    line = one_error_line(err)
    assert line.startswith(f"rprpr: {config}:") and expected in line, line


def test_configuration_numbers_follow_the_task_files_rules(tmp_path: Path) -> None:
    """Promise: the configuration's numbers are read as a task file's (exact decimal
    text, 40 digits, exponent within ±30): bounded work, one line for the rest
    (deterministic fuzz over literals, fixed seed)."""
    rng = random.Random(25)
    config = tmp_path / "rprpr.toml"
    for _ in range(300):
        digits = "".join(rng.choice("0123456789") for _ in range(rng.randint(1, 45)))
        exponent = rng.choice(["", f"e{rng.randint(-40, 40)}", f"E+{rng.randint(0, 99999)}"])
        config.write_text(f"min_slope = {digits[:1]}.{digits[1:] or '0'}{exponent}\n", "utf-8")
        try:
            settings = load_settings(str(config))
        except InputError as e:
            assert "\n" not in str(e) and str(e).startswith(f"{config}:1: min_slope: ")
            continue
        value = settings["min_slope"]
        assert value.denominator.bit_length() < 400 and value.numerator.bit_length() < 400


@pytest.mark.parametrize("kind", ["fifo", "device", "directory", "huge"])
def test_a_configuration_that_is_not_a_small_file_is_refused_without_reading(
    kind: str, tmp_path: Path
) -> None:
    """Promise: never a hang: --config names a FIFO (no writer), /dev/zero, a folder or a
    file over 1 MiB: one line, exit 2."""
    target = tmp_path / "rprpr.toml"
    if kind == "fifo":
        os.mkfifo(target)
    elif kind == "directory":
        target.mkdir()
    elif kind == "huge":
        target.write_text("# x\n" * 300_000, encoding="utf-8")
    name = "/dev/zero" if kind == "device" else str(target)
    code, out, err = run_cli("check", "--config", name, PATH1_FILE)
    assert code == 2 and out == ""
    line = one_error_line(err)
    if kind == "directory":  # click's own check of --config
        assert line.endswith(f"File '{name}' is a directory.")
    else:
        assert line.startswith(f"rprpr: {name}: cannot read the configuration: ")


def test_configuration_discovery_under_a_folder_without_permission_is_one_line(
    tmp_path: Path,
) -> None:
    """Promise: configuration discovery through a folder that cannot be searched (EACCES)
    is one line and exit 2, never an internal error (exit 3). Run as a user without the
    permission: root has it always, so as root the test drops to nobody (setpriv)."""
    inner = tmp_path / "locked" / "work"
    inner.mkdir(parents=True)
    locked = inner.parent
    command = [*RPRPR, "check", "-"]
    preexec = None
    if os.geteuid() == 0:
        setpriv = shutil.which("setpriv")
        if setpriv is None:
            pytest.skip(
                "running as root, which searches every folder, and no setpriv to drop to nobody"
            )
        command = [setpriv, "--reuid=65534", "--regid=65534", "--clear-groups", *command]
        locked.chmod(0o700)  # root's: nobody may not search it
    else:

        def preexec() -> None:  # after the child entered ``inner``: its parent locked
            locked.chmod(0o600)

    try:
        done = subprocess.run(
            command, cwd=inner, input=Path(PATH1_FILE).read_bytes(), capture_output=True,
            timeout=HANG_GUARD, preexec_fn=preexec,
        )  # fmt: skip
    finally:
        locked.chmod(0o700)
    assert done.returncode == 2, done.stderr
    line = one_error_line(done.stderr.decode("utf-8", "replace"))
    assert "cannot look for a configuration file there" in line and "--isolated" in line


# -- C3: every input of the run is known to the output guard -------------------------------
@pytest.mark.parametrize(
    "args",
    [
        ["check", "t.rprpr.yaml", "-o", "plan.csv"],
        ["check", "--format", "json", "-", "-o", "plan.csv"],
        ["export", "t.rprpr.yaml", "-o", "plan.csv"],
        ["repair", "t.rprpr.yaml", "-o", "plan.csv"],
        ["check", "t.rprpr.yaml", "-o", "./sub/../plan.csv"],
    ],
    ids=["check", "check stdin", "export", "repair", "another spelling"],
)
def test_an_output_onto_the_waypoint_csv_is_refused(
    args: list[str], waypoint_task: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Promise: inputs are never overwritten: the waypoint CSV a task reads is an input
    of the run; an output onto it is one line, exit 2, the plan intact."""
    folder = waypoint_task.parent
    (folder / "sub").mkdir()
    monkeypatch.setattr("sys.stdin", _stdin(waypoint_task.read_bytes()))
    with chdir(folder):
        code, _, err = run_cli(*args)
    assert code == 2
    line = one_error_line(err)
    assert "is also the waypoint CSV of" in line and "it would be overwritten" in line
    assert (folder / "plan.csv").read_text(encoding="utf-8") == PLAN
    assert sorted(p.name for p in folder.iterdir()) == ["plan.csv", "sub", "t.rprpr.yaml"]


def _stdin(data: bytes) -> object:
    import io

    return io.TextIOWrapper(io.BytesIO(data), encoding="utf-8")


def test_an_output_onto_the_configuration_is_refused(tmp_path: Path) -> None:
    """Promise: inputs are never overwritten: the configuration is an input of the run."""
    config = tmp_path / ".rprpr.toml"
    config.write_text("jobs = 1\n", encoding="utf-8")
    shutil.copyfile(PATH1_FILE, tmp_path / "t.rprpr.yaml")
    with chdir(tmp_path):
        code, _, err = run_cli("check", "t.rprpr.yaml", "-o", ".rprpr.toml")
    assert code == 2 and "is also the configuration" in one_error_line(err)
    assert config.read_text(encoding="utf-8") == "jobs = 1\n"


def test_two_outputs_onto_one_file_are_refused_before_any_work(tmp_path: Path) -> None:
    """Promise: usage errors before any work or write: repair's task and sheet onto one
    file would overwrite one with the other."""
    shutil.copyfile(PATH1_FILE, tmp_path / "t.rprpr.yaml")
    with chdir(tmp_path):
        code, _, err = run_cli("repair", "t.rprpr.yaml", "-o", "r.png", "--plot", "r.png")
    assert code == 2 and "is also another output of this run" in one_error_line(err)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.rprpr.yaml"]


# -- C4: the CSV rule holds after symbolic links; nothing of another file is quoted ---------
def _secret(tmp_path: Path) -> Path:
    outside = tmp_path / "outside"
    outside.mkdir()
    secret = outside / "secret.csv"
    secret.write_text(f"{SECRET}:x:0:0\n", encoding="utf-8")
    return secret


@pytest.mark.parametrize("how", ["file link", "folder link", "dangling link"])
def test_a_csv_link_out_of_the_tasks_folder_is_not_read(how: str, tmp_path: Path) -> None:
    """Promise: a waypoint CSV must resolve inside its task file's folder; a link out of
    it is one located line, and no report, in any format, quotes a byte of its target."""
    secret = _secret(tmp_path)
    repo = tmp_path / "repo"
    repo.mkdir()
    name = "plan.csv"
    if how == "file link":
        (repo / "plan.csv").symlink_to(secret)
    elif how == "folder link":
        (repo / "sub").symlink_to(secret.parent)
        name = "sub/secret.csv"
    else:
        (repo / "plan.csv").symlink_to(tmp_path / "outside" / "missing.csv")
    task = repo / "t.rprpr.yaml"
    task.write_text(WAYPOINT_TASK.replace("plan.csv", name), encoding="utf-8")
    for fmt in FORMATS:
        code, out, err = run_cli("check", "--format", fmt, str(task))
        assert code == 2, fmt
        assert SECRET not in out + err, fmt
    code, out, err = run_cli("check", str(task))
    assert (
        f"t.rprpr.yaml:10:14: motion.waypoints: {name}: resolves outside the task file's folder"
        in err
    )


def test_a_folder_search_does_not_follow_a_task_file_link_out_of_the_folder(
    tmp_path: Path,
) -> None:
    """Promise: reports carry only the repository's own data: a task file found by a
    folder search that links out of the folder is named on standard error and not read."""
    secret = _secret(tmp_path)
    repo = tmp_path / "repo"
    repo.mkdir()
    shutil.copyfile(CONFIGS / "paper_path2.rprpr.yaml", repo / "good.rprpr.yaml")
    (repo / "leak.rprpr.yaml").symlink_to(secret)
    code, out, err = run_cli("check", "--format", "json", str(repo))
    assert code == 0 and SECRET not in out + err
    assert json.loads(out)["summary"]["tasks"] == 1
    assert "leak.rprpr.yaml: a symbolic link out of" in one_error_line(err)


# -- C5: any name the OS can give, in every report ------------------------------------------
NAME = b"\xffgood.rprpr.yaml"  # its first byte is not UTF-8


@pytest.mark.parametrize("fmt", FORMATS)
def test_a_file_name_that_is_not_utf8_is_escaped_in_every_format(fmt: str, tmp_path: Path) -> None:
    """Promise: non-UTF-8 names are shown as escapes (\\xff) in every report, which stays
    valid UTF-8; exit 3 only for bugs (SARIF and GitLab exited 3)."""
    good = os.fsdecode(os.path.join(os.fsencode(tmp_path), NAME))
    shutil.copyfile(CONFIGS / "paper_path2.rprpr.yaml", good)
    bad = os.fsdecode(os.path.join(os.fsencode(tmp_path), b"\xfebad.rprpr.yaml"))
    Path(bad).write_text("name: [\n", encoding="utf-8")
    code, out, err = run_cli("check", "--format", fmt, good, bad)
    assert code == 2, err
    out.encode("utf-8")  # no lone surrogate reached the report
    assert "\\xfebad.rprpr.yaml" in out + err or "%5Cxfebad.rprpr.yaml" in out
    if fmt in ("json", "sarif", "gitlab"):
        json.loads(out)
    elif fmt == "junit":
        ET.fromstring(out.encode("utf-8"))


def test_any_name_renders_in_every_format_deterministic_fuzz() -> None:
    """Promise: every renderer takes every name the OS can give (random bytes, fixed
    seed), through the one shared function (``model.names.file_name``)."""
    from rprpr.render import github, gitlab, junit, sarif
    from rprpr.render import json as json_report

    rng = random.Random(25)
    run = Run()
    for _ in range(200):
        raw = bytes(rng.randrange(1, 256) for _ in range(rng.randint(1, 12))).replace(b"/", b"_")
        name = os.fsdecode(raw)
        run.add(INPUT, input_error(TaskFileError("bad", line=1, column=1, key="name"), name))
    for text in (
        json_report.render(run), junit.render(run), github.render(run), sarif.render(run),
        gitlab.render(run),
    ):  # fmt: skip
        text.encode("utf-8")


@pytest.mark.parametrize("command", ["plot", "export", "repair"])
def test_the_other_commands_take_a_name_that_is_not_utf8(command: str, tmp_path: Path) -> None:
    """Promise: exit 3 only for bugs: the sheet (matplotlib refused the name), the export
    and repair's comment (read back as YAML) take any name."""
    task = os.fsdecode(os.path.join(os.fsencode(tmp_path), NAME))
    shutil.copyfile(PATH1_FILE, task)
    args = {
        # the name is in the sheet's title whatever is drawn: one panel
        "plot": ["-o", str(tmp_path / "s.svg"), "--samples", "11", "--panels", "delta"],
        "export": ["--samples", "3", "--format", "json"],
        "repair": ["-o", str(tmp_path / "r.rprpr.yaml")],
    }[command]
    code, out, err = run_cli(command, task, *args)
    assert code == 0, err
    if command == "export":
        assert json.loads(out)["file"].endswith("\\xffgood.rprpr.yaml")
    if command == "repair":
        assert "from \\xffgood.rprpr.yaml" in (tmp_path / "r.rprpr.yaml").read_text("utf-8")


# -- C6: usage errors before any work or write ---------------------------------------------
@pytest.mark.parametrize(
    "extra",
    [["--plot", "r2.yaml"], ["--window", "abc"], ["--slope", "0"]],
    ids=["plot extension", "window", "slope"],
)
def test_repair_decides_its_usage_errors_before_writing(extra: list[str], tmp_path: Path) -> None:
    """Promise: usage errors exit 2 before any work or write (r.yaml was written, then
    exit 3)."""
    shutil.copyfile(PATH1_FILE, tmp_path / "t.rprpr.yaml")
    with chdir(tmp_path):
        code, out, err = run_cli("repair", "t.rprpr.yaml", "-o", "r.yaml", *extra)
    assert code == 2 and out == ""
    assert one_error_line(err).startswith("rprpr: usage error: ")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.rprpr.yaml"]


# -- C7: the text report costs what it prints ----------------------------------------------
def zigzag(pieces: int) -> str:
    """A task whose timing goes back and forth between x = 2 and x = 4, a piece a second,
    on a path crossing y = 0 three times: three singular instants a piece."""
    lines = [
        "name: zig-zag", "robot:", "  a1: 6", LINKS_ALIKE.rstrip("\n"), "path:",
        "  y: (x-2.5)*(x-3)*(x-3.5)", "  from: [2, -0.75]", "  to: [4, 0.75]", "timing:",
        f"  duration: {pieces}", "  x:",
    ]  # fmt: skip
    for i in range(pieces):
        x = f"{2 - 2 * i} + 2*t" if i % 2 == 0 else f"{4 + 2 * i} - 2*t"
        lines.append(f"    - {{until: {i + 1}, x: {x}}}")
    return "\n".join(lines) + "\n"


@pytest.fixture(scope="module")
def zigzag_run(tmp_path_factory: pytest.TempPathFactory) -> Run:
    """The run of a 1,001-piece zig-zag: 3,003 singular instants (audited once)."""
    from rprpr.cli.check import check_one
    from rprpr.cli.options import CheckOptions

    task = tmp_path_factory.mktemp("zigzag") / "zz.rprpr.yaml"
    task.write_text(zigzag(1001), encoding="utf-8")
    run = Run()
    run.add(*check_one(str(task), CheckOptions(budget=None)))
    return run


@pytest.mark.parametrize(("columns", "layout"), [(400, "table"), (80, "rows")])
def test_a_3000_instant_text_report_is_drawn_in_one_print_without_rich_tables(
    columns: int, layout: str, zigzag_run: Run, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Promise: each task has a work budget, and the report after it costs what it prints
    (the table took 23.5 s at 5 ms a row): the 3,003 instants are drawn without rich's
    Table or its per-line wrapping, in one print for the task (work counted, not timed)."""
    import io

    from rich.console import Console
    from rich.table import Table
    from rich.text import Text

    from rprpr.cli.output import make_console
    from rprpr.render.text import render

    def refused(*args: object, **kwargs: object) -> None:
        raise AssertionError("rich laid out a table or wrapped a Text")

    monkeypatch.setattr(Table, "__rich_console__", refused)
    monkeypatch.setattr(Text, "wrap", refused)
    prints = []
    real_print = Console.print

    def counted(self: Console, *args: object, **kwargs: object) -> None:
        prints.append(args)
        real_print(self, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(Console, "print", counted)
    monkeypatch.setenv("COLUMNS", str(columns))
    out = io.StringIO()
    render(zigzag_run, make_console(out, False), make_console(io.StringIO(), False), layout=layout)
    text = out.getvalue()
    assert len(prints) == 1
    report = zigzag_run.reports[0]
    assert len(report["singularities"]) == 3003
    if layout == "table":
        assert sum(line.startswith("│") for line in text.splitlines()) == 3003
    else:
        assert text.count("\ninstant ") == 3003
        # every line within the width but the findings (each one whole line, never wrapped,
        # and the only lines that start FILE:LINE:)
        finding = re.compile(re.escape(report["task"]) + r":\d+:")
        assert all(len(line) <= columns for line in text.splitlines() if not finding.match(line))


# -- C8: no line of a report can be taken for a CI runner's command -------------------------
FORGING = [
    "::warning::p1.rprpr.yaml",
    "  ::stop-commands::x.rprpr.yaml",
    "a ##[add-mask]b.rprpr.yaml",
]


def no_runner_command(text: str) -> bool:
    """No line that GitHub Actions, Azure Pipelines or TeamCity would act on."""
    import re

    lines = text.splitlines()
    return not any(re.match(r"\s*::", line) for line in lines) and not re.search(
        r"##(\[|vso\[|teamcity\[)", text, re.IGNORECASE
    )


@pytest.mark.parametrize("fmt", [f for f in FORMATS if f != "github"])
def test_no_report_line_starts_a_ci_runner_command(fmt: str, tmp_path: Path) -> None:
    """Promise: no line of a report can be forged: a file name that is a workflow command
    (forged annotations, ``::stop-commands::``) is escaped in every format, on standard
    output and standard error; JSON and XML keep the same characters (escaped)."""
    paths = []
    for name in FORGING:
        path = tmp_path / name
        shutil.copyfile(PATH1_FILE, path)
        paths.append(str(path.relative_to(tmp_path)))
    (tmp_path / "::error::bad.rprpr.yaml").write_text("name: [\n", encoding="utf-8")
    paths.append("::error::bad.rprpr.yaml")
    with chdir(tmp_path):
        code, out, err = run_cli("check", "--format", fmt, *paths)
    assert code == 2
    assert no_runner_command(out) and no_runner_command(err), out + err
    if fmt == "sarif":  # a URI: percent-encoded
        assert "%3A%3Awarning%3A%3Ap1.rprpr.yaml" in out
    elif fmt in ("json", "gitlab"):
        assert "::warning::p1.rprpr.yaml" in json.dumps(json.loads(out))
    elif fmt == "junit":
        root = ET.fromstring(out.encode("utf-8"))
        assert "::warning::p1.rprpr.yaml" in [c.attrib["file"] for c in root.iter("testcase")]
    else:
        assert "\\x3a:warning::p1.rprpr.yaml:19:1: RPR101" in out


def test_github_annotations_keep_a_forging_name_inside_their_properties(tmp_path: Path) -> None:
    """Promise: the GitHub format's lines are its own annotations, never a forged one."""
    path = tmp_path / FORGING[0]
    shutil.copyfile(PATH1_FILE, path)
    with chdir(tmp_path):
        code, out, _ = run_cli("check", "--format", "github", FORGING[0])
    assert code == 1
    assert all(line.startswith("::error file=%3A%3Awarning%3A%3Ap1") for line in out.splitlines())


def test_show_settings_cannot_forge_a_line(tmp_path: Path) -> None:
    """Promise: no line can be forged by a value of the configuration either."""
    (tmp_path / "rprpr.toml").write_text(
        'paths = ["a\\n::warning::forged", "##[add-mask]x"]\n', encoding="utf-8"
    )
    with chdir(tmp_path):
        code, out, _ = run_cli("check", "--show-settings")
    assert code == 0 and no_runner_command(out)
    assert '"a\\n::warning::forged", "\\x23#[add-mask]x"' in out


def test_a_line_cut_across_writes_is_still_escaped() -> None:
    """Promise: no line can be forged however the console cuts its writes."""
    import io

    from rprpr.cli.output import Inert

    out = io.StringIO()
    stream = Inert(out)
    for piece in [":", ":warn", "ing::x\n  ", "#", "#", "[add-mask]y\n", "ok\n"]:
        stream.write(piece)
        stream.flush()
    assert out.getvalue() == "\\x3a:warning::x\n  \\x23#[add-mask]y\nok\n"


def test_inert_keeps_every_other_text() -> None:
    """Promise: only what a runner acts on changes (deterministic fuzz, fixed seed)."""
    from rprpr.render.escape import inert

    rng = random.Random(25)
    alphabet = "ab :#[]\n\tv"
    for _ in range(2000):
        text = "".join(rng.choice(alphabet) for _ in range(rng.randint(0, 30)))
        escaped = inert(text)
        assert no_runner_command(escaped)
        assert escaped.replace("\\x3a", ":").replace("\\x23", "#") == text
    assert inert("x ::a\n") == "x ::a\n"

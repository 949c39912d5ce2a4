"""The hostile loader corpus (issue 11): each file in ``tests/corpora/hostile/loader/`` gets the
answer ``expected.txt`` gives it.

A bad file -- a tagged value that is not a value of its tag, digit strings with
thousands of zeros, a message about a value beyond the double range, nesting at and
over the cap, huge keys and lines, NUL bytes, UTF-16/32, invalid UTF-8, surrogate and
C1 escapes, tags on keys, complex keys, a root that aliases itself -- exits 2 with
exactly the one line the table gives, nothing on stdout and no traceback, in process
and in a real ``python -m rprpr check`` process. A valid but extreme file (BOM + CRLF,
CR or NEL line ends, aliases or tags on every node, thousands of zeros) is audited with
the exit status the table gives and loads to the same task as its reference file.
"""

from __future__ import annotations

import dataclasses
import math
import re
import sys
from decimal import ROUND_HALF_UP, Context, Decimal
from pathlib import Path

import pytest
import yaml
from flint import fmpq

from rprpr.cli.main import main
from rprpr.io import yaml_nodes
from rprpr.io.loader import load_task, parse_task
from rprpr.model.errors import TaskFileError
from rprpr.model.numbers import rational, to_float
from rprpr.model.task import Task
from tests.cli.forked import run_rprpr

HERE = Path(__file__).resolve().parent / "hostile" / "loader"
VALID = re.compile(r"(?P<file>\S+\.task) valid: exit (?P<code>\d), the task of (?P<ref>\S+)")


def _table() -> dict[str, str]:
    """File name -> its expected lines, one per error in the file, in order (or its
    "valid: ..." entry); consecutive lines of expected.txt naming the same file."""
    out: dict[str, str] = {}
    last = ""
    for line in (HERE / "expected.txt").read_text(encoding="utf-8").splitlines():
        if line and not line.startswith("#"):
            name = line.split(" valid: ")[0] if VALID.fullmatch(line) else line.split(":")[0]
            if name == last:  # another error of the same file
                out[name] += "\n" + line
                continue
            assert name not in out, f"{name} twice in expected.txt"
            out[name], last = line, name
    return out


TABLE = _table()
BAD = sorted(n for n, line in TABLE.items() if not VALID.fullmatch(line))
GOOD = sorted(n for n, line in TABLE.items() if VALID.fullmatch(line))


def run_cli(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    """``rprpr ARGS`` in-process: (exit status, stdout, stderr)."""
    with pytest.raises(SystemExit) as exc:
        main(list(args))
    out, err = capsys.readouterr()
    code = exc.value.code
    return (code if isinstance(code, int) else 1), out, err


def test_the_table_lists_every_file_of_the_corpus() -> None:
    assert sorted(TABLE) == sorted(p.name for p in HERE.glob("*.task"))
    assert len(BAD) >= 20 and len(GOOD) >= 5


@pytest.mark.parametrize("name", BAD)
def test_a_bad_file_is_one_line_and_exit_2(
    name: str, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(HERE)
    code, out, err = run_cli(capsys, "check", "--color", "never", name)
    assert (code, out, err) == (2, "", TABLE[name] + "\n")
    # the API raises the same error, and nothing else
    with pytest.raises(TaskFileError) as e:
        load_task(name)
    assert [f"{x} [RPR001]" for x in e.value.errors] == TABLE[name].splitlines()


def test_every_bad_file_in_one_real_process(tmp_path: Path) -> None:
    """The command line as a process runs it (``python -m rprpr``, in a process forked from
    this one and set up as a fresh one: ``tests/cli/forked.py``; the new interpreter's path
    is tests/corpora/test_bad_tasks.py's): exit 2, the lines in order, no traceback,
    nothing written."""
    proc = run_rprpr(["check", "--color", "never", *(str(HERE / n) for n in BAD)], tmp_path)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stdout + proc.stderr
    assert proc.stderr.splitlines() == [
        f"{HERE}/{line}" for n in BAD for line in TABLE[n].splitlines()
    ]
    assert f"{len(BAD)} errors" in proc.stdout  # the summary; no report
    assert list(tmp_path.iterdir()) == []


def _without_name(task: Task) -> Task:
    return dataclasses.replace(task, name="", lines={}, source="")


@pytest.mark.parametrize("name", GOOD)
def test_a_valid_extreme_file_is_audited(
    name: str, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    m = VALID.fullmatch(TABLE[name])
    assert m
    monkeypatch.chdir(HERE)
    code, out, err = run_cli(capsys, "check", "--color", "never", "--samples", "51", name)
    assert (code, err) == (int(m["code"]), ""), out  # 1: path 1 fails the slope principle
    assert _without_name(load_task(name)) == _without_name(load_task(m["ref"]))


@pytest.mark.parametrize("parser", ["libyaml", "pure Python"])
def test_a_lone_surrogate_escape_is_refused_by_either_yaml_parser(
    parser: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """libyaml refuses the escape itself; the pure-Python parser decodes it, and the
    loader refuses the value (it could not be written to any UTF-8 report)."""
    if parser == "pure Python":
        monkeypatch.setattr(yaml_nodes, "_Loader", yaml.SafeLoader)
    elif not hasattr(yaml, "CSafeLoader"):
        pytest.skip("PyYAML without libyaml")
    text = (HERE / "surrogate_escape.task").read_text(encoding="utf-8")
    with pytest.raises(TaskFileError) as e:
        parse_task(text, "s.yaml")
    assert (e.value.line, e.value.column) == (1, 10 if parser == "libyaml" else 7)
    assert e.value.message == (
        "YAML syntax error: while parsing a quoted scalar: found invalid Unicode character"
        " escape code"
        if parser == "libyaml"
        else "lone surrogate U+D800 in a value (written as a YAML escape) is not allowed"
    )


# -- the numbers in messages: exact beyond the double range --------------------------------


def _seventeen_digits(v: fmpq) -> Decimal:
    """``v`` rounded (half up) to 17 significant digits, by ``decimal`` (independently)."""
    ctx = Context(prec=17, rounding=ROUND_HALF_UP, Emax=10**6, Emin=-(10**6))
    return ctx.divide(Decimal(int(v.p)), Decimal(int(v.q)))


@pytest.mark.parametrize(
    "v",
    [
        fmpq(2) ** 1100,  # beyond the double range
        -(fmpq(2) ** 1100) / 3,
        fmpq(2048) * fmpq(10) ** -330,  # below it: (2e-30)^11, as in off_path_below_double
        fmpq(1, 3) * fmpq(10) ** -400,
        fmpq(10) ** 400 - 1,  # rounds up to the next power of ten
        fmpq(5) * fmpq(10) ** -320,  # subnormal as a double
    ],
)
def test_a_value_beyond_the_double_range_prints_exactly(v: fmpq) -> None:
    f = to_float(v)
    assert f == 0 or math.isinf(f) or abs(f) < sys.float_info.min  # no double holds it
    text, _, rest = rational(v).partition(" (≈; exactly a rational of ")
    assert rest == f"{len(str(v))} characters)"
    assert Decimal(text) == _seventeen_digits(v)
    assert "inf" not in text and text != "0"


def test_to_float_saturates_with_the_sign_of_the_value() -> None:
    assert to_float(fmpq(10) ** 400) == math.inf
    assert to_float(-(fmpq(10) ** 400)) == -math.inf
    assert to_float(fmpq(1, 10**400)) == 0.0

"""Bad input never crashes, never runs code, never passes silently (issue 5).

Every file in ``tests/corpora/bad_tasks/`` is one small mistake in an otherwise valid task (the
paper's path 2); each must exit 2 with one line naming the file, the line, the column
and the key, and saying what was expected and what was found. Inputs that are too big,
binary or not UTF-8 are generated here into ``tmp_path`` rather than committed.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from contextlib import chdir
from fractions import Fraction
from pathlib import Path

import pytest
import yaml

from rprpr.io import reading, source
from rprpr.io.loader import MAX_BYTES, load_task, parse_task
from rprpr.model.errors import TaskFileError
from tests.cli.forked import run_rprpr
from tests.conftest import run_cli

HERE = Path(__file__).resolve().parent
BAD = HERE / "bad_tasks"
ROOT = HERE.parents[1]
CANARY = "rprpr-pwned"  # the file a hostile input would create if it ran
CANARY_ENV = "RPRPR_PWNED"  # the variable a hostile input would set if it ran

GOOD = """\
name: good
robot:
  a1: 6
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
path:
  y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2
  from: [2, -1]
  to: [4, 1]
timing:
  duration: 5
  law: quintic
"""

# name -> (key path, line, column, fragments the message must contain); line/column 0:
# the error has no position (the whole file).
CASES: dict[str, tuple[str, int, int, tuple[str, ...]]] = {
    # -- YAML itself: YAML's own line and column -----------------------------------------
    "syntax_unclosed_flow": ("", 4, 1, ("YAML syntax error", "did not find expected node content")),
    "syntax_tab_indent": ("", 4, 1, ("YAML syntax error", "a tab: YAML indents with spaces")),
    "syntax_bad_indent": (
        "",
        5,
        4,
        ("YAML syntax error: wrong indentation: expected 2 (as line 4)", "mapping values"),
    ),
    "multi_document": ("", 18, 1, ("YAML syntax error", "single document")),
    "alias_undefined": ("", 4, 7, ("undefined alias *nowhere",)),
    "top_level_list": (
        "",
        2,
        1,
        ("expected a mapping with keys robot, path, timing", "found a list of 3"),
    ),
    "top_level_text": ("", 2, 1, ("expected a mapping", "found the text 'just some text'")),
    "top_level_null": ("", 2, 1, ("expected a mapping", "found null")),
    "comments_only": ("", 0, 0, ("empty task file",)),
    # -- tags, aliases, duplicates ---------------------------------------------------------
    "tag_python_object": (
        "robot.a1",
        4,
        7,
        ("YAML tag !!python/object/apply:os.system is not allowed",),
    ),
    "tag_python_name": ("robot.a1", 4, 7, ("YAML tag !!python/name:os.getcwd is not allowed",)),
    "tag_custom": ("robot.a1", 4, 7, ("YAML tag !metres is not allowed",)),
    "tag_binary": ("name", 2, 7, ("YAML tag !!binary is not allowed",)),
    "tag_set": ("timing.law", 17, 8, ("YAML tag !!set is not allowed",)),
    "timestamp": (
        "timing.duration",
        16,
        13,
        ("!!timestamp is not allowed", "'2001-12-14' reads as a date"),
    ),
    # every value a list, every key unknown: all reported, the aliases never expanded
    "alias_bomb": ("name", 2, 7, ("expected text (a name for reports)", "found a list of 9")),
    "alias_bomb_in_value": (
        "robot.a1",
        4,
        7,
        ("expected a number (|AB| [m])", "found a list of 9"),
    ),
    "merge_key": ("robot.links.4", 9, 9, ("merge keys (<<) are not supported",)),
    "duplicate_key": ("robot.a1", 6, 3, ("duplicate key 'a1' (first given on line 4)",)),
    "duplicate_top_key": ("path", 15, 1, ("duplicate key 'path' (first given on line 11)",)),
    "duplicate_link": ("robot.links.3", 11, 5, ("duplicate key '3' (first given on line 8)",)),
    # -- keys --------------------------------------------------------------------------------
    "unknown_timming": ("timming", 15, 1, ("unknown key 'timming'; did you mean 'timing'?",)),
    "unknown_mas": ("robot.links.3.mas", 8, 9, ("unknown key 'mas'; did you mean 'mass'?",)),
    "unknown_link_6": ("robot.links.6", 11, 5, ("unknown key '6'; expected one of: 2, 3, 4, 5",)),
    "unknown_key_far": (
        "timing.velocity",
        18,
        3,
        ("unknown key 'velocity'; expected one of: duration, law, cruise_speed, x",),
    ),
    "null_key": ("timing", 18, 3, ("expected a plain key, found null",)),
    "missing_a1": ("robot.a1", 4, 3, ("missing required key 'a1' in robot", "|AB| [m]")),
    "missing_links": ("robot.links", 4, 3, ("missing required key 'links' in robot",)),
    "missing_link_4": ("robot.links.4", 7, 5, ("missing required key '4' in robot.links",)),
    "missing_inertia": (
        "robot.links.5.inertia",
        10,
        8,
        ("missing required key 'inertia' in robot.links.5",),
    ),
    "missing_path_y": ("path.y", 12, 3, ("missing required key 'y' in path",)),
    "missing_duration": ("timing.duration", 16, 3, ("missing required key 'duration' in timing",)),
    "missing_timing": ("timing", 2, 1, ("missing required key 'timing' at the top level",)),
    # -- wrong types -------------------------------------------------------------------------
    "duration_five": (
        "timing.duration",
        16,
        13,
        ("expected a number (t_f [s])", "found the text 'five'"),
    ),
    "duration_quoted": ("timing.duration", 16, 13, ("expected a number", "found the text '5'")),
    "a1_boolean": ("robot.a1", 4, 7, ("expected a number (|AB| [m])", "found a boolean (yes)")),
    "a1_true": ("robot.a1", 4, 7, ("expected a number", "found a boolean (true)")),
    "mass_null": ("robot.links.2.mass", 7, 15, ("expected a number (m2 [kg])", "found null")),
    "mass_empty": ("robot.links.2.mass", 8, 12, ("expected a number (m2 [kg])", "found null")),
    "a1_list": ("robot.a1", 4, 7, ("expected a number", "found a list of 1")),
    "name_mapping": ("name", 2, 7, ("expected text", "found a mapping")),
    "robot_scalar": ("robot", 3, 8, ("expected a mapping (keys a1, links)", "found the number 6")),
    "links_list": (
        "robot.links",
        7,
        5,
        ("expected a mapping (keys 2, 3, 4, 5)", "found a list of 4"),
    ),
    "from_scalar": (
        "path.from",
        13,
        9,
        ("expected a number (x [m])", "found a boolean (true)"),
    ),
    "from_boolean": (
        "path.from[0]",
        13,
        10,
        ("expected a number (x [m])", "found a boolean (true)"),
    ),
    "strict_maybe": ("checks.strict", 19, 11, ("expected true or false", "found the text 'maybe'")),
    "law_misspelt": (
        "timing.law",
        17,
        8,
        ("expected one of quintic, cubic", "did you mean 'quintic'?"),
    ),
    "torque_limit_three": (
        "checks.torque_limit",
        19,
        17,
        ("expected a list of two numbers", "found a list of 3"),
    ),
    "torque_limit_scalar": (
        "checks.torque_limit",
        19,
        17,
        ("expected a list of two numbers", "found the number 300"),
    ),
    "octal_ambiguous": ("robot.a1", 4, 7, ("ambiguous number 010", "octal in YAML 1.1")),
    "sexagesimal": ("timing.duration", 16, 13, ("expected a decimal number, found '1:30'",)),
    "number_too_long": ("robot.a1", 4, 7, ("more than 40 digits",)),
    "number_exponent_huge": ("robot.a1", 4, 7, ("exponent beyond ±30",)),
    # -- numbers that are not finite or physically wrong ---------------------------------------
    "a1_nan": ("robot.a1", 4, 7, ("expected a finite number (|AB| [m]), found NaN",)),
    "a1_nan_tagged": ("robot.a1", 4, 7, ("expected a finite number", "found NaN")),
    "a1_inf": ("robot.a1", 4, 7, ("expected a finite number", "found infinity (.inf)")),
    "mass_minus_inf": (
        "robot.links.2.mass",
        7,
        15,
        ("expected a finite number", "found infinity (-.inf)"),
    ),
    "from_nan": ("path.from[0]", 13, 10, ("expected a finite number (x [m]), found NaN",)),
    "a1_zero": ("robot.a1", 4, 7, ("expected a number > 0 (|AB| [m]), found 0",)),
    "a1_negative": ("robot.a1", 4, 7, ("expected a number > 0 (|AB| [m]), found -6",)),
    "mass_negative": (
        "robot.links.3.mass",
        8,
        15,
        ("expected a number >= 0 (m3 [kg]), found -1.0",),
    ),
    "inertia_negative": ("robot.links.4.inertia", 9, 29, ("expected a number >= 0", "found -0.10")),
    "r_negative": (
        "robot.links.5.r",
        10,
        38,
        ("expected a number >= 0 (r5 = |EG5| [m]), found -0.5",),
    ),
    "gravity_negative": ("robot.gravity", 5, 12, ("expected a number >= 0", "found -9.81")),
    "duration_zero": ("timing.duration", 16, 13, ("expected a number > 0 (t_f [s]), found 0",)),
    "duration_negative": (
        "timing.duration",
        16,
        13,
        ("expected a number > 0 (t_f [s]), found -5",),
    ),
    "torque_limit_zero": (
        "checks.torque_limit[0]",
        19,
        18,
        ("expected a number > 0 (|T1| limit [N m]), found 0",),
    ),
    "torque_limit_negative": (
        "checks.torque_limit[1]",
        19,
        23,
        ("expected a number > 0 (|T2| limit [N m]), found -1",),
    ),
    "min_slope_negative": ("checks.min_slope", 19, 14, ("expected a number >= 0", "found -0.1")),
    # -- polynomial expressions (the column points at the offending character) -----------------
    "poly_name": ("path.y", 12, 6, ("unknown name 'sin'",)),
    "poly_call_import": ("path.y", 12, 6, ("unknown name '__import__'",)),
    "poly_environ": ("path.y", 12, 7, ("unknown name '__import__'",)),
    "poly_timing_open": ("timing.x", 17, 15, ("bad polynomial in t", "unknown name 'len'")),
    "poly_attribute": ("path.y", 12, 7, ("attribute access ('.__class__') is not allowed",)),
    "poly_string": ("path.y", 12, 11, ('unexpected character "\'"',)),
    "poly_lambda": ("path.y", 12, 8, ("unknown name 'lambda'",)),
    "poly_negative_exponent": ("path.y", 12, 7, ("negative exponent", "integers 0..60")),
    "poly_fractional_exponent": ("path.y", 12, 7, ("fractional exponent", "integers 0..60")),
    "poly_enormous_exponent": ("path.y", 12, 7, ("exceeds the cap of 60",)),
    "poly_degree_61": ("path.y", 12, 7, ("exponent 61 exceeds the cap of 60",)),
    "poly_degree_product": ("path.y", 12, 19, ("degree 61 exceeds the cap of 60",)),
    "poly_chained_exponent": ("path.y", 12, 9, ("chained exponents are ambiguous",)),
    "poly_coefficients_huge": ("path.y", 12, 18, ("numbers too large", "16384 bits")),
    "poly_division_by_zero": ("path.y", 12, 7, ("division by zero",)),
    "poly_division_by_zero_expr": ("path.y", 12, 7, ("division by zero",)),
    "poly_division_by_x": ("path.y", 12, 7, ("division by a non-constant",)),
    "poly_implicit_product": (
        "path.y",
        12,
        7,
        ("expected an operator after '2', found name 'x'", "'*'"),
    ),
    "poly_unbalanced": ("path.y", 12, 12, ("expected ')', found end of expression",)),
    "poly_empty": ("path.y", 12, 7, ("empty expression",)),
    "poly_boolean": ("path.y", 12, 6, ("expected a polynomial in x", "found a boolean (true)")),
    "poly_deep": ("path.y", 12, 57, ("nested deeper than 50 levels",)),
    "poly_wrong_variable": ("timing.x", 17, 10, ("bad polynomial in t", "unknown name 'x'")),
    "composition_degree_law": (
        "path.y",
        12,
        6,
        ("y(x(t)) has degree 65", "path degree 13 × timing degree 5", "cap of 60"),
    ),
    "composition_degree_explicit": ("path.y", 12, 6, ("y(x(t)) has degree 64", "cap of 60")),
    # -- the motion: from/to and the timing law -------------------------------------------------
    "from_off_path": (
        "path.from",
        13,
        9,
        ("point (2, 0) is not on the path: y(2) = -1, found y = 0",),
    ),
    "to_off_path": (
        "path.to",
        14,
        7,
        ("point (4, 1.5) is not on the path: y(4) = 1, found y = 1.5",),
    ),
    "x_mismatch_start": (
        "path.from",
        13,
        9,
        ("path.from has x = 2 but timing.x gives x(0) = 2.5",),
    ),
    "x_mismatch_end": (
        "path.to",
        14,
        7,
        ("path.to has x = 4 but timing.x gives x(t_f = 5) = 3.5",),
    ),
    "law_without_from": ("timing.law", 16, 8, ("law quintic needs path.from",)),
    "law_without_from_to": ("timing.law", 15, 8, ("law quintic needs path.from and path.to",)),
    "law_and_x": ("timing", 16, 3, ("give either law or x, not both",)),
    "no_law_no_x": ("timing", 16, 3, ("missing timing law",)),
    # uncertainty (docs/robust.md): a percentage out of the number rules, no period
    "uncertainty_percent_exponent": (
        "uncertainty.links",
        21,
        10,
        ("expected a percentage", "exponent beyond ±30"),
    ),
    "uncertainty_link_percent_exponent": (
        "uncertainty.links.3.mass",
        21,
        21,
        ("expected a percentage", "exponent beyond ±30"),
    ),
    "uncertainty_no_period": (
        "uncertainty.period",
        21,
        3,
        ("missing required key 'period'", "every window"),
    ),
}


def input_error(path: Path | str) -> dict[str, object]:
    """Check one bad file with ``--format json``: exit 2, one stderr line, the error entry."""
    code, out, err = run_cli("check", "--format", "json", str(path))
    assert code == 2, (code, out, err)
    assert "Traceback" not in out + err
    doc = json.loads(out)
    assert doc["reports"] == [] and doc["internal_errors"] == []
    (e,) = doc["input_errors"]
    assert e["task"] == str(path)
    lines = err.strip().splitlines()
    assert lines == [x["text"] for x in e["errors"]], err  # one line per error
    assert all(line.startswith(f"{path}:") for line in lines), lines
    first = {k: v for k, v in e.items() if k != "errors"}
    assert e["errors"][0] == first  # the entry's own fields are its first error's
    return e


def test_every_corpus_file_has_an_expectation() -> None:
    assert sorted(p.stem for p in BAD.glob("*.yaml")) == sorted(CASES)


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_task_file_exits_2_with_a_precise_message(
    name: str, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    key, line, column, fragments = CASES[name]
    monkeypatch.chdir(tmp_path)  # anything a hostile file managed to write would land here
    path = BAD / f"{name}.yaml"
    e = input_error(path)
    assert (e["key"] or "", e["line"] or 0, e["column"] or 0) == (key, line, column), e
    for fragment in fragments:
        assert fragment in e["message"], (fragment, e["message"])
    # the one line on stderr is file:line:col: key: message
    where = f"{path}" + (f":{line}" if line else "") + (f":{column}" if column else "")
    expected_start = f"{where}: {key}: " if key else f"{where}: "
    assert e["text"].startswith(expected_start), e["text"]
    # the API raises the same error, and only TaskFileError
    with pytest.raises(TaskFileError) as exc:
        load_task(path)
    assert (exc.value.key, exc.value.line, exc.value.column) == (key, line, column)
    assert list(tmp_path.iterdir()) == []


def test_the_corpus_differs_from_a_valid_task_only_by_its_mistake() -> None:
    task = parse_task(GOOD, "good.yaml")
    assert task.name == "good" and task.law == "quintic"


# -- the file itself: generated into tmp_path ------------------------------------------------


def test_no_such_file(tmp_path: Path) -> None:
    e = input_error(tmp_path / "nope.yaml")
    assert e["message"] == "no such file"


def test_a_directory_given_as_a_file_is_rejected(tmp_path: Path) -> None:
    # (the CLI searches a directory argument for *.yaml; the API names the problem)
    with pytest.raises(TaskFileError, match="is a directory"):
        load_task(tmp_path)


def test_a_fifo_is_not_read(tmp_path: Path) -> None:
    fifo = tmp_path / "pipe.yaml"
    os.mkfifo(fifo)
    with pytest.raises(TaskFileError, match="not a regular file"):
        load_task(fifo)  # opening a FIFO would block: it must be refused before


def test_unreadable_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "secret.yaml"
    path.write_text(GOOD)

    def denied(*args: object, **kwargs: object) -> None:
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(reading, "open", denied, raising=False)  # root could read a chmod 000 file
    e = input_error(path)
    assert e["message"] == "cannot read the file: Permission denied"


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads a mode-000 file anyway")
def test_unreadable_file_for_real(tmp_path: Path) -> None:
    path = tmp_path / "secret.yaml"
    path.write_text(GOOD)
    path.chmod(0)
    with pytest.raises(TaskFileError, match="cannot read the file"):
        load_task(path)


@pytest.mark.parametrize(
    "content", [b"", b"\n\n   \n", b"# only a comment\n", b"---\n", b"\xef\xbb\xbf"]
)
def test_empty_file(content: bytes, tmp_path: Path) -> None:
    path = tmp_path / "empty.yaml"
    path.write_bytes(content)
    e = input_error(path)
    assert e["message"].startswith("empty task file")


def test_not_utf8(tmp_path: Path) -> None:
    path = tmp_path / "latin1.yaml"
    path.write_bytes(b"# a comment\nname: caf\xe9\n")
    e = input_error(path)
    assert (e["line"], e["column"]) == (2, 10)
    assert "not UTF-8 text: byte 0xe9 at offset 21" in e["message"]


def test_utf16(tmp_path: Path) -> None:
    path = tmp_path / "utf16.yaml"
    path.write_bytes(GOOD.encode("utf-16"))
    e = input_error(path)
    assert e["message"] == "UTF-16 text, expected UTF-8: save the file as UTF-8"


def test_binary(tmp_path: Path) -> None:
    path = tmp_path / "image.yaml"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR" + bytes(range(256)))
    e = input_error(path)
    assert e["message"] == "binary file (NUL byte at offset 8), expected YAML text"


def test_control_character(tmp_path: Path) -> None:
    path = tmp_path / "bell.yaml"
    path.write_bytes(b"name: a\x07b\n")
    e = input_error(path)
    assert (e["line"], e["column"]) == (1, 8)
    assert "control character U+0007" in e["message"]


def test_characters_rejected_before_parsing_are_those_yaml_rejects() -> None:
    """The loader's own scan rejects exactly the characters YAML's reader does (PyYAML's
    NON_PRINTABLE), every code point checked: it only finds them first, with a line."""
    every = "".join(map(chr, range(0x110000)))
    rejected = [m.start() for m in source._NON_PRINTABLE.finditer(every)]
    assert rejected == [m.start() for m in yaml.reader.Reader.NON_PRINTABLE.finditer(every)]


def test_larger_than_one_mib(tmp_path: Path) -> None:
    path = tmp_path / "huge.yaml"
    path.write_text(GOOD + "#" * MAX_BYTES)
    e = input_error(path)
    size = len(GOOD) + MAX_BYTES
    assert e["message"] == f"file too large: {size} bytes, the cap is 1048576 bytes (1 MiB)"


def test_exactly_one_mib_is_still_read(tmp_path: Path) -> None:
    path = tmp_path / "padded.yaml"
    pad = MAX_BYTES - len(GOOD) - 1
    path.write_text(GOOD + "#" * pad + "\n")
    assert path.stat().st_size == MAX_BYTES
    assert load_task(path).name == "good"


def test_parse_task_caps_text_and_bytes_alike() -> None:
    with pytest.raises(TaskFileError, match="file too large"):
        parse_task(b" " * (MAX_BYTES + 1))
    with pytest.raises(TaskFileError, match="file too large"):
        parse_task(" " * (MAX_BYTES + 1))


@pytest.mark.parametrize(
    "text",
    [
        "[" * 200_000,  # libyaml's composer recurses in C: this used to kill the process
        "name: " + "[" * 40 + "]" * 40,
        "".join("  " * i + "- \n" for i in range(100)),
        "a:\n" + "".join("  " * i + "b:\n" for i in range(1, 60)),
    ],
    ids=["flow-200000", "flow-40", "block-list-100", "block-map-60"],
)
def test_deep_nesting_is_rejected_without_crashing(text: str) -> None:
    # rprpr's own message, located where the 33rd level opens, whatever limit the machine's
    # libyaml has of its own (PyYAML 6.0.4's stops a flow collection at 1,000 levels)
    with pytest.raises(TaskFileError, match="nested deeper than 32 levels") as e:
        parse_task(text)
    assert len(e.value.errors) == 1
    assert "\n" not in str(e.value)
    assert e.value.line >= 1 and e.value.column >= 1
    if text.startswith("["):
        assert (e.value.line, e.value.column) == (1, 33)


def test_too_many_nodes() -> None:
    text = GOOD.replace("name: good", "name: [" + ", ".join(["1"] * 20_000) + "]")
    with pytest.raises(TaskFileError, match="too many YAML nodes"):
        parse_task(text)


def test_alias_bomb_is_bounded_in_time() -> None:
    # 10 levels of 10: 10^10 strings if expanded; the node tree shares them instead.
    levels = ["&a0 [" + ", ".join(["lol"] * 10) + "]"]
    levels += [f"&a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, 11)]
    as_keys = "\n".join(f"a{i}: {v}" for i, v in enumerate(levels)) + "\nrobot: *a10\n"
    in_name = GOOD.replace("name: good", "name: [" + ", ".join(levels) + "]")
    in_a1 = GOOD.replace("  a1: 6", "  a1: [" + ", ".join(levels) + "]")
    start = time.process_time()
    with pytest.raises(TaskFileError, match="unknown key 'a0'"):
        parse_task(as_keys)
    with pytest.raises(TaskFileError, match="expected text"):
        parse_task(in_name)
    with pytest.raises(TaskFileError, match="expected a number"):
        parse_task(in_a1)
    assert time.process_time() - start < 1.0  # CPU seconds: deaf to a busy machine


def test_aliases_of_whole_values_are_fine() -> None:
    text = GOOD.replace("    2: {", "    2: &leg {").replace(
        "    4: {mass: 2.0, inertia: 0.10, r: 0.5}", "    4: *leg"
    )
    task = parse_task(text)
    assert task.robot.links[4] == task.robot.links[2]


@pytest.mark.parametrize(
    ("spelling", "value"),
    [
        ("6", Fraction(6)),
        ("+6.", Fraction(6)),
        ("0.1", Fraction(1, 10)),  # the decimal, not the nearest binary float
        ("1e3", Fraction(1000)),  # YAML 1.2 (and editors) read it as a number
        ("1E-3", Fraction(1, 1000)),
        ("0x1f", Fraction(31)),
        ("0o17", Fraction(15)),
        ("1_000", Fraction(1000)),
        ("!!float 6", Fraction(6)),
    ],
)
def test_number_spellings_that_are_read_exactly(spelling: str, value: Fraction) -> None:
    a1 = parse_task(GOOD.replace("  a1: 6", f"  a1: {spelling}")).robot.a1
    assert Fraction(int(a1.p), int(a1.q)) == value


@pytest.mark.parametrize(
    ("spelling", "message"),
    [
        ("017", "ambiguous number 017"),
        ("!!str 6", "found the text '6'"),
        ("'6'", "found the text '6'"),
        ("4/25", "a fraction is only allowed in path.y, timing.x, path.from and path.to"),
        ("6 m", "found the text '6 m'"),
        ("1:30", "expected a decimal number"),
        ("-.INF", "found infinity"),
        (".NaN", "found NaN"),
    ],
)
def test_number_spellings_that_are_rejected(spelling: str, message: str) -> None:
    with pytest.raises(TaskFileError) as exc:
        parse_task(GOOD.replace("  a1: 6", f"  a1: {spelling}"))
    assert exc.value.key == "robot.a1"
    assert message in exc.value.message


def test_expression_longer_than_the_cap() -> None:
    text = GOOD.replace("0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2", "x" + " + 0" * 2000)
    with pytest.raises(TaskFileError, match="longer than 4000 characters") as exc:
        parse_task(text)
    assert exc.value.key == "path.y"


def test_non_ascii_digits_are_not_numbers() -> None:
    text = GOOD.replace("0.8*x^3", "\u0663*x^3")  # ARABIC-INDIC DIGIT THREE
    with pytest.raises(TaskFileError, match="unexpected character"):
        parse_task(text)


# -- nothing in a task file ever runs ---------------------------------------------------------

HOSTILE = [
    ("name", f"!!python/object/apply:os.mkdir [{CANARY}]"),
    ("name", f"!!python/object/apply:os.putenv [{CANARY_ENV}, '1']"),
    ("name", f"!!python/object/new:os.mkdir [{CANARY}]"),
    ("name", f"!!python/object/apply:subprocess.check_call [[touch, {CANARY}]]"),
    ("path.y", f"\"__import__('os').mkdir('{CANARY}')\""),
    ("path.y", f"\"__import__('os').environ.__setitem__('{CANARY_ENV}', '1')\""),
    ("path.y", f"\"open('{CANARY}', 'w').write('x') and x\""),
    ("path.y", '"[c for c in ().__class__.__base__.__subclasses__()]"'),
    ("path.y", f"\"eval(\\\"__import__('os').mkdir('{CANARY}')\\\")\""),
    ("path.y", f"\"x; __import__('os').mkdir('{CANARY}')\""),
    ("timing.x", f'"2 + t*0 + exec(\\"import os; os.mkdir(\'{CANARY}\')\\")"'),
]


@pytest.mark.parametrize(("key", "value"), HOSTILE)
def test_hostile_input_has_no_side_effect(
    key: str,
    value: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv(CANARY_ENV, raising=False)
    if key == "name":
        text = GOOD.replace("name: good", f"name: {value}")
    elif key == "path.y":
        text = GOOD.replace("0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2", value)
    else:
        text = GOOD.replace("  law: quintic", f"  x: {value}").replace(
            "  from: [2, -1]\n  to: [4, 1]\n", ""
        )
    path = tmp_path / "hostile.yaml"
    path.write_text(text)
    e = input_error(path)
    assert e["key"] == key
    assert sorted(p.name for p in tmp_path.iterdir()) == ["hostile.yaml"]
    assert CANARY_ENV not in os.environ
    assert os.getenv(CANARY_ENV) is None


def test_the_canary_would_catch_a_loader_that_constructs(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Control: the same YAML through an unsafe loader does create the canary."""
    monkeypatch.chdir(tmp_path)
    yaml.unsafe_load(f"name: !!python/object/apply:os.mkdir [{CANARY}]")
    assert (tmp_path / CANARY).is_dir()


# -- batches: one bad file among good ones ------------------------------------------------------


def test_one_bad_file_among_good_ones(tmp_path: Path) -> None:
    good1 = str(ROOT / "configs" / "paper_path2.rprpr.yaml")
    good2 = str(ROOT / "configs" / "paper_path1.rprpr.yaml")
    bad = str(BAD / "unknown_timming.yaml")
    code, out, err = run_cli("check", "--format", "json", good1, bad, good2)
    assert code == 2
    doc = json.loads(out)
    assert [(r["task"], r["verdict"]) for r in doc["reports"]] == [(good1, "pass"), (good2, "fail")]
    assert doc["reports"][0]["singularities"][0]["order"] == 1
    assert doc["reports"][1]["singularities"][0]["order"] == 3
    (e,) = doc["input_errors"]
    assert (e["task"], e["key"], e["line"]) == (bad, "timming", 15)
    assert doc["internal_errors"] == []
    assert err.strip().splitlines() == [e["text"]]


def test_a_batch_of_only_good_files_is_not_tainted() -> None:
    good = str(ROOT / "configs" / "paper_path2.rprpr.yaml")
    code, out, _ = run_cli("check", "--format", "json", good)
    assert code == 0
    assert json.loads(out)["input_errors"] == []


def test_the_whole_corpus_in_one_run() -> None:
    files = sorted(str(p) for p in BAD.glob("*.yaml"))
    code, out, err = run_cli("check", "--format", "json", *files)
    assert code == 2
    doc = json.loads(out)
    assert doc["reports"] == [] and doc["internal_errors"] == []
    assert sorted(e["task"] for e in doc["input_errors"]) == files
    lines = err.strip().splitlines()
    assert lines == [x["text"] for e in doc["input_errors"] for x in e["errors"]]
    assert len(lines) >= len(files)


# -- the real process: one line, exit 2, no traceback -------------------------------------------


# The smoke corpus kept beside the clone (shared/smoke), copied here so that every clone
# collects and runs the same tests wherever it sits.
SMOKE_TASKS = {
    "s01_syntax.yaml": """\
name: broken yaml
robot: {a1: 6, links: [
""",
    "s02_code_in_expression.yaml": """\
name: an expression that must never run
robot:
  a1: 6
  links:
    2: {mass: 2.0, inertia: 0.1, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.1, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
path:
  y: __import__('os').getcwd()
timing:
  duration: 5
  x: 2 + t
""",
    "s03_missing_a1.yaml": """\
name: no base length
robot:
  links:
    2: {mass: 2.0, inertia: 0.1, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.1, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
path:
  y: x - 3
timing:
  duration: 2
  x: 2 + t
""",
}
SHARED_SMOKE = ROOT.parent / "shared" / "smoke"


def _one_line_exit_2(
    paths: list[Path], cwd: Path, *, process: bool = True, forked: bool = False
) -> None:
    """``rprpr check PATHS`` in ``cwd`` (as a new interpreter, as a process forked from this
    one and set up as a fresh one (``forked``), or in this one): exit 2, one stderr line per
    file naming it, no traceback, and nothing written into ``cwd``."""
    if forked:
        done = run_rprpr(["check", *map(str, paths)], cwd, timeout=60)
        code, out, err = done.returncode, done.stdout, done.stderr
    elif process:
        proc = subprocess.run(
            [sys.executable, "-m", "rprpr", "check", *map(str, paths)],
            capture_output=True,
            text=True,
            cwd=cwd,
            timeout=60,
            check=False,
        )
        code, out, err = proc.returncode, proc.stdout, proc.stderr
    else:
        with chdir(cwd):
            code, out, err = run_cli("check", *map(str, paths))
    assert code == 2, (code, out, err)
    assert "Traceback" not in out + err
    lines = err.strip().splitlines()
    assert len(lines) == len(paths), err
    assert all(ln.startswith(f"{p}:") for ln, p in zip(lines, paths, strict=True)), err
    assert list(cwd.iterdir()) == []


PROCESS_CASES = [*SMOKE_TASKS, "poly_call_import.yaml", "tag_python_object.yaml"]


def _process_case(name: str, folder: Path) -> Path:
    if name not in SMOKE_TASKS:
        return BAD / name
    path = folder / "smoke" / name
    path.parent.mkdir(exist_ok=True)
    path.write_text(SMOKE_TASKS[name], encoding="utf-8")
    return path


@pytest.mark.parametrize("name", PROCESS_CASES)
def test_each_exits_2_with_one_line(name: str, tmp_path: Path) -> None:
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    _one_line_exit_2([_process_case(name, tmp_path)], cwd, process=False)


def test_process_exits_2_with_one_line_per_file(tmp_path: Path) -> None:
    """The same files in one real process (the command line's path from start-up to exit
    status): one line each, in order."""
    cwd = tmp_path / "cwd"
    cwd.mkdir()
    _one_line_exit_2([_process_case(name, tmp_path) for name in PROCESS_CASES], cwd)


def test_shared_smoke_corpus_beside_the_clone_exits_2_with_one_line_each(tmp_path: Path) -> None:
    files = sorted(SHARED_SMOKE.glob("*.yaml")) if SHARED_SMOKE.is_dir() else []
    if not files:
        pytest.skip(f"no shared smoke corpus at {SHARED_SMOKE} (its copies above still run)")
    _one_line_exit_2(files, tmp_path, forked=True)  # the new interpreter's path: just above

"""A 5R five-bar in a task file (``robot.mechanism: 5R``): read to the exact ``FiveBar``,
validated (one located error per problem, exit 2), written back by the writer, and
accepted or rejected by the shipped JSON Schema as by the loader.

The reach of a leg is checked here against the geometry written apart from the loader:
leg i reaches E iff |l_p - l_d| <= |E - base_i| <= l_p + l_d (the triangle inequality),
compared exactly on squares with Python's ``Fraction``.
"""

from __future__ import annotations

import json
import re
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest
import yaml
from flint import fmpq, fmpq_poly

from rprpr.io.loader import load_task, parse_task
from rprpr.io.schema import FIVE_BAR_ROBOT, Spec
from rprpr.io.writer import task_text
from rprpr.model.errors import TaskFileError
from rprpr.model.five_bar import FiveBar
from rprpr.model.task import Link
from tests.conftest import run_cli
from tests.io.test_schema import VALIDATOR, schema_accepts
from tests.io.test_walk import dump

DATA = Path(__file__).resolve().parent / "data"
DEXTAR = DATA / "five_bar_dextar.rprpr.yaml"

# a 5R task: base 0.2 m, proximal 0.2 m, distal 0.3 m, along y = 0.3 from x = 0 to 0.2
GOOD = """\
name: five-bar
robot:
  mechanism: 5R
  base: 0.2
  lengths: [0.2, 0.2, 0.3, 0.3]
  modes: [+1, -1]
  links:
    1: {mass: 0.25, inertia: 0.00083, r: 0.1}
    2: {mass: 0.25, inertia: 0.00083, r: 0.1}
    3: {mass: 0.15, inertia: 0.001125, r: 0.15}
    4: {mass: 0.15, inertia: 0.001125, r: 0.15}
path:
  y: 0.3
  from: [0, 0.3]
  to: [0.2, 0.3]
timing:
  duration: 1
  law: quintic
"""


def _jsonish(text: str) -> object:
    """A task file as JSON sees it (mapping keys as strings: ``1:`` is the key "1")."""
    return json.loads(json.dumps(yaml.safe_load(text)))


def _q(text: str) -> fmpq:
    f = Fraction(text)
    return fmpq(f.numerator, f.denominator)


def _variant(old: str, new: str, text: str = GOOD) -> str:
    assert old in text, old
    return text.replace(old, new)


def _rprpr_text() -> str:
    from tests.corpora.test_bad_tasks import GOOD as RPRPR  # the paper's path 2

    return RPRPR


def _error(text: str) -> TaskFileError:
    with pytest.raises(TaskFileError) as info:
        parse_task(text, "t.yaml")
    return info.value


def _line(text: str, fragment: str) -> int:
    (line,) = [i for i, ln in enumerate(text.splitlines(), 1) if fragment in ln]
    return line


# -- valid files read to the exact FiveBar ---------------------------------------------


def test_the_dextar_example_reads_to_its_exact_five_bar() -> None:
    robot = load_task(DEXTAR).robot
    links = {
        1: Link(_q("0.25"), _q("0.00083"), _q("0.1")),
        2: Link(_q("0.25"), _q("0.00083"), _q("0.1")),
        3: Link(_q("0.15"), _q("0.001125"), _q("0.15")),
        4: Link(_q("0.15"), _q("0.001125"), _q("0.15")),
    }
    assert robot.five_bar == FiveBar(
        a=fmpq(1, 5), lengths=(fmpq(1, 5), fmpq(1, 5), fmpq(3, 10), fmpq(3, 10)),
        modes=(1, -1), links=links,
    )  # fmt: skip
    assert robot.mechanism == "5R"
    assert robot.a1 == fmpq(1, 5) and robot.links == links  # the robot's |AB| and links
    assert robot.gravity == fmpq(981, 100)
    assert robot.actuation == "revolute"  # the motors at A and B


def test_the_dextar_example_starts_inside_both_legs_reach() -> None:
    """Independently of the loader: |E - A| and |E - B| at path.from within [0.1, 0.5]."""
    doc = yaml.safe_load(DEXTAR.read_text(encoding="utf-8"))
    x, y = (Fraction(str(c)) for c in doc["path"]["from"])
    for base in (Fraction(0), Fraction(str(doc["robot"]["base"]))):
        assert Fraction(1, 10) ** 2 < (x - base) ** 2 + y**2 < Fraction(1, 2) ** 2


@pytest.mark.parametrize(
    ("modes", "expected"),
    [("[+1, -1]", (1, -1)), ("[-1, 1]", (-1, 1)), ("[1, 1]", (1, 1)), ("[-1, -1.0]", (-1, -1))],
)
def test_the_working_modes_are_two_signs(modes: str, expected: tuple[int, int]) -> None:
    robot = parse_task(_variant("modes: [+1, -1]", f"modes: {modes}")).robot
    assert robot.five_bar is not None
    assert robot.five_bar.modes == expected
    assert all(type(e) is int for e in robot.five_bar.modes)


def test_gravity_and_the_default_mechanism() -> None:
    assert parse_task(_variant("  links:", "  gravity: 1.62\n  links:")).robot.gravity == fmpq(
        162, 100
    )
    rprpr = load_task(Path(__file__).resolve().parents[2] / "configs" / "paper_path2.rprpr.yaml")
    assert (rprpr.robot.mechanism, rprpr.robot.five_bar) == ("rprpr", None)
    given = _variant("  a1: 6\n", "  mechanism: rprpr\n  a1: 6\n", _rprpr_text())
    assert parse_task(given).robot == parse_task(_rprpr_text()).robot


def test_every_motion_form_gives_the_start_point_checked() -> None:
    """motion.pieces and waypoints start where their first piece does: a start out of
    reach is found whatever form the motion takes."""
    head = GOOD.split("path:")[0]
    pieces = head + "motion:\n  pieces:\n    - {until: 1, x: 0.45 - t/10, y: 0.3}\n"
    e = _error(pieces)
    assert e.key == "motion.pieces[0].x" and "out of reach of leg 1" in e.message
    waypoints = head + "motion:\n  waypoints:\n"
    waypoints += "    - {t: 0, p: [0.45, 0.3]}\n    - {t: 1, p: [0.1, 0.3]}\n"
    e = _error(waypoints)
    assert e.key == "motion.waypoints[0].p" and "out of reach of leg 1" in e.message
    explicit = _variant("  law: quintic", "  x: 0.45 - t/2").replace(
        "  from: [0, 0.3]\n  to: [0.2, 0.3]\n", ""
    )
    e = _error(explicit)
    assert e.key == "timing.x" and "E(0) = (0.45, 0.3)" in e.message
    assert parse_task(head + "motion:\n  pieces:\n    - {until: 1, x: t/10, y: 0.3}\n")


# -- bad inputs: one located error each -------------------------------------------------

_OUT = "the start point E(0) = ({x}, 0.3) is out of reach of leg {i} (at {p}): expected"
BAD: dict[str, tuple[str, str, str, str]] = {
    # name: (the text, the key, the line's fragment, the whole message)
    "mechanism_name": (
        _variant("mechanism: 5R", "mechanism: 5r"),
        "robot.mechanism",
        "mechanism:",
        "expected one of rprpr, 5R, found the text '5r'; did you mean '5R'?",
    ),
    "mechanism_unknown": (
        _variant("mechanism: 5R", "mechanism: delta"),
        "robot.mechanism",
        "mechanism:",
        "expected one of rprpr, 5R, found the text 'delta'",
    ),
    "missing_lengths": (
        _variant("  lengths: [0.2, 0.2, 0.3, 0.3]\n", ""),
        "robot.lengths",
        "mechanism: 5R",
        "missing required key 'lengths' in robot ([l1, l2, l3, l4] [m], each > 0: the"
        " proximal links |AC| and |BD|, then the distal links |CE| and |DE|)",
    ),
    "missing_modes": (
        _variant("  modes: [+1, -1]\n", ""),
        "robot.modes",
        "mechanism: 5R",
        "missing required key 'modes' in robot ([e1, e2], each +1 or -1: the working modes"
        " at t = 0 (e1 = +1: the elbow C to the left of AE, seen from A towards E; e2 = +1:"
        " D to the left of BE))",
    ),
    "three_lengths": (
        _variant("[0.2, 0.2, 0.3, 0.3]", "[0.2, 0.2, 0.3]"),
        "robot.lengths",
        "lengths:",
        "expected a list of four numbers [l1 = |AC| [m], l2 = |BD| [m], l3 = |CE| [m],"
        " l4 = |DE| [m]], each > 0, found a list of 3",
    ),
    "zero_length": (
        _variant("[0.2, 0.2, 0.3, 0.3]", "[0.2, 0.2, 0, 0.3]"),
        "robot.lengths[2]",
        "lengths:",
        "expected a number > 0 (l3 = |CE| [m]), found 0",
    ),
    "mode_zero": (
        _variant("modes: [+1, -1]", "modes: [+1, 0]"),
        "robot.modes[1]",
        "modes:",
        "expected +1 or -1 (e2 (the elbow D)), found 0",
    ),
    "mode_two": (
        _variant("modes: [+1, -1]", "modes: [2, -1]"),
        "robot.modes[0]",
        "modes:",
        "expected +1 or -1 (e1 (the elbow C)), found 2",
    ),
    "mode_word": (
        _variant("modes: [+1, -1]", "modes: [up, -1]"),
        "robot.modes[0]",
        "modes:",
        "expected +1 or -1 (e1 (the elbow C)), found the text 'up'",
    ),
    "one_mode": (
        _variant("modes: [+1, -1]", "modes: [1]"),
        "robot.modes",
        "modes:",
        "expected a list of two signs [e1 (the elbow C), e2 (the elbow D)], each +1 or -1,"
        " found a list of 1",
    ),
    "a1_on_a_5r": (
        _variant("base: 0.2", "a1: 0.2"),
        "robot.a1",
        "a1:",
        "a1 is for mechanism: rprpr; a 5R takes base (|AB| [m]) instead",
    ),
    "actuation_on_a_5r": (
        _variant("  base: 0.2\n", "  base: 0.2\n  actuation: revolute\n"),
        "robot.actuation",
        "actuation:",
        "actuation is for mechanism: rprpr; a 5R is driven by its motors at A and B"
        " (revolute), with nothing to choose",
    ),
    "rprpr_links_on_a_5r": (
        _variant("path:", "    5: {mass: 0.15, inertia: 0.001125, r: 0.15}\npath:"),
        "robot.links.5",
        "5: {",
        "unknown key '5'; expected one of: 1, 2, 3, 4",
    ),
    "base_without_mechanism": (
        _variant("  mechanism: 5R\n", ""),
        "robot.base",
        "base:",
        "base, lengths, modes are for mechanism: 5R: add mechanism: 5R in robot (the"
        " default is rprpr)",
    ),
    "base_on_an_rprpr": (
        _variant("  a1: 6\n", "  a1: 6\n  base: 6\n", _rprpr_text()),
        "robot.base",
        "base:",
        "base is for mechanism: 5R (the all-revolute five-bar); the rprpr takes a1"
        " (|AB| [m]) instead",
    ),
    "uncertainty_on_a_5r": (
        GOOD + "checks:\n  torque_limit: [5, 5]\nuncertainty:\n  links: 5%\n  period: 0.001\n",
        "uncertainty",
        "links: 5%",
        "uncertainty is for mechanism: rprpr (its links 2..5); the robust audit of a 5R is"
        " not available in this build",
    ),
    "legs_cannot_meet": (
        _variant("base: 0.2", "base: 1.2"),
        "robot.lengths",
        "lengths:",
        "these lengths make no five-bar: the legs cannot meet: l1 + l3 + l2 + l4 = 1 m is"
        " shorter than base = 1.2 m (expected lengths for which some point is within reach"
        " of both legs)",
    ),
    "leg_2_inside_leg_1s_hole": (
        _variant("[0.2, 0.2, 0.3, 0.3]", "[2, 0.1, 0.2, 0.1]"),
        "robot.lengths",
        "lengths:",
        "these lengths make no five-bar: leg 2 cannot reach out of leg 1's hole: leg 1"
        " reaches no point nearer its base than |l1 - l3| = 1.8 m, leg 2 none farther from"
        " it than 0.4 m (expected lengths for which some point is within reach of both legs)",
    ),
    "leg_1_inside_leg_2s_hole": (
        _variant("[0.2, 0.2, 0.3, 0.3]", "[0.1, 0.3, 0.1, 2]"),
        "robot.lengths",
        "lengths:",
        "these lengths make no five-bar: leg 1 cannot reach out of leg 2's hole: leg 2"
        " reaches no point nearer its base than |l2 - l4| = 1.7 m, leg 1 none farther from"
        " it than 0.4 m (expected lengths for which some point is within reach of both legs)",
    ),
    "start_out_of_leg_1s_reach": (
        _variant("from: [0, 0.3]", "from: [0.45, 0.3]"),
        "path.from",
        "from:",
        _OUT.format(x="0.45", i=1, p="A")
        + " |E - A| in [|l1 - l3|, l1 + l3] = [0.1, 0.5] m, found |E - A| = 0.540833 m",
    ),
    "start_out_of_leg_2s_reach": (
        _variant("from: [0, 0.3]", "from: [-0.25, 0.3]"),
        "path.from",
        "from:",
        _OUT.format(x="-0.25", i=2, p="B")
        + " |E - B| in [|l2 - l4|, l2 + l4] = [0.1, 0.5] m, found |E - B| = 0.540833 m",
    ),
    "start_where_leg_1_is_stretched": (
        _variant("from: [0, 0.3]", "from: [0.4, 0.3]"),
        "robot.modes[0]",
        "modes:",
        "working mode e1 = +1 does not exist at the start point E(0) = (0.4, 0.3): leg 1 is"
        " stretched there (|E - A| = l1 + l3 = 0.5 m), where its two working modes"
        " coincide; expected a start point where leg 1 is neither stretched nor folded",
    ),
}


@pytest.mark.parametrize("name", sorted(BAD))
def test_each_bad_input_is_one_located_error(name: str) -> None:
    text, key, fragment, message = BAD[name]
    e = _error(text)
    assert (e.key, e.message) == (key, message)
    assert e.line == _line(text, fragment)
    assert e.column > 0
    assert len(e.errors) == 1, [str(x) for x in e.errors]


def test_the_start_check_agrees_with_the_triangle_inequality() -> None:
    """Start points on a grid about both bases: the loader accepts exactly those strictly
    inside both annuli, says "out of reach" outside one, and "stretched" or "folded" on
    a circle (the grid holds points on each of the four circles)."""
    path = "  y: {y}\n  from: [{x}, {y}]\n  to: [{x2}, {y}]\n"
    old = "  y: 0.3\n  from: [0, 0.3]\n  to: [0.2, 0.3]\n"
    seen = set()
    for i in range(-12, 14):
        for j in range(0, 11):
            x, y = Fraction(i, 20), Fraction(j, 20)
            inside = []
            for base in (Fraction(0), Fraction(1, 5)):
                r2 = (x - base) ** 2 + y**2
                inside.append(
                    "in" if Fraction(1, 100) < r2 < Fraction(1, 4)
                    else "on" if r2 in (Fraction(1, 100), Fraction(1, 4)) else "out"
                )  # fmt: skip
            text = _variant(old, path.format(x=float(x), y=float(y), x2=0.1))
            try:
                parse_task(text)
                found = "accepted"
            except TaskFileError as e:
                found = " | ".join(x.message for x in e.errors)
            if inside == ["in", "in"]:
                assert found == "accepted", (x, y, found)
            elif "out" in inside:
                assert "out of reach of leg" in found, (x, y, found)
            else:
                assert re.search("is (stretched|folded) there", found), (x, y, found)
            seen.add(tuple(inside))
    assert {("in", "in"), ("on", "in"), ("in", "on"), ("out", "in"), ("in", "out")} <= seen


_PATH = "  y: 0.3\n  from: [0, 0.3]\n  to: [0.2, 0.3]\n"


def test_a_stretched_leg_is_found_exactly_where_floats_miss_it() -> None:
    """l1 = 0.1, l3 = 0.2 and E = (0.18, 0.24): |E| = 0.3 = l1 + l3 exactly, where the
    float evaluation of D1 is not 0."""
    text = _variant("[0.2, 0.2, 0.3, 0.3]", "[0.1, 0.2, 0.2, 0.3]")
    text = _variant(_PATH, "  y: 0.24\n  from: [0.18, 0.24]\n  to: [0.1, 0.24]\n", text)
    l1, l3, x, y = 0.1, 0.2, 0.18, 0.24  # |E| = 0.3 = l1 + l3 exactly (a 3-4-5 triangle)
    k = (l1**2 + x**2 + y**2 - l3**2) / 2
    assert l1**2 * (x**2 + y**2) - k**2 != 0  # floats cannot tell
    e = _error(text)
    assert e.key == "robot.modes[0]"
    assert "leg 1 is stretched there (|E - A| = l1 + l3 = 0.3 m)" in e.message


def test_a_folded_leg_is_a_mode_that_does_not_exist() -> None:
    text = _variant(_PATH, "  y: 0.1\n  from: [0.2, 0.1]\n  to: [0.1, 0.1]\n")
    e = _error(text)
    assert (e.key, len(e.errors)) == ("robot.modes[1]", 1)
    assert e.message.startswith("working mode e2 = -1 does not exist at the start point")
    assert "leg 2 is folded there (|E - B| = |l2 - l4| = 0.1 m)" in e.message


def test_every_error_of_a_bad_5r_is_listed() -> None:
    """Independent mistakes are each reported (as for the RPRPR): a1 for base, a bad mode."""
    text = _variant("base: 0.2", "a1: 0.2").replace("modes: [+1, -1]", "modes: [+1, 0]")
    e = _error(text)
    assert [x.key for x in e.errors] == ["robot.a1", "robot.modes[1]"]


@pytest.mark.parametrize("name", sorted(BAD))
def test_the_command_line_says_it_in_one_line_and_exits_2(name: str, tmp_path: Path) -> None:
    text, key, _, message = BAD[name]
    task = tmp_path / f"{name}.rprpr.yaml"
    task.write_text(text, encoding="utf-8")
    code, out, _ = run_cli("check", "--format", "concise", str(task))
    assert code == 2
    e = _error(text)
    assert out == f"{task}:{e.line}:{e.column}: RPR001 [error] {key}: {message}\n"


def test_a_mode_that_does_not_exist_points_at_the_sign() -> None:
    text, _, fragment, _ = BAD["start_where_leg_1_is_stretched"]
    e = _error(text)
    assert (e.line, e.column) == (
        _line(text, fragment),
        text.splitlines()[e.line - 1].index("+1") + 1,
    )


@pytest.mark.parametrize("key", ["base", "lengths", "modes", "links", "links.1", "links.4.r"])
def test_a_5r_missing_a_required_key_says_which(key: str) -> None:
    doc = yaml.safe_load(GOOD)
    *parent, last = ["robot", *key.split(".")]
    mapping = doc
    for p in parent:
        mapping = mapping[int(p) if p.isdigit() else p]
    del mapping[int(last) if last.isdigit() else last]
    e = _error(dump(doc, sort_keys=False))
    assert e.key == f"robot.{key}"
    assert e.message.startswith(f"missing required key '{last}' in {'.'.join(parent)}")


def test_every_5r_key_is_in_the_schema_and_nothing_else() -> None:
    assert list(FIVE_BAR_ROBOT.children) == [
        "mechanism", "base", "lengths", "modes", "gravity", "links"
    ]  # fmt: skip
    assert list(FIVE_BAR_ROBOT.children["links"].children) == ["1", "2", "3", "4"]
    e = _error(_variant("  base: 0.2\n", "  base: 0.2\n  bogus: 1\n"))
    assert e.message == (
        "unknown key 'bogus'; expected one of: mechanism, base, lengths, modes, gravity, links"
    )


# -- the writer: a 5R task round-trips ----------------------------------------------------


@pytest.mark.parametrize("text", [DEXTAR.read_text(encoding="utf-8"), GOOD])
def test_a_5r_task_round_trips_through_the_writer(text: str) -> None:
    task = parse_task(text, "t.yaml")
    written = task_text(task)
    back = parse_task(written, "t.yaml")
    assert back.robot == task.robot
    assert back.name == task.name and back.duration == task.duration
    assert [(p.start, p.end, p.x, p.y) for p in back.motion] == [
        (p.start, p.end, p.x, p.y) for p in task.motion
    ]
    assert back.path == task.path == fmpq_poly([fmpq(3, 10)])
    robot = yaml.safe_load(written)["robot"]
    assert list(robot) == ["mechanism", "base", "lengths", "modes", "gravity", "links"]
    assert robot["modes"] == [1, -1]
    assert task_text(back) == written  # a fixed point


# -- the JSON Schema judges a 5R as the loader does ------------------------------------

# Bad 5R files that JSON Schema cannot judge: they need the start point's geometry.
LOADER_ONLY = {
    "legs_cannot_meet",
    "leg_2_inside_leg_1s_hole",
    "leg_1_inside_leg_2s_hole",
    "start_out_of_leg_1s_reach",
    "start_out_of_leg_2s_reach",
    "start_where_leg_1_is_stretched",
    "uncertainty_on_a_5r",  # the schema reads uncertainty apart from the robot
}


def test_the_schema_accepts_the_5r_examples() -> None:
    for text in (GOOD, DEXTAR.read_text(encoding="utf-8")):
        assert schema_accepts(text), list(VALIDATOR.iter_errors(_jsonish(text)))


@pytest.mark.parametrize("name", sorted(set(BAD) - LOADER_ONLY))
def test_the_schema_rejects_what_the_loader_rejects(name: str) -> None:
    assert not schema_accepts(BAD[name][0])


@pytest.mark.parametrize("name", sorted(LOADER_ONLY))
def test_what_only_the_loader_rejects_is_listed_honestly(name: str) -> None:
    assert schema_accepts(BAD[name][0])


def test_the_schema_keeps_each_mechanism_to_its_keys() -> None:
    doc: Any = _jsonish(GOOD)
    assert VALIDATOR.is_valid(doc)
    doc["robot"]["mechanism"] = "rprpr"
    assert not VALIDATOR.is_valid(doc)  # base, lengths, modes and links 1..4 are a 5R's
    rprpr: Any = _jsonish(_rprpr_text())
    rprpr["robot"]["mechanism"] = "rprpr"
    assert VALIDATOR.is_valid(rprpr)
    rprpr["robot"]["mechanism"] = "5R"
    assert not VALIDATOR.is_valid(rprpr)


# -- the mechanism key: how it chooses the robot's keys --------------------------------


def test_a_mechanism_given_twice_is_one_error_and_nothing_else_is_read() -> None:
    text = _variant("  base: 0.2\n", "  base: 0.2\n  mechanism: rprpr\n")
    e = _error(text)
    assert [x.key for x in e.errors] == ["robot.mechanism"]
    assert (
        e.message
        == "duplicate key 'mechanism' (first given on line 3); YAML would silently keep the last"
    )


def test_a_bad_mechanism_leaves_only_the_keys_of_no_mechanism_reported() -> None:
    text = _variant("mechanism: 5R", "mechanism: [5R]").replace(
        "  base: 0.2\n", "  base: 0.2\n  bogus: 1\n"
    )
    e = _error(text)
    assert [(x.key, x.message) for x in e.errors] == [
        ("robot.mechanism", "expected one of rprpr, 5R, found a list of 1"),
        (
            "robot.bogus",
            "unknown key 'bogus'; expected one of: a1, gravity, actuation, links, base,"
            " lengths, modes",
        ),
    ]


def test_a_tagged_mechanism_is_read_as_its_text() -> None:
    task = parse_task(_variant("mechanism: 5R", "mechanism: !!str 5R"))
    assert task.robot.mechanism == "5R"
    e = _error(_variant("mechanism: 5R", "mechanism: !!int 5"))
    assert e.key == "robot.mechanism" and len(e.errors) == 1


def test_the_rprpr_named_with_5r_keys_is_told_which_keys_are_the_5rs() -> None:
    text = _variant("  a1: 6\n", "  mechanism: rprpr\n  a1: 6\n  modes: [1, 1]\n", _rprpr_text())
    e = _error(text)
    assert [(x.key, x.message) for x in e.errors] == [
        (
            "robot.modes",
            "modes is for mechanism: 5R (the all-revolute five-bar): the working modes of"
            " its elbows",
        ),
    ]


def test_a_5r_given_rprpr_keys_as_well_is_told_key_by_key() -> None:
    """a1 stands for base: a 5R given a1 and base hears about a1 alone."""
    text = _variant("  base: 0.2\n", "  base: 0.2\n  a1: 0.2\n  actuation: prismatic\n")
    e = _error(text)
    assert [x.key for x in e.errors] == ["robot.a1", "robot.actuation"]


def _numbers(spec: Spec = FIVE_BAR_ROBOT, key: str = "robot") -> list[tuple[str, Spec]]:
    """Every number key of the 5R's robot, with its Spec."""
    out = []
    for k, child in spec.children.items():
        if child.kind == "number":
            out.append((f"{key}.{k}", child))
        out.extend(_numbers(child, f"{key}.{k}"))
    return out


@pytest.mark.parametrize(("key", "spec"), _numbers(), ids=[k for k, _ in _numbers()])
def test_every_5r_number_below_its_bound_is_one_located_error(key: str, spec: Spec) -> None:
    doc: Any = yaml.safe_load(GOOD)
    *parent, last = key.split(".")
    mapping = doc
    for p in parent:
        mapping = mapping[int(p) if p.isdigit() else p]
    mapping[int(last) if last.isdigit() else last] = -1
    text = dump(doc, sort_keys=False)
    e = _error(text)
    op = ">" if spec.exclusive else ">="
    assert (e.key, e.message) == (key, f"expected a number {op} 0 ({spec.description}), found -1")
    assert len(e.errors) == 1


def test_a_waypoint_csv_start_out_of_reach_points_at_the_csv(tmp_path: Path) -> None:
    (tmp_path / "plan.csv").write_text("t,x,y\n0,0.45,0.3\n1,0.1,0.3\n", encoding="utf-8")
    task = tmp_path / "t.rprpr.yaml"
    task.write_text(GOOD.split("path:")[0] + "motion:\n  waypoints: plan.csv\n", encoding="utf-8")
    with pytest.raises(TaskFileError) as info:
        load_task(task)
    e = info.value
    assert (e.key, e.line) == ("motion.waypoints", _line(task.read_text(), "waypoints:"))
    assert e.message.startswith("the start point E(0) = (0.45, 0.3) is out of reach of leg 1")


@pytest.mark.parametrize(
    ("modes", "message"),
    [
        ("[!metres 1, -1]", "YAML tag !metres is not allowed"),
        ("[.nan, -1]", "expected a finite number (e1 (the elbow C)), found NaN"),
        ("[[1], -1]", "expected +1 or -1 (e1 (the elbow C)), found a list of 1"),
        ("[true, -1]", "expected +1 or -1 (e1 (the elbow C)), found a boolean (true)"),
    ],
)
def test_a_mode_that_is_no_number_is_said_as_a_sign(modes: str, message: str) -> None:
    e = _error(_variant("modes: [+1, -1]", f"modes: {modes}"))
    assert e.key == "robot.modes[0]" and e.message.startswith(message)

"""The loader is driven by the schema (``schema.TASK``): every rule one key's ``Spec``
states -- its default, its kind, its bound, its choices, required and unknown keys -- holds
at every key of the tree, found by walking the tree here, not by listing keys by hand.

Each test builds a task file from a full valid task (every optional key given, with a
value other than its default), changes one key, and asserts the exact outcome.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
from collections.abc import Iterator
from fractions import Fraction
from typing import Any

import pytest
import yaml
from flint import fmpq

from rprpr.io import schema
from rprpr.io.loader import parse_task
from rprpr.io.schema import TASK, Spec
from rprpr.model.errors import TaskFileError
from rprpr.model.rules import RULES
from rprpr.model.task import Checks, Robot, Task
from tests.corpora.test_bad_tasks import GOOD  # the paper's path 2, without gravity or checks

FULL: dict[str, Any] = yaml.safe_load(GOOD)
FULL["robot"] = {"mechanism": "rprpr", **FULL["robot"]}  # the default, given
FULL["robot"]["gravity"] = 1.62  # the Moon: not the default
FULL["robot"]["actuation"] = "prismatic"  # not the default
FULL["checks"] = {
    "min_slope": 0.5, "min_speed": 0.25, "torque_limit": [300, 200], "strict": True,
    "peak": True,
    "unbounded_torque": "warn",
    # every rule a task can silence or demote, each with its reason (ignore wins over warn)
    # (by id and by name: either names the rule)
    "ignore": {k: f"why {k} is silenced" for r in RULES if r != "RPR001"
               for k in (r, RULES[r].name)},
    "warn": {k: f"why {k} is a warning" for r in RULES if r != "RPR001"
             for k in (r, RULES[r].name)},
}  # fmt: skip
FULL_X = copy.deepcopy(FULL)  # timing by x(t) instead of a law (x(0) = 2, x(5) = 4)
FULL_X["timing"] = {"duration": 5, "x": "2 + 2*t/5"}
FULL_TRAPEZOIDAL = copy.deepcopy(FULL)  # the trapezoidal law, cruising at 0.6 m/s
FULL_TRAPEZOIDAL["timing"] = {"duration": 5, "law": "trapezoidal", "cruise_speed": 0.6}
FULL_MOTION = copy.deepcopy(FULL)  # the end point's motion as pieces instead of path + timing
del FULL_MOTION["path"], FULL_MOTION["timing"]
FULL_MOTION["motion"] = {"pieces": [{"until": 5, "x": "2 + 2*t/5", "y": "-1 + 2*t/5"}]}
FULL_WAYPOINTS = copy.deepcopy(FULL_MOTION)  # ... and as waypoints
FULL_WAYPOINTS["motion"] = {"waypoints": [{"t": 0, "p": [2, -1]}, {"t": 5, "p": [4, 1]}]}
FULL_UNCERTAINTY = copy.deepcopy(FULL)  # ... with declared uncertainty (docs/robust.md)
FULL_UNCERTAINTY["uncertainty"] = {"links": "5%", "acceleration": 0.01, "period": 0.001}


def _specs(spec: Spec = TASK, key: str = "") -> Iterator[tuple[str, Spec]]:
    """Every (dotted key, Spec) of the tree, the root ('') first."""
    yield key, spec
    for k, child in spec.children.items():
        yield from _specs(child, f"{key}.{k}" if key else k)


SPECS = dict(_specs())
MAPPINGS = [k for k, s in SPECS.items() if s.kind == "mapping"]
DEFAULTED = [k for k, s in SPECS.items() if s.default is not None]
REQUIRED = [k for k, s in SPECS.items() if s.required]
LEAVES = [k for k, s in SPECS.items() if s.kind != "mapping"]


def dump(doc: Any, *, sort_keys: bool = False) -> str:
    """``yaml.safe_dump(doc)``, by libyaml's emitter where PyYAML has it (the same text,
    a tenth of the pure-Python emitter's work)."""
    return yaml.dump(doc, Dumper=getattr(yaml, "CSafeDumper", yaml.SafeDumper), sort_keys=sort_keys)


def _parts(key: str) -> list[str | int]:
    return [int(p) if p.isdigit() else p for p in key.split(".")] if key else []


def _base(key: str) -> dict[str, Any]:
    """A copy of the full task that gives ``key`` (timing.x is given instead of a law,
    cruise_speed with the trapezoidal law, motion instead of path and timing)."""
    for prefix, doc in (
        ("timing.x", FULL_X),
        ("timing.cruise_speed", FULL_TRAPEZOIDAL),
        ("motion.waypoints", FULL_WAYPOINTS),
        ("motion", FULL_MOTION),
        ("uncertainty", FULL_UNCERTAINTY),
    ):
        if key.startswith(prefix):
            return copy.deepcopy(doc)
    return copy.deepcopy(FULL)


def _at(doc: dict[str, Any], key: str) -> Any:
    """The value of ``doc`` at the dotted ``key``."""
    return functools.reduce(lambda d, p: d[p], _parts(key), doc)


def _edit(key: str, value: Any = None, *, delete: bool = False) -> str:
    """The full task as YAML text, with the value at ``key`` replaced (or deleted)."""
    doc = _base(key)
    *parent, last = _parts(key)
    mapping = functools.reduce(lambda d, p: d[p], parent, doc)
    if delete:
        del mapping[last]
    else:
        mapping[last] = value
    return dump(doc, sort_keys=False)


def _error(text: str) -> TaskFileError:
    with pytest.raises(TaskFileError) as info:
        parse_task(text, "t.yaml")
    return info.value


def _line_of(text: str, fragment: str) -> int:
    (line,) = [i for i, ln in enumerate(text.splitlines(), 1) if ln.strip().startswith(fragment)]
    return line


def _exact(v: fmpq) -> Fraction:
    return Fraction(int(v.p), int(v.q))


def test_the_full_task_reads_every_value_given() -> None:
    task = parse_task(dump(FULL, sort_keys=False), "full.yaml")
    assert task.robot.gravity == fmpq(162, 100)
    ignored = {r: "ignore" for r in RULES if r != "RPR001"}
    assert task.checks == Checks(
        fmpq(1, 2), fmpq(1, 4), (fmpq(300), fmpq(200)), True, "warn", ignored, True
    )


def test_the_defaulted_keys_are_gravity_and_the_checks_margins() -> None:
    assert DEFAULTED == [
        "robot.mechanism", "robot.gravity", "robot.actuation",
        "checks.min_slope", "checks.min_speed", "checks.strict",
        "checks.peak",
        "checks.unbounded_torque",
    ]  # fmt: skip


def _omissions() -> Iterator[tuple[str, str]]:
    """(defaulted key, key omitted): the key itself, and each optional mapping above it."""
    for key in DEFAULTED:
        parent, _, last = key.rpartition(".")
        if SPECS[parent].select == last:
            continue  # its other values choose another form (tests/io/test_five_bar.py)
        yield key, key
        parent = key.rpartition(".")[0]
        while parent and not SPECS[parent].required:
            yield key, parent
            parent = parent.rpartition(".")[0]


@pytest.mark.parametrize(("key", "omitted"), list(_omissions()))
def test_an_omitted_key_takes_its_spec_default(key: str, omitted: str) -> None:
    spec = SPECS[key]
    task = parse_task(_edit(omitted, delete=True))
    value = functools.reduce(getattr, key.split("."), task)
    full = parse_task(dump(FULL, sort_keys=False))
    given = functools.reduce(getattr, key.split("."), full)
    if spec.kind == "number":
        assert _exact(value) == Fraction(str(spec.default))
        assert _exact(given) != Fraction(str(spec.default))  # so the default is what we saw
    else:
        assert value is spec.default and given is not spec.default
    assert key in full.lines and key not in task.lines


def test_gravity_has_one_home_the_schema() -> None:
    task = parse_task(_edit("robot.gravity", delete=True), "t.yaml")
    assert task.robot.gravity == fmpq(981, 100)  # exactly 9.81, not the float
    assert SPECS["robot.gravity"].default == "9.81"
    # the model states no default of its own: Robot, Checks and Task need every value
    for cls, names in (
        (Robot, {"gravity"}),
        (Checks, {f.name for f in dataclasses.fields(Checks)}),
    ):
        for f in dataclasses.fields(cls):
            if f.name in names:
                assert f.default is dataclasses.MISSING
                assert f.default_factory is dataclasses.MISSING
    (checks,) = [f for f in dataclasses.fields(Task) if f.name == "checks"]
    assert checks.default is dataclasses.MISSING and checks.default_factory is dataclasses.MISSING


def test_the_loader_applies_whatever_default_the_schema_holds(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    robot = schema.TASK.children["robot"]
    moon = dataclasses.replace(robot.children["gravity"], default="1.625")
    monkeypatch.setitem(robot.children, "gravity", moon)
    task = parse_task(_edit("robot.gravity", delete=True), "t.yaml")
    assert task.robot.gravity == fmpq(13, 8)


@pytest.mark.parametrize("key", MAPPINGS)
def test_an_unknown_key_is_rejected_at_every_level(key: str) -> None:
    doc = _base(key)
    _at(doc, key)["bogus_key"] = 1
    text = dump(doc, sort_keys=False)
    e = _error(text)
    allowed = ", ".join(k for k in SPECS[key].children if k != SPECS[key].select)
    assert e.message == f"unknown key 'bogus_key'; expected one of: {allowed}"
    assert e.key == (f"{key}.bogus_key" if key else "bogus_key")
    assert e.line == _line_of(text, "bogus_key")


@pytest.mark.parametrize("key", [k for k in SPECS if k])
def test_a_misspelt_key_is_named_with_the_key_meant(key: str) -> None:
    parent, _, last = key.rpartition(".")
    doc = _base(key)
    mapping = _at(doc, parent)
    mapping[f"{last}_"] = mapping.pop(_parts(last)[0])
    e = _error(dump(doc, sort_keys=False))
    assert e.message == f"unknown key '{last}_'; did you mean '{last}'?"
    assert e.key == f"{key}_"


@pytest.mark.parametrize("key", REQUIRED)
def test_a_missing_required_key_is_named_where_it_belongs(key: str) -> None:
    parent, _, last = key.rpartition(".")
    text = _edit(key, delete=True)
    e = _error(text)
    where = f"in {parent}" if parent else "at the top level"
    description = SPECS[key].description.rstrip(".")
    assert e.message == f"missing required key '{last}' {where} ({description})"
    assert e.key == key
    if parent:  # at the mapping that lacks it
        assert e.line == _line_of(text, f"{_parts(parent)[-1]}:") + 1


@pytest.mark.parametrize("key", [k for k in SPECS if k and SPECS[k].kind == "mapping"])
def test_a_mapping_key_given_a_list_is_a_kind_error(key: str) -> None:
    e = _error(_edit(key, [1]))
    keys = ", ".join(k for k, s in SPECS[key].children.items() if s.required) or ", ".join(
        SPECS[key].children
    )
    assert e.message == f"expected a mapping (keys {keys}), found a list of 1"
    assert e.key == key


@pytest.mark.parametrize("key", [k for k in LEAVES if SPECS[k].kind not in ("point", "relative")])
def test_a_value_given_a_mapping_is_a_kind_error(key: str) -> None:
    e = _error(_edit(key, {"a": 1}))
    assert e.message.startswith("expected ") and e.message.endswith(", found a mapping")
    assert e.key == key


@pytest.mark.parametrize(
    ("key", "value", "at"),
    [
        (k, v, f"{k}[{i}]" if SPECS[k].kind == "pair" else k)
        for k, s in SPECS.items()
        if s.minimum is not None
        for v, i in ((-1, 0), (0, 1))
        if v < s.minimum or (v == s.minimum and s.exclusive)
    ],
)
def test_a_number_below_its_bound_is_rejected(key: str, value: int, at: str) -> None:
    spec = SPECS[key]
    given: Any = value
    if spec.kind == "pair":
        given = [value, 1] if at.endswith("[0]") else [1, value]
    e = _error(_edit(key, given))
    op = ">" if spec.exclusive else ">="
    what = spec.items[int(at[-2])] if spec.kind == "pair" else spec.description
    assert e.message == f"expected a number {op} 0 ({what}), found {value}"
    assert e.key == at


def test_every_bounded_number_is_tested_at_its_bound() -> None:
    bounded = {k for k, s in SPECS.items() if s.minimum is not None}
    assert bounded == {
        "robot.a1",
        "robot.gravity",
        *(f"robot.links.{i}.{f}" for i in (2, 3, 4, 5) for f in ("mass", "inertia", "r")),
        "timing.duration",
        "timing.cruise_speed",
        "checks.min_slope",
        "checks.min_speed",
        "checks.torque_limit",
        "uncertainty.acceleration",
        "uncertainty.period",
    }


@pytest.mark.parametrize("key", [k for k, s in SPECS.items() if s.kind == "enum"])
def test_an_enum_names_its_choices_and_the_nearest(key: str) -> None:
    choices = SPECS[key].choices
    e = _error(_edit(key, choices[0][:-1]))
    assert e.message == (
        f"expected one of {', '.join(choices)}, found the text {choices[0][:-1]!r};"
        f" did you mean {choices[0]!r}?"
    )
    assert e.key == key


@pytest.mark.parametrize("key", [k for k, s in SPECS.items() if s.kind == "pair"])
def test_a_pair_needs_exactly_two_numbers(key: str) -> None:
    for wrong in ([1], [1, 2, 3]):
        e = _error(_edit(key, wrong))
        items = ", ".join(SPECS[key].items)
        assert (
            e.message == f"expected a list of two numbers [{items}], found a list of {len(wrong)}"
        )
        assert e.key == key


def test_an_empty_tagged_number_is_an_input_error() -> None:
    e = _error(GOOD.replace("a1: 6", "a1: !!float"))
    assert (e.key, e.line, e.message) == (
        "robot.a1",
        3,
        "expected a number (|AB| [m]), found an empty value",
    )

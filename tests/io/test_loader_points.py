"""path.from and path.to: [x, y], {x, y}, x alone (y = p(x) exactly), fractions; the
shipped JSON schema accepts and rejects the same spellings."""

from __future__ import annotations

import jsonschema
import pytest
import yaml
from flint import fmpq

from rprpr.io.loader import parse_task
from rprpr.io.schema import json_schema
from rprpr.model.errors import TaskFileError
from tests.conftest import task_text
from tests.io.test_schema import _jsonish

# the path: y = x^2/3 - 1 starts at x = 1, y = -2/3 (no decimal equals it)
PATH = "x^2/3 - 1"


def _text(start: str, end: str = "[2, 1/3]") -> str:
    timing = "timing:\n  duration: 2\n  law: quintic\n"
    return task_text(PATH, timing).replace(
        f"  y: {PATH}\n", f"  y: {PATH}\n  from: {start}\n  to: {end}\n"
    )


@pytest.mark.parametrize(
    "start",
    ["[1, -2/3]", "1", "{x: 1}", "{x: 1, y: -2/3}", "[1, '-2/3']", "[1.0, -4/6]"],
)
def test_a_start_on_the_path_in_any_spelling(start: str) -> None:
    task = parse_task(_text(start), "t.yaml")
    # rest to rest from x = 1 to x = 2
    assert task.x_of_t(0) == 1 and task.x_of_t(2) == 2
    assert task.path(task.x_of_t(0)) == fmpq(-2, 3)


def test_a_fraction_as_the_x_of_a_point_alone() -> None:
    task = parse_task(_text("-3/2", "2"), "t.yaml")
    assert task.x_of_t(0) == fmpq(-3, 2)


def test_a_rounded_y_is_off_the_path_and_named_exactly() -> None:
    with pytest.raises(TaskFileError) as e:
        parse_task(_text("[1, -0.6667]"), "t.yaml")
    assert e.value.key == "path.from"
    assert e.value.message == (
        "point (1, -0.6667) is not on the path: y(1) = -2/3, found y = -0.6667"
    )


@pytest.mark.parametrize(
    ("start", "key", "message"),
    [
        ("{x: 1, z: 2}", "path.from.z", "unknown key 'z'; expected one of: x, y"),
        ("{y: 1}", "path.from.x", "missing required key 'x' in path.from (x [m])"),
        ("[1, 2/0]", "path.from[1]", "division by zero in '2/0'"),
        ("1/0", "path.from", "division by zero in '1/0'"),
        ("true", "path.from", "expected a number (x [m]), found a boolean (true)"),
    ],
)
def test_a_bad_point_names_its_key(start: str, key: str, message: str) -> None:
    with pytest.raises(TaskFileError) as e:
        parse_task(_text(start), "t.yaml")
    assert (e.value.key, e.value.message) == (key, message)


@pytest.mark.parametrize(
    ("start", "valid"),
    [
        ("[1, -2/3]", True),
        ("1", True),
        ("{x: 1}", True),
        ("{x: 1, y: -2/3}", True),
        ("[1, 1.5e-3/2]", True),
        ("{x: 1, z: 2}", False),
        ("{y: 1}", False),
        ("[1]", False),
        ("true", False),
        ("[1, x/2]", False),
    ],
)
def test_schema_accepts_the_spellings_the_loader_reads(start: str, valid: bool) -> None:
    doc = _jsonish(yaml.safe_load(_text(start)))
    errors = list(jsonschema.Draft202012Validator(json_schema()).iter_errors(doc))
    assert (not errors) == valid

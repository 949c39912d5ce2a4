"""The task-file JSON Schema: shipped, used by the configs, and in agreement with the loader.

The loader (``rprpr.io.loader``) and the JSON Schema (``schema.json_schema``, shipped as
``rprpr/io/task.schema.json`` for editors) come from the same ``schema.TASK``. They must
agree on every file JSON Schema can judge: both reject the bad-task corpus, both accept
the valid files below. Where JSON Schema cannot express a rule, the case is listed in
``LOADER_ONLY`` with the reason, and the test checks that the schema really accepts it
(so the list stays honest).
"""

from __future__ import annotations

import json
from importlib import resources
from pathlib import Path
from typing import Any

import jsonschema
import pytest
import yaml

from rprpr.io.loader import parse_task
from rprpr.io.schema import json_schema
from rprpr.model.errors import TaskFileError
from tests.conftest import run_cli
from tests.corpora.test_bad_tasks import GOOD  # the paper's path 2: the corpus's starting point

ROOT = Path(__file__).resolve().parents[2]
HERE = ROOT / "tests" / "corpora"
SHIPPED = ROOT / "rprpr" / "io" / "task.schema.json"
BAD = HERE / "bad_tasks"
CONFIGS = sorted((ROOT / "configs").glob("*.yaml"))
VALIDATOR = jsonschema.Draft202012Validator(json_schema())


# Bad files the loader rejects but JSON Schema cannot: name -> why the schema cannot say it.
_GRAMMAR = "the exact polynomial grammar (the schema's pattern admits only the right characters)"
_DEGREE = "the degree cap of 60 on a polynomial and on y(x(t))"
_GEOMETRY = "from/to lying on the path and agreeing with x(t) at 0 and t_f"
_EXPONENT = "the ±30 cap on a percentage's exponent (the schema's pattern admits any)"
LOADER_ONLY: dict[str, str] = {
    "duplicate_key": "duplicate keys: a YAML loader keeps the last before the schema sees them",
    "duplicate_top_key": "duplicate keys: a YAML loader keeps the last before the schema sees them",
    "duplicate_link": "duplicate keys: a YAML loader keeps the last before the schema sees them",
    "merge_key": "merge keys are expanded by a YAML loader before the schema sees them",
    "a1_nan": "finite numbers: JSON has no NaN, so JSON Schema has no rule against it",
    "a1_nan_tagged": "finite numbers: JSON has no NaN, so JSON Schema has no rule against it",
    "a1_inf": "finite numbers: JSON has no infinity (and inf > 0 holds)",
    "from_nan": "finite numbers: JSON has no NaN, so JSON Schema has no rule against it",
    "uncertainty_percent_exponent": _EXPONENT,
    "uncertainty_link_percent_exponent": _EXPONENT,
    "octal_ambiguous": "010 is 8 in YAML 1.1 and 10 in YAML 1.2: a question of YAML, not of JSON",
    "sexagesimal": "1:30 is the number 90 in YAML 1.1: a question of YAML, not of JSON",
    "number_too_long": "the loader's cap on digits in one number (exact arithmetic stays fast)",
    "poly_negative_exponent": _GRAMMAR,
    "poly_fractional_exponent": _GRAMMAR,
    "poly_enormous_exponent": _GRAMMAR,
    "poly_chained_exponent": _GRAMMAR,
    "poly_coefficients_huge": _GRAMMAR,
    "poly_division_by_zero": _GRAMMAR,
    "poly_division_by_zero_expr": _GRAMMAR,
    "poly_division_by_x": _GRAMMAR,
    "poly_implicit_product": _GRAMMAR,
    "poly_unbalanced": _GRAMMAR,
    "poly_deep": _GRAMMAR,
    "poly_degree_61": _DEGREE,
    "poly_degree_product": _DEGREE,
    "composition_degree_law": _DEGREE,
    "composition_degree_explicit": _DEGREE,
    "from_off_path": _GEOMETRY,
    "to_off_path": _GEOMETRY,
    "x_mismatch_start": _GEOMETRY,
    "x_mismatch_end": _GEOMETRY,
}


def _variant(old: str, new: str) -> str:
    assert old in GOOD
    return GOOD.replace(old, new)


_EXPLICIT = _variant("  law: quintic", "  x: 2 + 4/25*t^3 - 6/125*t^4 + 12/3125*t^5")
# Valid files: both the loader and the schema accept them.
VALID: dict[str, str] = {
    "paper_path2": GOOD,
    "explicit_x_with_ends": _EXPLICIT,
    "explicit_x_without_ends": _EXPLICIT.replace("  from: [2, -1]\n  to: [4, 1]\n", ""),
    "cubic": _variant("law: quintic", "law: cubic"),
    "all_checks": GOOD
    + "checks:\n  min_slope: 0.1\n  min_speed: 0\n  torque_limit: [300, 250.5]\n  strict: true\n",
    "strict_yes": GOOD + "checks:\n  strict: yes\n",
    "numeric_name": _variant("name: good", "name: 2024"),
    "no_name": _variant("name: good\n", ""),
    "no_gravity": _variant("  links:", "  gravity: 0\n  links:").replace("  gravity: 0\n", ""),
    "zero_gravity_and_mass": _variant("  links:", "  gravity: 0\n  links:").replace(
        "{mass: 1.0,", "{mass: 0,"
    ),
    "aliases": _variant("    2: {", "    2: &leg {").replace(
        "    4: {mass: 2.0, inertia: 0.10, r: 0.5}", "    4: *leg"
    ),
    "hex_and_underscores": _variant("  a1: 6", "  a1: 0x6").replace("duration: 5", "duration: 1_0"),
    "signed_and_float": _variant("  a1: 6", "  a1: +6.0"),
    "block_mappings": _variant(
        "    5: {mass: 1.0, inertia: 0.05, r: 0.5}",
        "    5:\n      mass: 1.0\n      inertia: 0.05\n      r: 0.5",
    ),
    "folded_polynomial": _variant(
        "  y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2",
        "  y: >-\n    0.8*x^3 - 7.2*x^2\n    + 21.8*x - 22.2",
    ),
    "quoted_polynomial": _variant(
        "  y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2", "  y: '0.8*x**3 - 7.2*x**2 + 21.8*x - 22.2'"
    ),
    "constant_path": _variant("  y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2", "  y: 0.5")
    .replace("[2, -1]", "[2, 0.5]")
    .replace("[4, 1]", "[4, 0.5]"),
    "comments_and_document_marker": "# a task\n---\n" + GOOD + "...\n",
}
# Valid files the loader accepts but the schema, as PyYAML reads the file, does not.
SCHEMA_STRICTER: dict[str, tuple[str, str]] = {
    # PyYAML (YAML 1.1) reads 1e3 as text; YAML 1.2, as editors read it, as the number 1000.
    # The loader follows YAML 1.2 for plain scalars of this form, and so agrees with editors.
    "yaml12_exponent": (_variant("  a1: 6", "  a1: 6e0"), "1e3 is text in YAML 1.1"),
}


def _jsonish(value: Any, seen: dict[int, Any] | None = None) -> Any:
    """YAML data as JSON sees it: mapping keys are strings (``2:`` is the key "2").

    Shared (aliased) values stay shared, so an alias bomb is not expanded here either.
    """
    seen = {} if seen is None else seen
    if id(value) in seen:
        return seen[id(value)]
    out: Any = value
    if isinstance(value, dict):
        out = seen[id(value)] = {}
        out.update({str(k): _jsonish(v, seen) for k, v in value.items()})
    elif isinstance(value, list):
        out = seen[id(value)] = []
        out.extend(_jsonish(v, seen) for v in value)
    return out


def schema_accepts(text: str) -> bool:
    """What an editor with the shipped schema says: YAML that does not load is rejected."""
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError:
        return False
    return VALIDATOR.is_valid(_jsonish(data))


def loader_accepts(text: str, directory: str = ".") -> bool:
    try:
        parse_task(text, directory=directory)
    except TaskFileError:
        return False
    return True


def test_shipped_schema_equals_json_schema() -> None:
    shipped = json.loads(SHIPPED.read_text(encoding="utf-8"))
    assert shipped == json_schema()
    assert SHIPPED.read_text(encoding="utf-8") == json.dumps(json_schema(), indent=2) + "\n", (
        "regenerate with: rprpr schema > rprpr/io/task.schema.json"
    )


def test_shipped_schema_is_package_data_and_a_valid_draft_2020_12_schema() -> None:
    text = (resources.files("rprpr.io") / "task.schema.json").read_text(encoding="utf-8")
    doc = json.loads(text)
    jsonschema.Draft202012Validator.check_schema(doc)
    assert doc["$schema"] == "https://json-schema.org/draft/2020-12/schema"


def test_rprpr_schema_prints_the_shipped_file() -> None:
    code, out, _ = run_cli("schema")
    assert code == 0
    assert json.loads(out) == json.loads(SHIPPED.read_text())


@pytest.mark.parametrize("config", CONFIGS, ids=lambda p: p.name)
def test_every_config_validates_and_points_at_the_schema(config: Path) -> None:
    text = config.read_text(encoding="utf-8")
    # VALIDATOR checks against json_schema(): the shipped file, a valid schema (tests above)
    VALIDATOR.validate(_jsonish(yaml.safe_load(text)))
    modeline = "# yaml-language-server: $schema=../rprpr/io/task.schema.json"
    assert text.splitlines()[0] == modeline
    assert (config.parent / "../rprpr/io/task.schema.json").resolve() == SHIPPED.resolve()
    assert loader_accepts(text, str(config.parent))  # a waypoint CSV is beside it


@pytest.mark.parametrize("name", sorted(VALID))
def test_loader_and_schema_both_accept(name: str) -> None:
    text = VALID[name]
    assert loader_accepts(text), name
    assert schema_accepts(text), list(VALIDATOR.iter_errors(_jsonish(yaml.safe_load(text))))


_BAD = sorted(p.stem for p in BAD.glob("*.yaml"))


@pytest.mark.parametrize("name", [n for n in _BAD if n not in LOADER_ONLY])
def test_loader_and_schema_both_reject(name: str) -> None:
    text = (BAD / f"{name}.yaml").read_text(encoding="utf-8")
    assert not loader_accepts(text)
    assert not schema_accepts(text), (
        f"the schema accepts {name}: add a rule, or list it in LOADER_ONLY"
    )


@pytest.mark.parametrize("name", sorted(LOADER_ONLY))
def test_what_only_the_loader_rejects_is_listed_honestly(name: str) -> None:
    text = (BAD / f"{name}.yaml").read_text(encoding="utf-8")
    assert not loader_accepts(text)
    assert schema_accepts(text), f"the schema rejects {name} too: move it to the agreement set"


@pytest.mark.parametrize("name", sorted(SCHEMA_STRICTER))
def test_what_only_the_loader_accepts_is_listed_honestly(name: str) -> None:
    text, _why = SCHEMA_STRICTER[name]
    assert loader_accepts(text)
    assert not schema_accepts(text)


def test_law_needs_from_and_to_in_the_schema_too() -> None:
    doc = _jsonish(yaml.safe_load(GOOD))
    del doc["path"]["from"]
    errors = list(VALIDATOR.iter_errors(doc))
    assert any("'from' is a required property" in e.message for e in errors)
    doc["timing"] = {"duration": 5, "x": "2 + t"}
    assert VALIDATOR.is_valid(doc)

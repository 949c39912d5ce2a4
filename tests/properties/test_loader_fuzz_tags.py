"""Explicit YAML tags, extreme digit strings and mutated configs: the loader only ever
raises ``TaskFileError``, and a tag never makes a value valid (issue 11, classes 3 and 8).

* Random explicit tags × random scalars at every key of the schema (values, list items,
  mappings, and the keys themselves): whatever the loader accepts with a tag, it accepts
  untagged too, as exactly the same ``Task`` (``!!str`` and quoted text stay text).
* Random digit strings -- thousands of leading zeros, long exponents, long fractions --
  at number keys and inside expressions: either the exact decimal value (checked here
  with ``decimal.Decimal``, which has no digit limit) or a one-line error naming a cap.
* Random mutations of every shipped config: only ``TaskFileError``, one line.

Deterministic: hypothesis is derandomized (the same examples on every run, in CI too).
"""

from __future__ import annotations

import dataclasses
import json
import re
from collections.abc import Iterator
from decimal import Decimal
from fractions import Fraction
from functools import cache
from pathlib import Path

import pytest
import yaml
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from rprpr.io import yaml_nodes
from rprpr.io.expression import MAX_DIGITS, MAX_EXP10, parse_polynomial
from rprpr.io.loader import parse_task
from rprpr.io.schema import TASK, Spec
from rprpr.model.errors import ExpressionError, TaskFileError
from rprpr.model.rules import RULES
from rprpr.model.task import Task

CONFIGS = sorted((Path(__file__).resolve().parents[2] / "configs").glob("*.yaml"))

FUZZ = settings(
    derandomize=True,
    database=None,
    max_examples=300,
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)

# -- a task document with a slot at every key of the schema ------------------------------
AUDIT_RULES = [r for r in RULES if r != "RPR001"]  # what checks.ignore and checks.warn name

# The paper's path 1 (Example 1), every optional key given. Values are YAML text.
BASE: dict[str, str] = {
    "name": "base",
    "robot.a1": "6",
    "robot.gravity": "9.81",
    **{
        f"robot.links.{i}.{k}": v
        for i in "2345"
        for k, v in zip(("mass", "inertia", "r"), ("2", "0.1", "0.5"), strict=True)
    },
    "path.y": "x^3 - 9*x^2 + 27*x - 27",
    "path.from[0]": "2",
    "path.from[1]": "-1",
    "path.to[0]": "4",
    "path.to[1]": "1",
    "timing.duration": "5",
    "timing.law": "quintic",
    "checks.min_slope": "0.5",
    "checks.min_speed": "0.25",
    "checks.torque_limit[0]": "300",
    "checks.torque_limit[1]": "200",
    "checks.strict": "true",
    "checks.unbounded_torque": "warn",
    **{f"checks.{level}.{r}": f"why {r}" for level in ("ignore", "warn") for r in AUDIT_RULES},
    "uncertainty.acceleration": "0.01",
    "uncertainty.period": "0.001",
}
EXPLICIT_X = "2 + 2*t/5"  # x(0) = 2, x(5) = 4: the same ends as the law


def _specs(spec: Spec = TASK, key: str = "") -> Iterator[tuple[str, Spec]]:
    for k, child in spec.children.items():
        full = f"{key}.{k}" if key else k
        yield full, child
        yield from _specs(child, full)


SPECS = dict(_specs())
# every value slot: scalars, each item of a pair, timing.x (in place of the law)
VALUES = [*BASE, "timing.x"]
MAPPINGS = [k for k, s in SPECS.items() if s.kind == "mapping" and k != "motion"]
# every key the document gives, whose key node can carry a tag too (not cruise_speed or
# motion: the paper's form, which the document is, has neither)
KEYS = [k for k in SPECS if any(v == k or v.startswith((f"{k}.", f"{k}[")) for v in VALUES)]


def document(
    values: dict[str, str], *, value_at: str = "", key_tag: tuple[str, str] = ("", "")
) -> str:
    """The task as YAML text, block style; ``value_at`` names a mapping given a tag
    (``values[value_at]`` is the tag), ``key_tag`` = (key, tag) tags that key's node."""

    def k(full: str) -> str:
        last = full.rsplit(".", 1)[-1]
        return f"{key_tag[1]} {last}" if key_tag[0] == full else last

    def m(full: str) -> str:  # a mapping's opening line
        tag = f" {values[full]}" if value_at == full else ""
        return f"{k(full)}:{tag}"

    def pair(full: str) -> str:
        return f"[{values[full + '[0]']}, {values[full + '[1]']}]"

    out = [f"{k('name')}: {values['name']}", m("robot"), f"  {k('robot.a1')}: {values['robot.a1']}"]
    out += [f"  {k('robot.gravity')}: {values['robot.gravity']}", "  " + m("robot.links")]
    for i in "2345":
        link = f"robot.links.{i}"
        out.append("    " + m(link))
        out += [
            f"      {k(f'{link}.{f}')}: {values[f'{link}.{f}']}" for f in ("mass", "inertia", "r")
        ]
    out += [m("path"), f"  {k('path.y')}: {values['path.y']}"]
    out += [f"  {k('path.from')}: {pair('path.from')}", f"  {k('path.to')}: {pair('path.to')}"]
    out += [m("timing"), f"  {k('timing.duration')}: {values['timing.duration']}"]
    if "timing.x" in values:
        out.append(f"  {k('timing.x')}: {values['timing.x']}")
    else:
        out.append(f"  {k('timing.law')}: {values['timing.law']}")
    out += [m("checks"), f"  {k('checks.min_slope')}: {values['checks.min_slope']}"]
    out += [f"  {k('checks.min_speed')}: {values['checks.min_speed']}"]
    out += [f"  {k('checks.torque_limit')}: {pair('checks.torque_limit')}"]
    out += [f"  {k('checks.strict')}: {values['checks.strict']}"]
    out += [f"  {k('checks.unbounded_torque')}: {values['checks.unbounded_torque']}"]
    for level in ("ignore", "warn"):
        out.append("  " + m(f"checks.{level}"))
        out += [
            f"    {k(f'checks.{level}.{r}')}: {values[f'checks.{level}.{r}']}" for r in AUDIT_RULES
        ]
    out += [m("uncertainty")]
    out += [
        f"  {k(f'uncertainty.{f}')}: {values[f'uncertainty.{f}']}"
        for f in ("acceleration", "period")
    ]
    return "\n".join(out) + "\n"


def with_value(slot: str, text: str) -> str:
    values = dict(BASE)
    if slot == "timing.x" or key_is(slot, "timing.x"):
        values["timing.x"] = EXPLICIT_X
    values[slot] = text
    return document(values)


def key_is(slot: str, key: str) -> bool:
    return slot == key or slot.startswith(key + ".")


def load(text: str, directory: str = ".") -> Task | TaskFileError:
    """The task, or the error; anything else escapes and fails the test."""
    try:
        return parse_task(text, "fuzz.yaml", directory=directory)
    except TaskFileError as e:
        assert str(e).startswith("fuzz.yaml")
        assert "\n" not in str(e) and "\r" not in str(e), str(e)  # one line
        assert len(str(e)) < 500, str(e)  # short, whatever the input
        return e


@cache
def untagged(text: str) -> Task | TaskFileError:
    """``load(text)`` once per text: the documents without tags that the tests of tagged
    keys compare with (the same few, example after example)."""
    return load(text)


def test_the_base_document_is_valid_in_both_forms() -> None:
    law, explicit = load(document(BASE)), load(with_value("timing.x", EXPLICIT_X))
    assert isinstance(law, Task) and isinstance(explicit, Task)
    assert law.robot.a1 == 6 and law.checks.strict is True and law.law == "quintic"
    assert explicit.x_of_t(5) == 4 and explicit.law == "explicit"


# -- explicit tags × scalars at every key ------------------------------------------------

TAGS = [
    "!!str",
    "!!int",
    "!!float",
    "!!bool",
    "!!null",
    "!!map",
    "!!seq",
    "!",
    "!<tag:yaml.org,2002:float>",
    "!<tag:yaml.org,2002:bool>",
    "!!binary",
    "!metres",
]
INTERESTING = [
    "", "_", "1/", "12/2", "-2/2", "maybe", "yes", "no", "on", "off", "y", "n", "true",
    "True", "TRUE", "tRuE", "false", "False", "null", "Null", "~", "6", "+6", "-0", "06",
    "6.0", "6.", ".5", "1e3", "1E+3", "6e0", "0x1f", "0o17", "0b101", "017", "1_000",
    "1:30", "1:30.5", ".nan", "nan", ".inf", "-.inf", "inf", "Infinity", " 6", "6 ", "6\n",
    "quintic", "cubic", "x^3 - 9*x^2 + 27*x - 27", "2 + 2*t/5", "2001-01-01", "0.1", "2",
    "-1", "4", "1", "300", "0.5", "0.25", "5", "9.81", "base",
]  # fmt: skip
SCALARS = st.one_of(
    st.sampled_from(INTERESTING),
    st.builds(lambda z, d: "0" * z + d, st.integers(0, 6000), st.sampled_from(["6", "6.0", "1e1"])),
    st.text(alphabet="0123456789.eE+-_/:x ", max_size=12),
    st.text(max_size=8),
)
STYLES = ["plain", "double", "single"]


def styled(text: str, style: str) -> str:
    """``text`` as a YAML scalar of ``style`` (double-quoted with JSON's escapes)."""
    if style == "double":
        return json.dumps(text, ensure_ascii=False)
    if style == "single":
        return "'" + text.replace("'", "''") + "'"
    return text


@FUZZ
@given(
    slot=st.sampled_from(VALUES),
    tag=st.sampled_from(TAGS),
    text=SCALARS,
    style=st.sampled_from(STYLES),
)
@example(slot="robot.a1", tag="!!float", text="", style="double")
@example(slot="robot.a1", tag="!!float", text="", style="plain")
@example(slot="robot.a1", tag="!!float", text="12/2", style="double")
@example(slot="checks.strict", tag="!!bool", text="maybe", style="plain")
@example(slot="checks.strict", tag="!!bool", text="", style="plain")
@example(slot="robot.a1", tag="!!str", text="1e3", style="plain")
@example(slot="robot.a1", tag="!!float", text="0" * 5000 + "6.0", style="plain")
def test_a_tag_never_makes_a_value_valid(slot: str, tag: str, text: str, style: str) -> None:
    got = load(with_value(slot, f"{tag} {styled(text, style)}"))
    if isinstance(got, TaskFileError):
        return
    name = tag.removeprefix("!!").removeprefix("!<tag:yaml.org,2002:").removesuffix(">")
    # the value as YAML reads it (a plain scalar loses surrounding spaces: " 6" reads "6")
    value = text if style != "plain" else _plain_value(f"{tag} {text}")
    if name in ("int", "float", "bool", "null"):
        # the value, untagged and plain, loads to exactly the same task
        assert value == value.strip() and value, (tag, value)
        assert same(load(with_value(slot, value)), got), (slot, tag, value)
        if name == "bool":
            assert value in ("true", "True", "TRUE", "false", "False", "FALSE")
        if name == "int":
            assert not re.search(r"[.eE]", value) or value.lower().startswith("0x"), value
    else:
        # !!str and the non-specific tag ! keep text: the same as the text double-quoted
        assert name in ("str", "!"), tag
        assert SPECS[re.sub(r"\[\d\]$", "", slot)].kind in ("string", "polynomial", "enum")
        assert same(load(with_value(slot, styled(value, "double"))), got)


def same(a: Task | TaskFileError, b: Task) -> bool:
    """The same task, but for the lines of its keys (a value may span lines)."""
    return isinstance(a, Task) and dataclasses.replace(a, lines={}) == dataclasses.replace(
        b, lines={}
    )


def _plain_value(scalar: str) -> str:
    """The value YAML reads from ``scalar`` (a tag and a plain scalar) as a mapping value."""
    node = yaml.compose(f"k: {scalar}\n", Loader=yaml.SafeLoader)
    return str(node.value[0][1].value)


@FUZZ
@given(key=st.sampled_from(KEYS), tag=st.sampled_from(TAGS))
def test_a_tag_on_a_key_never_makes_it_valid(key: str, tag: str) -> None:
    values = dict(BASE)
    if key_is(key, "timing.x"):
        values["timing.x"] = EXPLICIT_X
    if key_is(key, "timing.law"):
        return  # not in the document with timing.x, and the law's own: covered by values
    got = load(document(values, key_tag=(key, tag)))
    if isinstance(got, Task):
        # only tags that fit the key's text: text, or an integer for links 2..5
        last = key.rsplit(".", 1)[-1]
        number = tag in ("!!int", "!!float", "!<tag:yaml.org,2002:float>")
        assert tag in ("!!str", "!") or (last.isdigit() and number), tag
        assert got == untagged(document(values))


@FUZZ
@given(key=st.sampled_from(MAPPINGS), tag=st.sampled_from(TAGS))
def test_a_mapping_takes_no_tag_but_map(key: str, tag: str) -> None:
    values = dict(BASE)
    values[key] = tag
    got = load(document(values, value_at=key))
    if isinstance(got, Task):
        assert tag in ("!!map", "!")
        assert got == untagged(document(BASE))
    else:
        assert tag not in ("!!map", "!"), got


@pytest.mark.parametrize("parser", ["libyaml", "pure Python"])
@pytest.mark.parametrize(
    ("slot", "value", "message"),
    [
        ("checks.strict", "!!bool maybe", "found 'maybe' tagged !!bool, which is not a boolean"),
        ("checks.strict", "!!bool", "expected true or false, found an empty value"),
        ("robot.a1", "!!str 1e3", "found the text '1e3'"),
        ("robot.a1", '!!float "12/2"', "found '12/2' tagged !!float, which is not a decimal"),
    ],
)
def test_tags_are_read_alike_by_both_yaml_parsers(
    parser: str, slot: str, value: str, message: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    if parser == "pure Python":
        monkeypatch.setattr(yaml_nodes, "_Loader", yaml.SafeLoader)
    elif not hasattr(yaml, "CSafeLoader"):
        pytest.skip("PyYAML without libyaml")
    got = load(with_value(slot, value))
    assert isinstance(got, TaskFileError) and message in got.message
    assert got.key == slot


# -- digit strings: leading zeros, long exponents, long fractions ------------------------

CAPS = ("more than 40 digits", f"exponent beyond ±{MAX_EXP10}", "ambiguous number")


def _decimal_text(zeros: int, digits: str, point: int | None, exp: str) -> str:
    body = "0" * zeros + digits
    if point is not None:
        point = min(point, len(body))
        body = body[:point] + "." + body[point:]
    return body + exp


DIGIT_TEXTS = st.builds(
    _decimal_text,
    st.integers(0, 6000),
    st.text(alphabet="0123456789", min_size=1, max_size=60),
    st.one_of(st.none(), st.integers(0, 6100)),
    st.one_of(
        st.just(""),
        st.builds(
            lambda sign, z, e: f"e{sign}{'0' * z}{e}",
            st.sampled_from(["", "+", "-"]),
            st.integers(0, 6000),
            st.integers(0, 99),
        ),
    ),
)


def _significant(text: str) -> tuple[int, int]:
    """(digits after the integer part's leading zeros, |exponent|), as the caps count."""
    mantissa, _, exp = text.lower().partition("e")
    whole, _, frac = mantissa.partition(".")
    return len(whole.lstrip("0") + frac), int(Decimal(exp or "0").copy_abs())


@FUZZ
@given(text=DIGIT_TEXTS, slot=st.sampled_from(["robot.a1", "robot.links.3.mass", "path.to[0]"]))
@example(text="0" * 5000 + "6", slot="robot.a1")
@example(text="0" * 5000 + "6.0", slot="robot.a1")
@example(text="6e" + "0" * 5000 + "1", slot="robot.a1")
@example(text="0." + "0" * 5000 + "1", slot="robot.links.3.mass")
def test_digit_strings_are_exact_or_a_named_cap(text: str, slot: str) -> None:
    values = dict(BASE)
    values[slot] = text
    if slot == "path.to[0]":  # keep the end on the path: y = (x - 3)^3
        values["path.y"] = "0*x + 1"
        values["path.from[1]"] = values["path.to[1]"] = "1"
    got = load(document(values))
    digits, exp = _significant(text)
    integer = "." not in text and "e" not in text
    # 017 is octal in YAML 1.1 and 17 in YAML 1.2; 019 is text in YAML 1.1, so 19
    ambiguous = integer and len(text) > 1 and text.startswith("0") and set(text) <= set("01234567")
    if isinstance(got, TaskFileError):
        assert any(cap in got.message for cap in CAPS) or "expected a number >" in got.message, (
            got.message
        )
        assert ambiguous or digits > MAX_DIGITS or exp > MAX_EXP10 or Decimal(text) <= 0
        return
    assert not ambiguous and digits <= MAX_DIGITS and exp <= MAX_EXP10
    value = {
        "robot.a1": lambda t: t.robot.a1,
        "robot.links.3.mass": lambda t: t.robot.links[3].mass,
        "path.to[0]": lambda t: t.x_of_t(t.duration),
    }[slot](got)
    assert Fraction(int(value.p), int(value.q)) == Fraction(Decimal(text))


@FUZZ
@given(text=DIGIT_TEXTS, variable=st.sampled_from(["x", "t"]))
@example(text="0" * 3990 + "1", variable="x")
@example(text="1e-" + "0" * 3990 + "3", variable="x")
def test_digit_strings_in_expressions_are_exact_or_a_named_cap(text: str, variable: str) -> None:
    expr = f"{text}*{variable} + 1"
    try:
        p = parse_polynomial(expr, variable)
    except ExpressionError as e:
        assert any(cap in e.message for cap in (*CAPS, "longer than 4000")), e.message
        assert len(e.message) < 200
        return
    assert Fraction(int(p[1].p), int(p[1].q)) == Fraction(Decimal(text))
    assert p[0] == 1


# -- mutated configs ---------------------------------------------------------------------

_TOKENS = [
    *(t + " " for t in TAGS),
    "0" * 5000,
    "e" + "0" * 5000 + "1",
    "!!float ''",
    "!!bool",
    "&a ",
    "*a",
    "? ",
    ": ",
    "- ",
    "[",
    "]",
    "{",
    "}",
    "\n",
    "\n  ",
    "\r\n",
    "\ufeff",
    "\t",
    '"',
    "'",
    "\\",
    "#",
    "/",
    "12/2",
    "(1e30*x)^11",
    "1e-30",
    "maybe",
    "\x85",
    "\u2028",
]


PATH1 = CONFIGS[[c.name for c in CONFIGS].index("paper_path1.rprpr.yaml")]
_PATH1 = PATH1.read_text(encoding="utf-8")


@FUZZ
@given(
    config=st.sampled_from(CONFIGS),
    edits=st.lists(
        st.tuples(
            st.integers(0, 3000),
            st.integers(0, 12),
            st.one_of(st.sampled_from(_TOKENS), st.text(max_size=6)),
        ),
        min_size=1,
        max_size=5,
    ),
)
# the crashes of issue 11, as mutations: 5,000 zeros before a decimal, a long exponent
@example(config=PATH1, edits=[(_PATH1.index("r: 0.5") + 3, 0, "0" * 5000)])
@example(config=PATH1, edits=[(_PATH1.index("duration: 5") + 11, 0, "e" + "0" * 5000 + "1")])
@example(config=PATH1, edits=[(_PATH1.index("a1: 6") + 4, 1, '!!float ""')])
def test_mutated_configs_raise_only_task_file_errors(
    config: Path, edits: list[tuple[int, int, str]]
) -> None:
    text = config.read_text(encoding="utf-8")
    for where, cut, insert in edits:
        at = min(where, len(text))
        text = text[:at] + insert + text[at + cut :]
    load(text)


def test_every_shipped_config_loads() -> None:
    assert CONFIGS and all(
        isinstance(load(c.read_text(encoding="utf-8"), str(c.parent)), Task) for c in CONFIGS
    )

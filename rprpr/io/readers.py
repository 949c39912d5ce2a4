"""One reader per kind of value (``Spec.kind``): a node -> its exact value, or a
located ``TaskFileError``.

Numbers by their text (``scalars``); a polynomial by ``expression.parse_polynomial``,
its error pointing at the offending character; points, pairs and vectors; lists of
pieces and waypoints (inline, or a CSV file's name, read by ``waypoint_csv``).
"""

from __future__ import annotations

import functools
import os
import re
from typing import TYPE_CHECKING, Any

import yaml
from flint import fmpq, fmpq_poly

from ..model.defaults import PERCENT
from ..model.errors import ExpressionError, TaskFileError
from ..model.numbers import rational as _q
from .expression import parse_decimal, parse_fraction, parse_polynomial
from .messages import PERCENT_EXPECTED, expected, near, shorten, where
from .scalars import (
    ESCAPED_CONTROL,
    FRACTION,
    FRACTION_HINT,
    INF,
    NAN,
    NUMBER_TAGS,
    SCALAR_TEXT,
    SIMPLE_DECIMAL,
    SPECIAL_ENDS,
    TAG,
    kind_of,
    number_tag,
    number_value,
    simple_decimal,
)
from .schema import CSV_PATTERN, RELATIVE_LINKS, Spec
from .walk import Reader, Recorded, Stop, Walk

if TYPE_CHECKING:
    from ..model.waypoints import Waypoint

_POINT_KEYS = Spec(  # a point written as a mapping: {x: 1, y: -2/3}
    "mapping",
    "a point",
    children={"x": Spec("number", "x [m]", required=True), "y": Spec("number", "y [m]")},
)


def number(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> fmpq:
    if not isinstance(node, yaml.ScalarNode):
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    text = str(node.value).strip()
    if node.tag in NUMBER_TAGS and SIMPLE_DECIMAL.fullmatch(text) and not w.is_explicit(node):
        return _bounded(w, simple_decimal(text), node, spec, key, text)
    tag = number_tag(node, text, w.is_explicit(node))
    if tag not in ("int", "float"):
        hint = FRACTION_HINT if tag == "str" and FRACTION.fullmatch(text) else ""
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}{hint}", node, key)
    special = text[-1:] in SPECIAL_ENDS  # nan, inf and infinity end so; numbers do not
    if special and NAN.fullmatch(text):
        raise w.error(f"expected a finite number ({spec.description}), found NaN", node, key)
    if special and INF.fullmatch(text):
        raise w.error(
            f"expected a finite number ({spec.description}), found infinity ({text})", node, key
        )
    value = number_value(node, text.replace("_", ""), tag, key)
    return _bounded(w, value, node, spec, key, text)


def _bounded(w: Walk, value: fmpq, node: yaml.Node, spec: Spec, key: str, text: str) -> fmpq:
    """``value``, read from ``text``, checked against ``spec``'s bound."""
    if spec.minimum is not None:
        lo = _minimum(spec.minimum)
        if not (value > lo if spec.exclusive else value >= lo):
            raise w.error(
                f"expected a number {'>' if spec.exclusive else '>='} {_q(lo)}"
                f" ({spec.description}), found {shorten(text)}",
                node,
                key,
            )
    return value


def pair(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[fmpq, fmpq]:
    """Two numbers, ``spec.items`` saying what each is, both bounded as ``spec`` says."""
    if not isinstance(node, yaml.SequenceNode) or len(node.value) != 2:
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    a, b = (
        _item(w, v, spec, what, f"{key}[{i}]", depth + 1)
        for i, (v, what) in enumerate(zip(node.value, spec.items, strict=True))
    )
    return a, b


def numbers(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[fmpq, ...]:
    """``len(spec.items)`` numbers, ``spec.items`` saying what each is, each bounded as
    ``spec`` says (a 5R's ``robot.lengths``)."""
    if not isinstance(node, yaml.SequenceNode) or len(node.value) != len(spec.items):
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    return tuple(
        _item(w, v, spec, what, f"{key}[{i}]", depth + 1)
        for i, (v, what) in enumerate(zip(node.value, spec.items, strict=True))
    )


def signs(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[int, ...]:
    """``len(spec.items)`` signs, each +1 or -1 (a 5R's ``robot.modes``)."""
    if not isinstance(node, yaml.SequenceNode) or len(node.value) != len(spec.items):
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    out = []
    for i, (v, what) in enumerate(zip(node.value, spec.items, strict=True)):
        at = f"{key}[{i}]"
        try:
            value = _item(w, v, _SIGN, what, at, depth + 1)
        except TaskFileError as e:  # said as a sign's; any other error (a tag, caps) as is
            if isinstance(e, Stop) or not e.message.startswith("expected a number"):
                raise
            raise w.error(f"expected +1 or -1 ({what}), found {kind_of(v)}", v, at) from None
        if value not in (1, -1):
            raise w.error(f"expected +1 or -1 ({what}), found {shorten(str(v.value))}", v, at)
        out.append(int(value))
    return tuple(out)


_SIGN = Spec("signs", "a sign")


def point(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[fmpq, fmpq | None]:
    """A point of the path: x alone, [x, y] or {x: ..., y: ...}; (x, None) when y is
    left out (``cross_rules._on_path`` computes it)."""
    if isinstance(node, yaml.ScalarNode):
        return _coordinate(w, node, spec.items[0], key), None
    if isinstance(node, yaml.SequenceNode) and len(node.value) == 2:
        x, y = (
            _coordinate(w, v, what, f"{key}[{i}]", depth + 1)
            for i, (v, what) in enumerate(zip(node.value, spec.items, strict=True))
        )
        return x, y
    if isinstance(node, yaml.MappingNode):
        given = w.keys(node, _POINT_KEYS, key, depth)
        if "x" not in given:
            raise Recorded  # missing, or given twice: ``keys`` said so
        x = _coordinate(w, given["x"], spec.items[0], f"{key}.x", depth + 1)
        if "y" not in given:
            return x, None
        return x, _coordinate(w, given["y"], spec.items[1], f"{key}.y", depth + 1)
    raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)


def _coordinate(w: Walk, node: yaml.Node, what: str, key: str, depth: int = 0) -> fmpq:
    """A coordinate of a point: a number, or a fraction written as text (-2/3)."""
    w.visit(node, key, depth)
    spec = _number_spec(what)
    if (
        isinstance(node, yaml.ScalarNode)
        and node.tag == TAG + "str"
        and FRACTION.fullmatch(str(node.value).strip())
    ):
        try:
            return parse_fraction(str(node.value))
        except ExpressionError as e:
            raise w.error(e.message, node, key) from None
    w.fit(node, spec, key)
    return number(w, node, spec, key, depth)


def _item(w: Walk, node: yaml.Node, spec: Spec, what: str, key: str, depth: int) -> fmpq:
    w.visit(node, key, depth)
    bound = _number_spec(what, spec.minimum, spec.exclusive)
    w.fit(node, bound, key)
    return number(w, node, bound, key, depth)


def polynomial(
    w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int
) -> fmpq_poly | list[dict[str, Any]]:
    """A polynomial; with ``spec.item``, also a list of pieces (``items``)."""
    if spec.item is not None and isinstance(node, yaml.SequenceNode):
        return items(w, node, spec, key, depth)
    if not isinstance(node, yaml.ScalarNode) or node.tag not in SCALAR_TEXT:
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    text = str(node.value)
    try:
        return parse_polynomial(text, spec.variable)
    except ExpressionError as e:
        line, column = where(node)
        # Point at the offending character when the scalar is written on one line
        # exactly as its value reads (no escapes, no folding); else at the scalar.
        start, end = node.start_mark, node.end_mark
        quote = 1 if node.style in ("'", '"') else 0
        if (
            node.style in (None, "", "'", '"')
            and start.line == end.line
            and (end.index - start.index == len(text) + 2 * quote)
        ):
            column += quote + e.offset
        raise TaskFileError(
            f"bad polynomial in {spec.variable}: {e.message}", key=key, line=line, column=column
        ) from None


def time(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> fmpq:
    """An instant [s] >= 0: a decimal, or a fraction such as 5/3 (exact)."""
    if (
        isinstance(node, yaml.ScalarNode)
        and node.tag == TAG + "str"
        and FRACTION.fullmatch(str(node.value).strip())
    ):
        try:
            value = parse_fraction(str(node.value))
        except ExpressionError as e:
            raise w.error(e.message, node, key) from None
    else:
        value = number(w, node, _number_spec("t [s], a decimal or a fraction"), key, depth)
    if value < 0:
        raise w.error(f"expected a time >= 0 [s], found {_q(value)}", node, key)
    return value


def vector(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[fmpq, fmpq]:
    """Two numbers or fractions, [x, y]."""
    if not isinstance(node, yaml.SequenceNode) or len(node.value) != 2:
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    a, b = (
        _coordinate(w, v, what, f"{key}[{i}]", depth + 1)
        for i, (v, what) in enumerate(zip(node.value, spec.items, strict=True))
    )
    return a, b


def items(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> list[dict[str, Any]]:
    """A non-empty list of mappings, each read with ``spec.item`` under ``key[i]``:
    per element, its values by key and ``line``, the line of its first key (a
    piece's ``until``, a waypoint's ``t``)."""
    item = spec.item
    assert item is not None
    if not isinstance(node, yaml.SequenceNode) or not node.value:
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    before = len(w.errors)
    for i, element in enumerate(node.value):
        w.read(element, item, f"{key}[{i}]", depth + 1)
    if len(w.errors) > before:
        raise Recorded  # an element could not be read: said so already
    first = next(iter(item.children))
    out = []
    for i in range(len(node.value)):
        at = f"{key}[{i}]"
        values = {k: w.values[f"{at}.{k}"] for k in item.children if f"{at}.{k}" in w.values}
        out.append({**values, "line": w.lines.get(f"{at}.{first}", 0), "key": at})
    return out


def waypoints(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> list[Waypoint]:
    """Waypoints given inline (a list of {t, p, v, a}) or as a CSV file's name."""
    if isinstance(node, yaml.ScalarNode) and node.tag == TAG + "str":
        return _csv(w, node, key)
    if not isinstance(node, yaml.SequenceNode):
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    from ..model.waypoints import Waypoint  # a task of waypoints only

    points = []
    for it in items(w, node, spec, key, depth):
        if "a" in it and "v" not in it:
            raise w.error(
                "a waypoint giving a must give v too (p; p, v; or p, v, a)",
                w.nodes[f"{it['key']}.a"],
                f"{it['key']}.a",
            )
        points.append(Waypoint(it["t"], it["p"], it.get("v"), it.get("a"), it["line"]))
    return points


def _csv(w: Walk, node: yaml.ScalarNode, key: str) -> list[Waypoint]:
    """The waypoints of the CSV file named by ``node`` (relative to the task's
    directory); every problem of the file is an error at ``node`` naming the file
    and the row."""
    name = str(node.value)
    if not re.fullmatch(CSV_PATTERN, name) or ESCAPED_CONTROL.search(name):
        raise w.error(
            f"expected a CSV file's name relative to the task file (no '..', ending in"
            f" .csv), found {shorten(name)!r}",
            node,
            key,
        )
    path = os.path.normpath(os.path.join(w.directory, name))
    from .waypoint_csv import CsvProblem, parse_waypoints, read_bytes  # a CSV's task only

    try:
        points, problems = parse_waypoints(read_bytes(path, inside=w.directory))
    except CsvProblem as e:
        place = f"{name}:{e.row}" if e.row else name
        raise w.error(f"{place}: {e.message}", node, key) from None
    for row, message in problems:
        w.errors.append(w.error(f"{name}:{row}: {message}", node, key))
    if problems:
        raise Recorded
    w.csv_file, w.csv_name = path, name
    return points


def string(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> str:
    if not isinstance(node, yaml.ScalarNode) or node.tag not in SCALAR_TEXT:
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    return str(node.value)


def boolean(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> bool:
    if not isinstance(node, yaml.ScalarNode) or node.tag != TAG + "bool":
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
    return str(node.value).lower() in ("true", "yes", "on", "y")


def enum(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> str:
    v = str(node.value) if isinstance(node, yaml.ScalarNode) else ""
    if v not in spec.choices or node.tag != TAG + "str":
        lower = {c.lower(): c for c in spec.choices}  # 5r: did you mean 5R?
        meant = near(v.lower(), list(lower))
        hint = f"; did you mean {lower[meant[0]]!r}?" if meant else ""
        raise w.error(f"expected {expected(spec, key)}, found {kind_of(node)}{hint}", node, key)
    return v


_PERCENT = re.compile(PERCENT)


def percent(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> fmpq:
    """A percentage, as a fraction (``5%`` -> 1/20): 0 % <= value < 100 %."""
    text = str(node.value) if isinstance(node, yaml.ScalarNode) else ""
    m = _PERCENT.fullmatch(text) if node.tag.endswith(":str") else None
    if m is None:
        if isinstance(node, yaml.ScalarNode) and text.strip() in ("0", "0.0"):
            return fmpq(0)
        found = f"{text.strip()!r}" if isinstance(node, yaml.ScalarNode) else "a mapping or list"
        hint = " (write the percentage with %: 5% for 0.05)" if _is_number(text) else ""
        raise w.error(
            f"expected {PERCENT_EXPECTED} ({spec.description}), found {found}{hint}", node, key
        )
    try:
        value = parse_decimal(m.group(1) + (m.group(2) or "")) / 100
    except ExpressionError as e:  # too many digits, an exponent out of range
        raise w.error(
            f"expected {PERCENT_EXPECTED} ({spec.description}): {e.message}", node, key
        ) from None
    if value >= 1:
        raise w.error(
            f"expected {PERCENT_EXPECTED} ({spec.description}), found {text.strip()}: a"
            " half-width of 100% or more leaves the mass or length unbounded below",
            node,
            key,
        )
    return value


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def relative(w: Walk, node: yaml.Node, spec: Spec, key: str, depth: int) -> Any:
    """``uncertainty.links``: one percentage for every link, or per link and quantity
    (read as the mapping ``RELATIVE_LINKS``: its values land under ``key``.i.quantity)."""
    if isinstance(node, yaml.MappingNode):
        w.mapping(node, RELATIVE_LINKS, key, depth)
        return "per link"
    return percent(w, node, spec, key, depth)


READERS: dict[str, Reader] = {
    "number": number,
    "pair": pair,
    "numbers": numbers,
    "signs": signs,
    "point": point,
    "polynomial": polynomial,
    "time": time,
    "vector": vector,
    "list": items,
    "waypoints": waypoints,
    "string": string,
    "bool": boolean,
    "enum": enum,
    "percent": percent,
    "relative": relative,
}


@functools.cache
def _number_spec(what: str, minimum: float | None = None, exclusive: bool = False) -> Spec:
    """A number's Spec, made once: ``what`` it is, and its bound."""
    return Spec("number", what, minimum=minimum, exclusive=exclusive)


@functools.cache
def _minimum(bound: float) -> fmpq:
    """A ``Spec.minimum``, exactly (from its text)."""
    return parse_decimal(repr(bound))

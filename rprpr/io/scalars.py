"""YAML scalars and tags, as the task file reads them: one home for the YAML 1.1/1.2 rules.

PyYAML resolves plain scalars by YAML 1.1; the task file reads numbers as YAML 1.2 does
(``1e3`` a float, ``0o17`` an integer) and takes every number by its text (``0.1`` is
1/10). An explicit tag must fit its value as YAML 1.2 has it (``misfit``): a tag never
makes an invalid value valid. ``kind_of`` and ``tag_text`` say what a node is, for the
"found ..." of messages.
"""

from __future__ import annotations

import re

import yaml
from flint import fmpq

from ..model.errors import ExpressionError
from .expression import parse_decimal
from .messages import located, shorten

TAG = "tag:yaml.org,2002:"
MERGE = TAG + "merge"
NOT_KEYS = (TAG + "null", TAG + "bool")  # scalars that are not plain keys
NUMBER_TAGS = (TAG + "int", TAG + "float")
# A number as most task files write one (0, 12, -0.03): read directly, as the general
# path (``number_tag``, ``number_value``, ``parse_decimal``) would read it.
SIMPLE_DECIMAL = re.compile(r"-?(0|[1-9][0-9]{0,14})(\.[0-9]{1,15})?")
PLAIN_TAGS = {TAG + t for t in ("str", "int", "float", "bool", "null", "map", "seq")}
# Control characters in values after YAML's escapes are decoded: C0 but tab and line
# feed, DEL, C1, and the noncharacters U+FFFE/U+FFFF (terminal escapes, broken SVG/XML),
# and lone surrogates, which only the pure-Python YAML parser lets through.
ESCAPED_CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff]")
# YAML 1.2 reads 1e3 as a number; PyYAML (YAML 1.1) resolves it to text. A plain scalar
# in this form is taken as the number it means (editors using the shipped schema agree).
_YAML12_FLOAT = re.compile(r"[-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?")
_DECIMAL_INT = re.compile(r"[-+]?[0-9]+")
_RADIX_INT = re.compile(r"[-+]?0([xX][0-9a-fA-F]+|[oO][0-7]+|[bB][01]+)")
RESOLVER = yaml.resolver.Resolver()
NAN = re.compile(r"[-+]?\.?nan", re.IGNORECASE)
INF = re.compile(r"[-+]?\.?inf(inity)?", re.IGNORECASE)
SPECIAL_ENDS = "nNfFyY"  # the last letters of nan, inf, infinity (any case)
SCALAR_TEXT = {TAG + t for t in ("str", "int", "float")}  # what reads as text
# An explicit tag only narrows: the value must be one of its tag as YAML 1.2 has it,
# written as the loader reads an untagged value (see misfit).
_YAML12_BOOL = ("true", "True", "TRUE", "false", "False", "FALSE")
_YAML_NULL = ("", "~", "null", "Null", "NULL")
_NOT_DECIMAL = re.compile(r"[-+]?0[xXoObB]")  # hexadecimal, octal, binary
_TAG_MEANS = {
    "str": "text",
    "int": "an integer",
    "float": "a decimal number",
    "bool": "a boolean (YAML 1.2: true or false)",
    "null": "null",
    "map": "a mapping",
    "seq": "a list",
}
FRACTION = re.compile(r"[-+]?[0-9.]+\s*/\s*[0-9.]+")
FRACTION_HINT = (
    " (a fraction is only allowed in path.y, timing.x, path.from and path.to: write a decimal here)"
)


def simple_decimal(text: str) -> fmpq:
    """The value of ``text`` matching ``SIMPLE_DECIMAL``, exactly (as ``parse_decimal``)."""
    whole, _, frac = text.partition(".")
    return fmpq(int(whole + frac), 10 ** len(frac))


def number_tag(node: yaml.ScalarNode, text: str, explicit: bool) -> str:
    """The tag ``node`` is read with as a number ("int", "float", else not a number).

    An untagged plain scalar that YAML 1.1 reads as text but YAML 1.2 as a number
    (1e3, 0o17) is that number. A scalar tagged !!int or !!float (its tag checked to
    fit) is read as its text written plain; NaN and infinities keep !!float, to be
    named as such. !!str and quoted text stay text.
    """
    tag = node.tag.removeprefix(TAG)
    if explicit and tag == "float" and (NAN.fullmatch(text) or INF.fullmatch(text)):
        return tag
    if (explicit and tag in ("int", "float")) or (not explicit and tag == "str" and not node.style):
        return plain_tag(text).removeprefix(TAG)
    return tag


def number_value(node: yaml.Node, text: str, tag: str, key: str) -> fmpq:
    try:
        if tag == "int" and _RADIX_INT.fullmatch(text):
            if len(text) > 40:
                raise ExpressionError(f"number {shorten(text)!r} has more than 40 digits")
            return fmpq(int(text, 0))
        if tag == "int" and _DECIMAL_INT.fullmatch(text):
            body = text.lstrip("+-")
            if len(body) > 1 and body.startswith("0"):
                raise located(
                    f"ambiguous number {shorten(text)}: a leading 0 means octal in YAML 1.1"
                    " and decimal in YAML 1.2; write it without the leading 0 (or as"
                    " 0o... for octal)",
                    node,
                    key,
                )
            return parse_decimal(text)
        if tag == "float":
            return parse_decimal(text)
    except ExpressionError as e:
        raise located(e.message, node, key) from None
    raise located(f"expected a decimal number, found {shorten(text)!r}", node, key)


def misfit(node: yaml.Node, explicit: bool) -> str | None:
    """What ``node`` is, for "found ...", when its tag does not fit its value; else None.

    A mapping must be tagged !!map and a list !!seq. A scalar with an explicit tag must
    be, as written (no surrounding spaces), a value of that tag as YAML 1.2 has it and
    as the loader reads untagged values: !!int what an untagged value reads as an
    integer, !!float a decimal number (or NaN or an infinity, rejected as such later),
    !!bool true or false, !!null null; !!str anything. An empty tagged scalar is "an
    empty value".
    """
    tag = node.tag.removeprefix(TAG)
    if isinstance(node, yaml.MappingNode | yaml.SequenceNode):
        if tag == ("map" if isinstance(node, yaml.MappingNode) else "seq"):
            return None
        return f"{kind_of(node)} tagged !!{tag}, which is not {_TAG_MEANS[tag]}"
    value = str(node.value)
    if not explicit or tag == "str" or (tag == "null" and value in _YAML_NULL):
        return None
    if value == "":
        return "an empty value"
    plain = plain_tag(value).removeprefix(TAG) if value == value.strip() else ""
    special = bool(NAN.fullmatch(value) or INF.fullmatch(value))
    fits = {
        "int": plain == "int",
        "float": special or (plain in ("int", "float") and not _NOT_DECIMAL.match(value)),
        "bool": value in _YAML12_BOOL,
    }.get(tag, False)
    if fits:
        return None
    return f"{shorten(value)!r} tagged !!{tag}, which is not {_TAG_MEANS[tag]}"


def plain_tag(text: str) -> str:
    """The tag of ``text`` written as an untagged plain scalar: YAML 1.1's (PyYAML's),
    but a number as YAML 1.2 reads it (1e3 a float, 0o17 an integer; YAML 1.1: text)."""
    tag = _resolve(text)
    if tag == TAG + "str":
        if _YAML12_FLOAT.fullmatch(text):
            return TAG + "float"
        if _RADIX_INT.fullmatch(text):
            return TAG + "int"
    return tag


# -- nodes, for messages -----------------------------------------------------------------


# -- what a node is, for messages --------------------------------------------------------


def _resolve(text: str) -> str:
    """The tag YAML 1.1 (PyYAML) gives the plain scalar ``text``."""
    return str(RESOLVER.resolve(yaml.ScalarNode, text, (True, False)))


def tag_text(node: yaml.Node) -> str:
    """The tag of ``node`` as written (``!!binary``, ``!metres``), abbreviated if long."""
    return shorten(node.tag.replace(TAG, "!!"), 60)


def kind_of(node: yaml.Node) -> str:
    """What a node is, for "found ..." in messages."""
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return f"a list of {len(node.value)}"
    tag = node.tag.removeprefix(TAG)
    value = shorten(str(node.value))
    if tag == "null":
        return "null"
    if tag == "bool":
        return f"a boolean ({value})"
    if tag in ("int", "float"):
        return f"the number {value}"
    if tag == "str":
        return f"the text {value!r}"
    return f"{value!r} (tagged {tag_text(node)})"

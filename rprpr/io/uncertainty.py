"""The task file's ``uncertainty`` key (``docs/robust.md``): its readers, its cross-key
rule and its value, kept apart from the generic walk (``loader``), which registers them.

``uncertainty.links`` is a percentage (every link's mass, inertia and r) or a mapping
link -> quantity -> percentage; a percentage is written ``5%`` (0 % <= p < 100 %).
"""

from __future__ import annotations

import re
from typing import Any

import yaml
from flint import fmpq

from ..model.task import Uncertainty
from .expression import parse_decimal
from .schema import LINK_QUANTITIES, RELATIVE_LINKS, Spec

_PERCENT = re.compile(r"^\s*([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?\s*%\s*$")
EXPECTED = "a percentage such as 5% (0% <= value < 100%)"


def percent(walk: Any, node: yaml.Node, spec: Spec, key: str, depth: int) -> fmpq:
    """A percentage, as a fraction (``5%`` -> 1/20)."""
    text = str(node.value) if isinstance(node, yaml.ScalarNode) else ""
    m = _PERCENT.fullmatch(text) if node.tag.endswith(":str") else None
    if m is None:
        zero = isinstance(node, yaml.ScalarNode) and text.strip() in ("0", "0.0")
        if zero:
            return fmpq(0)
        found = f"{text.strip()!r}" if isinstance(node, yaml.ScalarNode) else "a mapping or list"
        hint = " (write the percentage with %: 5% for 0.05)" if _number(text) else ""
        raise walk.error(f"expected {EXPECTED} ({spec.description}), found {found}{hint}",
                         node, key)  # fmt: skip
    value = parse_decimal(m.group(1) + (m.group(2) or "")) / 100
    if value >= 1:
        raise walk.error(
            f"expected {EXPECTED} ({spec.description}), found {text.strip()}: a half-width"
            " of 100% or more leaves the mass or length unbounded below",
            node,
            key,
        )
    return value


def _number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def relative(walk: Any, node: yaml.Node, spec: Spec, key: str, depth: int) -> Any:
    """``uncertainty.links``: one percentage for every link, or per link and quantity
    (read as the mapping ``RELATIVE_LINKS``: its values land under ``key``.i.quantity)."""
    if isinstance(node, yaml.MappingNode):
        walk.mapping(node, RELATIVE_LINKS, key, depth)
        return "per link"
    return percent(walk, node, spec, key, depth)


def needs_limit(walk: Any, key: str) -> None:
    """``uncertainty`` needs ``checks.torque_limit``: a window is measured against it."""
    if "checks.torque_limit" in walk.nodes or {"checks", "checks.torque_limit"} & walk.misspelt:
        return  # given (a bad value is reported by its own reader), or misspelt (reported)
    raise walk.error(
        "uncertainty needs checks.torque_limit: the saturation window around each singular"
        " instant is measured against the actuators' limits (add checks: {torque_limit:"
        " [T1 max, T2 max]})",
        walk.nodes[key],
        key,
    )


def uncertainty_of(values: dict[str, Any], given: bool) -> Uncertainty | None:
    """The task's ``Uncertainty`` from the values read (None when the key is absent)."""
    if not given:
        return None
    links: dict[int, tuple[fmpq, fmpq, fmpq]] = {}
    every = values.get("uncertainty.links", fmpq(0))
    for i in (2, 3, 4, 5):
        if every == "per link":
            q = [values.get(f"uncertainty.links.{i}.{n}") for n in LINK_QUANTITIES]
            links[i] = tuple(fmpq(0) if v is None else v for v in q)
        else:
            links[i] = (every, every, every)
    zero = fmpq(0)  # a key not given (the schema states no default: "not given: 0")
    return Uncertainty(
        links, values.get("uncertainty.acceleration", zero), values.get("uncertainty.period", zero)
    )

"""The generic walk of a YAML node tree along a ``Spec`` tree (``schema.TASK``).

Every check one key's Spec states is made here from the Spec alone: kind (through the
reader of ``Spec.kind`` it is given), bound, choices, required and unknown keys, list
length; an omitted key takes its ``Spec.default``; the cross-field rule filed under a key
runs once that key is read. The readers and the rules are given to the walk
(``readers.READERS``, ``cross_rules.RULES``): this module knows neither.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Mapping
from dataclasses import replace
from typing import Any

import yaml
from flint import fmpq, fmpq_poly

from ..model.errors import TaskFileError
from .expression import parse_decimal
from .messages import expected, located, near, shorten, where
from .scalars import (
    ESCAPED_CONTROL,
    FRACTION,
    FRACTION_HINT,
    MERGE,
    NOT_KEYS,
    PLAIN_TAGS,
    TAG,
    kind_of,
    misfit,
    tag_text,
)
from .schema import Spec
from .yaml_nodes import MAX_DEPTH, MAX_NODES, span

_PLAIN_KEY = re.compile(r"[A-Za-z0-9_-]{1,40}")  # shown unquoted (rule names have -)


class Stop(TaskFileError):
    """An error after which the walk reads nothing more (the node budget, the depth)."""


class Missing(TaskFileError):
    """A required key not given (listed after the errors of the keys that are)."""


class Recorded(Exception):
    """A value that cannot be read, whose errors are already in ``Walk.errors``."""


# a reader: (the walk, the node, its Spec, its dotted key, its depth) -> its value
Reader = Callable[["Walk", yaml.Node, Spec, str, int], Any]
# a cross-field rule: (the walk, the key it is filed under) -> None, or a TaskFileError
Rule = Callable[["Walk", str], None]
# key -> (its rule, the values the rule needs besides the key's own)
Rules = Mapping[str, tuple[Rule, tuple[str, ...]]]


class Walk:
    """Reads a YAML node tree along a ``Spec`` tree (``schema.TASK``), generically.

    Every check one key's Spec states is made here from the Spec alone: kind, bound,
    choices, required and unknown keys, list length; an omitted key takes its
    ``Spec.default``. ``values`` maps each dotted key read or defaulted to its exact
    value, ``nodes`` each key given in the file to its value node, ``lines`` to the line
    of the key. Only the nodes the schema knows are visited, each counted against
    ``MAX_NODES`` (an alias counts every time it is followed), so aliasing cannot blow up
    the work. An explicit tag must fit its value (``misfit``), and a tagged value is
    then read as its text written plain: a tag never makes an invalid value valid.
    """

    def __init__(
        self,
        explicit: dict[tuple[int, int], str] | None = None,
        directory: str = os.curdir,
        *,
        escapes: bool = True,
        readers: Mapping[str, Reader],
        rules: Rules,
    ) -> None:
        self.readers = readers  # Spec.kind -> its reader
        self.rules = rules  # key -> the cross-field rule filed under it
        self.explicit = explicit or {}  # the explicit tags of scalars, by span
        self.escapes = escapes  # False: no value can hold a control character
        self.directory = directory  # where a waypoint CSV's name is relative to
        self.csv_file = ""  # the waypoint CSV read, as a path (relative to the working dir)
        self.csv_name = ""  # ... and as the task file names it
        self.visited = 0
        self.values: dict[str, Any] = {}
        self.nodes: dict[str, yaml.Node] = {}
        self.lines: dict[str, int] = {}
        self.errors: list[TaskFileError] = []  # every independent error, in reading order
        self.misspelt: set[str] = set()  # keys an unknown key was likely meant as
        self.x_pieces: list[tuple[fmpq, fmpq, fmpq_poly]] | None = None  # see build.timing

    def error(self, message: str, node: yaml.Node | None, key: str) -> TaskFileError:
        return located(message, node, key)

    def stop(self, message: str, node: yaml.Node | None, key: str) -> Stop:
        """An error after which nothing more is read (the node budget, the depth)."""
        line, column = where(node) if node is not None else (0, 0)
        return Stop(message, key=key, line=line, column=column)

    def read(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> None:
        """Check ``node`` against ``spec``, record its value under ``key``, then run the
        cross-field rule filed under ``key``, if any. An error is recorded in ``errors``
        (the key then has no value, and what depends on it is not checked) and the walk
        goes on with the next key; only a ``Stop`` ends it."""
        try:
            self.visit(node, key, depth)
            if self.explicit or type(node) is not yaml.ScalarNode:
                self.fit(node, spec, key)  # (an untagged scalar fits)
            if spec.kind == "mapping":
                self.mapping(node, spec, key, depth)
            else:
                self.values[key] = self.readers[spec.kind](self, node, spec, key, depth)
        except Stop:
            raise
        except TaskFileError as e:
            self.errors.append(e)
            return
        except Recorded:
            return
        if key in self.rules:
            self.check(key)

    def check(self, key: str) -> None:
        """The cross-field rule filed under ``key``, when every value it needs was read."""
        rule, needs = self.rules.get(key, (None, ()))
        if rule is None or (key not in self.values and key not in self.nodes):
            return
        if any(k not in self.values for k in needs):
            return
        try:
            rule(self, key)
        except Stop:
            raise
        except TaskFileError as e:
            self.errors.append(e)

    def omitted(self, spec: Spec, key: str) -> None:
        """A key not given: its default, and those of its keys if it is a mapping."""
        for below, value in _defaults(spec):
            self.values[key + below] = value

    def visit(self, node: yaml.Node, key: str, depth: int) -> None:
        self.visited += 1
        if self.visited > MAX_NODES:
            raise self.stop(
                f"too many YAML nodes (over {MAX_NODES}, aliases included):"
                " excessive aliasing rejected",
                node,
                key,
            )
        if depth > MAX_DEPTH:
            raise self.stop(f"nested deeper than {MAX_DEPTH} levels", node, key)
        tag = node.tag
        if tag == MERGE:
            raise self.error(
                "merge keys (<<) are not supported: write the keys out (an alias of a whole"
                " value, such as 3: *link, is fine)",
                node,
                key,
            )
        if type(node) is yaml.ScalarNode:
            if self.explicit and self.explicit.get(span(node)) == "!":
                # YAML 1.2: the non-specific tag makes a scalar text (PyYAML resolves
                # it as if untagged: ! "6" would be the integer 6)
                node.tag = tag = TAG + "str"
            bad = ESCAPED_CONTROL.search(str(node.value)) if self.escapes else None
            if bad:  # written as a YAML escape ("\e", "\x07"): it would reach terminals
                code = ord(bad.group(0))
                what = "lone surrogate" if 0xD800 <= code <= 0xDFFF else "control character"
                raise self.error(
                    f"{what} U+{code:04X} in a value (written as a YAML escape) is not allowed",
                    node,
                    key,
                )
        if tag not in PLAIN_TAGS:
            what = ""
            if node.tag == TAG + "timestamp":
                what = f" ({shorten(str(node.value))!r} reads as a date)"
            raise self.error(
                f"YAML tag {tag_text(node)} is not allowed{what}: only plain text,"
                " numbers, booleans, null, mappings and lists",
                node,
                key,
            )

    def is_explicit(self, node: yaml.Node) -> bool:
        """Whether ``node`` is a scalar with a tag written in the file."""
        explicit = self.explicit
        return bool(explicit) and type(node) is yaml.ScalarNode and span(node) in explicit

    def fit(self, node: yaml.Node, spec: Spec | None, key: str) -> None:
        """Reject a node whose explicit tag does not fit its value (``spec`` None: a key)."""
        explicit = self.is_explicit(node)
        if not explicit and type(node) is yaml.ScalarNode:
            return  # an untagged scalar always fits (``misfit``)
        found = misfit(node, explicit)
        if found is None:
            return
        wanted = "a plain key" if spec is None else expected(spec, key)
        hint = ""
        if spec is not None and spec.kind == "number" and FRACTION.fullmatch(str(node.value)):
            hint = FRACTION_HINT
        raise self.error(f"expected {wanted}, found {found}{hint}", node, key)

    def mapping(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> None:
        """Read the keys ``spec`` knows, in the schema's order; default the rest."""
        if not isinstance(node, yaml.MappingNode):
            raise self.error(f"expected {expected(spec, key)}, found {kind_of(node)}", node, key)
        if spec.variants:
            spec = self.variant(node, spec, key, depth)
        given = self.keys(node, spec, key, depth)
        for k, child in spec.children.items():
            full = f"{key}.{k}" if key else k
            if k in given:
                self.read(given[k], child, full, depth + 1)
            else:
                self.omitted(child, full)

    def variant(self, node: yaml.MappingNode, spec: Spec, key: str, depth: int) -> Spec:
        """The form of the mapping ``spec`` its ``select`` key names (``spec`` itself when
        the key is left out or gives its default). A ``select`` that names no form, or is
        given twice, is reported; the mapping's keys are then checked against every form's
        and none of their values is read."""
        values = [
            v
            for k, v in node.value
            if type(k) is yaml.ScalarNode and k.tag not in NOT_KEYS and k.value == spec.select
        ]
        if not values:
            return self.unnamed(node, spec, key)
        chosen = values[0]
        if len(values) == 1 and type(chosen) is yaml.ScalarNode and chosen.tag == TAG + "str":
            if chosen.value in spec.variants:
                return spec.variants[chosen.value]
            if chosen.value == spec.children[spec.select].default:
                return spec
        every = {k: replace(c, required=False) for v in (spec, *spec.variants.values())
                 for k, c in v.children.items()}  # fmt: skip
        given = self.keys(node, replace(spec, children=every, elsewhere={}), key, depth)
        if spec.select in given:
            full = f"{key}.{spec.select}" if key else spec.select
            self.read(given[spec.select], spec.children[spec.select], full, depth + 1)
        raise Recorded

    def unnamed(self, node: yaml.MappingNode, spec: Spec, key: str) -> Spec:
        """``spec`` itself, its ``select`` key left out; but a mapping given keys of one
        other form only (base, lengths, modes and no a1: a 5R without ``mechanism: 5R``)
        is that one error, and none of its values is read."""
        given = [str(k.value) for k, _ in node.value if type(k) is yaml.ScalarNode]
        for name, form in spec.variants.items():
            theirs = [k for k in given if k in form.children and k not in spec.children]
            ours = [k for k in given if k in spec.children and k not in form.children]
            if theirs and not ours:
                first = next(k for k, _ in node.value if str(k.value) == theirs[0])
                where = f" in {key}" if key else ""
                self.errors.append(
                    self.error(
                        f"{', '.join(theirs)} {'is' if len(theirs) == 1 else 'are'} for"
                        f" {spec.select}: {name}: add {spec.select}: {name}{where} (the default"
                        f" is {spec.children[spec.select].default})",
                        first,
                        f"{key}.{theirs[0]}" if key else theirs[0],
                    )
                )
                raise Recorded
        return spec

    def keys(
        self, node: yaml.MappingNode, spec: Spec, key: str, depth: int
    ) -> dict[str, yaml.Node]:
        """The mapping's value nodes by key: plain, known, unique keys; the required all given."""
        out: dict[str, yaml.Node] = {}
        bad: set[str] = set()  # keys given but unusable (duplicated): not "missing"
        for knode, vnode in node.value:
            if knode.tag == MERGE:  # its keys are unknown: none is "missing"
                bad.update(spec.children)
            try:
                k, full = self.known_key(knode, spec, key, depth)
            except Stop:
                raise
            except TaskFileError as e:
                self.errors.append(e)
                if isinstance(knode, yaml.ScalarNode):  # a misspelt key: not also "missing"
                    stands = spec.elsewhere.get(str(knode.value), ("", ""))[1]  # a1 for base
                    meant = [stands] if stands else near(str(knode.value), list(spec.children))
                    bad.update(meant)
                    self.misspelt.update(f"{key}.{k}" if key else k for k in meant)
                continue
            if k in out or k in bad:
                first = self.lines.get(full, 0)
                self.errors.append(
                    self.error(
                        f"duplicate key {k!r} (first given on line {first}); YAML would"
                        " silently keep the last",
                        knode,
                        full,
                    )
                )
                out.pop(k, None)  # neither value is read: which one was meant is unknown
                self.nodes.pop(full, None)
                bad.add(k)
                continue
            out[k] = self.nodes[full] = vnode
            self.lines[full] = knode.start_mark.line + 1
        for k, child in spec.children.items():
            instead = child.unless and (child.unless in out or child.unless in bad)
            if child.required and k not in out and k not in bad and not instead:
                full = f"{key}.{k}" if key else k
                place = f"in {key}" if key else "at the top level"
                line, column = where(node)
                self.errors.append(
                    Missing(
                        f"missing required key {k!r} {place} ({child.description.rstrip('.')})",
                        key=full,
                        line=line,
                        column=column,
                    )
                )
        return out

    def known_key(self, knode: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[str, str]:
        """A key of the mapping at ``key``, and its dotted path; unknown keys are errors."""
        self.visit(knode, key, depth + 1)
        if self.explicit or type(knode) is not yaml.ScalarNode:
            self.fit(knode, None, key)  # (an untagged scalar fits)
        if not isinstance(knode, yaml.ScalarNode) or knode.tag in NOT_KEYS:
            raise self.error(f"expected a plain key, found {kind_of(knode)}", knode, key)
        k = str(knode.value)
        shown = k if _PLAIN_KEY.fullmatch(k) else repr(shorten(k))
        full = f"{key}.{shown}" if key else shown
        if k in spec.elsewhere:  # a key of the mapping's other form (a1 on a 5R)
            raise self.error(spec.elsewhere[k][0], knode, full)
        if k not in spec.children:
            meant = near(k, list(spec.children))
            allowed = [c for c in spec.children if c != spec.select]  # (said apart)
            hint = (
                f"; did you mean {meant[0]!r}?"
                if meant
                else f"; expected one of: {', '.join(allowed)}"
            )
            raise self.error(f"unknown key {shorten(k)!r}{hint}", knode, full)
        return k, full


def _default(spec: Spec) -> Any:
    """The value of an omitted key: ``spec.default``, a number exactly (from its text)."""
    if spec.kind == "number":
        return parse_decimal(str(spec.default))
    return spec.default


_DEFAULTS: dict[int, tuple[Spec, tuple[tuple[str, Any], ...]]] = {}


def _defaults(spec: Spec) -> tuple[tuple[str, Any], ...]:
    """The values an omitted ``spec`` gives: (the dotted key below it, '' for itself,
    the default), for it and its keys if it is a mapping, depth first. Worked out once
    per Spec (the values are immutable)."""
    known = _DEFAULTS.get(id(spec))
    if known is not None and known[0] is spec:
        return known[1]
    out: list[tuple[str, Any]] = []
    if spec.default is not None:
        out.append(("", _default(spec)))
    for k, child in spec.children.items():
        out.extend((f".{k}{below}", value) for below, value in _defaults(child))
    _DEFAULTS[id(spec)] = (spec, tuple(out))
    return tuple(out)

"""The task file's YAML node tree, composed within caps: text -> nodes.

One pass of YAML's parser bounds the nesting (``MAX_DEPTH``) and the number of nodes
(``MAX_NODES``) before any node is made, then the tree is composed from those events as
PyYAML composes it (``_Composer``); nothing is constructed into Python objects, so no tag
can run code. Explicit tags are kept by where their scalar lies (``span``). A syntax
error is YAML's own complaint at YAML's line and column, with a hint where one helps
(a tab, an indentation that matches no open block).
"""

from __future__ import annotations

import re
from typing import Any

import yaml

from ..model.errors import TaskFileError
from .messages import shorten, where
from .scalars import RESOLVER, TAG

MAX_NODES = 10_000  # YAML nodes in the file, and nodes visited with aliases followed
MAX_DEPTH = 32  # nesting of mappings and lists

_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
_STR, _MAP, _SEQ = (TAG + t for t in ("str", "map", "seq"))
_NODE_EVENTS = {yaml.ScalarEvent, yaml.AliasEvent, yaml.SequenceStartEvent, yaml.MappingStartEvent}
_END_EVENTS = {yaml.SequenceEndEvent, yaml.MappingEndEvent}


def compose(text: str) -> tuple[yaml.Node | None, dict[tuple[int, int], str]]:
    """The YAML node tree, and the explicit tags of scalars by where they start.

    One pass of YAML's parser (``_events``) bounds nesting and size before any node is
    made: libyaml's own composer recurses in C, and a deeply nested flow list would
    crash the process. The tree is then composed from those events (``_Composer``),
    as PyYAML composes it.
    """
    try:
        events, explicit = _events(text)
        return _Composer(events).single_node(), explicit
    except yaml.MarkedYAMLError as e:
        raise _syntax_error(e, text) from None
    except yaml.YAMLError as e:
        raise TaskFileError(f"YAML error: {' '.join(str(e).split())}") from None


def _events(text: str) -> tuple[list[yaml.Event], dict[tuple[int, int], str]]:
    """Parse ``text`` as a stream of events: at most MAX_NODES nodes, MAX_DEPTH deep.

    Returns the events, and the tag of every scalar with an explicit tag (``!!float
    ""``, ``! 6``) by ``span``: the node tree does not tell such a scalar from a plain
    one YAML resolved to the same tag, nor keep the non-specific tag ``!``.

    Some libyaml builds scan ahead and stop a deep flow collection with a nesting limit of
    their own (1,000 levels, before any event reaches the check here). Such a file is
    parsed again by the pure-Python parser, which has no limit of its own: the check here
    then stops it where it passes MAX_DEPTH, with the same message and location whatever
    libyaml the machine has.
    """
    try:
        return _events_of(_Loader, text)
    except yaml.MarkedYAMLError as e:
        if _Loader is yaml.SafeLoader or not _libyaml_depth_limit(e):
            raise
    return _events_of(yaml.SafeLoader, text)


def _libyaml_depth_limit(e: yaml.MarkedYAMLError) -> bool:
    """Whether ``e`` is libyaml's own nesting limit ("exceeded maximum nesting depth")."""
    return "nesting depth" in f"{e.context} {e.problem}"


def _events_of(
    loader: type[yaml.SafeLoader] | type[yaml.CSafeLoader], text: str
) -> tuple[list[yaml.Event], dict[tuple[int, int], str]]:
    """``_events`` with the parser of ``loader``."""
    depth = nodes = 0
    explicit: dict[tuple[int, int], str] = {}
    events: list[yaml.Event] = []
    parser = loader(text)
    get, append = parser.get_event, events.append
    try:
        while True:  # get_event parses what check_event would, then None after the end
            ev = get()
            if ev is None:
                break
            append(ev)
            kind = type(ev)
            if kind in _NODE_EVENTS:
                nodes += 1
                if nodes > MAX_NODES:
                    line, column = where(ev)
                    raise TaskFileError(
                        f"too many YAML nodes (more than {MAX_NODES}); a task file has a few dozen",
                        line=line,
                        column=column,
                    )
                if kind is yaml.ScalarEvent:
                    if ev.tag is not None:
                        explicit[span(ev)] = ev.tag
                elif kind is not yaml.AliasEvent:
                    depth += 1
                    if depth > MAX_DEPTH:
                        line, column = where(ev)
                        raise TaskFileError(
                            f"nested deeper than {MAX_DEPTH} levels", line=line, column=column
                        )
            elif kind in _END_EVENTS:
                depth -= 1
    finally:
        parser.dispose()
    return events, explicit


class _Composer:
    """The node tree of one YAML stream's events, as PyYAML's composer (libyaml's or
    the pure-Python one, whichever ``_Loader`` is) makes it with the safe loader's
    resolver: the same nodes, tags, styles and marks, an alias the very node of its
    anchor, and the same errors (an undefined alias, a duplicate anchor, a second
    document)."""

    def __init__(self, events: list[yaml.Event]) -> None:
        self.events = iter(events)
        self.anchors: dict[str, yaml.Node] = {}
        self.c = not issubclass(_Loader, yaml.composer.Composer)  # libyaml's messages
        self.implicit = RESOLVER.yaml_implicit_resolvers  # first character -> resolvers
        self.wildcard = self.implicit.get(None, [])

    def single_node(self) -> yaml.Node | None:
        events = self.events
        next(events)  # the stream start
        ev = next(events)
        document = None
        if type(ev) is not yaml.StreamEndEvent:  # a document start
            document = self.node(next(events))
            next(events)  # the document end
            ev = next(events)
        if type(ev) is not yaml.StreamEndEvent:
            assert document is not None
            raise yaml.composer.ComposerError(
                "expected a single document in the stream",
                document.start_mark,
                "but found another document",
                ev.start_mark,
            )
        return document

    def node(self, ev: Any) -> yaml.Node:
        kind = type(ev)
        anchor = ev.anchor
        if anchor is not None:
            if kind is yaml.AliasEvent:
                if anchor not in self.anchors:
                    shown = "" if self.c else f" {anchor!r}"
                    raise yaml.composer.ComposerError(
                        None, None, f"found undefined alias{shown}", ev.start_mark
                    )
                return self.anchors[anchor]
            if anchor in self.anchors:
                shown = "" if self.c else f" {anchor!r}"
                raise yaml.composer.ComposerError(
                    f"found duplicate anchor{shown}; first occurrence",
                    self.anchors[anchor].start_mark,
                    "second occurrence",
                    ev.start_mark,
                )
        tag = ev.tag
        node: yaml.Node
        if kind is yaml.ScalarEvent:
            if tag is None or tag == "!":
                tag = self.scalar_tag(ev.value, ev.implicit)
            node = yaml.ScalarNode(tag, ev.value, ev.start_mark, ev.end_mark, style=ev.style)
            if anchor is not None:
                self.anchors[anchor] = node
            return node
        # a collection: the resolver's default tags (the safe loader has no path resolvers)
        if kind is yaml.MappingStartEvent:
            node = yaml.MappingNode(
                _MAP if tag is None or tag == "!" else tag,
                [],
                ev.start_mark,
                None,
                flow_style=ev.flow_style,
            )
        else:
            node = yaml.SequenceNode(
                _SEQ if tag is None or tag == "!" else tag,
                [],
                ev.start_mark,
                None,
                flow_style=ev.flow_style,
            )
        if anchor is not None:
            self.anchors[anchor] = node
        return self._items(node, kind is yaml.MappingStartEvent)

    def _items(self, node: Any, pairs: bool) -> yaml.Node:
        """A collection's items up to its end event (``_item`` of each), and its end mark."""
        items, events, item = node.value, self.events, self._item
        for ev in events:
            if type(ev) in _END_EVENTS:
                node.end_mark = ev.end_mark
                return node
            items.append((item(ev), item(next(events))) if pairs else item(ev))
        raise AssertionError("a collection without its end event")  # the parser pairs them

    def _item(self, ev: Any) -> yaml.Node:
        """``node`` of an item's first event, a scalar without an anchor made at once."""
        if type(ev) is yaml.ScalarEvent and ev.anchor is None:
            return self._scalar(ev)
        return self.node(ev)

    def _scalar(self, ev: Any) -> yaml.ScalarNode:
        """``node`` of a scalar event without an anchor (most of a file's events)."""
        tag = ev.tag
        if tag is None or tag == "!":
            tag = self.scalar_tag(ev.value, ev.implicit)
        return yaml.ScalarNode(tag, ev.value, ev.start_mark, ev.end_mark, style=ev.style)

    def scalar_tag(self, value: str, implicit: tuple[bool, bool]) -> str:
        """The tag PyYAML's resolver gives a scalar without one (``Resolver.resolve``);
        a function of the text alone, kept for the texts seen (``_RESOLVED``)."""
        if not implicit[0]:
            return _STR
        tag = _RESOLVED.get(value)
        if tag is None:
            tag = _STR
            for t, regexp in self.implicit.get(value[:1], []) + self.wildcard:
                if regexp.match(value):
                    tag = str(t)
                    break
            if len(value) <= _RESOLVED_LEN:  # numbers, names: a file's text is not kept
                if len(_RESOLVED) >= _RESOLVED_MAX:
                    _RESOLVED.clear()
                _RESOLVED[value] = tag
        return tag


# the implicit tag of a plain scalar's text, as the safe loader's resolver gives it (a
# pure function of the text: 'true', '6', '0.1', 'x'...), for the texts already seen
_RESOLVED: dict[str, str] = {}
_RESOLVED_MAX = 4096
_RESOLVED_LEN = 64


def span(item: yaml.Node | yaml.Event) -> tuple[int, int]:
    """Where a scalar event or node starts and ends (an empty untagged scalar may start
    where the next one does, but ends there too)."""
    return item.start_mark.index, item.end_mark.index


def _syntax_error(e: yaml.MarkedYAMLError, text: str) -> TaskFileError:
    """YAML's own complaint, at YAML's line and column, with a hint where one helps."""
    mark = e.problem_mark or e.context_mark
    problem = ": ".join(str(x).strip() for x in (e.context, e.problem) if x)
    alias = re.match(r"\*([^\s,\[\]{}]+)", text[mark.index :]) if mark else None
    if "undefined alias" in problem and alias:
        name = shorten(alias.group(1))
        problem += f" *{name} (no anchor &{name} before it)"
    if mark and text[mark.index : mark.index + 1] == "\t":
        problem += " (a tab: YAML indents with spaces only)"
    elif mark and any(p in problem for p in _BLOCK_PROBLEMS):
        hint = _indentation(text, e.problem_mark.line if e.problem_mark else mark.line)
        if hint is not None:
            line, found, message = hint
            return TaskFileError(
                f"YAML syntax error: {message} (YAML says: {problem})",
                line=line + 1,
                column=found + 1,
            )
    return TaskFileError(
        f"YAML syntax error: {problem}",
        line=mark.line + 1 if mark else 0,
        column=mark.column + 1 if mark else 0,
    )


# libyaml's and PyYAML's complaints about a block whose indentation went wrong


# libyaml's and PyYAML's complaints about a block whose indentation went wrong
_BLOCK_PROBLEMS = (
    "did not find expected key",
    "mapping values are not allowed",
    "did not find expected '-' indicator",
    "expected <block end>",
)


def _indentation(text: str, at: int) -> tuple[int, int, str] | None:
    """Where a block's indentation goes wrong at or just before line ``at`` (0-based):
    (line, its indentation, "wrong indentation: ...") when that line is indented to
    none of the levels of the blocks open above it (each key's column, and a list
    item's dash and its content), naming the nearest; None when every line fits."""
    lines = text.splitlines()
    for line in (at, at - 1):
        if not 0 <= line < len(lines) or not _content(lines[line]):
            continue
        found = _indent(lines[line])
        levels: dict[int, int] = {}  # indentation -> the line (0-based) that opens it
        deepest = None
        for j in range(line - 1, -1, -1):
            if not _content(lines[j]):
                continue
            ind = _indent(lines[j])
            if deepest is not None and ind >= deepest:
                continue  # inside a block already closed above this line
            deepest = ind
            levels.setdefault(ind, j)
            dash = re.match(r" *(- +)", lines[j])
            if dash:  # a list item's content is indented past its dash
                levels.setdefault(ind + len(dash.group(1)), j)
            if ind == 0:
                break
        if not levels or found in levels:
            continue
        gap = min(abs(v - found) for v in levels)
        near = sorted((v for v in levels if abs(v - found) == gap), reverse=True)
        expected = " or ".join(f"{v} (as line {levels[v] + 1})" for v in near)
        return (
            line,
            found,
            f"wrong indentation: expected {expected} but found {found}"
            + (" space" if found == 1 else " spaces"),
        )
    return None


def _indent(line: str) -> int:
    return len(line) - len(line.lstrip(" "))


def _content(line: str) -> bool:
    """Whether a line holds YAML content (not blank, not only a comment)."""
    return bool(line.strip()) and not line.lstrip().startswith("#")

"""Reading a task file: bytes -> YAML node tree -> validated ``Task`` (exact numbers).

Safety: the YAML is only *composed* (parsed into nodes), never constructed into Python
objects, so no tag can run code; only the plain tags (str, int, float, bool, null, map,
seq) are accepted, and an explicit one must fit its value: a tag never makes an invalid
value valid (``_misfit``). Duplicate keys are errors (PyYAML would silently keep the
last), and aliases are followed with a budget on visited nodes, so an alias bomb is
rejected rather than expanded. Numbers are taken by their text (``0.1`` is 1/10). Every error is a
``TaskFileError`` naming the file, line, column and dotted key.
"""

from __future__ import annotations

import functools
import itertools
import os
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml
from flint import fmpq, fmpq_poly

from ..model.errors import ExpressionError, TaskFileError
from ..model.motion import position_jump
from ..model.numbers import rational as _q
from ..model.rules import rule_id
from ..model.task import Checks, Link, Piece, Robot, Task
from ..model.timing import LAWS, timing_law, trapezoidal
from ..model.waypoints import Waypoint
from ..model.waypoints import pieces as waypoint_pieces
from .expression import MAX_DEGREE, height, parse_decimal, parse_fraction, parse_polynomial
from .reading import ReadProblem, read_file, read_stream, too_large
from .schema import CSV_PATTERN, TASK, TRAPEZOIDAL, Spec
from .uncertainty import EXPECTED as _PERCENT_EXPECTED
from .uncertainty import needs_limit, percent, relative, uncertainty_of
from .waypoint_csv import CsvProblem, parse_waypoints, read_bytes

MAX_BYTES = 1 << 20  # 1 MiB: a task file is a few hundred bytes
MAX_NODES = 10_000  # YAML nodes in the file, and nodes visited with aliases followed
MAX_DEPTH = 32  # nesting of mappings and lists
MAX_COMPOSED_BITS = 1 << 16  # bound on the coefficients of y(x(t)), see _composition_within_caps

_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
_TAG = "tag:yaml.org,2002:"
_MERGE = _TAG + "merge"
_STR, _MAP, _SEQ = (_TAG + t for t in ("str", "map", "seq"))
_NOT_KEYS = (_TAG + "null", _TAG + "bool")  # scalars that are not plain keys
_NUMBER_TAGS = (_TAG + "int", _TAG + "float")
# A number as most task files write one (0, 12, -0.03): read directly, as the general
# path (``_Walk.number_tag``, ``_number_value``, ``parse_decimal``) would read it.
_SIMPLE_DECIMAL = re.compile(r"-?(0|[1-9][0-9]{0,14})(\.[0-9]{1,15})?")
_PLAIN_TAGS = {_TAG + t for t in ("str", "int", "float", "bool", "null", "map", "seq")}
# Control characters in values after YAML's escapes are decoded: C0 but tab and line
# feed, DEL, C1, and the noncharacters U+FFFE/U+FFFF (terminal escapes, broken SVG/XML),
# and lone surrogates, which only the pure-Python YAML parser lets through.
_ESCAPED_CONTROL = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\ud800-\udfff\ufffe\uffff]")
# Characters YAML does not allow in a stream, found here first so that the message names
# the line and column whichever YAML parser runs: the very pattern of PyYAML's reader
# (yaml.reader.Reader.NON_PRINTABLE), so that re compiles it once (20 ms) for both.
_NON_PRINTABLE = re.compile(
    "[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]"
)
# YAML 1.2 reads 1e3 as a number; PyYAML (YAML 1.1) resolves it to text. A plain scalar
# in this form is taken as the number it means (editors using the shipped schema agree).
_YAML12_FLOAT = re.compile(r"[-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?")
_DECIMAL_INT = re.compile(r"[-+]?[0-9]+")
_RADIX_INT = re.compile(r"[-+]?0([xX][0-9a-fA-F]+|[oO][0-7]+|[bB][01]+)")
_RESOLVER = yaml.resolver.Resolver()
_LINE_BREAK = re.compile("\r\n|[\r\n\x85\u2028\u2029]")
_PLAIN_KEY = re.compile(r"[A-Za-z0-9_-]{1,40}")  # shown unquoted (rule names have -)
_NAN = re.compile(r"[-+]?\.?nan", re.IGNORECASE)
_INF = re.compile(r"[-+]?\.?inf(inity)?", re.IGNORECASE)
_SPECIAL_ENDS = "nNfFyY"  # the last letters of nan, inf, infinity (any case)
_LINKS = TASK.children["robot"].children["links"]  # the paper's moving links 2..5
_SCALAR_TEXT = {_TAG + t for t in ("str", "int", "float")}  # what reads as text
# An explicit tag only narrows: the value must be one of its tag as YAML 1.2 has it,
# written as the loader reads an untagged value (see _misfit).
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
_FRACTION = re.compile(r"[-+]?[0-9.]+\s*/\s*[0-9.]+")
_FRACTION_HINT = (
    " (a fraction is only allowed in path.y, timing.x, path.from and path.to: write a decimal here)"
)
_POINT_KEYS = Spec(  # a point written as a mapping: {x: 1, y: -2/3}
    "mapping",
    "a point",
    children={"x": Spec("number", "x [m]", required=True), "y": Spec("number", "y [m]")},
)


def load_task(path: str | os.PathLike[str]) -> Task:
    """Read and validate the task file at ``path``; raises ``TaskFileError``. A waypoint
    CSV it names is read relative to the task file's directory."""
    name = os.fspath(path)
    try:
        data = read_file(name, MAX_BYTES, "a task file (YAML)")
    except ReadProblem as e:
        raise TaskFileError(e.message, file=name) from None
    return parse_task(data, name, directory=os.path.dirname(name) or os.curdir)


def read_stdin(name: str = "-") -> bytes:
    """Standard input, at most ``MAX_BYTES`` (``reading.read_stream``: an endless or
    stalled pipe is stopped at the cap); a ``TaskFileError`` naming ``name`` beyond it."""
    import sys

    try:
        return read_stream(getattr(sys.stdin, "buffer", None), MAX_BYTES)
    except ReadProblem as e:
        raise TaskFileError(e.message, file=name) from None


def waypoint_file(path: str, data: bytes | None = None) -> str | None:
    """The waypoint CSV the task file ``path`` names (``motion.waypoints: plan.csv``), as
    a path from the working directory, or None. ``data``: the task's bytes (standard
    input: its CSV is named from the working directory). Found by composing the YAML
    alone, within the loader's caps and nothing validated: what the output guard of a run
    needs before any task is loaded; a file that cannot be read or composed names none
    (loading it says why)."""
    try:
        if data is None:
            data = read_file(path, MAX_BYTES, "a task file (YAML)")
            directory = os.path.dirname(path) or os.curdir
        else:
            directory = os.curdir
        root, _ = _compose(_decode(data))
    except (ReadProblem, TaskFileError, yaml.YAMLError, RecursionError):
        return None
    node = _child(_child(root, "motion"), "waypoints")
    if not isinstance(node, yaml.ScalarNode) or not re.fullmatch(CSV_PATTERN, str(node.value)):
        return None
    return os.path.normpath(os.path.join(directory, str(node.value)))


def _child(node: yaml.Node | None, key: str) -> yaml.Node | None:
    """The value of ``key`` in the mapping ``node`` (None: not a mapping, or no such key)."""
    if not isinstance(node, yaml.MappingNode):
        return None
    for k, v in node.value:
        if isinstance(k, yaml.ScalarNode) and k.value == key:
            return v
    return None


def parse_task(data: bytes | str, file: str = "<task>", *, directory: str = os.curdir) -> Task:
    """Validate a task given as bytes or text; ``file`` names it in errors, and a
    waypoint CSV it names (``motion.waypoints: planned.csv``) is read relative to
    ``directory`` (default: the working directory, as for a task on standard input).

    Raises ``TaskFileError`` and nothing else, whatever ``data`` holds: the first error
    found, with every independent error of the file in its ``errors`` (by line and column).
    An error that makes the rest meaningless (the file cannot be decoded, a YAML syntax
    error, a file too large, too many nodes or too deep) is the only one.
    """
    try:
        return _parse(data, file, directory)
    except TaskFileError as e:
        first, *others = (
            TaskFileError(
                _one_line(x.message), file=file, line=x.line, column=x.column, key=_one_line(x.key)
            )
            for x in e.errors
        )
        first.errors = (first, *others)
        raise first from None
    except RecursionError:
        raise TaskFileError(f"nested deeper than {MAX_DEPTH} levels", file=file) from None


def _one_line(text: str) -> str:
    """``text`` with line breaks and other unprintable characters escaped: one line."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def _too_large(size: int) -> str:
    return too_large(MAX_BYTES, size)


def _line_col(text: str, index: int) -> tuple[int, int]:
    """1-based (line, column) of the character at ``index``, counting lines as YAML does
    (CR LF, CR, LF, NEL, LS and PS each end one)."""
    breaks = list(_LINE_BREAK.finditer(text, 0, index))
    start = breaks[-1].end() if breaks else 0
    return len(breaks) + 1, index - start + 1


def _decode(data: bytes | str) -> str:
    """The task file as text: size cap, binary and encoding checks."""
    if isinstance(data, str):
        try:
            data = data.encode("utf-8")
        except UnicodeEncodeError as e:
            raise TaskFileError(
                f"not valid Unicode text (lone surrogate at character {e.start})"
            ) from None
    if len(data) > MAX_BYTES:
        raise TaskFileError(_too_large(len(data)))
    text = _utf8(data).removeprefix("\ufeff")
    bad = _NON_PRINTABLE.search(text)
    if bad:
        line, column = _line_col(text, bad.start())
        raise TaskFileError(
            f"control character U+{ord(bad.group(0)):04X} is not allowed in YAML text"
            " (a binary file?)",
            line=line,
            column=column,
        )
    return text


def _utf8(data: bytes) -> str:
    """``data`` decoded as UTF-8; UTF-32, UTF-16 and binary files are named as such."""
    if data.startswith((b"\xff\xfe\x00\x00", b"\x00\x00\xfe\xff")):
        raise TaskFileError("UTF-32 text, expected UTF-8: save the file as UTF-8")
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise TaskFileError("UTF-16 text, expected UTF-8: save the file as UTF-8")
    nul = data.find(b"\x00")
    if nul >= 0:
        line = data.count(b"\n", 0, nul) + 1
        column = nul - (data.rfind(b"\n", 0, nul) + 1) + 1  # in bytes
        raise TaskFileError(
            f"binary file (NUL byte at offset {nul}), expected YAML text",
            line=line,
            column=column,
        )
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        column = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1  # in bytes
        raise TaskFileError(
            f"not UTF-8 text: byte 0x{data[e.start]:02x} at offset {e.start} ({e.reason})",
            line=line,
            column=column,
        ) from None
    return text


def _compose(text: str) -> tuple[yaml.Node | None, dict[tuple[int, int], str]]:
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
    ""``, ``! 6``) by ``_span``: the node tree does not tell such a scalar from a plain
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
    events = []
    parser = loader(text)
    try:
        while parser.check_event():
            ev = parser.get_event()
            events.append(ev)
            kind = type(ev)
            if kind in _NODE_EVENTS:
                nodes += 1
                if nodes > MAX_NODES:
                    line, column = _where(ev)
                    raise TaskFileError(
                        f"too many YAML nodes (more than {MAX_NODES}); a task file has a few dozen",
                        line=line,
                        column=column,
                    )
                if kind is yaml.ScalarEvent:
                    if ev.tag is not None:
                        explicit[_span(ev)] = ev.tag
                elif kind is not yaml.AliasEvent:
                    depth += 1
                    if depth > MAX_DEPTH:
                        line, column = _where(ev)
                        raise TaskFileError(
                            f"nested deeper than {MAX_DEPTH} levels", line=line, column=column
                        )
            elif kind in _END_EVENTS:
                depth -= 1
    finally:
        parser.dispose()
    return events, explicit


_NODE_EVENTS = {yaml.ScalarEvent, yaml.AliasEvent, yaml.SequenceStartEvent, yaml.MappingStartEvent}
_END_EVENTS = {yaml.SequenceEndEvent, yaml.MappingEndEvent}


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
        self.implicit = _RESOLVER.yaml_implicit_resolvers  # first character -> resolvers
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
        items, events = node.value, self.events
        pairs = kind is yaml.MappingStartEvent
        for ev in events:
            if type(ev) in _END_EVENTS:
                node.end_mark = ev.end_mark
                return node
            item = self.node(ev)
            items.append((item, self.node(next(events))) if pairs else item)
        raise AssertionError("a collection without its end event")  # the parser pairs them

    def scalar_tag(self, value: str, implicit: tuple[bool, bool]) -> str:
        """The tag PyYAML's resolver gives a scalar without one (``Resolver.resolve``)."""
        if implicit[0]:
            for tag, regexp in self.implicit.get(value[:1], []) + self.wildcard:
                if regexp.match(value):
                    return str(tag)
        return _STR


def _span(item: yaml.Node | yaml.Event) -> tuple[int, int]:
    """Where a scalar event or node starts and ends (an empty untagged scalar may start
    where the next one does, but ends there too)."""
    return item.start_mark.index, item.end_mark.index


def _syntax_error(e: yaml.MarkedYAMLError, text: str) -> TaskFileError:
    """YAML's own complaint, at YAML's line and column, with a hint where one helps."""
    mark = e.problem_mark or e.context_mark
    problem = ": ".join(str(x).strip() for x in (e.context, e.problem) if x)
    alias = re.match(r"\*([^\s,\[\]{}]+)", text[mark.index :]) if mark else None
    if "undefined alias" in problem and alias:
        name = _short(alias.group(1))
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


def _parse(data: bytes | str, file: str, directory: str) -> Task:
    text = _decode(data)
    if all(not ln.strip() or ln.lstrip().startswith("#") for ln in text.splitlines()):
        raise TaskFileError("empty task file, expected a mapping with robot, path and timing")
    root, explicit = _compose(text)
    if root is None or (isinstance(root, yaml.ScalarNode) and root.value == "" and not root.style):
        raise TaskFileError("empty task file, expected a mapping with robot, path and timing")
    # a value can hold a control character only by an escape (decoded) or as written
    escapes = "\\" in text or _ESCAPED_CONTROL.search(text) is not None
    walk = _Walk(explicit, directory, escapes=escapes)
    walk.read(root, TASK, "", 0)
    if walk.errors:  # in the order of the file, as a linter lists them; missing keys last
        errors = sorted(walk.errors, key=lambda e: (isinstance(e, _Missing), e.line, e.column))
        errors[0].errors = tuple(errors)
        raise errors[0]
    return _task(walk, file)


# -- the Task, from the values read ------------------------------------------------------


def _task(w: _Walk, file: str) -> Task:
    """The ``Task`` of a walk over the whole file (defaults applied); the file's stem
    names it when the file does not."""
    v = w.values
    law, x_of_t, pieces = _motion(w)
    return Task(
        name=v["name"] if "name" in v else Path(file).stem,
        robot=_robot(v),
        path=v.get("path.y"),
        x_of_t=x_of_t,
        duration=pieces[-1].end if pieces else v["timing.duration"],
        checks=Checks(
            min_slope=v["checks.min_slope"],
            min_speed=v["checks.min_speed"],
            torque_limit=v.get("checks.torque_limit"),
            strict=v["checks.strict"],
            unbounded_torque=v["checks.unbounded_torque"],
            rules=_levels(w),
            peak=v["checks.peak"],
        ),
        law=law,
        lines=dict(w.lines),
        source=file,
        pieces=tuple(pieces),
        uncertainty=uncertainty_of(v, "uncertainty" in w.nodes),
    )


def _levels(w: _Walk) -> dict[str, str]:
    """Rule id -> "warn" or "ignore", from checks.warn and checks.ignore (both: ignore),
    whose keys are rule ids or names."""
    if "checks.warn" not in w.nodes and "checks.ignore" not in w.nodes:
        return {}  # neither given: no key below them has a value
    out = {}
    for level in ("warn", "ignore"):  # both: ignore wins
        for k in w.values:
            if k.startswith(f"checks.{level}."):
                name = k[len(f"checks.{level}.") :]
                out[rule_id(name) or name] = level
    return out


def _robot(v: dict[str, Any]) -> Robot:
    links = {int(i): _link(v, f"robot.links.{i}") for i in _LINKS.children}
    return Robot(
        a1=v["robot.a1"], links=links, gravity=v["robot.gravity"], actuation=v["robot.actuation"]
    )


def _link(v: dict[str, Any], key: str) -> Link:
    return Link(mass=v[f"{key}.mass"], inertia=v[f"{key}.inertia"], r=v[f"{key}.r"])


def _motion(w: _Walk) -> tuple[str, fmpq_poly | None, list[Piece]]:
    """(law, x_E(t), pieces): the paper's form (a rest-to-rest law from path.from to
    path.to, or "explicit" timing.x) with no pieces, or a piecewise motion ("trapezoidal",
    "pieces", "motion", "waypoints") with x_E(t) None."""
    v = w.values
    if "motion.pieces" in v:
        return "motion", None, _motion_pieces(v["motion.pieces"])
    if "motion.waypoints" in v:
        return "waypoints", None, _waypoint_pieces(v["motion.waypoints"], w.csv_file)
    p = v["path.y"]
    if v.get("timing.law") == TRAPEZOIDAL:
        line = w.lines.get("timing.law", 0)
        return TRAPEZOIDAL, None, [Piece(s, e, x, p(x), p, line) for s, e, x in _timing(w)]
    if "timing.law" in v:
        return v["timing.law"], _timing(w)[0][2], []
    if isinstance(v["timing.x"], list):
        return "pieces", None, [Piece(s, e, x, p(x), p, ln) for s, e, x, ln in _timed(v)]
    return "explicit", v["timing.x"], []


def _x_pieces(v: dict[str, Any]) -> list[tuple[fmpq, fmpq, fmpq_poly]]:
    """(start, end, x(t)) of the timing: the trapezoidal law's pieces, timing.x's pieces,
    or the one polynomial of a rest-to-rest law or of an explicit x(t)."""
    t_f = v["timing.duration"]
    if v.get("timing.law") == TRAPEZOIDAL:
        law = trapezoidal(v["path.from"][0], v["path.to"][0], t_f, v["timing.cruise_speed"])
        ends = [fmpq(0), *(end for end, _ in law)]
        return [(s, e, x) for s, (e, x) in zip(ends, law, strict=False)]
    if "timing.law" in v:
        return [
            (fmpq(0), t_f, timing_law(v["timing.law"], v["path.from"][0], v["path.to"][0], t_f))
        ]
    if isinstance(v["timing.x"], list):
        return [(s, e, x) for s, e, x, _ in _timed(v)]
    return [(fmpq(0), t_f, v["timing.x"])]


def _timing(w: _Walk) -> list[tuple[fmpq, fmpq, fmpq_poly]]:
    """``_x_pieces`` of the walk's values, worked out once (the caps check needs them
    before the ``Task`` does)."""
    if w.x_pieces is None:
        w.x_pieces = _x_pieces(w.values)
    return w.x_pieces


def _timed(v: dict[str, Any]) -> list[tuple[fmpq, fmpq, fmpq_poly, int]]:
    """(start, end, x(t), line) of each piece of timing.x given as pieces."""
    items = v["timing.x"]
    starts = [fmpq(0), *(it["until"] for it in items[:-1])]
    return [(s, it["until"], it["x"], it["line"]) for s, it in zip(starts, items, strict=True)]


def _motion_pieces(items: list[dict[str, Any]]) -> list[Piece]:
    """The pieces of motion.pieces, from t = 0 (polynomials in absolute time)."""
    starts = [fmpq(0), *(it["until"] for it in items[:-1])]
    return [
        Piece(s, it["until"], it["x"], it["y"], None, it["line"])
        for s, it in zip(starts, items, strict=True)
    ]


def _waypoint_pieces(points: list[Waypoint], file: str) -> list[Piece]:
    """The joint_trajectory_controller's pieces through the waypoints; ``file`` is the
    CSV file they were read from ('' when inline: their lines are the task file's)."""
    return waypoint_pieces(points, file)


# -- cross-field rules: what no single key's Spec can say --------------------------------
# Each runs as soon as the key it is filed under in _RULES has been read (a mapping: with
# all its keys), so the error reported is the first problem in reading order.


def _on_path(w: _Walk, key: str) -> None:
    """path.from or path.to lies on y = p(x); a point given by its x alone gets y = p(x)."""
    p = w.values["path.y"]
    x0, y0 = w.values[key]
    if y0 is None:
        w.values[key] = (x0, p(x0))
        return
    if p(x0) != y0:
        raise w.error(
            f"point ({_q(x0)}, {_q(y0)}) is not on the path: y({_q(x0)}) = {_q(p(x0))},"
            f" found y = {_q(y0)}",
            w.nodes[key],
            key,
        )


def _law_or_x(w: _Walk, key: str) -> None:
    """timing gives exactly one of law and x (checked once its duration is read); with
    motion, neither (nor cruise_speed): its duration alone."""
    if "motion" in w.nodes:
        given = [k for k in ("law", "cruise_speed", "x") if f"timing.{k}" in w.nodes]
        if given:
            raise w.error(
                f"with motion, timing gives only duration (the motion's own times say how"
                f" it moves), found {', '.join(given)}",
                w.nodes[f"timing.{given[0]}"],
                f"timing.{given[0]}",
            )
        return
    law, x = "timing.law" in w.nodes, "timing.x" in w.nodes
    if not (law or x) and {"timing.law", "timing.x"} & w.misspelt:
        return  # the misspelt key is reported as such
    if law and x:
        raise w.error(
            "give either law or x, not both (law moves x between path.from and path.to;"
            " x gives x(t) explicitly)",
            w.nodes["timing"],
            "timing",
        )
    if not law and not x:
        raise w.error(
            f"missing timing law: give law ({', '.join(LAWS)}, or {TRAPEZOIDAL} with"
            " cruise_speed) or x (a polynomial in t, or pieces {until, x})",
            w.nodes["timing"],
            "timing",
        )


def _law_needs(w: _Walk, key: str) -> None:
    """A rest-to-rest law moves between path.from and path.to: both must be given; the
    trapezoidal law needs its cruise_speed too."""
    if "motion" in w.nodes:
        return  # timing.law with motion: _law_or_x said so
    cruise = "timing.cruise_speed"
    if w.values[key] == TRAPEZOIDAL and cruise not in w.nodes and cruise not in w.misspelt:
        w.errors.append(
            w.error(
                "law trapezoidal needs cruise_speed (|dx/dt| while cruising [m/s], in"
                " (D/t_f, 2D/t_f], D = |x1 - x0|)",
                w.nodes[key],
                key,
            )
        )
    if "path" not in w.nodes:
        return  # the path is missing (or misspelt): reported as such
    ends = [f"path.{end}" for end in ("from", "to")]
    missing = [end[5:] for end in ends if end not in w.nodes and end not in w.misspelt]
    if missing:
        raise w.error(
            f"law {w.values[key]} needs path.{' and path.'.join(missing)} (the points it"
            " moves between)",
            w.nodes[key],
            key,
        )


def _cruise(w: _Walk, key: str) -> None:
    """cruise_speed goes with law trapezoidal, and lies in (D/t_f, 2D/t_f]: slower, the
    motion cannot cover D in t_f; faster, it cannot reach the speed and stop again."""
    if "motion" in w.nodes or ("timing.law" in w.nodes and "timing.law" not in w.values):
        return  # said so by _law_or_x, or the law is bad: reported as such
    if w.values.get("timing.law") != TRAPEZOIDAL:
        raise w.error("cruise_speed is only for law: trapezoidal", w.nodes[key], key)
    if "path.from" not in w.values or "path.to" not in w.values:
        return  # missing or bad: reported as such
    V, t_f = w.values[key], w.values["timing.duration"]
    D = abs(w.values["path.to"][0] - w.values["path.from"][0])
    if D == 0:
        raise w.error(
            "law trapezoidal needs path.from and path.to at different x (it moves x"
            f" from one to the other), both have x = {_q(w.values['path.to'][0])}",
            w.nodes["timing.law"],
            "timing.law",
        )
    lo, hi = D / t_f, 2 * D / t_f
    if not lo < V <= hi:
        why = (
            "too slow to cover D in t_f"
            if lo >= V
            else "too fast to reach and leave again in t_f (at 2D/t_f the profile is a triangle)"
        )
        raise w.error(
            f"cruise_speed {_q(V)} is outside (D/t_f, 2D/t_f] = ({_q(lo)}, {_q(hi)}] for"
            f" D = |x1 - x0| = {_q(D)} m and t_f = {_q(t_f)} s: {why}",
            w.nodes[key],
            key,
        )


def _pieces_meet(w: _Walk, key: str, coords: tuple[str, ...], t_f: fmpq | None) -> bool:
    """The pieces at ``key`` are consecutive from t = 0, in increasing time, end at
    ``t_f`` (when given) and are continuous in position (``coords``) at every knot;
    errors are recorded, True when there were none."""
    items = w.values[key]
    before = len(w.errors)
    prev = fmpq(0)
    for i, it in enumerate(items):
        if not it["until"] > prev:
            after = "t = 0" if i == 0 else f"the previous piece's until ({_q(prev)})"
            w.errors.append(
                w.error(
                    f"until {_q(it['until'])} must come after {after}: pieces are consecutive"
                    " from t = 0, in increasing time",
                    w.nodes[f"{it['key']}.until"],
                    f"{it['key']}.until",
                )
            )
        prev = max(prev, it["until"])
    if len(w.errors) > before:
        return False
    for a, b in itertools.pairwise(items):
        t = a["until"]
        jump = position_jump([a[c] for c in coords], [b[c] for c in coords], t)
        if jump is not None:
            names = coords[0] if len(coords) == 1 else f"({', '.join(coords)})"
            left, right = (
                _q(v[0]) if len(v) == 1 else f"({', '.join(_q(c) for c in v)})" for v in jump
            )
            w.errors.append(
                w.error(
                    f"the position jumps at the knot t = {_q(t)}: {names} = {left} before,"
                    f" {right} after (line {b['line']}); position must be continuous",
                    w.nodes[f"{a['key']}.until"],
                    f"{a['key']}.until",
                )
            )
    last = items[-1]
    if t_f is not None and last["until"] != t_f:
        w.errors.append(
            w.error(
                f"the last piece ends at until = {_q(last['until'])}, but timing.duration is"
                f" {_q(t_f)}: they must be equal",
                w.nodes[f"{last['key']}.until"],
                f"{last['key']}.until",
            )
        )
    return len(w.errors) == before


def _x_meets_ends(w: _Walk, key: str) -> None:
    """An explicit x(t) starts at path.from's x and ends at path.to's, where given; given
    as pieces, they are consecutive and continuous, and end at the duration."""
    x, t_f = w.values[key], w.values["timing.duration"]
    if isinstance(x, list):
        if not _pieces_meet(w, key, ("x",), t_f):
            return
        first, last = x[0]["x"], x[-1]["x"]
    else:
        first = last = x
    for end, poly, at, when in (
        ("path.from", first, fmpq(0), "0"),
        ("path.to", last, t_f, f"t_f = {_q(t_f)}"),
    ):
        if end in w.values and poly(at) != w.values[end][0]:
            raise w.error(
                f"{end} has x = {_q(w.values[end][0])} but timing.x gives"
                f" x({when}) = {_q(poly(at))}: they must agree",
                w.nodes[end],
                end,
            )


def _composition_within_caps(w: _Walk, key: str) -> None:
    """Cap the degree of y(x(t)) and bound the size of its coefficients.

    With p = P/dp and x = X/dx (integer polynomials over their common denominators),
    p(x) = sum P_k X^k dx^(d-k) / (dp dx^d), so every integer in it has at most
    h(p) + d (h(x) + log2 len(X)) + log2 (d + 1) bits, h = ``expression.height``.
    """
    v = w.values
    if "motion" in w.nodes:
        return
    if not ("timing.x" in v or all(k in v for k in ("timing.law", "path.from", "path.to"))):
        return  # x(t) could not be read: its own error is reported
    try:
        pieces = _timing(w)
    except (KeyError, ValueError):
        return  # no cruise_speed, or a bad one: reported as such
    for _, _, x in pieces:
        _composed_within_caps(w, v["path.y"], x)


def _composed_within_caps(w: _Walk, p: fmpq_poly, x: fmpq_poly) -> None:
    dp, dx = max(p.degree(), 0), max(x.degree(), 0)
    if dp * dx > MAX_DEGREE:
        raise w.error(
            f"the composition y(x(t)) has degree {dp * dx} (path degree {dp} × timing degree"
            f" {dx}), beyond the cap of {MAX_DEGREE}",
            w.nodes["path.y"],
            "path.y",
        )
    bits = height(p) + dp * (height(x) + len(x.coeffs()).bit_length()) + (dp + 1).bit_length()
    if bits > MAX_COMPOSED_BITS:
        raise w.error(
            f"numbers too large: the coefficients of y(x(t)) may reach {bits} bits, beyond the"
            f" cap of {MAX_COMPOSED_BITS}",
            w.nodes["path.y"],
            "path.y",
        )


def _given_duration(w: _Walk) -> fmpq | None:
    """timing.duration when the task gives it with motion (then the motion must end
    there), else None."""
    return w.values.get("timing.duration") if "timing.duration" in w.nodes else None


def _motion_pieces_meet(w: _Walk, key: str) -> None:
    """motion.pieces: consecutive from t = 0, continuous in (x, y), ending at
    timing.duration when given."""
    _pieces_meet(w, key, ("x", "y"), _given_duration(w))


def _waypoints_in_order(w: _Walk, key: str) -> None:
    """At least two waypoints, from t = 0, in increasing time, all giving the same
    fields; the last at timing.duration when given. A CSV row's error names the file
    and the row (at the line of ``waypoints:``)."""
    points: list[Waypoint] = w.values[key]

    def error(i: int, message: str) -> TaskFileError:
        if w.csv_name:
            return w.error(f"{w.csv_name}:{points[i].line}: {message}", w.nodes[key], key)
        return w.error(message, w.nodes[f"{key}[{i}].t"], f"{key}[{i}].t")

    if len(points) < 2:
        raise w.error(f"expected at least two waypoints, found {len(points)}", w.nodes[key], key)
    if points[0].t != 0:
        w.errors.append(
            error(0, f"the first waypoint is at t = {_q(points[0].t)}; waypoints start at t = 0")
        )
    first = _fields(points[0])
    for i in range(1, len(points)):
        if not points[i].t > points[i - 1].t:
            w.errors.append(
                error(
                    i,
                    f"t = {_q(points[i].t)} does not come after the previous waypoint's"
                    f" t = {_q(points[i - 1].t)}: times must increase",
                )
            )
        if _fields(points[i]) != first:
            w.errors.append(
                error(
                    i,
                    f"this waypoint gives {_fields(points[i])} but the first gives {first}:"
                    " every waypoint must give the same fields (p; p, v; or p, v, a)",
                )
            )
    t_f = _given_duration(w)
    if t_f is not None and points[-1].t != t_f:
        w.errors.append(
            error(
                len(points) - 1,
                f"the last waypoint is at t = {_q(points[-1].t)}, but timing.duration is"
                f" {_q(t_f)}: they must be equal",
            )
        )


def _fields(point: Waypoint) -> str:
    return ", ".join(k for k, v in (("p", 1), ("v", point.v), ("a", point.a)) if v is not None)


def _motion_alone(w: _Walk, key: str) -> None:
    """motion gives exactly one of pieces and waypoints, and replaces path."""
    given = [k for k in ("pieces", "waypoints") if f"motion.{k}" in w.nodes]
    if "path" in w.nodes:
        w.errors.append(
            w.error(
                "give either path (with timing) or motion, not both (motion gives the end"
                " point's x(t) and y(t) directly)",
                w.nodes[key],
                key,
            )
        )
    if len(given) == 2:
        raise w.error("give either pieces or waypoints, not both", w.nodes[key], key)
    if not given and not {"motion.pieces", "motion.waypoints"} & w.misspelt:
        raise w.error(
            "missing motion: give pieces (a list of {until, x, y}) or waypoints (a list of"
            " {t, p, v, a}, or a CSV file's name)",
            w.nodes[key],
            key,
        )


_Rule = Callable[["_Walk", str], None]
# key -> (its rule, the values the rule needs besides the key's own): a rule runs only
# when they were all read, so that a bad value is reported once, by its own reader
_RULES: dict[str, tuple[_Rule, tuple[str, ...]]] = {
    "path.from": (_on_path, ("path.y",)),
    "path.to": (_on_path, ("path.y",)),
    "timing.duration": (_law_or_x, ()),  # before law or x is read
    "timing.law": (_law_needs, ()),
    "timing.cruise_speed": (_cruise, ("timing.duration",)),
    "timing.x": (_x_meets_ends, ("timing.duration",)),
    "timing": (_composition_within_caps, ("path.y", "timing.duration")),
    "motion.pieces": (_motion_pieces_meet, ()),
    "motion.waypoints": (_waypoints_in_order, ()),
    "motion": (_motion_alone, ()),
    "uncertainty": (needs_limit, ()),
}


# -- the generic walk along the schema ---------------------------------------------------


class _Stop(TaskFileError):
    """An error after which the walk reads nothing more (the node budget, the depth)."""


class _Missing(TaskFileError):
    """A required key not given (listed after the errors of the keys that are)."""


class _Recorded(Exception):
    """A value that cannot be read, whose errors are already in ``_Walk.errors``."""


class _Walk:
    """Reads a YAML node tree along a ``Spec`` tree (``schema.TASK``), generically.

    Every check one key's Spec states is made here from the Spec alone: kind, bound,
    choices, required and unknown keys, list length; an omitted key takes its
    ``Spec.default``. ``values`` maps each dotted key read or defaulted to its exact
    value, ``nodes`` each key given in the file to its value node, ``lines`` to the line
    of the key. Only the nodes the schema knows are visited, each counted against
    ``MAX_NODES`` (an alias counts every time it is followed), so aliasing cannot blow up
    the work. An explicit tag must fit its value (``_misfit``), and a tagged value is
    then read as its text written plain: a tag never makes an invalid value valid.
    """

    def __init__(
        self,
        explicit: dict[tuple[int, int], str] | None = None,
        directory: str = os.curdir,
        *,
        escapes: bool = True,
    ) -> None:
        self.explicit = explicit or {}  # the explicit tags of scalars, by _span
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
        self.x_pieces: list[tuple[fmpq, fmpq, fmpq_poly]] | None = None  # see _timing

    def error(self, message: str, node: yaml.Node | None, key: str) -> TaskFileError:
        line, column = _where(node) if node is not None else (0, 0)
        return TaskFileError(message, key=key, line=line, column=column)

    def stop(self, message: str, node: yaml.Node | None, key: str) -> _Stop:
        """An error after which nothing more is read (the node budget, the depth)."""
        line, column = _where(node) if node is not None else (0, 0)
        return _Stop(message, key=key, line=line, column=column)

    def read(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> None:
        """Check ``node`` against ``spec``, record its value under ``key``, then run the
        cross-field rule filed under ``key``, if any. An error is recorded in ``errors``
        (the key then has no value, and what depends on it is not checked) and the walk
        goes on with the next key; only a ``_Stop`` ends it."""
        try:
            self.visit(node, key, depth)
            if self.explicit or type(node) is not yaml.ScalarNode:
                self.fit(node, spec, key)  # (an untagged scalar fits)
            if spec.kind == "mapping":
                self.mapping(node, spec, key, depth)
            else:
                self.values[key] = _READERS[spec.kind](self, node, spec, key, depth)
        except _Stop:
            raise
        except TaskFileError as e:
            self.errors.append(e)
            return
        except _Recorded:
            return
        if key in _RULES:
            self.check(key)

    def check(self, key: str) -> None:
        """The cross-field rule filed under ``key``, when every value it needs was read."""
        rule, needs = _RULES.get(key, (None, ()))
        if rule is None or (key not in self.values and key not in self.nodes):
            return
        if any(k not in self.values for k in needs):
            return
        try:
            rule(self, key)
        except _Stop:
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
        if tag == _MERGE:
            raise self.error(
                "merge keys (<<) are not supported: write the keys out (an alias of a whole"
                " value, such as 3: *link, is fine)",
                node,
                key,
            )
        if type(node) is yaml.ScalarNode:
            if self.explicit and self.explicit.get(_span(node)) == "!":
                # YAML 1.2: the non-specific tag makes a scalar text (PyYAML resolves
                # it as if untagged: ! "6" would be the integer 6)
                node.tag = tag = _TAG + "str"
            bad = _ESCAPED_CONTROL.search(str(node.value)) if self.escapes else None
            if bad:  # written as a YAML escape ("\e", "\x07"): it would reach terminals
                code = ord(bad.group(0))
                what = "lone surrogate" if 0xD800 <= code <= 0xDFFF else "control character"
                raise self.error(
                    f"{what} U+{code:04X} in a value (written as a YAML escape) is not allowed",
                    node,
                    key,
                )
        if tag not in _PLAIN_TAGS:
            what = ""
            if node.tag == _TAG + "timestamp":
                what = f" ({_short(str(node.value))!r} reads as a date)"
            raise self.error(
                f"YAML tag {_tag_text(node)} is not allowed{what}: only plain text,"
                " numbers, booleans, null, mappings and lists",
                node,
                key,
            )

    def is_explicit(self, node: yaml.Node) -> bool:
        """Whether ``node`` is a scalar with a tag written in the file."""
        explicit = self.explicit
        return bool(explicit) and type(node) is yaml.ScalarNode and _span(node) in explicit

    def fit(self, node: yaml.Node, spec: Spec | None, key: str) -> None:
        """Reject a node whose explicit tag does not fit its value (``spec`` None: a key)."""
        explicit = self.is_explicit(node)
        if not explicit and type(node) is yaml.ScalarNode:
            return  # an untagged scalar always fits (``_misfit``)
        found = _misfit(node, explicit)
        if found is None:
            return
        expected = "a plain key" if spec is None else _expected(spec, key)
        hint = ""
        if spec is not None and spec.kind == "number" and _FRACTION.fullmatch(str(node.value)):
            hint = _FRACTION_HINT
        raise self.error(f"expected {expected}, found {found}{hint}", node, key)

    def mapping(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> None:
        """Read the keys ``spec`` knows, in the schema's order; default the rest."""
        if not isinstance(node, yaml.MappingNode):
            raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)
        given = self.keys(node, spec, key, depth)
        for k, child in spec.children.items():
            full = f"{key}.{k}" if key else k
            if k in given:
                self.read(given[k], child, full, depth + 1)
            else:
                self.omitted(child, full)

    def keys(
        self, node: yaml.MappingNode, spec: Spec, key: str, depth: int
    ) -> dict[str, yaml.Node]:
        """The mapping's value nodes by key: plain, known, unique keys; the required all given."""
        out: dict[str, yaml.Node] = {}
        bad: set[str] = set()  # keys given but unusable (duplicated): not "missing"
        for knode, vnode in node.value:
            if knode.tag == _MERGE:  # its keys are unknown: none is "missing"
                bad.update(spec.children)
            try:
                k, full = self.known_key(knode, spec, key, depth)
            except _Stop:
                raise
            except TaskFileError as e:
                self.errors.append(e)
                if isinstance(knode, yaml.ScalarNode):  # a misspelt key: not also "missing"
                    near = _near(str(knode.value), list(spec.children))
                    bad.update(near)
                    self.misspelt.update(f"{key}.{k}" if key else k for k in near)
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
                where = f"in {key}" if key else "at the top level"
                line, column = _where(node)
                self.errors.append(
                    _Missing(
                        f"missing required key {k!r} {where} ({child.description.rstrip('.')})",
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
        if not isinstance(knode, yaml.ScalarNode) or knode.tag in _NOT_KEYS:
            raise self.error(f"expected a plain key, found {_kind_of(knode)}", knode, key)
        k = str(knode.value)
        shown = k if _PLAIN_KEY.fullmatch(k) else repr(_short(k))
        full = f"{key}.{shown}" if key else shown
        if k not in spec.children:
            allowed = list(spec.children)
            near = _near(k, allowed)
            hint = (
                f"; did you mean {near[0]!r}?"
                if near
                else f"; expected one of: {', '.join(allowed)}"
            )
            raise self.error(f"unknown key {_short(k)!r}{hint}", knode, full)
        return k, full

    # -- one reader per kind of value (``Spec.kind``) ---------------------------------
    def number(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> fmpq:
        if not isinstance(node, yaml.ScalarNode):
            raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)
        text = str(node.value).strip()
        if (
            node.tag in _NUMBER_TAGS
            and _SIMPLE_DECIMAL.fullmatch(text)
            and not self.is_explicit(node)
        ):
            return self.bounded(_simple_decimal(text), node, spec, key, text)
        tag = self.number_tag(node, text)
        if tag not in ("int", "float"):
            hint = _FRACTION_HINT if tag == "str" and _FRACTION.fullmatch(text) else ""
            raise self.error(
                f"expected {_expected(spec, key)}, found {_kind_of(node)}{hint}", node, key
            )
        special = text[-1:] in _SPECIAL_ENDS  # nan, inf and infinity end so; numbers do not
        if special and _NAN.fullmatch(text):
            raise self.error(f"expected a finite number ({spec.description}), found NaN", node, key)
        if special and _INF.fullmatch(text):
            raise self.error(
                f"expected a finite number ({spec.description}), found infinity ({text})", node, key
            )
        value = self._number_value(node, text.replace("_", ""), tag, key)
        return self.bounded(value, node, spec, key, text)

    def bounded(self, value: fmpq, node: yaml.Node, spec: Spec, key: str, text: str) -> fmpq:
        """``value``, read from ``text``, checked against ``spec``'s bound."""
        if spec.minimum is not None:
            lo = _minimum(spec.minimum)
            if not (value > lo if spec.exclusive else value >= lo):
                raise self.error(
                    f"expected a number {'>' if spec.exclusive else '>='} {_q(lo)}"
                    f" ({spec.description}), found {_short(text)}",
                    node,
                    key,
                )
        return value

    def number_tag(self, node: yaml.ScalarNode, text: str) -> str:
        """The tag ``node`` is read with as a number ("int", "float", else not a number).

        An untagged plain scalar that YAML 1.1 reads as text but YAML 1.2 as a number
        (1e3, 0o17) is that number. A scalar tagged !!int or !!float (its tag checked to
        fit) is read as its text written plain; NaN and infinities keep !!float, to be
        named as such. !!str and quoted text stay text.
        """
        tag = node.tag.removeprefix(_TAG)
        explicit = self.is_explicit(node)
        if explicit and tag == "float" and (_NAN.fullmatch(text) or _INF.fullmatch(text)):
            return tag
        if (explicit and tag in ("int", "float")) or (
            not explicit and tag == "str" and not node.style
        ):
            return _plain_tag(text).removeprefix(_TAG)
        return tag

    def _number_value(self, node: yaml.Node, text: str, tag: str, key: str) -> fmpq:
        try:
            if tag == "int" and _RADIX_INT.fullmatch(text):
                if len(text) > 40:
                    raise ExpressionError(f"number {_short(text)!r} has more than 40 digits")
                return fmpq(int(text, 0))
            if tag == "int" and _DECIMAL_INT.fullmatch(text):
                body = text.lstrip("+-")
                if len(body) > 1 and body.startswith("0"):
                    raise self.error(
                        f"ambiguous number {_short(text)}: a leading 0 means octal in YAML 1.1"
                        " and decimal in YAML 1.2; write it without the leading 0 (or as"
                        " 0o... for octal)",
                        node,
                        key,
                    )
                return parse_decimal(text)
            if tag == "float":
                return parse_decimal(text)
        except ExpressionError as e:
            raise self.error(e.message, node, key) from None
        raise self.error(f"expected a decimal number, found {_short(text)!r}", node, key)

    def pair(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[fmpq, fmpq]:
        """Two numbers, ``spec.items`` saying what each is, both bounded as ``spec`` says."""
        if not isinstance(node, yaml.SequenceNode) or len(node.value) != 2:
            raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)
        a, b = (
            self.item(v, spec, what, f"{key}[{i}]", depth + 1)
            for i, (v, what) in enumerate(zip(node.value, spec.items, strict=True))
        )
        return a, b

    def point(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[fmpq, fmpq | None]:
        """A point of the path: x alone, [x, y] or {x: ..., y: ...}; (x, None) when y is
        left out (``_on_path`` computes it)."""
        if isinstance(node, yaml.ScalarNode):
            return self.coordinate(node, spec.items[0], key), None
        if isinstance(node, yaml.SequenceNode) and len(node.value) == 2:
            x, y = (
                self.coordinate(v, what, f"{key}[{i}]", depth + 1)
                for i, (v, what) in enumerate(zip(node.value, spec.items, strict=True))
            )
            return x, y
        if isinstance(node, yaml.MappingNode):
            given = self.keys(node, _POINT_KEYS, key, depth)
            if "x" not in given:
                raise _Recorded  # missing, or given twice: ``keys`` said so
            x = self.coordinate(given["x"], spec.items[0], f"{key}.x", depth + 1)
            if "y" not in given:
                return x, None
            return x, self.coordinate(given["y"], spec.items[1], f"{key}.y", depth + 1)
        raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)

    def coordinate(self, node: yaml.Node, what: str, key: str, depth: int = 0) -> fmpq:
        """A coordinate of a point: a number, or a fraction written as text (-2/3)."""
        self.visit(node, key, depth)
        spec = _number_spec(what)
        if (
            isinstance(node, yaml.ScalarNode)
            and node.tag == _TAG + "str"
            and _FRACTION.fullmatch(str(node.value).strip())
        ):
            try:
                return parse_fraction(str(node.value))
            except ExpressionError as e:
                raise self.error(e.message, node, key) from None
        self.fit(node, spec, key)
        return self.number(node, spec, key, depth)

    def item(self, node: yaml.Node, spec: Spec, what: str, key: str, depth: int) -> fmpq:
        self.visit(node, key, depth)
        bound = _number_spec(what, spec.minimum, spec.exclusive)
        self.fit(node, bound, key)
        return self.number(node, bound, key, depth)

    def polynomial(
        self, node: yaml.Node, spec: Spec, key: str, depth: int
    ) -> fmpq_poly | list[dict[str, Any]]:
        """A polynomial; with ``spec.item``, also a list of pieces (``items``)."""
        if spec.item is not None and isinstance(node, yaml.SequenceNode):
            return self.items(node, spec, key, depth)
        if not isinstance(node, yaml.ScalarNode) or node.tag not in _SCALAR_TEXT:
            raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)
        text = str(node.value)
        try:
            return parse_polynomial(text, spec.variable)
        except ExpressionError as e:
            line, column = _where(node)
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

    def time(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> fmpq:
        """An instant [s] >= 0: a decimal, or a fraction such as 5/3 (exact)."""
        if (
            isinstance(node, yaml.ScalarNode)
            and node.tag == _TAG + "str"
            and _FRACTION.fullmatch(str(node.value).strip())
        ):
            try:
                value = parse_fraction(str(node.value))
            except ExpressionError as e:
                raise self.error(e.message, node, key) from None
        else:
            value = self.number(node, _number_spec("t [s], a decimal or a fraction"), key, depth)
        if value < 0:
            raise self.error(f"expected a time >= 0 [s], found {_q(value)}", node, key)
        return value

    def vector(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[fmpq, fmpq]:
        """Two numbers or fractions, [x, y]."""
        if not isinstance(node, yaml.SequenceNode) or len(node.value) != 2:
            raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)
        a, b = (
            self.coordinate(v, what, f"{key}[{i}]", depth + 1)
            for i, (v, what) in enumerate(zip(node.value, spec.items, strict=True))
        )
        return a, b

    def items(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> list[dict[str, Any]]:
        """A non-empty list of mappings, each read with ``spec.item`` under ``key[i]``:
        per element, its values by key and ``line``, the line of its first key (a
        piece's ``until``, a waypoint's ``t``)."""
        item = spec.item
        assert item is not None
        if not isinstance(node, yaml.SequenceNode) or not node.value:
            raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)
        before = len(self.errors)
        for i, element in enumerate(node.value):
            self.read(element, item, f"{key}[{i}]", depth + 1)
        if len(self.errors) > before:
            raise _Recorded  # an element could not be read: said so already
        first = next(iter(item.children))
        out = []
        for i in range(len(node.value)):
            at = f"{key}[{i}]"
            values = {
                k: self.values[f"{at}.{k}"] for k in item.children if f"{at}.{k}" in self.values
            }
            out.append({**values, "line": self.lines.get(f"{at}.{first}", 0), "key": at})
        return out

    def waypoints(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> list[Waypoint]:
        """Waypoints given inline (a list of {t, p, v, a}) or as a CSV file's name."""
        if isinstance(node, yaml.ScalarNode) and node.tag == _TAG + "str":
            return self.csv(node, key)
        if not isinstance(node, yaml.SequenceNode):
            raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)
        points = []
        for it in self.items(node, spec, key, depth):
            if "a" in it and "v" not in it:
                raise self.error(
                    "a waypoint giving a must give v too (p; p, v; or p, v, a)",
                    self.nodes[f"{it['key']}.a"],
                    f"{it['key']}.a",
                )
            points.append(Waypoint(it["t"], it["p"], it.get("v"), it.get("a"), it["line"]))
        return points

    def csv(self, node: yaml.ScalarNode, key: str) -> list[Waypoint]:
        """The waypoints of the CSV file named by ``node`` (relative to the task's
        directory); every problem of the file is an error at ``node`` naming the file
        and the row."""
        name = str(node.value)
        if not re.fullmatch(CSV_PATTERN, name) or _ESCAPED_CONTROL.search(name):
            raise self.error(
                f"expected a CSV file's name relative to the task file (no '..', ending in"
                f" .csv), found {_short(name)!r}",
                node,
                key,
            )
        path = os.path.normpath(os.path.join(self.directory, name))
        try:
            points, problems = parse_waypoints(read_bytes(path, inside=self.directory))
        except CsvProblem as e:
            where = f"{name}:{e.row}" if e.row else name
            raise self.error(f"{where}: {e.message}", node, key) from None
        for row, message in problems:
            self.errors.append(self.error(f"{name}:{row}: {message}", node, key))
        if problems:
            raise _Recorded
        self.csv_file, self.csv_name = path, name
        return points

    def text(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> str:
        if not isinstance(node, yaml.ScalarNode) or node.tag not in _SCALAR_TEXT:
            raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)
        return str(node.value)

    def boolean(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> bool:
        if not isinstance(node, yaml.ScalarNode) or node.tag != _TAG + "bool":
            raise self.error(f"expected {_expected(spec, key)}, found {_kind_of(node)}", node, key)
        return str(node.value).lower() in ("true", "yes", "on", "y")

    def enum(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> str:
        v = str(node.value) if isinstance(node, yaml.ScalarNode) else ""
        if v not in spec.choices or node.tag != _TAG + "str":
            near = _near(v.lower(), list(spec.choices))
            hint = f"; did you mean {near[0]!r}?" if near else ""
            raise self.error(
                f"expected {_expected(spec, key)}, found {_kind_of(node)}{hint}", node, key
            )
        return v


_READERS: dict[str, Callable[[_Walk, yaml.Node, Spec, str, int], Any]] = {
    "number": _Walk.number,
    "pair": _Walk.pair,
    "point": _Walk.point,
    "polynomial": _Walk.polynomial,
    "time": _Walk.time,
    "vector": _Walk.vector,
    "list": _Walk.items,
    "waypoints": _Walk.waypoints,
    "string": _Walk.text,
    "bool": _Walk.boolean,
    "enum": _Walk.enum,
    "percent": percent,
    "relative": relative,
}


def _near(key: str, allowed: list[str]) -> list[str]:
    """The key of ``allowed`` that ``key`` is likely a misspelling of ([] when none)."""
    import difflib  # only for a file with an error: not on the import path

    return difflib.get_close_matches(key, allowed, n=1, cutoff=0.6)


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


@functools.cache
def _number_spec(what: str, minimum: float | None = None, exclusive: bool = False) -> Spec:
    """A number's Spec, made once: ``what`` it is, and its bound."""
    return Spec("number", what, minimum=minimum, exclusive=exclusive)


def _simple_decimal(text: str) -> fmpq:
    """The value of ``text`` matching ``_SIMPLE_DECIMAL``, exactly (as ``parse_decimal``)."""
    whole, _, frac = text.partition(".")
    return fmpq(int(whole + frac), 10 ** len(frac))


@functools.cache
def _minimum(bound: float) -> fmpq:
    """A ``Spec.minimum``, exactly (from its text)."""
    return parse_decimal(repr(bound))


def _expected(spec: Spec, key: str) -> str:
    """What a key of ``spec`` takes, for "expected ..." in messages."""
    if spec.kind == "mapping":
        keys = ", ".join(k for k, c in spec.children.items() if c.required) or ", ".join(
            spec.children
        )
        return f"a mapping with keys {keys}" if not key else f"a mapping (keys {keys})"
    if spec.kind == "number":
        return f"a number ({spec.description.rstrip('.')})"
    if spec.kind == "pair":
        return f"a list of two numbers [{', '.join(spec.items)}]"
    if spec.kind == "point":
        return "a point: x alone, [x, y] or {x: ..., y: ...} (numbers, or fractions such as -2/3)"
    if spec.kind == "polynomial":
        text = f"a polynomial in {spec.variable} (text such as '2*{spec.variable}^2 - 1')"
        return text if spec.item is None else f"{text} or a list of pieces {_keys(spec.item)}"
    if spec.kind == "time":
        return "a time [s] >= 0 (a decimal or a fraction such as 5/3)"
    if spec.kind == "vector":
        return f"a list of two numbers [{', '.join(spec.items)}]"
    if spec.kind == "list":
        assert spec.item is not None
        return f"a list of {_keys(spec.item)}"
    if spec.kind == "waypoints":
        assert spec.item is not None
        return f"a list of waypoints {_keys(spec.item)} or a CSV file's name"
    if spec.kind == "string" and key.startswith(("checks.ignore.", "checks.warn.")):
        return "text: why this task may break the rule (a reason is required)"
    if spec.kind == "string":
        return "text (a name for reports)"
    if spec.kind == "bool":
        return "true or false"
    if spec.kind in ("percent", "relative"):
        return _PERCENT_EXPECTED
    return f"one of {', '.join(spec.choices)}"  # enum


def _keys(spec: Spec) -> str:
    """The keys of a mapping ``spec``, as written in YAML: {until, x, y}."""
    return "{" + ", ".join(spec.children) + "}"


def _misfit(node: yaml.Node, explicit: bool) -> str | None:
    """What ``node`` is, for "found ...", when its tag does not fit its value; else None.

    A mapping must be tagged !!map and a list !!seq. A scalar with an explicit tag must
    be, as written (no surrounding spaces), a value of that tag as YAML 1.2 has it and
    as the loader reads untagged values: !!int what an untagged value reads as an
    integer, !!float a decimal number (or NaN or an infinity, rejected as such later),
    !!bool true or false, !!null null; !!str anything. An empty tagged scalar is "an
    empty value".
    """
    tag = node.tag.removeprefix(_TAG)
    if isinstance(node, yaml.MappingNode | yaml.SequenceNode):
        if tag == ("map" if isinstance(node, yaml.MappingNode) else "seq"):
            return None
        return f"{_kind_of(node)} tagged !!{tag}, which is not {_TAG_MEANS[tag]}"
    value = str(node.value)
    if not explicit or tag == "str" or (tag == "null" and value in _YAML_NULL):
        return None
    if value == "":
        return "an empty value"
    plain = _plain_tag(value).removeprefix(_TAG) if value == value.strip() else ""
    special = bool(_NAN.fullmatch(value) or _INF.fullmatch(value))
    fits = {
        "int": plain == "int",
        "float": special or (plain in ("int", "float") and not _NOT_DECIMAL.match(value)),
        "bool": value in _YAML12_BOOL,
    }.get(tag, False)
    if fits:
        return None
    return f"{_short(value)!r} tagged !!{tag}, which is not {_TAG_MEANS[tag]}"


def _plain_tag(text: str) -> str:
    """The tag of ``text`` written as an untagged plain scalar: YAML 1.1's (PyYAML's),
    but a number as YAML 1.2 reads it (1e3 a float, 0o17 an integer; YAML 1.1: text)."""
    tag = _resolve(text)
    if tag == _TAG + "str":
        if _YAML12_FLOAT.fullmatch(text):
            return _TAG + "float"
        if _RADIX_INT.fullmatch(text):
            return _TAG + "int"
    return tag


# -- nodes, for messages -----------------------------------------------------------------


def _resolve(text: str) -> str:
    """The tag YAML 1.1 (PyYAML) gives the plain scalar ``text``."""
    return str(_RESOLVER.resolve(yaml.ScalarNode, text, (True, False)))


def _where(node: yaml.Node | yaml.Event) -> tuple[int, int]:
    """1-based (line, column) where ``node`` starts."""
    return node.start_mark.line + 1, node.start_mark.column + 1


def _short(text: str, n: int = 40) -> str:
    return text if len(text) <= n else text[: n - 3] + "..."


def _tag_text(node: yaml.Node) -> str:
    """The tag of ``node`` as written (``!!binary``, ``!metres``), abbreviated if long."""
    return _short(node.tag.replace(_TAG, "!!"), 60)


def _kind_of(node: yaml.Node) -> str:
    """What a node is, for "found ..." in messages."""
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return f"a list of {len(node.value)}"
    tag = node.tag.removeprefix(_TAG)
    value = _short(str(node.value))
    if tag == "null":
        return "null"
    if tag == "bool":
        return f"a boolean ({value})"
    if tag in ("int", "float"):
        return f"the number {value}"
    if tag == "str":
        return f"the text {value!r}"
    return f"{value!r} (tagged {_tag_text(node)})"

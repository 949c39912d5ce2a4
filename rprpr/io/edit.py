"""A task file edited where its task changed, and nowhere else (what ``rprpr repair``
writes): comments, key order, flow or block style, quoting and the spelling of every
number outside the changed keys are the file's own, byte for byte.

How: the file is composed with PyYAML (its nodes carry start and end marks), the old and
the new task are compared key by key, and only the text of the keys whose values differ
is replaced, with values written as ``writer`` writes them (exact rationals). No
round-trip YAML library is needed: a repair changes the motion (``path``, ``timing``,
``motion``) and perhaps the name, whose nodes the marks locate exactly. What changes:

* the paper's form kept (``path`` and ``timing`` in both tasks): ``path.y``, ``path.from``
  and ``path.to`` each only when its value differs (a point given as x alone stays so
  while x is the same); in ``timing`` the law's keys (``law``, ``cruise_speed``, ``x``)
  give way to the new ``x`` (a polynomial, or pieces), in the place of the first of them;
  ``duration`` only when it differs;
* another form (the repaired motion as ``motion.pieces``): the entries ``path``,
  ``timing`` and ``motion`` give way to the new ``motion`` entry, in the place of the
  first of them;
* ``name`` when asked to (``rename``) and the file gives one (a task without a name is
  named after its file's stem, which a new file changes anyway).

A replaced value's comment on its own line goes with it (it spoke of the old value); a
removed entry's lines go whole. Line endings (LF or CRLF) are the file's. ``edit``
returns None when the file cannot be edited so (a robot or checks that differ, anchors
or merge keys, a document that is not a mapping): the caller then writes the task whole
(``writer.task_text``). The caller reads the result back and compares it with the task,
so an edit never silently changes the motion.
"""

from __future__ import annotations

import re
from typing import Any

import yaml
from flint import fmpq

from ..model.task import Piece, Task
from . import writer

MOTION_KEYS = ("path", "timing", "motion")  # the top-level entries that give the motion
LAW_KEYS = ("law", "cruise_speed", "x")  # the timing keys that give x(t)
SCHEMA_MODELINE = re.compile(r"^#\s*yaml-language-server:\s*\$schema=(\S+)\s*$")
_TRAILING_COMMENT = re.compile(r"[ \t]*(#[^\r\n]*)?")

Edit = tuple[int, int, str]  # (start, end, replacement) in the text's characters


class _NotEditable(Exception):
    """The file's form does not lend itself to an edit (the caller writes it whole)."""


def edit(text: str, old: Task, new: Task, *, rename: bool = False) -> str | None:
    """``text`` (the task file of ``old``) with the keys where ``new`` differs rewritten,
    and the rest kept byte for byte; ``rename`` also writes ``new.name``. None when the
    file's form cannot be edited so (then write ``writer.task_text(new)`` whole)."""
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
        return _apply(text, _edits(text, root, old, new, rename))
    except (_NotEditable, yaml.YAMLError, ValueError, KeyError):
        return None


def same_motion(a: Task, b: Task) -> bool:
    """Whether ``a`` and ``b`` give the same motion, exactly (the pieces' times and
    polynomials and the path; not the lines they came from)."""

    def key(p: Piece) -> tuple[Any, ...]:
        return (p.start, p.end, p.x, p.y, p.path)

    return (
        a.duration == b.duration
        and a.path == b.path
        and [key(p) for p in a.motion] == [key(p) for p in b.motion]
    )


def _edits(text: str, root: yaml.Node, old: Task, new: Task, rename: bool) -> list[Edit]:
    if not isinstance(root, yaml.MappingNode) or root.flow_style:
        raise _NotEditable("the document is not a block mapping")
    if ("&" in text and _has_anchors(root)) or old.robot != new.robot:
        raise _NotEditable("anchors, or a robot that differs")
    if _checks(old) != _checks(new):
        raise _NotEditable("checks that differ")
    top = _entries(root)
    mapping = writer.task_mapping(new)
    edits: list[Edit] = []
    if rename and new.name != old.name and "name" in top:  # (else: the new file's stem)
        edits.append(_replace_value(text, top["name"][1], mapping["name"]))
    if same_motion(old, new):
        return edits
    if (
        new.path is not None
        and all(k in top for k in ("path", "timing"))
        and "motion" not in top
        and all(_block(top[k][1]) for k in ("path", "timing"))
    ):
        edits += _path_edits(text, top["path"][1], old, new, mapping["path"])
        edits += _timing_edits(text, top["timing"][1], old, new, mapping["timing"])
        return edits
    present = [k for k in MOTION_KEYS if k in top]
    if not present:
        raise _NotEditable("no motion entry to replace")
    entries = {k: mapping[k] for k in MOTION_KEYS if k in mapping}
    first = min(present, key=lambda k: top[k][0].start_mark.index)
    for k in present:
        start, end = _entry_lines(text, *top[k])
        block = _block_text(entries, 0, _newline(text)) if k == first else ""
        edits.append((start, end, block))
    return edits


def _path_edits(
    text: str, node: yaml.MappingNode, old: Task, new: Task, values: dict[str, Any]
) -> list[Edit]:
    """``path.y``, ``from`` and ``to`` where they differ."""
    assert old.path is not None and new.path is not None
    given = _entries(node)
    edits = []
    if old.path != new.path:
        edits.append(_replace_value(text, given["y"][1], values["y"]))
    for key, t_old, t_new in (
        ("from", fmpq(0), fmpq(0)),
        ("to", old.duration, new.duration),
    ):
        x_old = old.motion[0 if key == "from" else -1].x(t_old)
        x_new = new.motion[0 if key == "from" else -1].x(t_new)
        if (x_old, old.path(x_old)) != (x_new, new.path(x_new)):
            edits.append(_replace_value(text, given[key][1], values[key]))
    return edits


def _timing_edits(
    text: str, node: yaml.MappingNode, old: Task, new: Task, values: dict[str, Any]
) -> list[Edit]:
    """``duration`` where it differs; the law's keys given way to the new ``x``."""
    given = _entries(node)
    edits = []
    if old.duration != new.duration:
        edits.append(_replace_value(text, given["duration"][1], values["duration"]))
    law = [k for k in LAW_KEYS if k in given]
    if not law:
        raise _NotEditable("a timing without its law")
    first = min(law, key=lambda k: given[k][0].start_mark.index)
    indent = given[first][0].start_mark.column
    for k in law:
        start, end = _entry_lines(text, *given[k])
        block = _block_text({"x": values["x"]}, indent, _newline(text)) if k == first else ""
        edits.append((start, end, block))
    return edits


def _checks(t: Task) -> tuple[Any, ...]:
    c = t.checks
    return (c.min_slope, c.min_speed, c.torque_limit, c.strict, c.unbounded_torque, c.rules)


def _entries(node: yaml.MappingNode) -> dict[str, tuple[yaml.Node, yaml.Node]]:
    """The mapping's (key node, value node) by key (the loader made them plain and unique)."""
    out = {}
    for k, v in node.value:
        if not isinstance(k, yaml.ScalarNode) or k.tag == "tag:yaml.org,2002:merge":
            raise _NotEditable("a key that is not plain")
        out[str(k.value)] = (k, v)
    return out


def _block(node: yaml.Node) -> bool:
    return isinstance(node, yaml.MappingNode) and not node.flow_style


def _has_anchors(node: yaml.Node) -> bool:
    """Whether the same node appears twice (an alias): an edit would change both."""
    seen: set[int] = set()

    def walk(n: yaml.Node) -> bool:
        if id(n) in seen:
            return True
        seen.add(id(n))
        if isinstance(n, yaml.MappingNode):
            return any(walk(k) or walk(v) for k, v in n.value)
        if isinstance(n, yaml.SequenceNode):
            return any(walk(c) for c in n.value)
        return False

    return walk(node)


def _last_end(node: yaml.Node) -> int:
    """Where the text of ``node`` ends: a block collection's end mark lies at the next
    key (past comments that are not its own), so it ends with its last child instead."""
    if isinstance(node, yaml.MappingNode | yaml.SequenceNode) and not node.flow_style:
        children = [v for _, v in node.value] if isinstance(node, yaml.MappingNode) else node.value
        return _last_end(children[-1]) if children else int(node.start_mark.index)
    return int(node.end_mark.index)


def _line_start(text: str, index: int) -> int:
    return text.rfind("\n", 0, index) + 1


def _line_end(text: str, index: int) -> int:
    """The index just past the line break of the line holding ``index`` (or the end)."""
    end = text.find("\n", index)
    return len(text) if end < 0 else end + 1


def _entry_lines(text: str, key: yaml.Node, value: yaml.Node) -> tuple[int, int]:
    """The whole lines of a block mapping's entry: from its key's line to its value's
    last line, with the line break (a key not first on its line cannot be removed so)."""
    start = int(key.start_mark.index)
    if text[_line_start(text, start) : start].strip():
        raise _NotEditable("a key that does not start its line")
    last = max(_last_end(value), int(key.end_mark.index))
    return _line_start(text, start), _line_end(text, max(last - 1, start))


def _replace_value(text: str, node: yaml.Node, value: Any) -> Edit:
    """The value ``node`` of a block mapping (a scalar or a flow collection) rewritten as
    ``value`` (a list in flow form), with its comment on the same line."""
    if isinstance(node, yaml.MappingNode | yaml.SequenceNode) and not node.flow_style:
        raise _NotEditable("a block value")
    if isinstance(node, yaml.ScalarNode) and node.style in ("|", ">"):
        raise _NotEditable("a block scalar")
    start, end = int(node.start_mark.index), int(node.end_mark.index)
    trailing = _TRAILING_COMMENT.match(text, end)
    if trailing is not None and trailing.group(1):
        end = trailing.end()
    return start, end, _flow(value) if isinstance(value, list) else _scalar(value)


def _scalar(value: Any) -> str:
    """``value`` as a plain (or, when it must be, quoted) scalar of a block mapping."""
    text = yaml.dump({"k": value}, Dumper=writer.Dumper, allow_unicode=True, width=1 << 30)
    if not text.startswith("k: ") or text.count("\n") != 1:
        raise _NotEditable("a value that is not one line")
    return text[3:-1]


def _flow(value: Any) -> str:
    """``value`` as YAML in flow form, as ``writer`` writes it (exact numbers)."""
    text = yaml.dump([value], Dumper=writer.Dumper, default_flow_style=True,
                     allow_unicode=True, width=1 << 30)  # fmt: skip
    text = text.strip()
    if not (text.startswith("[") and text.endswith("]")):
        raise _NotEditable("a value with no flow form")
    return text[1:-1]


def _block_text(entries: dict[str, Any], indent: int, newline: str) -> str:
    """``entries`` as block YAML lines, indented by ``indent`` columns."""
    text = yaml.dump(entries, Dumper=writer.Dumper, sort_keys=False, allow_unicode=True,
                     width=1 << 30)  # fmt: skip
    pad = " " * indent
    return "".join(pad + line + newline for line in text.splitlines())


def _newline(text: str) -> str:
    return "\r\n" if "\r\n" in text else "\n"


def _apply(text: str, edits: list[Edit]) -> str:
    """``text`` with ``edits`` made (they never overlap), from the last to the first."""
    out = text
    for start, end, new in sorted(edits, key=lambda e: e[0], reverse=True):
        out = out[:start] + new + out[end:]
    return out


def modeline(text: str) -> str | None:
    """The schema the file's modeline points at (``# yaml-language-server: $schema=X``
    on its first line), or None."""
    first = text.split("\n", 1)[0].rstrip("\r")
    m = SCHEMA_MODELINE.match(first)
    return m.group(1) if m else None

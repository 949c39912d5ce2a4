"""Reading a task file: bytes -> YAML node tree -> validated ``Task`` (exact numbers).

Safety: the YAML is only *composed* (parsed into nodes), never constructed into Python
objects, so no tag can run code; only the plain tags (str, int, float, bool, null, map,
seq) are accepted. Duplicate keys are errors (PyYAML would silently keep the last), and
aliases are followed with a budget on visited nodes, so an alias bomb is rejected rather
than expanded. Numbers are taken by their text (``0.1`` is 1/10). Every error is a
``TaskFileError`` naming the file, line, column and dotted key.
"""

from __future__ import annotations

import difflib
import os
from pathlib import Path
from typing import Any

import yaml
from flint import fmpq, fmpq_poly

from .errors import ExpressionError, TaskFileError
from .polynomial import MAX_DEGREE, parse_decimal, parse_polynomial
from .schema import TASK, Spec
from .task import Checks, Link, Robot, Task
from .trajectory import timing_law

MAX_BYTES = 1 << 20  # 1 MiB
MAX_NODES = 10_000  # nodes visited, aliases followed included
MAX_DEPTH = 32

_Loader = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
_TAG = "tag:yaml.org,2002:"
_PLAIN_TAGS = {_TAG + t for t in ("str", "int", "float", "bool", "null", "map", "seq")}


def load_task(path: str | os.PathLike[str]) -> Task:
    """Read and validate the task file at ``path``; raises ``TaskFileError``."""
    name = os.fspath(path)
    p = Path(name)
    try:
        if not p.exists():
            raise TaskFileError("no such file", file=name)
        if not p.is_file():
            raise TaskFileError("not a regular file", file=name)
        if p.stat().st_size > MAX_BYTES:
            raise TaskFileError(f"file larger than {MAX_BYTES // 1024} KiB", file=name)
        with p.open("rb") as fh:
            data = fh.read(MAX_BYTES + 1)
    except OSError as e:
        raise TaskFileError(f"cannot read: {e.strerror or e}", file=name) from None
    return parse_task(data, name)


def parse_task(data: bytes | str, file: str = "<task>") -> Task:
    """Validate a task given as bytes or text; ``file`` names it in errors."""
    try:
        return _parse(data, file)
    except TaskFileError as e:
        raise e.with_file(file) from None


def _parse(data: bytes | str, file: str) -> Task:
    if isinstance(data, bytes):
        if len(data) > MAX_BYTES:
            raise TaskFileError(f"file larger than {MAX_BYTES // 1024} KiB")
        if b"\x00" in data:
            raise TaskFileError("binary file (contains NUL bytes), expected YAML text")
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError as e:
            line = data[: e.start].count(b"\n") + 1
            raise TaskFileError(f"not UTF-8 text (byte 0x{data[e.start]:02x} at offset {e.start})", line=line) from None
    else:
        text = data
    text = text.removeprefix("\ufeff")
    if not text.strip() or all(
        not ln.strip() or ln.lstrip().startswith("#") for ln in text.splitlines()
    ):
        raise TaskFileError("empty task file, expected a mapping with robot, path and timing")
    try:
        root = yaml.compose(text, Loader=_Loader)
    except yaml.MarkedYAMLError as e:
        mark = e.problem_mark or e.context_mark
        problem = " ".join(str(x) for x in (e.context, e.problem) if x)
        raise TaskFileError(
            f"YAML syntax error: {problem}",
            line=mark.line + 1 if mark else 0,
            column=mark.column + 1 if mark else 0,
        ) from None
    except yaml.YAMLError as e:
        raise TaskFileError(f"YAML error: {e}") from None
    except RecursionError:
        raise TaskFileError("YAML nested too deeply") from None
    if root is None:
        raise TaskFileError("empty task file, expected a mapping with robot, path and timing")
    return _Builder(file).task(root, Path(file).stem)


def _where(node: yaml.Node) -> dict[str, int]:
    return {"line": node.start_mark.line + 1, "column": node.start_mark.column + 1}


def _kind_of(node: yaml.Node) -> str:
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return "a list"
    tag = node.tag.removeprefix(_TAG)
    if tag == "null":
        return "null"
    if tag == "bool":
        return f"a boolean ({node.value})"
    if tag in ("int", "float"):
        return f"the number {node.value}"
    return f"the text {node.value!r}"


class _Builder:
    def __init__(self, file: str) -> None:
        self.file = file
        self.visited = 0
        self.lines: dict[str, int] = {}

    # -- generic validation against the schema -----------------------------------
    def error(self, message: str, node: yaml.Node | None, key: str) -> TaskFileError:
        w = _where(node) if node is not None else {"line": 0, "column": 0}
        return TaskFileError(message, key=key, **w)

    def visit(self, node: yaml.Node, key: str, depth: int) -> None:
        self.visited += 1
        if self.visited > MAX_NODES:
            raise self.error(
                f"too many YAML nodes (over {MAX_NODES}, aliases included): excessive aliasing rejected",
                node, key,
            )  # fmt: skip
        if depth > MAX_DEPTH:
            raise self.error(f"nested deeper than {MAX_DEPTH} levels", node, key)
        if node.tag not in _PLAIN_TAGS:
            raise self.error(
                f"YAML tag {node.tag.replace(_TAG, '!!')} is not allowed: only plain text, numbers, "
                "booleans, null, mappings and lists",
                node, key,
            )  # fmt: skip

    def mapping(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> dict[str, yaml.Node]:
        self.visit(node, key, depth)
        if not isinstance(node, yaml.MappingNode):
            what = "the task file's top level" if not key else key
            raise self.error(f"expected a mapping for {what}, found {_kind_of(node)}", node, key)
        out: dict[str, yaml.Node] = {}
        for knode, vnode in node.value:
            self.visit(knode, key, depth + 1)
            if not isinstance(knode, yaml.ScalarNode):
                raise self.error(f"expected a plain key, found {_kind_of(knode)}", knode, key)
            k = str(knode.value)
            full = f"{key}.{k}" if key else k
            if k in out:
                first = out[k].start_mark.line + 1
                raise self.error(f"duplicate key {k!r} (first given on line {first})", knode, full)
            if k not in spec.children:
                allowed = list(spec.children)
                near = difflib.get_close_matches(k, allowed, n=1, cutoff=0.6)
                hint = f"; did you mean {near[0]!r}?" if near else f"; expected one of: {', '.join(allowed)}"
                raise self.error(f"unknown key {k!r}{hint}", knode, full)
            out[k] = vnode
            self.lines[full] = knode.start_mark.line + 1
        for k, child in spec.children.items():
            if child.required and k not in out:
                full = f"{key}.{k}" if key else k
                raise self.error(f"missing required key {k!r} ({child.description})", node, full)
        return out

    def number(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> fmpq:
        self.visit(node, key, depth)
        if not isinstance(node, yaml.ScalarNode) or node.tag not in (_TAG + "int", _TAG + "float"):
            raise self.error(f"expected a number ({spec.description}), found {_kind_of(node)}", node, key)
        text = str(node.value).replace("_", "")
        low = text.lower().lstrip("+-")
        if low in (".nan",):
            raise self.error("expected a finite number, found NaN", node, key)
        if low in (".inf",):
            raise self.error("expected a finite number, found infinity", node, key)
        try:
            if node.tag == _TAG + "int":
                body = text.lstrip("+-")
                octal = body.startswith("0") and body.strip("0") != ""
                value = fmpq(_int8(text) if octal else int(text, 10))
            else:
                value = parse_decimal(text)
        except (ValueError, ExpressionError):
            raise self.error(f"expected a number, found {node.value!r}", node, key) from None
        if spec.minimum is not None:
            lo = fmpq(int(spec.minimum)) if float(spec.minimum).is_integer() else parse_decimal(str(spec.minimum))
            if spec.exclusive and not value > lo:
                raise self.error(f"expected a number > {spec.minimum:g} ({spec.description}), found {node.value}", node, key)
            if not spec.exclusive and not value >= lo:
                raise self.error(f"expected a number >= {spec.minimum:g} ({spec.description}), found {node.value}", node, key)
        return value

    def pair(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> tuple[fmpq, fmpq]:
        self.visit(node, key, depth)
        if not isinstance(node, yaml.SequenceNode) or len(node.value) != 2:
            n = f"a list of {len(node.value)}" if isinstance(node, yaml.SequenceNode) else _kind_of(node)
            raise self.error(f"expected a list of two numbers [{'a, b'}], found {n}", node, key)
        item = Spec("number", spec.description, minimum=spec.minimum, exclusive=spec.exclusive)
        a, b = (self.number(v, item, f"{key}[{i}]", depth + 1) for i, v in enumerate(node.value))
        return a, b

    def polynomial(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> fmpq_poly:
        self.visit(node, key, depth)
        if not isinstance(node, yaml.ScalarNode) or node.tag not in (_TAG + "str", _TAG + "int", _TAG + "float"):
            raise self.error(f"expected a polynomial in {spec.variable}, found {_kind_of(node)}", node, key)
        try:
            return parse_polynomial(str(node.value), spec.variable)
        except ExpressionError as e:
            w = _where(node)
            col = w["column"]
            if node.style is None and "\n" not in str(node.value):
                col += e.offset
            elif node.style in ("'", '"') and "\n" not in str(node.value):
                col += e.offset + 1
            raise TaskFileError(
                f"bad polynomial in {spec.variable}: {e.message}", line=w["line"], column=col, key=key
            ) from None

    def text(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> str:
        self.visit(node, key, depth)
        if not isinstance(node, yaml.ScalarNode) or node.tag == _TAG + "null":
            raise self.error(f"expected text, found {_kind_of(node)}", node, key)
        return str(node.value)

    def boolean(self, node: yaml.Node, key: str, depth: int) -> bool:
        self.visit(node, key, depth)
        if not isinstance(node, yaml.ScalarNode) or node.tag != _TAG + "bool":
            raise self.error(f"expected true or false, found {_kind_of(node)}", node, key)
        return str(node.value).lower() in ("true", "yes", "on", "y")

    def enum(self, node: yaml.Node, spec: Spec, key: str, depth: int) -> str:
        self.visit(node, key, depth)
        v = str(node.value) if isinstance(node, yaml.ScalarNode) else None
        if v not in spec.choices or node.tag != _TAG + "str":
            near = difflib.get_close_matches(v or "", spec.choices, n=1, cutoff=0.6)
            hint = f"; did you mean {near[0]!r}?" if near else ""
            raise self.error(
                f"expected one of {', '.join(spec.choices)}, found {_kind_of(node)}{hint}", node, key
            )
        return v

    # -- the task ------------------------------------------------------------------
    def task(self, root: yaml.Node, stem: str) -> Task:
        top = self.mapping(root, TASK, "", 0)
        S = TASK.children
        name = self.text(top["name"], S["name"], "name", 1) if "name" in top else stem

        rs = S["robot"]
        rob = self.mapping(top["robot"], rs, "robot", 1)
        a1 = self.number(rob["a1"], rs.children["a1"], "robot.a1", 2)
        g = self.number(rob["gravity"], rs.children["gravity"], "robot.gravity", 2) if "gravity" in rob else fmpq(981, 100)
        ls = rs.children["links"]
        lnodes = self.mapping(rob["links"], ls, "robot.links", 2)
        links = {}
        for i in (2, 3, 4, 5):
            lk = f"robot.links.{i}"
            spec = ls.children[str(i)]
            ln = self.mapping(lnodes[str(i)], spec, lk, 3)
            links[i] = Link(*(self.number(ln[f], spec.children[f], f"{lk}.{f}", 4) for f in ("mass", "inertia", "r")))
        robot = Robot(a1=a1, links=links, gravity=g)

        ps = S["path"]
        pth = self.mapping(top["path"], ps, "path", 1)
        p = self.polynomial(pth["y"], ps.children["y"], "path.y", 2)
        ends = {}
        for end in ("from", "to"):
            if end in pth:
                ends[end] = self.pair(pth[end], ps.children[end], f"path.{end}", 2)
                x0, y0 = ends[end]
                if p(x0) != y0:
                    raise self.error(
                        f"point ({_q(x0)}, {_q(y0)}) is not on the path: y({_q(x0)}) = {_q(p(x0))}, found {_q(y0)}",
                        pth[end], f"path.{end}",
                    )  # fmt: skip

        ts = S["timing"]
        tim = self.mapping(top["timing"], ts, "timing", 1)
        duration = self.number(tim["duration"], ts.children["duration"], "timing.duration", 2)
        if "law" in tim and "x" in tim:
            raise self.error("give either law or x, not both", top["timing"], "timing")
        if "law" in tim:
            law = self.enum(tim["law"], ts.children["law"], "timing.law", 2)
            missing = [e for e in ("from", "to") if e not in ends]
            if missing:
                raise self.error(
                    f"law {law} needs path.{' and path.'.join(missing)} (the points it moves between)",
                    tim["law"], "timing.law",
                )  # fmt: skip
            x_of_t = timing_law(law, ends["from"][0], ends["to"][0], duration)
        elif "x" in tim:
            law = "explicit"
            x_of_t = self.polynomial(tim["x"], ts.children["x"], "timing.x", 2)
            for end, at in (("from", fmpq(0)), ("to", duration)):
                if end in ends and x_of_t(at) != ends[end][0]:
                    raise self.error(
                        f"path.{end} has x = {_q(ends[end][0])} but timing.x gives x({_q(at)}) = {_q(x_of_t(at))}",
                        pth[end], f"path.{end}",
                    )  # fmt: skip
        else:
            raise self.error("missing timing law: give law (quintic or cubic) or x (a polynomial in t)", top["timing"], "timing")
        degree = max(p.degree(), 0) * max(x_of_t.degree(), 0)
        if degree > MAX_DEGREE:
            raise self.error(
                f"the composition y(x(t)) has degree {degree}, beyond the cap of {MAX_DEGREE}", pth["y"], "path.y"
            )

        checks = Checks()
        if "checks" in top:
            cs = S["checks"]
            ch = self.mapping(top["checks"], cs, "checks", 1)
            kw: dict[str, Any] = {}
            for k in ("min_slope", "min_speed"):
                if k in ch:
                    kw[k] = self.number(ch[k], cs.children[k], f"checks.{k}", 2)
            if "torque_limit" in ch:
                kw["torque_limit"] = self.pair(ch["torque_limit"], cs.children["torque_limit"], "checks.torque_limit", 2)
            if "strict" in ch:
                kw["strict"] = self.boolean(ch["strict"], "checks.strict", 2)
            checks = Checks(**kw)
        return Task(
            name=name, robot=robot, path=p, x_of_t=x_of_t, duration=duration, law=law,
            checks=checks, lines=dict(self.lines), source=self.file,
        )  # fmt: skip


def _int8(text: str) -> int:
    """YAML 1.1 integers with a leading 0 are octal (0o17 or 017)."""
    sign = -1 if text.startswith("-") else 1
    body = text.lstrip("+-")
    if body[:2].lower() in ("0x", "0o", "0b"):
        return sign * int(body, 0)
    return sign * int(body, 8)


def _q(v: fmpq) -> str:
    """A rational for messages: as a decimal when it is one, else p/q."""
    d = int(v.q)
    while d % 2 == 0:
        d //= 2
    while d % 5 == 0:
        d //= 5
    if d == 1:
        s = f"{float(int(v.p) / int(v.q)):.15g}"
        if parse_decimal(s) == v:
            return s
    return str(v)


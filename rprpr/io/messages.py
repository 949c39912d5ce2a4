"""The words of the messages about bad input, in one place: a value shown shortened, the
key a misspelt one was likely meant as ("did you mean"), where in the file a problem lies
(line and column), a file over its size cap, and what a key of the schema expects.

Plain Python: the polynomial parser, the waypoint CSV reader, the capped reader and the
repository's configuration use it too, without loading YAML, flint or the engine.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from typing import TYPE_CHECKING, Any

from ..model.errors import TaskFileError

if TYPE_CHECKING:
    from .schema import Spec

_LINE_BREAK = re.compile("\r\n|[\r\n\x85\u2028\u2029]")


def shorten(text: str, n: int = 40, cut: int = 3) -> str:
    """``text`` for a message: whole up to ``n`` characters, else its first ``n - cut``
    and "..." (the polynomial parser's messages keep one character fewer: ``cut=4``)."""
    return text if len(text) <= n else text[: n - cut] + "..."


def near(key: str, allowed: Iterable[str]) -> list[str]:
    """The word of ``allowed`` that ``key`` is likely a misspelling of ([] when none):
    what "did you mean ...?" names."""
    import difflib  # only for a file with an error: not on the import path

    return difflib.get_close_matches(key, list(allowed), n=1, cutoff=0.6)


def one_line(text: str) -> str:
    """``text`` with line breaks and other unprintable characters escaped: one line."""
    if text.isprintable():
        return text
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in text)


def line_col(text: str, index: int) -> tuple[int, int]:
    """1-based (line, column) of the character at ``index``, counting lines as YAML does
    (CR LF, CR, LF, NEL, LS and PS each end one)."""
    breaks = list(_LINE_BREAK.finditer(text, 0, index))
    start = breaks[-1].end() if breaks else 0
    return len(breaks) + 1, index - start + 1


def where(node: Any) -> tuple[int, int]:
    """1-based (line, column) where a YAML node or event starts."""
    return node.start_mark.line + 1, node.start_mark.column + 1


def located(message: str, node: Any, key: str) -> TaskFileError:
    """A ``TaskFileError`` at the key ``key``, where the YAML node ``node`` starts
    (``node`` None: no line or column)."""
    line, column = where(node) if node is not None else (0, 0)
    return TaskFileError(message, key=key, line=line, column=column)


def size_name(cap: int) -> str:
    """``cap`` bytes in words when it is a round size (``1 MiB``, ``16 MiB``, ``4 KiB``),
    else ''."""
    for unit, shift in (("MiB", 20), ("KiB", 10)):
        if cap >= 1 << shift and cap % (1 << shift) == 0:
            return f"{cap >> shift} {unit}"
    return ""


def too_large(cap: int, size: int | None = None) -> str:
    """The message for a file over ``cap`` bytes (``size`` None: a stream, whose size is
    only known to pass the cap)."""
    held = f"{size} bytes" if size is not None else f"more than {cap} bytes"
    words = size_name(cap)
    return f"file too large: {held}, the cap is {cap} bytes" + (f" ({words})" if words else "")


_COUNT = {2: "two", 3: "three", 4: "four"}
PERCENT_EXPECTED = "a percentage such as 5% (0% <= value < 100%)"


def expected(spec: Spec, key: str) -> str:
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
    if spec.kind == "numbers":
        bound = ""
        if spec.minimum is not None:
            bound = f", each {'>' if spec.exclusive else '>='} {spec.minimum:g}"
        return f"a list of {_COUNT[len(spec.items)]} numbers [{', '.join(spec.items)}]{bound}"
    if spec.kind == "signs":
        return f"a list of {_COUNT[len(spec.items)]} signs [{', '.join(spec.items)}], each +1 or -1"
    if spec.kind == "point":
        return "a point: x alone, [x, y] or {x: ..., y: ...} (numbers, or fractions such as -2/3)"
    if spec.kind == "polynomial":
        text = f"a polynomial in {spec.variable} (text such as '2*{spec.variable}^2 - 1')"
        return text if spec.item is None else f"{text} or a list of pieces {keys_text(spec.item)}"
    if spec.kind == "time":
        return "a time [s] >= 0 (a decimal or a fraction such as 5/3)"
    if spec.kind == "vector":
        return f"a list of two numbers [{', '.join(spec.items)}]"
    if spec.kind == "list":
        assert spec.item is not None
        return f"a list of {keys_text(spec.item)}"
    if spec.kind == "waypoints":
        assert spec.item is not None
        return f"a list of waypoints {keys_text(spec.item)} or a CSV file's name"
    if spec.kind == "string" and key.startswith(("checks.ignore.", "checks.warn.")):
        return "text: why this task may break the rule (a reason is required)"
    if spec.kind == "string":
        return "text (a name for reports)"
    if spec.kind == "bool":
        return "true or false"
    if spec.kind in ("percent", "relative"):
        return PERCENT_EXPECTED
    return f"one of {', '.join(spec.choices)}"  # enum


def keys_text(spec: Spec) -> str:
    """The keys of a mapping ``spec``, as written in YAML: {until, x, y}."""
    return "{" + ", ".join(spec.children) + "}"

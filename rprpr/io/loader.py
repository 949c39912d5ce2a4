"""Reading a task file: bytes -> text -> YAML node tree -> values -> validated ``Task``.

The pipeline, one module a step:

1. ``source``: bytes -> text (the size cap, a byte order mark, UTF-8 only, no character
   YAML does not allow);
2. ``yaml_nodes``: text -> node tree, within caps (depth, node budget), explicit tags
   kept; YAML syntax errors located, with a hint;
3. ``walk``: the node tree read along ``schema.TASK``, one reader per ``Spec.kind``
   (``readers``, numbers and tags by ``scalars``) and, as each key is read, the
   cross-field rule filed under it (``cross_rules``);
4. ``build``: the ``Task`` from the values read.

Safety: the YAML is only *composed* (parsed into nodes), never constructed into Python
objects, so no tag can run code; only the plain tags (str, int, float, bool, null, map,
seq) are accepted, and an explicit one must fit its value: a tag never makes an invalid
value valid (``scalars.misfit``). Duplicate keys are errors (PyYAML would silently keep
the last), and aliases are followed with a budget on visited nodes, so an alias bomb is
rejected rather than expanded. Numbers are taken by their text (``0.1`` is 1/10). Every
error is a ``TaskFileError`` naming the file, line, column and dotted key (``messages``).
"""

from __future__ import annotations

import os
import re

import yaml

from ..model.errors import TaskFileError
from ..model.task import Task
from . import build
from .cross_rules import RULES, TASK_RULES
from .messages import one_line
from .readers import READERS
from .reading import ReadProblem, read_file, read_stream
from .scalars import ESCAPED_CONTROL
from .schema import CSV_PATTERN, TASK
from .source import MAX_BYTES, decode
from .walk import Missing, Walk
from .yaml_nodes import MAX_DEPTH, compose

__all__ = ["MAX_BYTES", "TaskFileError", "load_task", "parse_task", "read_stdin", "waypoint_file"]

_EMPTY = "empty task file, expected a mapping with robot, path and timing"


def load_task(path: str | os.PathLike[str]) -> Task:
    """Read and validate the task file at ``path``; raises ``TaskFileError``. A waypoint
    CSV it names is read relative to the task file's directory."""
    name = os.fspath(path)
    try:
        data = read_file(name, MAX_BYTES, "a task file (YAML)")
    except ReadProblem as e:
        raise TaskFileError(e.message, file=name) from None
    return parse_task(data, name, directory=os.path.dirname(name) or os.curdir)


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
                one_line(x.message), file=file, line=x.line, column=x.column, key=one_line(x.key)
            )
            for x in e.errors
        )
        first.errors = (first, *others)
        raise first from None
    except RecursionError:
        raise TaskFileError(f"nested deeper than {MAX_DEPTH} levels", file=file) from None


def _parse(data: bytes | str, file: str, directory: str) -> Task:
    text = decode(data)
    if all(not ln.strip() or ln.lstrip().startswith("#") for ln in text.splitlines()):
        raise TaskFileError(_EMPTY)
    root, explicit = compose(text)
    if root is None or (isinstance(root, yaml.ScalarNode) and root.value == "" and not root.style):
        raise TaskFileError(_EMPTY)
    # a value can hold a control character only by an escape (decoded) or as written
    escapes = "\\" in text or ESCAPED_CONTROL.search(text) is not None
    walk = Walk(explicit, directory, escapes=escapes, readers=READERS, rules=RULES)
    walk.read(root, TASK, "", 0)
    if not walk.errors:
        task = build.task(walk, file)
        for rule in TASK_RULES:  # what needs the whole task (a 5R's start point)
            rule(walk, task)
    if walk.errors:  # in the order of the file, as a linter lists them; missing keys last
        errors = sorted(walk.errors, key=lambda e: (isinstance(e, Missing), e.line, e.column))
        errors[0].errors = tuple(errors)
        raise errors[0]
    return task


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
        root, _ = compose(decode(data))
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

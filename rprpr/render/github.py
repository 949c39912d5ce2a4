"""``rprpr check --format github``: GitHub Actions workflow commands, one line per finding.

    ::error file=configs/paper_path1.rprpr.yaml,line=19,title=RPR101 slope-principle::t = 2.5 s, ...

A finding that fails the task is an ``::error`` (unbounded torques, RPR201, among them);
a strict-mode-only finding (RPR202, or RPR201 accepted with ``checks.unbounded_torque:
warn`` or ``--warn-unbounded``) when not strict is a ``::warning``. ``line`` is the line
of the task-file key the finding belongs to (``path.y``, ``timing``, ...), or of the
offending key for a task file that could not be read (then with ``col`` when known; one
annotation for each error in that file).
Passing tasks print nothing.

Escaping is that of the Actions toolkit (``@actions/core``, ``command.ts``): in the
message ``%`` -> ``%25``, ``\\r`` -> ``%0D``, ``\\n`` -> ``%0A``; in a property value
also ``:`` -> ``%3A`` and ``,`` -> ``%2C``; so a newline never ends the command, it is a
line break in the annotation. Every other control character (an ANSI escape, a bidi
override, a byte of a file name that is not UTF-8), in the message and every property,
is first escaped for people (``escape.printable``: ``\\x1b``): the line may be read on
a terminal, and a file whose name holds such a character has no annotation to point at.
"""

from __future__ import annotations

import os
from typing import Any

from ..model.rules import RULES
from ..report.run import BUDGET, INTERNAL, Run
from .escape import printable


def escape_data(s: str) -> str:
    """A workflow command's message, escaped as ``escapeData`` of the toolkit."""
    return s.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def escape_property(s: str) -> str:
    """A workflow command's property value, escaped as ``escapeProperty`` of the toolkit."""
    return escape_data(s).replace(":", "%3A").replace(",", "%2C")


def command(name: str, properties: dict[str, Any], message: str) -> str:
    """``::name key=value,...::message``; properties that are None are left out; the
    message and the ``title`` with their control characters escaped for people."""
    props = ",".join(
        f"{k}={escape_property(_for_people(str(v)))}"
        for k, v in properties.items()
        if v is not None
    )
    return f"::{name}{' ' + props if props else ''}::{escape_data(_for_people(message))}"


def _for_people(text: str) -> str:
    """Control characters escaped, but the line breaks the toolkit's escaping carries."""
    return printable(text, keep="\r\n")


def annotation_path(path: str, root: str | None = None) -> str:
    """The task path as GitHub wants it: relative to the workspace, with forward slashes.

    A relative path is normalised (``./configs/a.yaml`` -> ``configs/a.yaml``); an absolute
    path inside ``root`` (default: the working directory) is made relative to it. When
    there is no working directory (deleted under a running job), the path is kept."""
    if os.path.isabs(path):
        try:
            base = os.path.abspath(root or os.getcwd())
        except OSError:  # the working directory no longer exists
            base = None
        rel = os.path.relpath(path, base) if base else os.pardir
        if not rel.startswith(os.pardir):
            path = rel
    else:
        path = os.path.normpath(path)
    return path.replace(os.sep, "/")


def render(run: Run, *, quiet: bool = False, root: str | None = None) -> str:
    """The annotations of ``run``, in task order; ``quiet`` leaves out the warnings."""
    lines = []
    for kind, item, _ in run.entries():
        file = annotation_path(item["task"], root)
        if kind == "report":
            for f in item["findings"]:
                if f["severity"] != "error" and quiet:
                    continue
                props = {"file": file, "line": f["line"], "title": RULES[f["rule"]].title}
                lines.append(command(f["severity"], props, f["message"]))
        elif kind == INTERNAL:
            lines.append(
                command("error", {"file": file, "title": "rprpr internal error"}, item["text"])
            )
        elif kind == BUDGET:
            lines.append(
                command("error", {"file": file, "title": "rprpr budget exceeded"}, item["message"])
            )
        else:  # a task file that could not be read: an annotation per error in it
            for e in item["errors"]:
                props = {
                    "file": file,
                    "line": e["line"],
                    "col": e["column"] if e["line"] else None,
                    "title": RULES[e["rule"]].title,
                }
                message = f"{e['key']}: {e['message']}" if e["key"] else e["message"]
                lines.append(command("error", props, message))
    return "".join(line + "\n" for line in lines)

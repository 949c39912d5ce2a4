"""``rprpr check --output-format concise``: the findings only, one line each, as ruff's
concise format::

    configs/paper_path1.rprpr.yaml:19:1: RPR101 [error] t = 2.5 s, (x, y) = (3, 0), ...

``FILE:LINE:COL: RPRnnn [severity] message``: the line of the task-file key the finding
points at (column 1: the key starts its line), the rule, ``error`` for a finding that
fails its task and ``warning`` for one that fails only in strict mode. A task file that
could not be read gives one ``RPR001 [error]`` line per error in it, at the offending
key's line and column (1:1 when the file has none, as a YAML file that cannot be
decoded); a bug or a task stopped at its work budget the line ``rprpr check`` says on
standard error. Passing tasks without findings print nothing; no line is ever wrapped,
and every text from outside (a file name, a quoted value) has its control characters
escaped (``escape.printable``): one finding is one line, whatever it quotes.

``quiet`` leaves out the warnings (what fails the run stays).
"""

from __future__ import annotations

from ..report.run import BUDGET, INTERNAL, REPORT, Run
from .escape import printable


def render(run: Run, *, quiet: bool = False) -> str:
    """The findings of ``run``, one line each, in task order and, within a task, in the
    audit's order."""
    lines = []
    for kind, item, _ in run.entries():
        task = item["task"]
        if kind == REPORT:
            for f in item["findings"]:
                if quiet and f["severity"] != "error":
                    continue
                where = f"{task}:{f['line']}:1"
                lines.append(f"{where}: {f['rule']} [{f['severity']}] {f['message']}")
        elif kind in (INTERNAL, BUDGET):  # the line said on standard error
            lines.append(item["text"])
        else:  # a task file that could not be read: a line per error in it
            for e in item["errors"]:
                where = f"{e['line'] or 1}:{(e['column'] or 1) if e['line'] else 1}"
                message = f"{e['key']}: {e['message']}" if e["key"] else e["message"]
                lines.append(f"{task}:{where}: {e['rule']} [error] {message}")
    return "".join(printable(line) + "\n" for line in lines)

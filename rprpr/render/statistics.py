"""``rprpr check --statistics``: how many findings each rule made over the run (as ruff's
``--statistics``), most frequent first; a task file that could not be read counts for
RPR001. Text, one rule a line (``3  RPR101  slope-principle``), or a JSON list."""

from __future__ import annotations

import json
from collections import Counter

from ..model.rules import INVALID_TASK, RULES
from ..report.run import Run


def counts(run: Run) -> list[tuple[str, int]]:
    """(rule id, number of findings) of every rule that found something, most first, then
    by id."""
    found = Counter(f["rule"] for r in run.reports for f in r["findings"])
    found[INVALID_TASK] += len(run.input_errors)
    return sorted(((rule, n) for rule, n in found.items() if n), key=lambda x: (-x[1], x[0]))


def render(run: Run, *, as_json: bool = False) -> str:
    """The statistics of ``run``: text lines, or a JSON list of ``{"code", "name",
    "count"}``."""
    rows = counts(run)
    if as_json:
        doc = [{"code": rule, "name": RULES[rule].name, "count": n} for rule, n in rows]
        return json.dumps(doc, indent=2) + "\n"
    width = max((len(str(n)) for _, n in rows), default=1)
    return "".join(f"{n:>{width}}  {rule}  {RULES[rule].name}\n" for rule, n in rows)

"""``rprpr check --output-format gitlab``: a GitLab Code Quality report (JSON).

A list of issues, one per finding (as GitLab's ``codequality`` artifact reads them):
``check_name`` the rule id, ``description`` the rule and the message, ``severity``
"major" for a finding that fails its task and "minor" for one that only warns (a task
file that could not be read: "major", RPR001), ``location`` the task file's path
relative to the working directory and the line of the key, ``fingerprint`` an MD5 of
the file, rule and message (stable from run to run, unique within the report). A bug or
a task stopped at its work budget is a "blocker" issue at the task file's first line.
"""

from __future__ import annotations

import hashlib
import json
from typing import Any

from ..model.rules import RULES
from ..report.run import BUDGET, INPUT, INTERNAL, REPORT, Run
from .escape import inert_json
from .github import annotation_path

SEVERITY = {"error": "major", "warning": "minor"}


def _issue(check: str, description: str, severity: str, path: str, line: int | None,
           seen: dict[str, int]) -> dict[str, Any]:  # fmt: skip
    key = f"{path}\0{check}\0{description}"
    n = seen.get(key, 0)
    seen[key] = n + 1
    fingerprint = hashlib.md5(f"{key}\0{n}".encode(), usedforsecurity=False).hexdigest()
    return {
        "type": "issue",
        "check_name": check,
        "description": description,
        "categories": ["Bug Risk"],
        "severity": severity,
        "fingerprint": fingerprint,
        "location": {"path": path, "lines": {"begin": int(line or 1)}},
    }


def document(run: Run, root: str | None = None) -> list[dict[str, Any]]:
    """The Code Quality issues of ``run``, in task order."""
    issues: list[dict[str, Any]] = []
    seen: dict[str, int] = {}
    for kind, item, _ in run.entries():
        path = annotation_path(item["task"], root)
        if kind == REPORT:
            for f in item["findings"]:
                text = f"{RULES[f['rule']].title}: {f['message']}"
                issues.append(
                    _issue(f["rule"], text, SEVERITY[f["severity"]], path, f["line"], seen)
                )
        elif kind == INPUT:
            message = f"{item['key']}: {item['message']}" if item["key"] else item["message"]
            text = f"{RULES[item['rule']].title}: {message}"
            issues.append(_issue(item["rule"], text, "major", path, item["line"], seen))
        elif kind == INTERNAL:
            issues.append(_issue("internal-error", item["text"], "blocker", path, 1, seen))
        elif kind == BUDGET:
            issues.append(_issue("budget-exceeded", item["message"], "blocker", path, 1, seen))
    return issues


def render(run: Run, root: str | None = None) -> str:
    """The report of ``run`` as text: indented by 2, ending with a newline."""
    return inert_json(json.dumps(document(run, root), indent=2)) + "\n"

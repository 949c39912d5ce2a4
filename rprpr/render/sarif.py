"""``rprpr check --output-format sarif``: SARIF 2.1.0, the format of GitHub code scanning.

One ``run`` with the tool's rules (every rule of ``model.rules``, each with what it checks,
the paper's equation, why it matters and how to fix it) and one ``result`` per finding:
``level`` "error" for a finding that fails its task, "warning" for one that only warns;
the location is the task file (a URI relative to the working directory, as GitHub wants
it) at the line of the key the finding belongs to. A task file that could not be read is
a result of RPR001 at its line and column. A bug or a task stopped at its work budget is
not a finding of the task: it is a ``toolExecutionNotification`` of the invocation, and
``executionSuccessful`` is then false. Passing tasks add no result. The document holds
no time, so the same tasks always give the same bytes.

The document is valid against the OASIS schema (``sarif-schema-2.1.0.json``, errata 01;
``tests/render/test_sarif_gitlab.py`` checks it).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any
from urllib.parse import quote

from .._version import __version__
from ..model.rules import RULES, Rule
from ..report.run import BUDGET, INPUT, INTERNAL, REPORT, Run
from .escape import inert_json
from .github import annotation_path

SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"
RULE_IDS = list(RULES)
# rules only a declared ``uncertainty`` can raise (docs/robust.md): listed among the tool's
# rules when a task of the run declares it (they are the last rules: no index moves)
OPT_IN = ("RPR205",)


def uri(path: str, root: str | None = None) -> str:
    """The artifact URI of a task file: relative to ``root`` (the working directory) with
    forward slashes and percent-encoded, or a ``file://`` URI when outside it."""
    rel = annotation_path(path, root)
    if os.path.isabs(rel):
        return Path(rel).as_uri()
    return quote(rel, safe="/")


def rule_descriptor(rule: Rule) -> dict[str, Any]:
    """A SARIF ``reportingDescriptor`` for ``rule``."""
    silence = (
        "It cannot be silenced: a task file that cannot be read is never audited."
        if rule.id == "RPR001"
        else f"To silence it for one task: checks: {{ignore: {{{rule.id}: <reason>}}}}; for "
        f'the repository: ignore = ["{rule.id}"] in [tool.rprpr].'
    )
    full = rule.meaning + (f" Paper: {rule.equation}." if rule.equation else "")
    help_text = f"{rule.why} Fix: {rule.fix} {silence}".strip()
    return {
        "id": rule.id,
        "name": rule.name,
        "shortDescription": {"text": rule.meaning},
        "fullDescription": {"text": full},
        "help": {"text": help_text},
        "defaultConfiguration": {"level": "warning" if rule.strict_only else "error"},
        "properties": {"tags": ["rprpr", "robotics"]},
    }


def _location(path: str, line: int | None, column: int | None, root: str | None) -> dict[str, Any]:
    physical: dict[str, Any] = {"artifactLocation": {"uri": uri(path, root)}}
    if line:
        region: dict[str, Any] = {"startLine": int(line)}
        if column:
            region["startColumn"] = int(column)
        physical["region"] = region
    return {"physicalLocation": physical}


def _result(rule: str, level: str, message: str, location: dict[str, Any]) -> dict[str, Any]:
    return {
        "ruleId": rule,
        "ruleIndex": RULE_IDS.index(rule),
        "level": level,
        "message": {"text": message},
        "locations": [location],
    }


def document(run: Run, root: str | None = None) -> dict[str, Any]:
    """The SARIF log of ``run``."""
    results = []
    notifications = []
    for kind, item, _ in run.entries():
        path = item["task"]
        if kind == REPORT:
            for f in item["findings"]:
                where = _location(path, f["line"], f.get("column"), root)
                results.append(_result(f["rule"], f["severity"], f["message"], where))
        elif kind == INPUT:
            where = _location(path, item["line"], item["column"], root)
            message = f"{item['key']}: {item['message']}" if item["key"] else item["message"]
            results.append(_result(item["rule"], "error", message, where))
        elif kind in (INTERNAL, BUDGET):
            text = item["text"] if kind == INTERNAL else item["message"]
            notifications.append(
                {
                    "level": "error",
                    "message": {"text": text},
                    "locations": [_location(path, None, None, root)],
                    "descriptor": {"id": "internal-error" if kind == INTERNAL else "budget"},
                }
            )
    invocation: dict[str, Any] = {"executionSuccessful": not notifications}
    if notifications:
        invocation["toolExecutionNotifications"] = notifications
    return {
        "$schema": SCHEMA,
        "version": "2.1.0",
        "runs": [
            {
                "tool": {
                    "driver": {
                        "name": "rprpr",
                        "version": __version__,
                        "semanticVersion": __version__,
                        "rules": [
                            rule_descriptor(r)
                            for r in RULES.values()
                            if r.id not in OPT_IN or _uncertain(run)
                        ],
                    }
                },
                "invocations": [invocation],
                "columnKind": "unicodeCodePoints",
                "results": results,
            }
        ],
    }


def _uncertain(run: Run) -> bool:
    """Whether a task of ``run`` declares uncertainty (then the ``OPT_IN`` rules are
    listed)."""
    return any(kind == REPORT and "uncertainty" in item for kind, item, _ in run.entries())


def render(run: Run, root: str | None = None) -> str:
    """The SARIF log of ``run`` as text: indented by 2, ending with a newline."""
    return inert_json(json.dumps(document(run, root), indent=2)) + "\n"

"""``rprpr rule [ID]``: what a rule checks, the paper's equation it rests on, why it
matters, how to fix a finding and how to silence it (as ruff's ``rule``); with no ID, the
list of every rule. An ID may also be the rule's name (``unbounded-torque``)."""

from __future__ import annotations

import difflib
from collections.abc import Iterator

import click

from ..model.rules import INVALID_TASK, RULES, Rule
from ..model.rules import rule_id as id_of
from ..report.exit import ExitCode


@click.command()
@click.argument("rule_id", metavar="[ID]", required=False)
def rule(rule_id: str | None) -> ExitCode:
    """Explain the rule ID (e.g. RPR201): what it checks, the paper's equation, why it
    matters, how to fix and how to silence it. With no ID: every rule, one a line."""
    if rule_id is None:
        for r in RULES.values():
            level = "warning (error if strict)" if r.strict_only else "error"
            click.echo(f"{r.id}  {r.name:<22} {level}")
        return ExitCode.PASSED
    click.echo("\n".join(explain(find(rule_id))))
    return ExitCode.PASSED


def find(rule_id: str) -> Rule:
    """The rule named by its id (any case) or its name; a usage error naming the closest."""
    found = id_of(rule_id)
    if found is not None:
        return RULES[found]
    wanted = rule_id.strip()
    known = [*RULES, *(r.name for r in RULES.values())]
    near = difflib.get_close_matches(wanted, known, n=1, cutoff=0.6)
    hint = f" (did you mean {near[0]}?)" if near else ""
    raise click.UsageError(f"unknown rule {rule_id!r}{hint}; `rprpr rule` lists them")


def explain(r: Rule) -> Iterator[str]:
    """The explanation of ``r``, line by line."""
    yield f"{r.id} {r.name}"
    yield ""
    yield f"What it checks: {r.meaning}"
    if r.equation:
        yield f"Paper: {r.equation}."
    if r.why:
        yield f"Why it matters: {r.why}"
    if r.id == INVALID_TASK:
        yield "Level: always an error (exit status 2); the other tasks are still audited."
    elif r.strict_only:
        yield "Level: a warning; fails the task in strict mode (--strict, checks.strict)."
    else:
        yield "Level: an error: fails the task (exit status 1)."
    if r.key:
        yield f"Points at: the task file's {r.key} key."
    yield f"How to fix: {r.fix}"
    yield ""
    if r.id == INVALID_TASK:
        yield "How to silence: it cannot be: a task file that cannot be read is never audited."
        return
    yield "How to silence (say why: the reason is required):"
    yield "  in the task file, for that task alone (warn: instead of ignore: keeps a warning):"
    yield "    checks:"
    yield "      ignore:"
    yield f"        {r.id}: <why this task may break it>"
    yield "  in pyproject.toml ([tool.rprpr]) or rprpr.toml, for every task:"
    yield f'    ignore = ["{r.id}"]     # or warn = ["{r.id}"]; error = [...] promotes'
    if r.id == "RPR201":
        yield "  also: checks.unbounded_torque: warn in the task, or check --warn-unbounded."

"""``rprpr rule [ID]``: what a rule checks, the paper's equation it rests on, why it
matters, what it means for a 5R five-bar (the rules it shares), how to fix a finding and
how to silence it (as ruff's ``rule``); with no ID, the list of every rule. An ID may also
be the rule's name (``unbounded-torque``)."""

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


# what a rule shared by the 5R means for it (docs/five-bar.md: §2 the working modes, §3
# the Type II curves S₊ and S₋, §4 the principles, §6 the consistency conditions)
FIVE_BAR = {
    "RPR101": (
        "the path is tangent to the Type II curve S₊ or S₋ at the instant (∇S·E' = 0), passes"
        " a singular point of the curve, or crosses it at an angle α whose tan α ="
        " |∇S·E'|/|∇S × E'| does not exceed checks.min_slope: the singularity is of high"
        " order; cross the curve transversally (§4)."
    ),
    "RPR102": (
        "the end point is at rest on S₊ or S₋ (E' = 0) or slower than checks.min_speed:"
        " the singularity is of high order, as for the RPRPR (§4)."
    ),
    "RPR103": (
        "a leg is stretched or folded (|E - A| = l1 + l3 or |l1 - l3|, likewise |E - B| with"
        " l2, l4): a Type I singularity, where the leg's two working modes meet and the"
        " working mode is lost; the analysis stops there (the Type II instants before it"
        " are reported). Keep E inside both legs' reach (§2)."
    ),
    "RPR104": (
        "the path, or a piece of it, runs along S₊ or S₋ (the distal links stay lined up):"
        " every instant of it is a Type II singularity (§3)."
    ),
    "RPR201": (
        "the reciprocity condition w = h1/l3 + σ h2/l4 = 0 fails at t_s (the distal links'"
        " transverse dynamic forces at E do not cancel: the dynamic wrench is not"
        " reciprocal to the uncontrollable twist), or, at an instant of order k, fewer than"
        " the k conditions w = w' = ... = w^(k-1) = 0 (σ frozen at t_s) hold; the 5R's"
        " eq. (34) and higher-order conditions (§6)."
    ),
}


def explain(r: Rule) -> Iterator[str]:
    """The explanation of ``r``, line by line."""
    yield f"{r.id} {r.name}"
    yield ""
    yield f"What it checks: {r.meaning}"
    if r.equation:
        yield f"Paper: {r.equation}."
    if r.why:
        yield f"Why it matters: {r.why}"
    if r.id in FIVE_BAR:
        yield f"For a 5R (robot.mechanism: 5R): {FIVE_BAR[r.id]} See docs/five-bar.md."
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

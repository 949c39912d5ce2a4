"""The findings of an audit: one function per rule of ``model.rules`` (pure).

Each function decides, from the exact singular analysis, whether its rule is broken and
says where; the key a finding points back to is its rule's (``Rule.key``). Every number in
a message goes through ``model.numbers``; the instants of a task are told apart together
(``numbers.labels``), so that two close instants never read alike.
"""

from __future__ import annotations

from collections.abc import Callable

from ..model.numbers import apart, labels, to_float
from ..model.rules import Finding
from ..model.task import Task
from .singular import KinematicSingularity, SingularAnalysis, SingularInstant

At = Callable[[float], str]  # an instant's time -> "t = ... s"


def findings(task: Task, a: SingularAnalysis, peak: tuple[float, float] | None) -> list[Finding]:
    """What the audit found wrong with ``task``, in report order: the path on the singular
    line, the inverse-kinematic singularities, each singular instant's broken principles
    and unbounded torques, then the torque limit. ``peak`` = (max |T1|, max |T2|) [N m]."""
    at = instant_text(a)
    out = path_on_singular_line(a)
    out += [kinematic(k, at) for k in a.kinematic]
    for s in a.instants:
        out += slope(s, at) + velocity(s, at) + unbounded(s, at)
    out += torque_limit(task, a, peak, at)
    return out


def instant_text(a: SingularAnalysis) -> At:
    """``t = ... s`` for each instant of ``a``, with the digits that tell them apart."""
    text = labels([k.t for k in a.kinematic] + [s.t for s in a.instants])
    return lambda t: f"t = {text[t]} s"


def _where(s: SingularInstant, at: At) -> str:
    return f"{at(s.t)}, (x, y) = ({s.number('x')}, 0), case {s.case.number}, order {s.order}"


def path_on_singular_line(a: SingularAnalysis) -> list[Finding]:
    """RPR104: y(t) ≡ 0, so δ ≡ 0 (eq. 29) all along the motion."""
    if not a.on_singular_line:
        return []
    message = (
        "the path lies on the singular line y = 0 (δ ≡ 0): every instant is a Type II singularity"
    )
    return [Finding("RPR104", message)]


def kinematic(k: KinematicSingularity, at: At) -> Finding:
    """RPR103: E at A (s1 = 0) or at B (s2 = 0)."""
    joint = "A" if k.leg == 1 else "B"
    message = (
        f"{at(k.t)}: the end point is at {joint} (s{k.leg} = 0): inverse-kinematic singularity"
    )
    return Finding("RPR103", message, k.t)


def slope(s: SingularInstant, at: At) -> list[Finding]:
    """RPR101: the slope principle (eq. 48) fails at ``s``."""
    if s.slope_principle.passed:
        return []
    message = f"{_where(s, at)}: slope principle fails: {s.slope_principle.reason}"
    return [Finding("RPR101", message, s.t)]


def velocity(s: SingularInstant, at: At) -> list[Finding]:
    """RPR102: the velocity principle (eq. 47) fails at ``s``."""
    if s.velocity_principle.passed:
        return []
    message = f"{_where(s, at)}: velocity principle fails: {s.velocity_principle.reason}"
    return [Finding("RPR102", message, s.t)]


def unbounded(s: SingularInstant, at: At) -> list[Finding]:
    """RPR201: the torques have a pole at ``s`` (eq. 34 fails, or not all the boundedness
    conditions hold)."""
    if s.torque_bounded:
        return []
    why = (
        f"consistent, but only {s.conditions_met} of {s.conditions_required}"
        " boundedness conditions hold"
        if s.consistent
        else f"inconsistent (eq. 34 residual {s.number('consistency_residual')} N)"
    )
    message = f"{_where(s, at)}: {why}: torques unbounded (pole of order {s.pole_order})"
    return [Finding("RPR201", message, s.t)]


def torque_limit(
    task: Task, a: SingularAnalysis, peak: tuple[float, float] | None, at: At
) -> list[Finding]:
    """RPR202: a torque beyond ``checks.torque_limit``: at every pole (beyond any limit;
    near a pole the sampled peak only says where the grid fell), else where the peak
    exceeds the limit of its actuator."""
    limit = task.checks.torque_limit
    if limit is None:
        return []
    poles = [s for s in a.instants if not s.torque_bounded]
    if poles:
        return [
            Finding(
                "RPR202",
                f"{at(s.t)}: the torques are unbounded (pole of order {s.pole_order}):"
                " beyond any limit",
                s.t,
            )
            for s in poles
        ]
    if peak is None:
        return []
    out = []
    for j in (0, 1):
        lim = to_float(limit[j])
        if peak[j] > lim:
            reached, allowed = apart(peak[j], lim)
            message = f"|T{j + 1}| reaches {reached} N m, beyond the limit {allowed} N m"
            out.append(Finding("RPR202", message))
    return out

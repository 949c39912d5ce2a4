"""The sheet's words: titles, summaries and what a singular instant's label says.

Every number goes through ``rprpr.model.numbers``; every status and order is the
engine's (``AuditResult.status_of``, ``SingularInstant.high_order``)."""

from __future__ import annotations

from collections.abc import Sequence

from ..._version import __version__
from ...engine.audit import AuditResult
from ...engine.bounds.verdicts import Approach
from ...engine.exact.singular import SingularInstant
from ...model.actuation import REVOLUTE, SCHEMES, Scheme
from ...model.numbers import distinct, number
from .motion import Motion

LABEL_DIGITS = 4  # significant digits of a number written on the sheet


def instant_times(result: AuditResult) -> list[str]:
    """The times t_s [s] of ``result``'s singular instants as label text: 4 significant
    digits, or as many as ``distinct`` needs where two instants would read alike."""
    return distinct([s.t for s in result.singularities], LABEL_DIGITS)


def order_text(s: SingularInstant) -> str:
    """``order k``, with ``high-order`` added for a high-order instant."""
    return f"order {s.order}, high-order" if s.high_order else f"order {s.order}"


def vanishing(order: int) -> str:
    """What vanishes at a singular instant of this order: δ and its first order-1 derivatives."""
    names = ["δ", "δ'", "δ''"]
    if order <= 3:
        return " = ".join(names[:order]) + " = 0"
    return f"δ = δ' = … = δ^({order - 1}) = 0"


def verdict_text(s: SingularInstant, e: Scheme = SCHEMES[REVOLUTE]) -> str:
    """Why a singular instant is marked as it is, in a few words (the efforts of the
    actuation scheme ``e``: T [N m] or F [N])."""
    why = []
    if not s.slope_principle.passed:
        why.append("slope principle fails")
    if not s.velocity_principle.passed:
        why.append("velocity principle fails")
    if not s.torque_bounded:
        why.append(f"{e.letter} unbounded (pole {s.pole_order})")
    elif s.torque_at_singularity is not None:
        t1, t2 = (number(v, LABEL_DIGITS) for v in s.torque_at_singularity)
        why.append(f"{e.letter} → ({t1}, {t2}) {e.unit}")
    return ", ".join(why)


def summary(m: Motion) -> str:
    """One line per task for the sheet's title: verdict, singular instants, torques."""
    r = m.result
    n = len(r.singularities)
    parts = [f"{n} singular instant{'' if n == 1 else 's'}"]
    if n:
        parts[0] += f" ({sum(s.high_order for s in r.singularities)} high-order)"
    if r.on_singular_line:
        parts.append("the path lies on the singular line")
    if r.kinematic_singularities:
        parts.append("inverse-kinematic singularity")
    parts += _torque_summary(r)
    where = f" ({m.source})" if m.source else ""
    return f"{m.name}{where}: {r.verdict.upper()} — " + "; ".join(parts)


def near_miss_delta(a: Approach) -> str:
    """A closest approach as the δ panel keys it: min |δ|, never 0."""
    lo, hi = number(a.delta_lo, 3), number(a.delta_hi, 3)
    value = f"= {lo}" if lo == hi else f"in [{lo}, {hi}]"
    return f"near miss: min |δ| {value} at t = {number(a.t_delta, LABEL_DIGITS)} s (never 0)"


def near_miss_path(a: Approach) -> str:
    """A closest approach as the workspace keys it: E's least distance to the line AB."""
    return (
        f"near miss: E passes {number(a.distance, 3)} m from the line AB "
        f"at t = {number(a.t_y, LABEL_DIGITS)} s"
    )


def heading_lines(m: Motion) -> tuple[str, str]:
    """The sheet title's lines for one task: its name, verdict and summary; and its file
    (the directories abbreviated when the path is long), or "" without one."""
    full = summary(Motion("", m.result, m.s))
    return full, ("file: " + abbreviated(m.source) if m.source else "")


def abbreviated(path: str, n: int = 80) -> str:
    """``path`` kept whole up to ``n`` characters, else ``…/`` and its last parts."""
    if len(path) <= n:
        return path
    parts = path.replace("\\", "/").split("/")
    tail = parts[-1]
    for p in reversed(parts[:-1]):
        if len(p) + len(tail) + 3 > n:
            break
        tail = f"{p}/{tail}"
    return "…/" + short(tail, n - 2)


def _torque_summary(r: AuditResult) -> list[str]:
    """Where the torques are unbounded, or else their peak (nothing if neither is known)."""
    times = instant_times(r)
    e = SCHEMES[r.task.robot.actuation]
    unbounded = [times[k] for k, s in enumerate(r.singularities) if not s.torque_bounded]
    if len(unbounded) > 4:
        return [f"{e.noun} unbounded at {len(unbounded)} instants"]
    if unbounded:
        return [f"{e.noun} unbounded at t = " + ", ".join(unbounded) + " s"]
    if r.torque_peak is not None:
        t1, t2 = (number(p.value, LABEL_DIGITS) for p in r.torque_peak)
        return [f"peak |{e.letter}1|, |{e.letter}2| = {t1}, {t2} {e.unit}"]
    return []


def title(motions: Sequence[Motion]) -> str:
    """The sheet's title: rprpr's version, then one summary line per task."""
    return "\n".join([f"rprpr {__version__} audit sheet", *(summary(m) for m in motions)])


def names(motions: Sequence[Motion]) -> str:
    """The tasks' names for a panel's title (a count when they would not fit)."""
    if len(motions) == 1:
        return motions[0].name
    joined = " vs ".join(m.name for m in motions)
    return joined if len(joined) <= 90 else f"{len(motions)} tasks (see legend)"


def short(name: str, n: int = 36) -> str:
    """``name`` cut to ``n`` characters, an ellipsis marking the cut."""
    return name if len(name) <= n else name[: n - 1] + "…"


def description(motions: Sequence[Motion]) -> str:
    """The tasks' verdicts and singular instants in one line (the files' metadata)."""
    out = []
    for m in motions:
        r = m.result
        sings = "; ".join(
            f"t = {t} s order {s.order} {r.status_of(s)}"
            for s, t in zip(r.singularities, distinct([s.t for s in r.singularities]), strict=True)
        )
        out.append(f"{m.name}: {r.verdict}" + (f" ({sings})" if sings else ""))
    return " | ".join(out)

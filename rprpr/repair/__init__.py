"""Repair of a failing motion: the smallest local, exact change that makes it pass (pure).

A failing instant is repaired by local bumps about t_s (a first-order crossing: eq. (34),
``consistency``, is its only condition) and a knot where the velocity or the acceleration
jumps by a quintic blend of its two pieces; ``bumps`` states both, with their formulas.

Every bump is a polynomial with rational coefficients in rational windows, so the
repaired motion is exact and its audit is exact; every candidate is audited (strict)
and only a passing one is returned.

The modules, in the order a repair uses them: ``windows`` (where a change fits), ``plan``
(the bumps' coefficients at each instant, by ``consistency``), ``snap`` (irrational
instants moved to rational times), ``bumps`` (the changes applied, exactly), ``account``
(what changed, and by how much); ``records`` holds what it returns.
"""

from __future__ import annotations

import itertools
from collections.abc import Iterable
from dataclasses import replace

from flint import fmpq

from ..engine.audit import AuditResult, audit
from ..engine.exact.singular import SingularInstant
from ..model.actuation import PRISMATIC
from ..model.options import AuditOptions
from ..model.rules import Finding
from ..model.task import Task
from .account import account
from .bumps import apply, blended, bump, smoothstep
from .consistency import consistent_acceleration, consistent_ydd
from .effort import effort_warning
from .plan import plan_at
from .records import Change, NoRepair, Repair
from .snap import snap_plans
from .windows import FRACTIONS, blend_width

__all__ = [
    "KEEPS",
    "Change",
    "NoRepair",
    "Repair",
    "bump",
    "consistent_acceleration",
    "consistent_ydd",
    "passes",
    "repair",
    "smoothstep",
    "strict_audit",
]

KEEPS = ("path", "timing")
JUMP_RULES = ("RPR203", "RPR204")  # a velocity or acceleration jump at a knot
STRICT = AuditOptions(strict=True, peak=True)  # every candidate: strict, its peak shown


def repair(
    task: Task,
    *,
    keep: str | None = None,
    window: fmpq | None = None,
    slope: fmpq | None = None,
    clearance: fmpq | None = None,
    blend: bool = True,
    snap: bool = True,
) -> Repair:
    """The nearest passing motion: local bumps at each failing singular instant, each
    candidate window tried (``window``, or the largest that fits, then halves) and
    audited strictly; the first that passes is returned. ``keep`` = "path" (timing
    changes only) or "timing" (path changes only); ``slope`` the |dy/dx| to give a
    zero-slope crossing (default max(1/5, 2 min_slope)); ``clearance`` the lift of a
    touch [m] (default w ẋ(t_s) slope / 2, at least 1/100); ``blend``: first smooth the
    knots whose velocity or acceleration jump fails (``_smooth_knots``); ``snap``: move
    failing instants at irrational times to rational ones (``_snap_instants``). Raises
    ``NoRepair``. The repaired motion's efforts far above the original's are a warning
    (``Repair.warnings``, ``effort.effort_warning``). With ``task.uncertainty`` the
    acceleration set at a crossing is the box's middle (``middle``), a candidate passes
    as ``passes`` says (the nominal pole left to RPR205), and ``Repair.after.robust``
    holds the repaired motion's worst case at each instant (``docs/robust.md``)."""
    r = _repair(task, keep, window, slope, clearance, blend, snap)
    if not r.changed:
        return r
    windows = [(float(c.t), float(c.window)) for c in r.changes]
    warning = effort_warning(r.before, r.after, windows)
    return replace(r, warnings=(warning,)) if warning is not None else r


def _repair(
    task: Task,
    keep: str | None,
    window: fmpq | None,
    slope: fmpq | None,
    clearance: fmpq | None,
    blend: bool,
    snap: bool,
) -> Repair:
    """``repair``, but the warnings."""
    if keep not in (None, *KEEPS):
        raise ValueError(f"keep is 'path', 'timing' or None, not {keep!r}")
    before = strict_audit(task)
    if passes(before):
        return Repair(task, before, before)
    jumps = [f.t for f in before.findings if f.rule in JUMP_RULES and f.fails(True)]
    if jumps and blend:
        return _smooth_knots(task, before, jumps, keep, window, slope, clearance)
    failing = [s for s in before.singularities if blocking(before.findings_at(s), task)]
    if not failing:
        raise NoRepair(_no_local_repair(before, blocking(before.findings, task)))
    if before.on_singular_line:
        raise NoRepair("the path lies on the singular line y = 0: no local change helps")
    irrational = [s for s in failing if s.t_rational is None]
    if irrational and snap:
        return _snap_instants(task, before, irrational, keep, window, slope, clearance)
    target = slope if slope is not None else max(fmpq(1, 5), 2 * task.checks.min_slope)
    last = "no candidate window"
    # the candidates: each window (the largest that fits, then halves) and, where the
    # prismatic scheme can set ÿ(t_s) by the timing or by the path, the timing first
    routes = (True, False) if task.robot.actuation == PRISMATIC and keep is None else (True,)
    for fraction, timing in itertools.product(FRACTIONS, routes):
        plans = [
            plan_at(task, before, s, keep, window, fraction, target, clearance, timing)
            for s in failing
        ]
        new = apply(task, plans)
        if new is None:
            last = "the changed timing law is not monotone in x"
            continue
        after = strict_audit(new)
        if passes(after):
            return account(task, new, before, after, plans)
        left = blocking(after.findings, task)
        if _spread_only(left, after, failing):
            raise NoRepair(_window_only(left, task))
        last = "; ".join(f.message for f in left)[:400]
        if window is not None:
            break
    raise NoRepair(f"no candidate passes the strict check (last: {last})")


def _smooth_knots(
    task: Task,
    before: AuditResult,
    jumps: list[float | None],
    keep: str | None,
    window: fmpq | None,
    slope: fmpq | None,
    clearance: fmpq | None,
) -> Repair:
    """Blend the pieces at each knot whose jump fails (``jumps``: the findings' times),
    then repair what still fails at the singular instants (``repair`` on the blended
    motion); the account is against the task as given."""
    if keep == "timing" or (keep == "path" and task.path is None):
        raise NoRepair(
            "a knot's velocity or acceleration jump is smoothed by blending the pieces"
            " about it, which changes the timing (and, without a path, the path); allow"
            " it (drop --keep)"
        )
    knots = [i for i, p in enumerate(task.motion[:-1]) if float(p.end) in set(jumps)]
    last = ""
    for fraction in FRACTIONS:
        widths = [blend_width(task, before, i, window, fraction) for i in knots]
        new = blended(task, dict(zip(knots, widths, strict=True)))
        if new is None:
            last = "the blended timing law is not monotone in x"
            continue
        try:
            inner = repair(new, keep=keep, window=window, slope=slope, clearance=clearance,
                           blend=False)  # fmt: skip
        except NoRepair as why:
            last = str(why)
            if window is not None:
                break
            continue
        blends = tuple(
            f"knot t = {task.motion[i].end} s: the pieces blended over ±{w} s (C2)"
            for i, w in zip(knots, widths, strict=True)
        )
        path_changed = task.path is None or not inner.path_kept
        r = account(task, inner.task, before, inner.after, [], path_changed)
        return replace(r, changes=inner.changes, notes=blends + inner.notes)
    raise NoRepair(f"no blend of the knots passes the strict check (last: {last})")


def strict_audit(task: Task) -> AuditResult:
    """A candidate's audit: strict, with the certified peak (the account's and the effort
    warning's). With uncertainty, the robust analysis at the instants (RPR205) but not
    the worst-case peak over the box, which costs seconds and which no repair decision
    reads: the peak is the nominal model's, as in the full audit, from the task audited
    without the box."""
    if task.uncertainty is None:
        return audit(task, STRICT)
    nominal = audit(replace(task, uncertainty=None), STRICT)
    result = audit(task, STRICT, peak=False)
    return replace(result, torque_peak=nominal.torque_peak, peak_computed=nominal.peak_computed)


def passes(result: AuditResult) -> bool:
    """The repair's verdict on a strict audit (``STRICT``): no finding fails it but,
    with declared uncertainty, RPR201 (``blocking``)."""
    return not blocking(result.findings, result.task)


def blocking(findings: Iterable[Finding], task: Task) -> list[Finding]:
    """The findings that fail a repair's candidate: every one (strict) but, when the task
    declares uncertainty, the nominal model's pole at a singular instant (RPR201, and
    RPR202's "beyond any limit" there). That pole is then RPR205's to decide
    (``docs/robust.md``, *Repair*): a crossing aimed at the box's middle keeps a nominal
    residual of order ρ² when r is uncertain, and the window over the box, which holds
    the nominal model's, is what counts. RPR202 away from the instants still fails."""
    if task.uncertainty is None:
        return [f for f in findings if f.fails(True)]
    return [f for f in findings if f.fails(True) and not _nominal_pole(f)]


def _nominal_pole(f: Finding) -> bool:
    """RPR201, or RPR202 made at a singular instant (its pole is beyond any limit)."""
    return f.rule == "RPR201" or (f.rule == "RPR202" and f.instant is not None)


CENTRED = fmpq(1, 10**5)  # |lo + hi| <= this (hi - lo): the residual's interval centred on 0


def _spread_only(left: list[Finding], after: AuditResult, failing: list[SingularInstant]) -> bool:
    """Whether what still fails is only RPR205 at the task's own failing instants, each
    with its residual aimed (the nominal model consistent, or the interval over the box
    centred on 0): then the window comes from the box's spread, which no acceleration at
    t_s removes. An RPR205 at an instant the candidate made, or at one whose residual is
    off centre, is the candidate's to fix (another window)."""
    if not left or any(f.rule != "RPR205" or f.instant is None for f in left):
        return False
    times = [s.t for s in failing]
    for f in left:
        assert f.instant is not None
        s, r = after.singularities[f.instant], after.robust[f.instant]
        if not any(abs(s.t - t) <= 1e-9 * max(1.0, abs(t)) for t in times):
            return False
        lo, hi = (fmpq(*v.as_integer_ratio()) for v in r.residual)
        if not (s.consistent or abs(lo + hi) <= CENTRED * (hi - lo)):
            return False
    return True


def _window_only(left: list[Finding], task: Task) -> str:
    """Why a crossing whose only failure is its saturation window is not repaired."""
    u = task.uncertainty
    error = u is not None and u.acceleration != 0
    masses = u is not None and any(v != 0 for t in u.links.values() for v in t)
    part = " (the tracking error's part at least)" if error and masses else ""
    advice = [
        *(["track the acceleration more closely"] if error else []),
        *(["identify the masses better"] if masses else []),
        "cross AB faster (the window shrinks as 1/|ẏ|)",
    ]
    return (
        "with the consistency aimed at the box's middle, what still fails is the saturation"
        f" window (RPR205: {'; '.join(f.message for f in left)[:400]}); it comes from the"
        f" residual's spread over the declared box{part}, which no acceleration at t_s"
        f" removes: {', '.join(advice[:-1])}{', or ' if len(advice) > 1 else ''}{advice[-1]}"
    )


def _no_local_repair(before: AuditResult, other: Iterable[object]) -> str:
    rules = sorted({getattr(f, "rule", "") for f in other})
    peak = before.torque_peak
    where = ""
    if peak is not None:
        t1, t2 = peak
        where = (
            f"; peak |T1| {t1.value:.6g} N m at t = {t1.t:.4g} s,"
            f" |T2| {t2.value:.6g} N m at t = {t2.t:.4g} s"
        )
    return (
        f"every singular instant passes; what fails ({', '.join(rules)}) is not at a"
        " singular instant, and rprpr repair changes the motion only locally around"
        " singular instants and its knots (a torque limit exceeded away from them needs a"
        f" slower or longer motion){where}"
    )


def _snap_instants(
    task: Task,
    before: AuditResult,
    instants: list[SingularInstant],
    keep: str | None,
    window: fmpq | None,
    slope: fmpq | None,
    clearance: fmpq | None,
) -> Repair:
    """Failing instants at irrational times moved to rational ones (``snap.snap_plans``),
    then repaired as rational ones (``repair``); the account is against the task as given."""
    plans = snap_plans(task, before, instants, keep, window)
    new = apply(task, plans)
    if new is None:
        raise NoRepair("moving the irrational singular instants to rational times makes x(t)"
                       " non-monotone")  # fmt: skip
    inner = repair(new, keep=keep, window=window, slope=slope, clearance=clearance, blend=False,
                   snap=False)  # fmt: skip
    path_changed = any(p.h != 0 for p in plans) or not inner.path_kept
    r = account(task, inner.task, before, inner.after, [], path_changed)
    moved = tuple(
        f"t ≈ {s.t:.12g} s (irrational) moved to t = {p.t} s" for s, p in zip(instants, plans,
                                                                            strict=True)
    )  # fmt: skip
    return replace(r, changes=inner.changes, notes=moved + inner.notes)

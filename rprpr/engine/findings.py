"""The findings of an audit: one function per rule of ``model.rules`` (pure).

Each function decides, from the exact singular analysis, whether its rule is broken and
says where; the key a finding points back to is its rule's (``Rule.key``). Every number in
a message goes through ``model.numbers``; the instants of a task are told apart together
(``numbers.labels``), so that two close instants never read alike.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from decimal import Decimal
from fractions import Fraction
from typing import TYPE_CHECKING

from flint import fmpq

from ..model.actuation import REVOLUTE, SCHEMES, Scheme
from ..model.numbers import apart, distinct, labels, number, outward, to_float, with_unit
from ..model.rules import Finding
from ..model.task import Task, Uncertainty
from .bounds.verdicts import LimitCheck, Peak, Window
from .exact.knots import Knot
from .exact.mechanism import of
from .exact.singular import KinematicSingularity, SingularAnalysis, SingularInstant

if TYPE_CHECKING:  # the robust machinery loads only for a task that declares uncertainty
    from .robust.windows import Robust

At = Callable[[float], str]  # an instant's time -> "t = ... s"


def exact_text(t: fmpq | Fraction) -> str:
    """An exact time as text: its decimal when finite and short ("2.5", "0.001"), else
    the fraction ("5/3")."""
    q = Fraction(int(t.p), int(t.q)) if isinstance(t, fmpq) else t
    d, twos_fives = q.denominator, 0
    for f in (2, 5):
        while d % f == 0:
            d, twos_fives = d // f, twos_fives + 1
    if d == 1 and twos_fives <= 24:
        text = format(Decimal(q.numerator) / Decimal(q.denominator), "f")
        return text.rstrip("0").rstrip(".") if "." in text else text
    return str(q)


def findings(
    task: Task,
    a: SingularAnalysis,
    peak: tuple[Peak, Peak] | None,
    limit: tuple[LimitCheck, LimitCheck] | None,
    knots: Sequence[Knot] = (),
    on_line: Sequence[tuple[fmpq, fmpq]] = (),
    robust: Sequence[Robust] = (),
) -> list[Finding]:
    """What the audit found wrong with ``task``, in report order: the path on the singular
    line, the inverse-kinematic singularities, each singular instant's broken principles
    and unbounded torques, then the torque limit (``limit``: the certified check of
    ``checks.torque_limit`` over [0, t_f], ``envelope.limit_violations``; ``peak``: the
    certified max |T1|, max |T2|, ``envelope.torque_peak``). A piecewise motion adds
    its ``knots`` (velocity and torque jumps) and ``on_line``, the pieces [start, end]
    that lie on y = 0 (then RPR104 names each). With ``task.uncertainty``, ``robust``
    holds each instant's robust analysis: RPR205 fails a window longer than the period,
    and RPR201 is a warning that says what the window is (``docs/robust.md``)."""
    at = instant_text(a)
    e = of(task.robot).words
    out = path_on_singular_line(a) if not on_line else pieces_on_singular_line(on_line)
    out += [f for k in knots for f in knot(k, e)]
    out += [kinematic(k, at) for k in a.kinematic]
    accepted = task.checks.unbounded_torque == "warn"
    u = task.uncertainty
    for i, s in enumerate(a.instants):
        pole = unbounded(s, at, accepted or u is not None, e)
        r = robust[i] if u is not None and i < len(robust) else None
        if u is not None and r is not None:
            pole = [replace(f, message=f.message + robust_note(r, u)) for f in pole]
            pole += window(s, r, task, at, e)
        out += [replace(f, instant=i) for f in slope(s, at) + velocity(s, at) + pole]
    out += torque_limit(task, a, peak, limit, at)
    return out


PRECISION = 1e-12  # [s] a window below this is the rounding of the input, not a saturation


def robust_note(r: Robust, u: Uncertainty) -> str:
    """What RPR201's warning adds with declared uncertainty: the window decides."""
    w = number(r.window, toward=1)
    lo, hi = outward(*r.residual)
    if r.window < PRECISION:
        return (
            f"; consistent to the input's precision: residual {lo} .. {hi} N,"
            f" window < {_one_digit_up(r.window)} s"
            if lo != hi
            else f"; consistent to the input's precision: residual {lo} N,"
            f" window < {_one_digit_up(r.window)} s"
        )
    return f"; with the declared uncertainty the saturation window is {w} s (RPR205 decides)"


def _one_digit_up(v: float) -> str:
    """``v`` rounded up to one significant digit: 7.3e-16 -> 8e-16, 0 -> 1e-300."""
    if v <= 0:
        return "1e-300"
    e = math.floor(math.log10(v))
    d = math.ceil(v / 10.0**e)
    if d == 10:
        d, e = 1, e + 1
    return f"{d}e{e:+03d}" if e < -4 or e > 4 else number(d * 10.0**e)


def box_text(u: Uncertainty) -> str:
    """The declared box in words: "every mass, inertia and r within ±5 % and tracking
    error ≤ 0.01 m/s²"."""
    parts = []
    rel = {v for t in u.links.values() for v in t}
    if rel == {fmpq(0)}:
        parts.append("the nominal masses")
    elif len(rel) == 1:
        parts.append(f"every mass, inertia and r within ±{number(to_float(rel.pop()) * 100)} %")
    else:
        parts.append("every link parameter within its declared half-width")
    if u.acceleration != 0:
        parts.append(f"tracking error ≤ {number(to_float(u.acceleration))} m/s²")
    return " and ".join(parts)


def window(s: SingularInstant, r: Robust, task: Task, at: At, e: Scheme) -> list[Finding]:
    """RPR205: the proven saturation window around ``s`` exceeds ``uncertainty.period``."""
    u = task.uncertainty
    limit = task.checks.torque_limit
    if u is None or limit is None or r.window <= float(u.period) or r.joint is None:
        return []
    j = r.joint
    span = ""
    if r.span is not None:
        t0, t1 = outward(*r.span)
        span = f" (t = {t0} .. {t1} s)"
    message = (
        f"for {box_text(u)}, |{e.letter}{j}| > {number(to_float(limit[j - 1]))} {e.unit}"
        f" for at most {with_unit(r.window, 's', toward=1)} around {at(s.t)}{span}: longer than the"
        f" {with_unit(float(u.period), 's')} period"
    )
    return [Finding("RPR205", message, s.t)]


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


def pieces_on_singular_line(spans: Sequence[tuple[fmpq, fmpq]]) -> list[Finding]:
    """RPR104 for a piecewise motion: y ≡ 0 on the piece [start, end] (one finding each)."""
    out = []
    for start, end in spans:
        message = (
            f"the path lies on the singular line y = 0 for t = {exact_text(start)} .."
            f" {exact_text(end)} s (δ ≡ 0): every instant of that piece is a Type II"
            " singularity"
        )
        out.append(Finding("RPR104", message, to_float(start)))
    return out


def knot(k: Knot, e: Scheme = SCHEMES[REVOLUTE]) -> list[Finding]:
    """RPR203 where the velocity jumps at the knot ``k``, RPR204 where only the
    acceleration does (with the jumps of T1, T2 when both sides' torques are defined;
    F1, F2 [N] under the prismatic scheme ``e``)."""
    if k.velocity_jump is None and k.acceleration_jump is None:
        return []  # a smooth knot (the words below are made only for a finding)
    row = f", row {k.line} of {k.file}" if k.file and k.line else ""
    pieces = f"knot between pieces {k.before + 1} and {k.before + 2}{row}"
    at = f"t = {exact_text(k.t_exact)} s ({pieces})"
    line = k.line if k.line and not k.file else None
    if k.velocity_jump is not None:
        dx, dy = (number(v) for v in k.velocity_jump)
        message = (
            f"{at}: the end-point velocity jumps by (Δẋ, Δẏ) = ({dx}, {dy}) m/s"
            f" (a C0 knot): the {e.noun} are impulsive there"
        )
        return [Finding("RPR203", message, k.t, line=line)]
    if k.acceleration_jump is None:
        return []
    ax, ay = (number(v) for v in k.acceleration_jump)
    jump = k.torque_jump
    torques = (
        f": {e.letter}1 jumps by {number(jump[0])} {e.unit},"
        f" {e.letter}2 by {number(jump[1])} {e.unit}"
        if jump is not None
        else f" (the {e.noun} are undefined or unbounded on a side)"
    )
    message = f"{at}: the end-point acceleration jumps by (Δẍ, Δÿ) = ({ax}, {ay}) m/s²{torques}"
    return [Finding("RPR204", message, k.t, line=line)]


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


def unbounded(
    s: SingularInstant, at: At, accepted: bool = False, e: Scheme = SCHEMES[REVOLUTE]
) -> list[Finding]:
    """RPR201: the torques (forces, prismatic ``e``) have a pole at ``s``, and why: the
    consistency condition (eq. 34; the legs' moment balance) fails (with its residual),
    or it holds but only k of the m boundedness conditions do. ``accepted``
    (``checks.unbounded_torque: warn``): the finding is downgraded to a warning."""
    if s.torque_bounded:
        return []
    why = (
        f"consistent ({e.cited}), but only {s.conditions_met} of {s.conditions_required}"
        " boundedness conditions hold"
        if s.consistent
        else f"inconsistent: {e.condition} residual {s.number('consistency_residual')} N ≠ 0"
    )
    message = f"{_where(s, at)}: {e.noun} unbounded (pole of order {s.pole_order}): {why}"
    return [Finding("RPR201", message, s.t, downgraded=accepted)]


def torque_limit(
    task: Task,
    a: SingularAnalysis,
    peak: tuple[Peak, Peak] | None,
    checks: tuple[LimitCheck, LimitCheck] | None,
    at: At,
) -> list[Finding]:
    """RPR202: |T_i(t)| beyond ``checks.torque_limit`` at some t in [0, t_f], decided for
    every t (certified, ``envelope.limit_violations``), never at samples only. Each
    unbounded instant is beyond any limit (one finding there, with the window around it
    in which each limit is exceeded); each other interval above a limit is named with
    its crossings; a limit that the certified bounds can neither prove kept nor broken
    (the peak touches it) fails too: a gate passes only what is proven."""
    if task.checks.torque_limit is None or checks is None:
        return []
    e = of(task.robot).words
    out = []
    for i, s in enumerate(a.instants):
        if s.torque_bounded:
            continue
        windows = [_around(s, c, j, at, e) for j, c in enumerate(checks)]
        beyond = "; ".join(w for w in windows if w)
        message = (
            f"{at(s.t)}: the {e.noun} are unbounded (pole of order {s.pole_order}):"
            f" beyond any limit{': ' + beyond if beyond else ''}"
        )
        out.append(Finding("RPR202", message, s.t, instant=i))
    for j, c in enumerate(checks):
        limit = number(c.limit)
        above = [w for w in c.windows if not w.pole]
        if above:
            top = peak[j] if peak is not None and math.isfinite(peak[j].value) else None
            out.append(Finding("RPR202", _exceeded(j, c.limit, top, above, e)))
        elif c.passed is None:
            message = (
                f"|{e.letter}{j + 1}| cannot be proven within the limit {limit} {e.unit}:"
                " its maximum"
                " touches the limit (within the certified bounds)"
            )
            out.append(Finding("RPR202", message))
    return out


def _span(w: Window) -> tuple[float, float]:
    """A window's extent: from the first certified crossing to the last."""
    return w.start_lo, w.end_hi


def _exceeded(j: int, limit: float, peak: Peak | None, windows: list[Window], e: Scheme) -> str:
    """|Tj| above ``limit`` in ``windows`` (each bracketed by its certified crossings),
    with the peak it reaches (told apart from the limit)."""
    ends = distinct([v for w in windows for v in _span(w)])
    spans = [f"{ends[2 * k]} .. {ends[2 * k + 1]}" for k in range(len(windows))]
    shown = ", ".join(spans[:3]) + (f" and {len(spans) - 3} more" if len(spans) > 3 else "")
    if peak is None:
        head = f"|{e.letter}{j + 1}| exceeds the limit {number(limit)} {e.unit}"
    else:
        reached, allowed = apart(peak.value, limit)
        head = (
            f"|{e.letter}{j + 1}| reaches {reached} {e.unit} at t = {number(peak.t)} s,"
            f" beyond the limit {allowed} {e.unit}"
        )
    return f"{head}: above it from t = {ends[0]} s (t = {shown} s)"


def _around(s: SingularInstant, check: LimitCheck, j: int, at: At, e: Scheme) -> str:
    """The window around the unbounded instant ``s`` in which |Tj| exceeds its limit, in
    words: ``|T1| > 300 N m for 10.8 ms around t = 2 s (t = 1.99689 .. 2.00769 s)``."""
    for w in check.windows:
        if w.pole and w.start_lo <= s.t <= w.end_hi:
            start, end = _span(w)
            t0, t1 = distinct([start, end])
            return (
                f"|{e.letter}{j + 1}| > {number(check.limit)} {e.unit}"
                f" for {with_unit(end - start, 's')}"
                f" around {at(s.t)} (t = {t0} .. {t1} s)"
            )
    return ""

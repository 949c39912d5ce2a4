"""Where a change fits: the half-width of a window about an instant or a knot (inside its
piece, half-way to the other singular instants), rounded to a short rational."""

from __future__ import annotations

from flint import fmpq

from ..engine.audit import AuditResult
from ..model.task import Piece, Task
from .records import NoRepair

FRACTIONS = tuple(fmpq(1, 2**k) for k in range(8))  # of the largest window, tried in turn


_DENOMINATORS = (1, 2, 4, 5, 8, 10, 16, 20, 40, 80, 160, 320, 640, 1280)


def short(value: fmpq, up: bool = False) -> fmpq:
    """A short rational (a denominator of a power of two times 1, 5 or 10) near
    ``value`` >= 0: at most it and at least 3/4 of it, or (``up``) at least it and at
    most 5/4 of it; ``value`` itself when none is found."""
    for den in _DENOMINATORS:
        n = -((-value.p * den) // value.q) if up else (value.p * den) // value.q
        r = fmpq(int(n), den)
        if (r <= value * fmpq(5, 4)) if up else (r > 0 and r >= value * fmpq(3, 4)):
            return r
    return value


def piece_at(task: Task, t: fmpq) -> Piece:
    for p in task.motion:
        if p.start < t < p.end:
            return p
    raise NoRepair(f"the singular instant t = {t} s is at a knot of the motion: not repaired")


def window_about(
    task: Task, before: AuditResult, t: fmpq, window: fmpq | None, fraction: fmpq
) -> tuple[Piece, fmpq]:
    """The piece holding the singular instant t and the half-width of the window about
    it: ``window``, or the largest that fits (``neighbours``) times ``fraction``, at most
    t_f/5 (``NoRepair`` when ``window`` does not fit)."""
    piece = piece_at(task, t)
    gap = neighbours(task, before, t)
    w = window if window is not None else short(min(gap * fraction, task.duration / 5))
    if w > gap:
        raise NoRepair(
            f"the window ±{w} s about t = {t} s reaches past a knot, an end of the motion"
            f" or another singular instant's window (at most ±{gap} s fits)"
        )
    return piece, w


def neighbours(task: Task, before: AuditResult, t: fmpq) -> fmpq:
    """The largest half-width that keeps the window inside the piece holding t (so off
    every knot, 0 and t_f) and clear of the other singular instants' windows."""
    p = piece_at(task, t)
    return half_way(before, t, min(t - p.start, p.end - t))


def half_way(before: AuditResult, t: fmpq, gap: fmpq, skip: object = None) -> fmpq:
    """``gap``, or less: half-way from t to every singular instant but ``skip`` (and
    one at t itself), exactly to a rational instant, rounded down to an irrational one."""
    for s in before.singularities:
        q = s.t_rational
        d = abs(q - t) / 2 if q is not None else fmpq(int(abs(s.t - float(t)) * 512), 1024)
        if s is not skip and d > 0:
            gap = min(gap, d)
    return gap


def blend_width(task: Task, before: AuditResult, i: int, window: fmpq | None,
                 fraction: fmpq) -> fmpq:  # fmt: skip
    """The half-width of the blend at the knot after piece i: ``window``, or the largest
    that keeps to a quarter of each neighbouring piece and half-way to any singular
    instant, times ``fraction``."""
    left, right = task.motion[i], task.motion[i + 1]
    t = left.end
    gap = half_way(before, t, min(left.end - left.start, right.end - right.start) / 4)
    w = window if window is not None else short(min(gap * fraction, task.duration / 5))
    if w > gap:
        raise NoRepair(
            f"the blend ±{w} s about the knot t = {t} s reaches past a quarter of a"
            f" neighbouring piece or half-way to a singular instant (at most ±{gap} s fits)"
        )
    return w

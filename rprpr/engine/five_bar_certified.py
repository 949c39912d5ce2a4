"""The certified torque verdicts of a 5R motion of one piece: the grid-free peak of |T1|,
|T2| over [0, t_f] and the check of ``checks.torque_limit`` with its windows (pure).

Both are a branch and bound on boxes of time [lo, hi] with exact rational ends, over
the enclosures of ``certified.five_bar`` (the Taylor form about each box's midpoint away
from Type II instants, the Taylor form about t_s near one: 0/0 divided out at a bounded
instant, the pole's lower bound at an unbounded one). The records are the RPRPR's
(``bounds.verdicts``: ``Peak``, ``LimitCheck``, ``Window``) with its tolerances:

* **peak**: a box is cut while its upper bound of |T_i| exceeds the best certified value
  by more than PEAK_REL (relative) or PEAK_ABS; the lower bound is a certified value at
  a double time (box midpoints, the ends, the limits at bounded instants); the peak is
  infinite at the first instant with a pole (no search), as for the RPRPR.
* **limit**: a box is below (|T_i| <= L_i proven), above (|T_i| > L_i proven over all of
  it, t_s excluded at a pole) or open; open boxes are cut until they are within
  CROSSING_REL t_f; the runs of boxes not below that hold one above (or a pole) are the
  windows, their open ends the brackets of the crossings.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from itertools import pairwise
from typing import Any

from flint import arb, ctx, fmpq

from ..model.numbers import to_float
from .bounds.boxes import last_float
from .bounds.search import PEAK_ABS, PEAK_REL
from .bounds.verdicts import CROSSING_REL, LimitCheck, Peak, Window
from .certified.five_bar import PREC, FiveBarMotion, abs_bounds
from .exact.five_bar_instants import FiveBarInstant

START_BOXES = 32  # the first partition of [0, t_f]
MAX_ROUNDS = 80  # bisection passes, at most
MAX_LIVE = 4096  # boxes kept alive, at most (beyond: the bracket stays uncertified)

Box = tuple[fmpq, fmpq]


def partition(duration: fmpq, n: int = START_BOXES) -> list[Box]:
    """[0, t_f] cut into n equal boxes with exact ends."""
    ends = [duration * fmpq(j, n) for j in range(n + 1)]
    return list(pairwise(ends))


def halves(b: Box) -> list[Box]:
    mid = (b[0] + b[1]) / 2
    return [(b[0], mid), (mid, b[1])]


def up(q: fmpq) -> float:
    """The smallest double >= q."""
    f = to_float(q)
    return math.nextafter(f, math.inf) if fmpq(*f.as_integer_ratio()) < q else f


def value_at(fm: FiveBarMotion, t: float) -> tuple[float, float]:
    """Certified lower bounds of |T1|, |T2| at the double t (0 where not decided)."""
    T = fm.point(fmpq(*t.as_integer_ratio()))
    return abs_bounds(T[0])[0], abs_bounds(T[1])[0]


def _inside(lo: fmpq, hi: fmpq) -> float:
    """A double in [lo, hi], near its middle."""
    t = to_float((lo + hi) / 2)
    q = fmpq(*t.as_integer_ratio())
    return t if lo <= q <= hi else to_float(lo)


def torque_peak(
    fm: FiveBarMotion, rel: float = PEAK_REL, span: Box | None = None
) -> tuple[Peak, Peak]:
    """max |T1| and max |T2| over [0, t_f], or over ``span`` (exact ends within it),
    certified (module docstring)."""
    lo, hi = span if span is not None else (fmpq(0), fm.duration)
    poles = [s for s in fm.instants if not s.bounded and _holds(s, lo, hi)]
    if poles:
        t = poles[0].t
        return Peak(math.inf, t, math.inf, True), Peak(math.inf, t, math.inf, True)
    with ctx.workprec(PREC):
        best, best_t = [0.0, 0.0], [0.0, 0.0]
        first, last = up(lo), last_float(hi)
        candidates = [(first, value_at(fm, first)), (last, value_at(fm, last))]
        for s in fm.instants:  # the limits at bounded instants are values of T
            if (
                s.t_exact is not None
                and lo <= s.t_exact <= hi
                and fmpq(*s.t.as_integer_ratio()) == s.t_exact
            ):
                T = fm.limit_at(s)
                candidates.append((s.t, (abs_bounds(T[0])[0], abs_bounds(T[1])[0])))
        for t, v in candidates:
            _raise(best, best_t, v, t)
        boxes = partition(hi - lo)
        return _maximise(fm, [(a + lo, b + lo) for a, b in boxes], best, best_t, rel)


def _raise(best: list[float], best_t: list[float], v: Sequence[float], t: float) -> None:
    for i in (0, 1):
        if v[i] > best[i]:
            best[i], best_t[i] = v[i], t


def _maximise(
    fm: FiveBarMotion, live: list[Box], best: list[float], best_t: list[float], rel: float
) -> tuple[Peak, Peak]:
    """The peak's branch and bound from the boxes ``live``: ``dropped`` the largest upper
    bound of a box set aside, ``alive`` of the boxes still kept when a cap stops it."""
    dropped, alive = [0.0, 0.0], [0.0, 0.0]
    for _ in range(MAX_ROUNDS):
        kept = []
        for lo, hi in live:
            T = fm.box(lo, hi)
            u = (abs_bounds(T[0])[1], abs_bounds(T[1])[1])
            t = _inside(lo, hi)
            _raise(best, best_t, value_at(fm, t), t)
            kept.append(((lo, hi), u))
        alive = [0.0, 0.0]
        live = []
        for b, u in kept:
            keep = [u[i] > best[i] * (1 + rel) + PEAK_ABS for i in (0, 1)]
            for i in (0, 1):
                if keep[i]:
                    alive[i] = max(alive[i], u[i])
                else:
                    dropped[i] = max(dropped[i], u[i])
            if any(keep):
                live += halves(b)
        if not live or len(live) > MAX_LIVE:
            break
    top = [max(dropped[i], best[i], alive[i]) for i in (0, 1)]
    return (
        Peak(best[0], best_t[0], top[0], top[0] - best[0] <= rel * best[0] + PEAK_ABS),
        Peak(best[1], best_t[1], top[1], top[1] - best[1] <= rel * best[1] + PEAK_ABS),
    )


# -- the limit check ----------------------------------------------------------------------
BELOW, OPEN, ABOVE = -1, 0, 1


def _holds(s: FiveBarInstant, lo: fmpq, hi: fmpq) -> bool:
    """Whether the box [lo, hi] may hold the instant ``s``."""
    if s.t_exact is not None:
        return lo <= s.t_exact <= hi
    return not (s.t_ball < arb(lo) or s.t_ball > arb(hi))


def _states(fm: FiveBarMotion, b: Box, L: Sequence[float]) -> tuple[int, int]:
    """The state of each torque over the box ``b`` against the limits ``L``."""
    lo, hi = b
    poles = [s for s in fm.instants if not s.bounded and _holds(s, lo, hi)]
    if poles:
        low = fm.pole_lower(poles[0], lo, hi)
        return ABOVE if low[0] > L[0] else OPEN, ABOVE if low[1] > L[1] else OPEN
    T = fm.box(lo, hi)
    out = []
    for i in (0, 1):
        a, z = abs_bounds(T[i])
        out.append(BELOW if z <= L[i] else ABOVE if a > L[i] else OPEN)
    return out[0], out[1]


def limit_check(
    fm: FiveBarMotion, limit: tuple[float, float], peak: tuple[Peak, Peak] | None = None
) -> tuple[LimitCheck, LimitCheck]:
    """Whether |T_i(t)| <= limit_i for every t in [0, t_f], per torque, with the windows
    where it is exceeded (module docstring); a certified peak below a limit decides it."""
    res = CROSSING_REL * float(fm.duration)
    done: list[list[tuple[Box, int]]] = [[], []]
    active = [True, True]
    if peak is not None:
        for i in (0, 1):
            if peak[i].certified and peak[i].upper <= limit[i]:
                active[i] = False
    with ctx.workprec(PREC):
        live = [(b, list(active)) for b in partition(fm.duration)]
        for _ in range(MAX_ROUNDS * 4):
            if not live:
                break
            nxt = []
            for b, act in live:
                st = _states(fm, b, limit)
                wide = to_float(b[1] - b[0]) > res
                cut = [act[i] and st[i] == OPEN and wide for i in (0, 1)]
                for i in (0, 1):
                    if act[i] and not cut[i]:
                        done[i].append((b, st[i]))
                if any(cut):
                    nxt += [(h, cut) for h in halves(b)]
            if len(nxt) > MAX_LIVE:
                for b, act in nxt:
                    for i in (0, 1):
                        if act[i]:
                            done[i].append((b, OPEN))
                nxt = []
            live = nxt
        for b, act in live:  # the rounds ran out: the boxes left stay open
            for i in (0, 1):
                if act[i]:
                    done[i].append((b, OPEN))
    poles = [s for s in fm.instants if not s.bounded]
    return (
        _verdict(limit[0], res, done[0], poles, not active[0], fm.duration),
        _verdict(limit[1], res, done[1], poles, not active[1], fm.duration),
    )


def _verdict(
    limit: float, res: float, boxes: list[tuple[Box, int]], poles: Sequence[FiveBarInstant],
    kept: bool, duration: fmpq,
) -> LimitCheck:  # fmt: skip
    """One torque's check from its recorded boxes (``kept``: decided by the peak)."""
    if kept:
        return LimitCheck(limit, True, (), res)
    boxes = sorted(boxes, key=lambda bs: bs[0][0])
    windows = _windows(boxes, poles)
    states = [s for _, s in boxes]
    above = ABOVE in states or bool(poles)
    passed: bool | None = False if above else (True if all(s == BELOW for s in states) else None)
    return LimitCheck(limit, passed, tuple(windows), res)


def _windows(boxes: list[tuple[Box, int]], poles: Sequence[FiveBarInstant]) -> list[Window]:
    """Maximal runs of boxes not below the limit that hold a box above it (or a pole):
    the run's open boxes at its ends bracket the crossings."""
    out = []
    j = 0
    while j < len(boxes):
        if boxes[j][1] == BELOW:
            j += 1
            continue
        k = j
        while k + 1 < len(boxes) and boxes[k + 1][1] != BELOW:
            k += 1
        run = boxes[j : k + 1]
        inner = [n for n, (_, s) in enumerate(run) if s == ABOVE]
        lo, hi = run[0][0][0], run[-1][0][1]
        pole = any(_in_run(s, lo, hi) for s in poles)
        if inner or pole:
            first, last = (inner[0], inner[-1]) if inner else (0, len(run) - 1)
            start_hi = run[first][0][0] if inner else run[0][0][1]
            end_lo = run[last][0][1] if inner else run[-1][0][0]
            out.append(Window(last_float(lo), up(start_hi), last_float(end_lo), up(hi), pole))
        j = k + 1
    return out


def _in_run(s: FiveBarInstant, lo: fmpq, hi: fmpq) -> bool:
    if s.t_exact is not None:
        return lo <= s.t_exact <= hi
    return bool(arb(lo) <= s.t_ball.mid() <= arb(hi))


# -- RPR202 -------------------------------------------------------------------------------
class _Instant:
    """A 5R instant as RPR202's text reads an RPRPR one (time, bounded, pole order)."""

    def __init__(self, s: FiveBarInstant) -> None:
        self.t = s.t
        self.torque_bounded = s.bounded
        self.pole_order = s.order - s.conditions_met


class _Instants:
    def __init__(self, instants: Sequence[FiveBarInstant]) -> None:
        self.instants = [_Instant(s) for s in instants]


def limit_findings(
    task: Any, instants: Sequence[FiveBarInstant], peak: tuple[Peak, Peak] | None,
    checks: tuple[LimitCheck, LimitCheck] | None, at: Callable[[float], str],
) -> list[Any]:  # fmt: skip
    """RPR202 for a 5R task, in the RPRPR's words (``findings.torque_limit``)."""
    from .findings import torque_limit

    return torque_limit(task, _Instants(instants), peak, checks, at)  # type: ignore[arg-type]

"""The worst-case effort peak over the box of ``docs/robust.md``, between the singular
instants: for each effort, a certified [lower, upper] of sup |E_i(t)| over every link
parameter in the box, every tracking error within the bound, and every time t of the
motion outside the proven saturation windows (``Robust.span``; within them some |E_i|
may exceed the limit, and near a possible pole it is unbounded).

Branch and bound on time intervals in each piece's local time, every interval at once
(``balls.Ball`` arrays). An interval's upper bound is the mean-value form's: every
coefficient of the efforts at t lies in Y(m) + (t - m) Y'(I) (m the interval's middle,
Y'(I) the derivative's enclosure over it, by first-order jets of the closed-form
regressor, ``regressor.regressor_balls``, over the motion's second-order Taylor form on
the interval), and the largest effort over the box is convex in t - m there, so its
bound at the two ends t - m = ±w/2 (``regressor.form_bounds``) bounds it; its excess is
about K w². A lower bound of the peak is that bound's lower counterpart at a point.

Guided by the same largest effort in doubles (``_Guess``, never a bound itself): the
first partition, uniform and cut finer towards each window's edge (2^-k of the span:
beside the edge the worst case is about the limit and steep), is read at its ends to
guess each effort's summit, refined on ``ZOOM`` finer grids; the summit is the first
lower bound's point (with the stretches' ends: a window's edge is where the peak sits
when the window is the limit's) and a ladder of intervals about it is added (``NEAR``).
Intervals whose upper bound cannot beat the best lower bound are dropped (their bound
kept for the final upper); the others are cut where their bounds can meet the goal
(``_Guess.cut``: K from each interval's own excess, the pieces equidistributed over the
room the doubles leave under the goal), until the two meet within ``REL`` (the nominal
peak's ``PEAK_REL``), or ``ROUNDS`` rounds, or ``CAP`` live intervals (an uncertified
bracket, still proven). Most motions take one round, a sharp summit two or three.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

import numpy as np
from flint import fmpq_poly

from ...model.numbers import to_float
from ...model.task import Task
from ..bounds.search import PEAK_ABS, PEAK_REL
from ..certified.balls import Ball, horner, poly_balls, quiet
from ..certified.jets import Jet
from ..certified.motion import dyadic_middle
from ..exact.mechanism import of
from .regressor import closed_form, form_bounds, form_worst, regressor_balls, regressor_floats
from .unbounded import poles
from .windows import Box, Robust, float_box
from .worst import bands_of, regressor_jet

REL = PEAK_REL  # the peak's bounds meet within this relative width (the nominal peak's) ...
ABS = PEAK_ABS  # ... or this absolute one, whichever is larger (a peak near 0)
ROUNDS = 48  # refining rounds at most
START = 64  # intervals per piece at the start
LADDER = 24  # ... and from a window's edge, intervals of 2^-k of the span, k = 1..LADDER
RUNGS = 12  # ... and two per halving for the first RUNGS halvings
ZOOM = 2  # finer grids about the largest effort in doubles (``_Guess.summits``) ...
ZGRID = 64  # ... each of 2 ZGRID + 1 points over the last one's two cells
NEAR = 12  # a ladder about each summit in the first round, 2^-j of its interval
CELLS = 8  # cells of a live interval read in doubles (``_Guess.cut``)
ROOM = 0.25  # a cut interval's bound aimed at this share of the room under the goal
WIDE = 384  # intervals per refining round, about, at most (``_Guess.cut``)
BUDGET = 64  # intervals per refining round, about (live intervals times their fan: a
# round's ball operations cost their calls more than their length, so a round of few
# narrow intervals where the bound is decided costs little more than its calls)
MAX_FAN = 512  # a live interval is cut into at most this many
CAP = 1 << 15  # live intervals kept at most
MEAN_CAP = 1 << 12  # the mean-value form while the intervals are at most this many, else
# the interval evaluation (past it, a bound that does not narrow costs less)


def worst_peak(
    task: Task, parts: Sequence[Any], robust: Sequence[Robust]
) -> tuple[tuple[float, float], tuple[float, float]]:
    """((lower, upper) of sup |E1|, (lower, upper) of sup |E2|) over the box and the
    times outside the proven windows (``robust``: the audit's, one per singular
    instant); upper is +inf where it cannot be bounded (a possible pole without a proven
    window around it)."""
    u = task.uncertainty
    assert u is not None
    box = Box.of(task.robot, u)
    spans = [r.span for r in robust if r.span is not None]
    a, b, k = _domain(parts, spans)
    # lower bounds at the ends of the stretches between the windows (a window's edge is
    # where the peak sits when the window is the limit's), then at the guessed summits
    first = np.r_[True, (a[1:] != b[:-1]) | (k[1:] != k[:-1])][: len(a)]
    last = np.r_[first[1:], True][: len(a)]
    pts, at = _distinct(np.concatenate([a[first], b[last]]), np.concatenate([k[first], k[last]]))
    proven = {p.effort for p in poles(task, parts, box, spans)}
    if proven:  # E passes A or B: a worst case proven unbounded ends the search at once
        with quiet():
            low = _lows(task, parts, box, pts, at)
        return tuple(
            (math.inf, math.inf) if j in proven else (float(low[j]), math.inf) for j in (0, 1)
        )  # type: ignore[return-value]
    best = np.full(2, -np.inf)
    dropped = np.full(2, -np.inf)  # the largest upper bound of the intervals dropped
    top = np.full(2, np.inf)
    centred: dict[int, Any] = {}  # per piece, made when first needed (``_centred``)
    with quiet():
        guess = _Guess(task, parts, box, centred)
        if len(a):  # the largest effort's place, found in doubles: its lower bound first
            h, hk = guess.summits(a, b, k)
            pts, at = _distinct(np.concatenate([pts, h]), np.concatenate([at, hk]))
            ladder = guess.peaks + guess.ends
            if ladder:
                a, b, k = _about_summits(a, b, k, np.array([t for t, _ in ladder]),
                                         np.array([i for _, i in ladder]))  # fmt: skip
        for _ in range(ROUNDS):
            if not len(a):
                break
            form = centred if len(a) <= MEAN_CAP else None
            ups, lows = _bounds(task, parts, box, (a, b, k), (pts, at), form)
            best = np.maximum(best, lows)
            top = np.maximum(ups.max(axis=1), dropped)
            goal = best * (1 + REL) + ABS
            if np.all(top <= goal):
                break
            live = np.any(ups > goal[:, None], axis=0)
            dropped = np.maximum(dropped, ups[:, ~live].max(axis=1, initial=-np.inf))
            a, b, k, ups = a[live], b[live], k[live], ups[:, live]
            if len(a) > CAP:
                break
            a, b, k, pts, at = guess.cut(a, b, k, ups, best, goal)
    return (float(best[0]), float(max(top[0], best[0]))), (
        float(best[1]),
        float(max(top[1], best[1])),
    )


class _Guess:
    """The largest effort over the box in doubles (``regressor.regressor_floats``,
    ``form_worst``; not proven):
    where to look for the peak's lower bound, and how finely to cut an interval whose
    upper bound is still above the goal. Only guides the search; every bound it returns
    is the balls'."""

    def __init__(self, task: Task, parts: Sequence[Any], box: Box, centred: dict[int, Any]
                 ) -> None:  # fmt: skip
        self.task, self.parts, self.box, self.centred = task, parts, box, centred
        self.fbox = float_box(box)
        self.corners = box.corners()
        self.about: dict[int, Any] = {}
        self.peaks: list[tuple[float, int]] = []  # the summits found (``summits``)
        self.ends: list[tuple[float, int]] = []  # ... those at a stretch's end

    def at(self, h: np.ndarray, hk: np.ndarray) -> np.ndarray:
        """[effort, time]: the largest |E_j| over the box at the local times ``h`` (pieces
        ``hk``), in doubles (NaN read as +inf: beside a pole)."""
        out = np.full((2, len(h)), np.inf)
        for i in np.unique(hk):
            sel = hk == i
            coeffs, c = self._floats(int(i))
            w = h[sel] - c
            kin = [np.polynomial.polynomial.polyval(w, q) for q in coeffs]
            with np.errstate(all="ignore"):
                Y = regressor_floats(self.task.robot, kin)
                v = form_worst(Y, self.corners, self.fbox)
            out[:, sel] = np.where(np.isnan(v), np.inf, v)
        return out

    def _floats(self, i: int) -> tuple[list[np.ndarray], float]:
        """The piece's x, ẋ, ẍ, y, ẏ, ÿ about its ``_centred`` c, as doubles, and c."""
        got = self.about.get(i)
        if got is None:
            if i not in self.centred:
                self.centred[i] = _centred(self.parts[i].traj)
            coeffs, c = self.centred[i]
            polys = [np.array([float(b.mid) for b in coeffs[j]]) for j in (0, 1, 2, 6, 7, 8)]
            got = self.about[i] = (polys, c)
        return got

    def summits(self, a: np.ndarray, b: np.ndarray, k: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
        """Per effort, the local time (and piece) where the largest effort is largest
        over the intervals [a, b], to about ZGRID^-ZOOM of an interval's width: the
        largest at the intervals' ends, then ``ZOOM`` finer grids about it (within its
        two intervals); none where that is a stretch's end (already a lower bound's
        point: ``worst_peak``)."""
        left = {(int(kk), float(t)): float(s) for kk, s, t in zip(k, a, b, strict=True)}
        right = {(int(kk), float(s)): float(t) for kk, s, t in zip(k, a, b, strict=True)}
        ends = sorted(set(left) | set(right))
        hk = np.array([e[0] for e in ends], dtype=int)
        h = np.array([e[1] for e in ends])
        lo = np.array([left.get(e, e[1]) for e in ends])  # the intervals on each side
        hi = np.array([right.get(e, e[1]) for e in ends])
        v = self.at(h, hk)
        out = []  # per effort: its summit's time, piece, reach, effort, zoom step
        for j in (0, 1):
            finite = np.where(np.isfinite(v[j]), v[j], -np.inf)
            n = int(np.argmax(finite))
            if not np.isfinite(finite[n]):
                continue
            if not lo[n] < h[n] < hi[n]:  # a stretch's end: the ladder about it only
                self.ends.append((float(h[n]), int(hk[n])))
                continue
            step = max(h[n] - lo[n], hi[n] - h[n])
            out.append([h[n], int(hk[n]), lo[n], hi[n], j, step])
        grid = np.linspace(-1.0, 1.0, 2 * ZGRID + 1)
        for _ in range(ZOOM if out else 0):  # both efforts' grids in one evaluation
            gs = [np.clip(o[0] + o[5] * grid, o[2], o[3]) for o in out]
            w = self.at(np.concatenate(gs), np.repeat([o[1] for o in out], len(grid)))
            for n, (o, g_) in enumerate(zip(out, gs, strict=True)):
                wj = w[o[4], n * len(grid) : (n + 1) * len(grid)]
                o[0] = g_[int(np.argmax(np.where(np.isfinite(wj), wj, -np.inf)))]
                o[5] /= ZGRID
        self.peaks += [(float(o[0]), int(o[1])) for o in out]
        return np.array([o[0] for o in out], dtype=float), np.array([o[1] for o in out], dtype=int)

    def cut(self, a: np.ndarray, b: np.ndarray, k: np.ndarray, ups: np.ndarray,
            best: np.ndarray, goal: np.ndarray) -> tuple[np.ndarray, ...]:  # fmt: skip
        """The live intervals [a, b] (upper bounds ``ups``, [effort, interval]) cut where
        their bounds can meet the goal: the mean-value bound's excess over the largest
        effort shrinks as the square of the width (K w², K from the interval's own
        excess), so about a time where the largest effort leaves a room r under the goal
        a piece of width √(``ROOM`` r / K) is narrow enough. Read on a grid of ``CELLS``
        cells of each interval (the room there from the doubles at the cells' ends, no
        more than the least, ``goal - best``, in a cell holding a summit), the cuts
        equidistribute the pieces each cell needs; at least ``BUDGET`` / (live
        intervals) pieces an interval, at most ``MAX_FAN``, about ``WIDE`` in all. The
        new intervals, their pieces, the new cut points and theirs."""
        n = len(a)
        base = int(min(MAX_FAN, max(2, BUDGET // max(n, 1))))
        frac = np.arange(CELLS + 1) / CELLS
        g = a[:, None] + (b - a)[:, None] * frac  # [interval, cell end]
        g[:, 0], g[:, -1] = a, b
        v = self.at(g.ravel(), np.repeat(k, CELLS + 1)).reshape(2, n, CELLS + 1)
        high = v.max(axis=2)  # [effort, interval]
        cell = np.maximum(v[:, :, 1:], v[:, :, :-1])  # [effort, interval, cell]
        floor = (goal - best)[:, None, None]
        for h, hk in self.peaks:  # a summit's cell: the least room
            inside = (k == hk) & (a <= h) & (h <= b)
            m = np.clip(((h - a) / np.maximum(b - a, 1e-300) * CELLS).astype(int), 0, CELLS - 1)
            for r in np.nonzero(inside)[0]:
                cell[:, r, m[r]] = np.inf
        w = np.maximum(b - a, 0.0)
        with np.errstate(all="ignore"):
            K = np.maximum(ups - high, 0.0) / (w * w)  # [effort, interval]
            room = np.maximum(goal[:, None, None] - cell, floor)
            # pieces per cell: its width over the width allowed there, per effort
            per = (w / CELLS)[None, :, None] * np.sqrt(K[:, :, None] / (ROOM * room))
        live = ups > goal[:, None]
        per = np.where(live[:, :, None], per, 0.0).max(axis=0)  # [interval, cell]
        total = per.sum(axis=1)
        known = np.isfinite(total)
        f = np.where(known, np.ceil(total), base)
        f = np.clip(f, base, MAX_FAN)
        if f.sum() > WIDE:  # too many at once: each cut down in proportion
            f = np.maximum(2, np.floor(f * (WIDE / f.sum())))
        f = f.astype(int)
        out: list[list[np.ndarray]] = [[], [], []]
        for i in range(n):
            if known[i] and total[i] > 0:  # equidistributed: as many pieces in each cell
                cum = np.concatenate([[0.0], np.cumsum(per[i])])  # as it needs
                e = np.interp(np.arange(f[i] + 1) * (cum[-1] / f[i]), cum, g[i])
            else:
                e = a[i] + (b[i] - a[i]) * (np.arange(f[i] + 1) / f[i])
            e[0], e[-1] = a[i], b[i]
            e = np.maximum.accumulate(np.clip(e, a[i], b[i]))
            for o, x in zip(out, (e[:-1], e[1:], np.full(f[i], k[i])), strict=True):
                o.append(x)
        # the next lower bounds: per effort, the grid's point where the doubles are largest
        flat = np.where(np.isfinite(v), v, -np.inf).reshape(2, -1)
        top = np.unique(np.argmax(flat, axis=1))
        hh, hk2 = g.ravel()[top], np.repeat(k, CELLS + 1)[top]
        aa, bb, kk = (np.concatenate(o) for o in out)
        return aa, bb, kk.astype(int), hh, hk2.astype(int)


def _about_summits(a: np.ndarray, b: np.ndarray, k: np.ndarray, h: np.ndarray,
                   hk: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """The intervals [a, b] (pieces ``k``) cut at each summit ``h`` (pieces ``hk``) and
    at 2^-j of its interval's width on each side of it, j = 1..``NEAR``: about a summit
    the bounds need narrow intervals, and a ladder gives them in the first round."""
    cuts: dict[int, list[float]] = {}
    for t, kk in zip(h, hk, strict=True):
        inside = np.nonzero((k == kk) & (a <= t) & (t <= b))[0]
        if not len(inside):
            continue
        i = int(inside[0])
        w = b[i] - a[i]
        steps = w * 2.0 ** -np.arange(0, NEAR + 1)
        cuts.setdefault(i, []).extend([t, *(t - steps), *(t + steps)])
        for j in (i - 1, i + 1):  # the neighbours too: the ladder reaches into them
            if 0 <= j < len(a) and k[j] == kk:
                cuts.setdefault(j, []).extend([*(t - steps), *(t + steps)])
    if not cuts:
        return a, b, k
    out_a, out_b, out_k = [a], [b], [k]
    keep = np.ones(len(a), dtype=bool)
    for i, cs in cuts.items():
        g = np.unique(np.clip(np.array(cs), a[i], b[i]))
        g = np.unique(np.concatenate([[a[i]], g[(g > a[i]) & (g < b[i])], [b[i]]]))
        keep[i] = False
        out_a.append(g[:-1])
        out_b.append(g[1:])
        out_k.append(np.full(len(g) - 1, k[i]))
    out_a[0], out_b[0], out_k[0] = a[keep], b[keep], k[keep]
    aa, bb, kk2 = np.concatenate(out_a), np.concatenate(out_b), np.concatenate(out_k)
    order = np.lexsort((aa, kk2))
    return aa[order], bb[order], kk2[order].astype(int)


def _distinct(h: np.ndarray, k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The times ``h`` with their pieces ``k``, each (time, piece) once."""
    order = np.lexsort((h, k))
    h, k = h[order], k[order]
    keep = np.ones(len(h), dtype=bool)
    keep[1:] = (h[1:] != h[:-1]) | (k[1:] != k[:-1])
    return h[keep], k[keep]


def _lows(task: Task, parts: Sequence[Any], box: Box, h: np.ndarray, hk: np.ndarray
          ) -> np.ndarray:  # fmt: skip
    """Lower bounds of max |E_j| over the box at the local times ``h`` (pieces ``hk``),
    their largest per effort."""
    lows = np.full(2, -np.inf)
    for i in np.unique(hk):
        at = h[hk == i]
        kin = parts[int(i)].motion.end_point(Ball.hull(at, at))
        for j, (l_, h_) in enumerate(bands_of(_regressor(task, kin), box, True)):
            lows[j] = max(lows[j], np.max(np.maximum(h_, -l_), initial=-np.inf))
    return lows


def _domain(
    parts: Sequence[Any], spans: Sequence[tuple[float, float]]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The starting intervals [a, b] and their pieces: each piece cut in ``START``, less
    the spans; in the piece's local time (t - origin), each end rounded into its
    interval."""
    a: list[np.ndarray] = []
    b: list[np.ndarray] = []
    k: list[np.ndarray] = []
    for i, p in enumerate(parts):
        lo, hi, o = to_float(p.start), to_float(p.end), to_float(p.origin)
        cuts = [lo, hi]
        for s0, s1 in spans:
            cuts += [c for c in (s0, s1) if lo < c < hi]
        cuts.sort()
        for c0, c1 in itertools.pairwise(cuts):
            if any(s0 <= c0 and c1 <= s1 for s0, s1 in spans) or c1 <= c0:
                continue  # inside a window
            n = max(1, int(START * (c1 - c0) / max(hi - lo, 1e-300)))
            h0, h1 = _local(c0, o, up=True), _local(c1, o, up=False)
            if h1 < h0:
                continue
            grid = np.linspace(h0, h1, n + 1)
            steps = (h1 - h0) * 2.0 ** -np.unique(
                np.r_[np.arange(1, LADDER + 1), np.arange(1, 2 * RUNGS + 1) / 2]
            )
            if any(c0 == s1 for _, s1 in spans):  # a window's edge: the ladder from it
                grid = np.concatenate([grid, h0 + steps])
            if any(c1 == s0 for s0, _ in spans):
                grid = np.concatenate([grid, h1 - steps])
            grid = np.unique(np.clip(grid, h0, h1))
            if len(grid) == 1:  # a single double: the interval [h0, h0], as before
                grid = np.repeat(grid, 2)
            n = len(grid) - 1
            a.append(grid[:-1])
            b.append(grid[1:])
            k.append(np.full(n, i))
    if not a:
        return np.zeros(0), np.zeros(0), np.zeros(0, dtype=int)
    return np.concatenate(a), np.concatenate(b), np.concatenate(k)


def _local(t: float, o: float, up: bool) -> float:
    """A double h with o + h >= t (``up``) or <= t, exactly, next to t - o (``o``: the
    piece's origin, a double)."""
    h = t - o
    while (Fraction(o) + Fraction(h) < t) if up else (Fraction(o) + Fraction(h) > t):
        h = math.nextafter(h, math.inf if up else -math.inf)
    return h


def _bounds(
    task: Task,
    parts: Sequence[Any],
    box: Box,
    spans: tuple[np.ndarray, np.ndarray, np.ndarray],
    points: tuple[np.ndarray, np.ndarray],
    centred: dict[int, Any] | None,
) -> tuple[np.ndarray, np.ndarray]:
    """Upper bounds of max |E_j| over the box and the local intervals [a, b] (``spans``:
    a, b and their pieces), [effort, interval]; and lower bounds of it at the local
    times ``points`` (times, pieces), their largest per effort. One evaluation a piece."""
    a, b, k = spans
    h, hk = points
    ups = np.full((2, len(a)), np.inf)
    lows = np.full(2, -np.inf)
    for i in np.unique(np.concatenate([k, hk])):
        sel, at = np.nonzero(k == i)[0], h[hk == i]
        pad = 4 * np.spacing(np.maximum(np.abs(a[sel]), np.abs(b[sel])))  # the ends' rounding
        if centred is None:  # the points, then the efforts' enclosures over the intervals
            lo, hi = np.concatenate([at, a[sel] - pad]), np.concatenate([at, b[sel] + pad])
            kin = parts[int(i)].motion.end_point(Ball.hull(lo, hi))
            lower = np.arange(len(lo)) < len(at)
            for j, (l_, h_) in enumerate(bands_of(_regressor(task, kin), box, lower)):
                v = np.maximum(h_, -l_)
                ups[j, sel] = v[len(at) :]
                lows[j] = max(lows[j], np.max(v[: len(at)], initial=-np.inf))
            continue
        a0, b0 = a[sel] - pad, b[sel] + pad
        if int(i) not in centred:
            centred[int(i)] = _centred(parts[int(i)].traj)
        m = 0.5 * a0 + 0.5 * b0
        hw = np.nextafter(np.maximum(m - a0, b0 - m), np.inf)  # |t - m| <= hw on [a0, b0]
        q = len(m)
        # one run of ball operations: the values at the midpoints, over the intervals and
        # at the points, the derivatives over the intervals (the others' are not read)
        kin = _jets(centred[int(i)], m, hw, at)
        Y, Yd = _regressor(task, kin, jets=True)
        Ym = Ball._of(Y.mid[..., :q], Y.rad[..., :q])
        D = Ball._of(Yd.mid[..., q : 2 * q], Yd.rad[..., q : 2 * q])
        # the mean-value form over [a0, b0]: every coefficient at t lies in Ym + (t - m) D,
        # and the largest effort over the box is convex in t - m there: its ends bound it
        YP = Ball._of(Y.mid[..., 2 * q :], Y.rad[..., 2 * q :])  # at the points
        Yt = [Ym + D * Ball.exact(hw), Ym - D * Ball.exact(hw)]
        ends = form_bounds(_joined(Yt, axis=-1), box.links, box.corners(), True)
        ups[:, sel] = np.maximum(ends[:, :q], ends[:, q:])
        if len(at):  # lower bounds at the points
            v = form_bounds(YP, box.links, box.corners(), False)
            lows = np.maximum(lows, v.max(axis=1))
    return ups, lows


def _regressor(task: Task, kin: Sequence[Any], jets: bool = False) -> Any:
    """``regressor.regressor_balls`` where the robot's mechanism has the closed form, else
    ``worst.regressor_jet``'s evaluation of its own equations at every setting."""
    if closed_form(of(task.robot)):
        return regressor_balls(task.robot, kin, jets)
    if jets:
        return regressor_jet(task, kin)
    return regressor_jet(task, [Jet(k, k * 0.0) for k in kin])[0]


def _jets(about: tuple[list[list[Ball]], float], m: np.ndarray, hw: np.ndarray,
          at: np.ndarray) -> tuple[Jet, ...]:  # fmt: skip
    """x, ẋ, ẍ, y, ẏ, ÿ of a piece as jets (the value's and the derivative's enclosures)
    at the local times ``m``, over the boxes [m - hw, m + hw], at the local times ``at``,
    in that order. ``about``: ``_centred``'s. Over a box, the second-order Taylor form
    p(m + s) ∈ p(m) + p'(m) s + p''(box) [0, hw²/2] (|s| <= hw), from p^(5) over the box
    by Horner's rule down: an excess of the order of hw² (Horner's rule over a box
    widens by about hw times the partial sums' sizes, vast for a long motion)."""
    coeffs, c = about
    q = len(m)
    w = Ball.exact(np.concatenate([m, at])) - Ball.exact(c)
    top = [horner(coeffs[5], Ball.hull(m - hw, m + hw) - Ball.exact(c)),
           horner(coeffs[11], Ball.hull(m - hw, m + hw) - Ball.exact(c))]  # fmt: skip
    zero = Ball.exact(np.zeros(len(m) + len(at)))
    e = Ball(np.zeros(q), hw)
    h2 = Ball.exact(hw) * Ball.exact(hw) * 0.5
    e2 = Ball.hull(np.zeros(q), h2.upper())  # s²/2 for |s| <= hw
    jets = []
    for axis in (0, 1):
        P = [horner(coeffs[6 * axis + k], w) + zero for k in range(5)]  # at m, at
        Pm = [p[:q] for p in P]
        B: list[Ball] = [top[axis]] * 6  # B[5]: Horner's rule over the box
        B[4] = Pm[4] + B[5] * e
        for k in (3, 2, 1, 0):
            B[k] = Pm[k] + Pm[k + 1] * e + B[k + 2] * e2
        L = [_joined((Pm[k], B[k], P[k][q:])) for k in range(4)]
        jets += [Jet(L[0], L[1]), Jet(L[1], L[2]), Jet(L[2], L[3])]
    return tuple(jets)


def _centred(traj: Any) -> tuple[list[list[Ball]], float]:
    """The coefficients of x and y and of their first five derivatives, of the piece
    ``traj``, about a short dyadic c near its middle (shifted exactly, then rounded to
    balls), and c: about c the polynomials lose few digits over the piece."""
    c = dyadic_middle(to_float(traj.lead), to_float(traj.duration))
    out = []
    for p in (traj.x, traj.y):
        ps = [p]
        for _ in range(5):
            ps.append(ps[-1].derivative())
        out += [poly_balls(q(fmpq_poly([c, 1]))) for q in ps]
    return out, to_float(c)


def _joined(balls: Sequence[Ball], axis: int = 0) -> Ball:
    """Ball arrays end to end (along ``axis``)."""
    return Ball._of(np.concatenate([b.mid for b in balls], axis=axis),
                    np.concatenate([b.rad for b in balls], axis=axis))  # fmt: skip

"""The envelope of many plain pieces at once: one branch and bound over the boxes of all
of them (pure).

A piece is *plain* when its motion holds no singular instant, no instant at which E is
at A or B, and does not lie on y = 0: then its torques over a box are enclosed by the
direct forms of ``envelope`` alone (the mean-value form and plain interval evaluation,
no zone or Taylor form). Those forms are the same operations for every piece; only the
ball coefficients of x(t) and y(t) (or of the path) differ. Here every box carries the
index of its piece and the coefficients become arrays indexed by box (Horner's rule
works elementwise), so one pass of ball operations encloses every box of every piece:
the cost of a pass is its operations' calls, not its length.

The proofs are those of ``Envelope.bounds`` box by box (each box is evaluated with its
own piece's exact coefficients, rounded outward); only the pruning is shared: a box is
set aside when its upper bound of |T_i| is below the best certified value of any piece
(the peak), or its lower bound of |δ| above the least certified |δ| of any piece (the
closest approach). The answers are the same suprema and infima over all the pieces
that ``pieces.peaks`` and ``pieces.approach`` would make from one envelope per piece.
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np

from .balls import Ball, horner, quiet, round_up
from .certified import CertifiedMotion, per_robot
from .envelope import (
    MAX_LIVE,
    MAX_ROUNDS,
    PEAK_ABS,
    PEAK_REL,
    Approach,
    Jet,
    Peak,
    _Bounds,
    _boxes,
    _fan,
    _full,
    _last_float,
    _Polys,
    _split,
    _Stacked,
    min_abs_y,
)

START_PER_PIECE = 2  # the initial partition: boxes per piece (short pieces, smooth torques)


def plain(motion: CertifiedMotion) -> bool:
    """Whether the piece's torques need no form but the direct ones (module docstring)."""
    a = motion.analysis
    return not (a.instants or a.kinematic or a.on_singular_line or motion.kinematic)


def _gather(coeffs: list[list[Ball]]) -> tuple[np.ndarray, np.ndarray]:
    """Ball coefficients of many polynomials (low to high, one list per piece) as two
    arrays (degree + 1, pieces), padded with exact zeros."""
    n = max(len(c) for c in coeffs)
    mid, rad = np.zeros((n, len(coeffs))), np.zeros((n, len(coeffs)))
    for j, c in enumerate(coeffs):
        for k, b in enumerate(c):
            mid[k, j], rad[k, j] = float(b.mid), float(b.rad)
    return mid, rad


class Batch:
    """The direct torque and δ enclosures of many plain pieces (``plain``), one pass for
    all their boxes; the pieces share one robot and one form (a path, or y(t))."""

    def __init__(self, motions: list[CertifiedMotion], polys: list[_Polys]) -> None:
        self.motions = motions
        self.direct = polys[0].direct
        assert all(p.direct == self.direct for p in polys)
        self.x = [_gather([p.x[k] for p in polys]) for k in range(4)]
        self.q = [_gather([p.q[k] for p in polys]) for k in range(4)]
        cs = [Ball.of_rational(m.t_center if self.direct else m.center) for m in motions]
        self.center = Ball._of(np.array([float(c.mid) for c in cs]),
                               np.array([float(c.rad) for c in cs]))  # fmt: skip
        self.stacked = per_robot(motions[0].robot, _Stacked)
        self.durations = [m.traj.duration for m in motions]
        self.t_last = np.array([_last_float(d) for d in self.durations])

    # -- one pass ---------------------------------------------------------------------------
    def jets(self, box: Ball, idx: np.ndarray) -> tuple[Jet, Jet, Jet, Jet, Jet, Jet]:
        """``_Polys.jets`` over boxes of many pieces (box j of piece idx[j])."""

        def at(pm: tuple[np.ndarray, np.ndarray], x: Ball) -> Ball:
            mid, rad = pm[0][:, idx], pm[1][:, idx]
            return horner([Ball._of(mid[k], rad[k]) for k in range(len(mid))], x)

        xv = [at(c, box) for c in self.x]
        x, xd, xdd = Jet(xv[0], xv[1]), Jet(xv[1], xv[2]), Jet(xv[2], xv[3])
        c = Ball._of(self.center.mid[idx], self.center.rad[idx])
        if self.direct:
            yv = [at(q, box - c) for q in self.q]
            return x, xd, xdd, Jet(yv[0], yv[1]), Jet(yv[1], yv[2]), Jet(yv[2], yv[3])
        w = xv[0] - c
        qv = [at(q, w) for q in self.q]
        q1 = Jet(qv[1], qv[2] * xv[1])
        q2 = Jet(qv[2], qv[3] * xv[1])
        y = Jet(qv[0], qv[1] * xv[1])
        return x, xd, xdd, y, q1 * xd, q2 * xd * xd + q1 * xdd

    def _pass(self, t: Ball, idx: np.ndarray) -> tuple[Ball, Ball]:
        x, xd, xdd, y, yd, ydd = self.jets(t, idx)
        T, _ = self.stacked.torques(self.stacked.legs(x, xd, xdd, y, yd, ydd), y)
        return _full(T.v, len(idx)), _full(T.d, len(idx))

    def _values(self, t: np.ndarray, idx: np.ndarray) -> Ball:
        x, xd, xdd, y, yd, ydd = (J.v for J in self.jets(Ball.exact(t), idx))
        T, _ = self.stacked.torques(self.stacked.legs(x, xd, xdd, y, yd, ydd), y)
        return _full(T, len(idx))

    def bounds(self, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray) -> _Bounds:
        """``Envelope.bounds`` over boxes of many pieces (no instant: direct forms)."""
        n = len(lo)
        with quiet():
            box = Ball.hull(lo, hi)
            B, D = self._pass(box, idx)
            P = self._values(np.concatenate([lo, hi]), np.concatenate([idx, idx]))
            pa, pb = P[:, :n], P[:, n:]
            ua, ub = pa.upper_abs(), pb.upper_abs()
            la, lb = pa.lower_abs(), pb.lower_abs()
            last = self.t_last[idx]
            la = np.where(lo <= last, la, 0.0)
            lb = np.where(hi <= last, lb, 0.0)
            width = 2.0 * box.rad
            slope = D.upper_abs()
            mean_value = round_up((ua + ub + slope * width) * 0.5)
            up = np.minimum(B.upper_abs(), mean_value)
            mono = D.lower_abs() > 0
            mono_ok = mono & np.isfinite(ua) & np.isfinite(ub)
            up = np.where(mono_ok, np.minimum(up, np.maximum(ua, ub)), up)
            low = np.maximum(la, lb)
            low_t = np.where(la >= lb, lo, hi)
        up = np.where(np.isnan(up), np.inf, up)
        return _Bounds(lo, hi, low, low_t, up, np.zeros_like(up))

    @cached_property
    def _start(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The first partition: START_PER_PIECE boxes per piece, each box's piece."""
        parts = [_boxes(d, START_PER_PIECE) for d in self.durations]
        lo = np.concatenate([p[0] for p in parts])
        hi = np.concatenate([p[1] for p in parts])
        return lo, hi, np.repeat(np.arange(len(parts)), START_PER_PIECE)

    # -- the peak ---------------------------------------------------------------------------
    def torque_peak(self, rel: float = PEAK_REL) -> tuple[tuple[Peak, int], tuple[Peak, int]]:
        """max |T1| and max |T2| over all the pieces, each with the index of the piece
        where its value is reached (``t``: local time of that piece)."""
        lo, hi, idx = self._start
        cap = MAX_LIVE * len(self.motions)
        best, best_t = np.zeros(2), np.zeros(2)
        best_j = np.zeros(2, dtype=int)
        dropped = np.zeros(2)
        certified = False
        b = self.bounds(lo, hi, idx)
        for _ in range(MAX_ROUNDS):
            for i in (0, 1):
                j = int(np.argmax(b.low[i]))
                if b.low[i, j] > best[i]:
                    best[i], best_t[i], best_j[i] = b.low[i, j], b.low_t[i, j], idx[j]
            keep_i = b.up > (best * (1 + rel) + PEAK_ABS)[:, None]
            dropped = np.maximum(dropped, np.where(keep_i, 0.0, b.up).max(axis=1))
            keep = keep_i.any(axis=0)
            n = int(keep.sum())
            if not n:
                certified = True
                break
            if n > cap:
                break
            k = _fan(n)
            lo, hi = _split(b.lo[keep], b.hi[keep], k)
            idx = np.repeat(idx[keep], k)
            b = self.bounds(lo, hi, idx)
        out = []
        for i in (0, 1):
            up = max(best[i], dropped[i])
            if not certified:
                up = max(up, float(b.up[i].max(initial=0.0)))
            peak = Peak(float(best[i]), float(best_t[i]), float(up), certified)
            out.append((peak, int(best_j[i])))
        return out[0], out[1]

    # -- near misses ------------------------------------------------------------------------
    def closest_approach(self, rel: float = PEAK_REL) -> tuple[Approach, int, int]:
        """``Envelope.closest_approach`` over all the pieces: the Approach (``t_y`` local
        to the piece of the first index, ``t_delta`` to that of the second)."""
        ys = [min_abs_y(m.traj, d) for m, d in zip(self.motions, self.durations, strict=True)]
        jy = min(range(len(ys)), key=lambda j: ys[j][0])
        lo, hi, idx = self._start
        cap = MAX_LIVE * len(self.motions)
        best, best_t, best_j = math.inf, 0.0, 0
        floor = math.inf
        low = np.zeros(0)
        for _ in range(MAX_ROUNDS):
            low, up, ends, where = self._delta_bounds(lo, hi, idx)
            j = int(np.argmin(up))
            if up[j] < best:
                best, best_t, best_j = float(up[j]), float(ends[j]), int(where[j])
            keep = low < best * (1 - rel)
            floor = min(floor, float(low[~keep].min(initial=math.inf)))
            n = int(keep.sum())
            if not n:
                low = np.zeros(0)
                break
            if n > cap:
                break
            k = _fan(n)
            lo, hi = _split(lo[keep], hi[keep], k)
            idx = np.repeat(idx[keep], k)
        delta_lo = min(floor, best, float(low.min(initial=best)))
        a = Approach(ys[jy][0], ys[jy][1], delta_lo, best, best_t)
        return a, jy, best_j

    def _delta_bounds(
        self, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``Envelope._delta_bounds`` over boxes of many pieces, with the piece of each end."""
        n = len(lo)
        pts = np.concatenate([lo, hi])
        both = np.concatenate([idx, idx])
        with quiet():
            box = Ball.hull(lo, hi)
            x, xd, xdd, y, yd, ydd = self.jets(box, idx)
            lg = self.stacked.legs(x, xd, xdd, y, yd, ydd)
            delta = -(y * self.stacked.a1) / (lg.s[0] * lg.s[1])
            V, D = _full(delta.v, n, 0), _full(delta.d, n, 0)
            v = [J.v for J in self.jets(Ball.exact(pts), both)]
            lp = self.stacked.legs(*v)
            P = _full(-(v[3] * self.stacked.a1) / (lp.s[0] * lp.s[1]), 2 * n, 0)
            width = 2.0 * box.rad
            around = P[:n] + D * Ball(0.5 * width, 0.5 * width)
            low = np.maximum(V.lower_abs(), around.lower_abs())
            up = P.upper_abs()
        up = np.where(pts <= self.t_last[both], up, np.inf)
        return low, up, pts, both

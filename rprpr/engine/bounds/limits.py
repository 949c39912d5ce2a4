"""The limit check of an envelope: whether |T_i(t)| <= L_i for every t in [0, t_f].

Branch and bound on the states of boxes (below, above, open): the open boxes are cut,
boxes holding a pole cut about it (``_around_pole``), the monotone ones holding one
crossing set aside and bracketed together to the resolution CROSSING_REL t_f by
certified point values (``_bracket``: regula falsi, Illinois variant, to choose the
points); the runs of boxes not below the limit that hold a box above it are the windows
(``Window``). ``LimitChecks`` is a part of ``envelope.Envelope``."""

from __future__ import annotations

import math
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np
from flint import fmpq

from ...model.dataclass import dataclass
from ..certified.balls import Ball, quiet
from ..certified.motion import CertifiedMotion
from ..exact.singular import SingularInstant
from .boxes import START_BOXES, Bounds, partition, sorted_unique, split
from .poles import pole_bands
from .scalars import Scalars
from .search import MAX_FAN, MAX_LIVE, MAX_ROUNDS
from .verdicts import CROSSING_REL, LimitCheck, Peak, Window

CROSSING_STEPS = 12  # point passes that bracket the crossings in monotone boxes, at most
PROBE_SPREAD = 2.0  # the points of a bracketing pass: est ± 0.45 res PROBE_SPREAD^j
POLE_REACH = 16  # boxes of the first partition each side of a pole cut about it (``_around_pole``)
POLE_GROWTH = 0.1  # pieces about a pole of order k grow by 1 + POLE_GROWTH/k outward
LIMIT_BUDGET = 256  # boxes per refining pass of the limit check, about (``fan``)


def fan(n_live: int) -> int:
    """How many boxes each open box is cut into: fewer than the peak's (``search.fan``),
    the open boxes of a limit check being few and near its crossings, and a pass of
    1,000 boxes costing a third more than one of 250."""
    return int(min(MAX_FAN, max(2, LIMIT_BUDGET // max(n_live, 1))))


def loose(c: LimitCheck) -> bool:
    """Whether a limit check is undecided or a crossing of it is not bracketed to its
    resolution."""
    if c.passed is None:
        return True
    return any(w.start_hi - w.start_lo > c.resolution or w.end_hi - w.end_lo > c.resolution
               for w in c.windows)  # fmt: skip


@dataclass
class _Crossings:
    """Crossings set aside by a round of the limit check (``Envelope._crossings``): the
    boxes [lo, hi] (``mask`` of the round's boxes, rows: torques) on which |T_i| - L_i
    is monotone and changes sign, rising (``up``) or falling; ``rows``: i; va, vb: |T_i|
    at lo and hi (estimates, to choose the points of the regula falsi)."""

    mask: np.ndarray
    rows: np.ndarray
    lo: np.ndarray
    hi: np.ndarray
    up: np.ndarray
    va: np.ndarray
    vb: np.ndarray


def _estimate(
    a: np.ndarray, fa: np.ndarray, z: np.ndarray, fz: np.ndarray, c: np.ndarray,
    fc: np.ndarray, lo: np.ndarray, hi: np.ndarray,
) -> np.ndarray:  # fmt: skip
    """Where |T| - L (estimates f at a, z, c) vanishes in (lo, hi), to choose where to
    probe: inverse quadratic interpolation through a, z and c, else the regula falsi on
    [a, z], else the midpoint (only a choice of points: what is certified is decided by
    the points' balls)."""
    with quiet():
        secant = a - fa * (z - a) / (fz - fa)
        quad = (a * fz * fc / ((fa - fz) * (fa - fc)) + z * fa * fc / ((fz - fa) * (fz - fc))
                + c * fa * fz / ((fc - fa) * (fc - fz)))  # fmt: skip
    est = np.where((quad > lo) & (quad < hi), quad, secant)
    return np.where((est > lo) & (est < hi), est, 0.5 * lo + 0.5 * hi)


def _closer(
    p: np.ndarray, f: np.ndarray, below: np.ndarray, above: np.ndarray, *ends: np.ndarray
) -> tuple[np.ndarray, ...]:
    """The brackets [a, z] (a below the limit, z above, ``ends``: a, fa, z, fz, c, fc)
    moved to the points p (rows: probes, columns: brackets; estimates f) certified
    below or above strictly inside them, the nearest to the crossing; the third point
    c: the next nearest such point, else the end that moved."""
    a, fa, z, fz, c, fc = ends
    cols = np.arange(p.shape[1])
    toward = np.sign(z - a) * p  # larger: nearer z
    out = []
    for ok, sign in ((below, 1.0), (above, -1.0)):  # a: the largest, z: the smallest
        score = np.where(ok, sign * toward, -np.inf)
        best = np.argmax(score, axis=0)
        score[best, cols] = -np.inf
        nxt = np.argmax(score, axis=0)
        out.append((ok.any(axis=0), best, score[nxt, cols] > -np.inf, nxt))
    (has_a, ia, has_a2, ia2), (has_z, iz, has_z2, iz2) = out
    c = np.where(has_a, a, np.where(has_z, z, c))
    fc = np.where(has_a, fa, np.where(has_z, fz, fc))
    c = np.where(has_z2, p[iz2, cols], c)
    fc = np.where(has_z2, f[iz2, cols], fc)
    c = np.where(has_a2, p[ia2, cols], c)
    fc = np.where(has_a2, f[ia2, cols], fc)
    a, fa = np.where(has_a, p[ia, cols], a), np.where(has_a, f[ia, cols], fa)
    z, fz = np.where(has_z, p[iz, cols], z), np.where(has_z, f[iz, cols], fz)
    return a, fa, z, fz, c, fc


def _record(
    rows: np.ndarray, lo: np.ndarray, hi: np.ndarray, up: np.ndarray, a: np.ndarray,
    z: np.ndarray, res: float, done: list[list[tuple[np.ndarray, np.ndarray, np.ndarray]]],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
    """The crossings' boxes [lo, hi] recorded in ``done`` (per torque ``rows``) as three
    once bracketed by [a, z] (``Envelope._bracket``): on the side of its end up to the
    bracket, open on it, on the other side beyond; the brackets wider than ``res`` come
    back as boxes, each active for its torque (rows)."""
    x0, x1 = np.minimum(a, z), np.maximum(a, z)
    ok = x1 - x0 <= res
    left = np.where(up, -1, 1)  # the state of [lo, x0]
    for i in (0, 1):
        sel = rows == i
        if not sel.any():
            continue
        mid = np.where(ok[sel], 0, 2)  # the unclosed [x0, x1] come back (dropped below)
        states = np.concatenate([left[sel], mid, -left[sel]])
        keep = states != 2
        done[i].append((np.concatenate([lo[sel], x0[sel], x1[sel]])[keep],
                        np.concatenate([x0[sel], x1[sel], hi[sel]])[keep],
                        states[keep]))  # fmt: skip
    back = ~ok
    act = np.zeros((2, int(back.sum())), dtype=bool)
    act[rows[back], np.arange(int(back.sum()))] = True
    return x0[back], x1[back], act


def _joined(a: Bounds, b: Bounds) -> Bounds:
    """The boxes of a and of b as one ``Bounds`` (both with their ends)."""
    assert a.ends is not None and b.ends is not None
    assert a.monotone is not None and b.monotone is not None
    lo, hi = np.concatenate([a.lo, b.lo]), np.concatenate([a.hi, b.hi])
    pairs = ((a.low, b.low), (a.low_t, b.low_t), (a.up, b.up), (a.floor, b.floor))
    low, low_t, up, floor = (np.concatenate([p, q], axis=1) for p, q in pairs)
    ends = tuple(np.concatenate([p, q], axis=1) for p, q in zip(a.ends, b.ends, strict=True))
    return Bounds(
        lo, hi, low, low_t, up, floor, ends, np.concatenate([a.monotone, b.monotone], axis=1)
    )


def _windows(L: np.ndarray, H: np.ndarray, S: np.ndarray, pole_times: list[float]) -> list[Window]:
    """Maximal runs of boxes not below the limit that hold a box above it (or a pole):
    the run's open boxes at its ends bracket the crossings."""
    edges = np.diff(np.concatenate([[0], (S != -1).astype(int), [0]]))
    starts, ends = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0] - 1
    ones = np.nonzero(S == 1)[0]
    out = []
    for j, k in zip(starts.tolist(), ends.tolist(), strict=True):
        inner = ones[np.searchsorted(ones, j) : np.searchsorted(ones, k, side="right")]
        has_pole = any(L[j] <= t <= H[k] for t in pole_times)
        if len(inner) or has_pole:
            first = int(inner[0]) if len(inner) else j
            last = int(inner[-1]) if len(inner) else k
            out.append(Window(float(L[j]), float(L[first] if len(inner) else H[j]),
                              float(H[last] if len(inner) else L[k]), float(H[k]),
                              has_pole))  # fmt: skip
    return out


class LimitChecks:
    """Whether |T_i| <= L_i over [0, t_f], with the windows above it, for ``Envelope``
    (a part of it: what it reads of the envelope is declared here)."""

    motion: CertifiedMotion
    duration: fmpq
    tf: float
    t_last: float
    poles: list[SingularInstant]
    box_models: int
    throughs: list[Any]
    _hull_first: bool
    _first: Bounds | None
    _peak: tuple[Peak, Peak] | None

    if TYPE_CHECKING:

        def bounds(
            self, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray | None = None,
            need: float = 0.0, limit: np.ndarray | None = None,
        ) -> Bounds: ...  # fmt: skip

        def _pass(self, t: Ball) -> tuple[Ball, Ball]: ...

        def _values(self, t: np.ndarray) -> Ball: ...

        def coarse(self, lo: np.ndarray, hi: np.ndarray, need: float) -> Ball: ...

    @cached_property
    def scalars(self) -> Scalars:
        """T1, T2 in arb at a point, and the Taylor coefficients about each instant that the
        pole bands read (``scalars``, ``poles.pole_bands``)."""
        return Scalars(self.motion)

    def _limits(self, limit: tuple[float, float]) -> tuple[LimitCheck, LimitCheck]:
        """Branch and bound on the states of boxes (below, above, open): the open boxes
        are cut, the monotone ones holding a crossing set aside, and all crossings set
        aside are bracketed together when no box is left open (``_bracket``: the point
        passes that bracket them serve every round's crossings at once)."""
        res = CROSSING_REL * self.tf
        L = np.array(limit)
        b = self._limit_start(L, res)
        active = np.ones((2, len(b.lo)), dtype=bool)
        seen_above = np.zeros(2, dtype=bool)
        if self._peak is not None:  # a known peak decides a limit above it at once
            for i in (0, 1):
                if self._peak[i].certified and self._peak[i].upper <= L[i]:
                    active[i] = False
        done: list[list[tuple[np.ndarray, np.ndarray, np.ndarray]]] = [[], []]
        if not active.all():
            for i in (0, 1):
                if not active[i].any():
                    done[i].append((b.lo, b.hi, np.full(len(b.lo), -1)))
        pending: list[_Crossings] = []
        for _ in range(MAX_ROUNDS):
            state = np.where(b.up <= L[:, None], -1, np.where(b.floor > L[:, None], 1, 0))
            seen_above |= (active & (b.low > L[:, None])).any(axis=1)
            wide = b.hi - b.lo > res
            open_ = active & (state == 0) & wide[None, :]
            found = self._crossings(b, L, open_)
            open_ &= ~found.mask
            pending.append(found)
            for i in (0, 1):
                rec = active[i] & ~open_[i] & ~found.mask[i]
                if rec.any():
                    done[i].append((b.lo[rec], b.hi[rec], state[i][rec]))
            lo, hi, act = b.lo, b.hi, open_
            if not open_.any():  # bracket what was set aside; the unclosed come back
                lo, hi, act = self._bracket(pending, L, res, done)
                pending = []
            split = act.any(axis=0)
            n = int(split.sum())
            if not n:
                break
            k = fan(n)
            if n * k > MAX_LIVE * 4:  # the work cap: the open boxes stay undecided
                for i in (0, 1):
                    rec = act[i]
                    done[i].append((lo[rec], hi[rec], np.zeros(int(rec.sum()), dtype=int)))
                break
            lo, hi, src = self._refine(lo, hi, split, k, res)
            active = act[:, src]
            b = self.bounds(lo, hi, need=float(L.min()), limit=L)
        if pending:  # stopped by a cap: the brackets not closed stay undecided
            lo, hi, act = self._bracket(pending, L, res, done)
            for i in (0, 1):
                done[i].append((lo[act[i]], hi[act[i]], np.zeros(int(act[i].sum()), dtype=int)))
        return self._verdict(0, L, res, done, seen_above), self._verdict(
            1, L, res, done, seen_above
        )

    def _verdict(
        self, i: int, L: np.ndarray, res: float,
        done: list[list[tuple[np.ndarray, np.ndarray, np.ndarray]]], seen_above: np.ndarray,
    ) -> LimitCheck:  # fmt: skip
        """Torque i's check from the boxes recorded in ``done`` (in order, sharpened):
        failed where a value above L_i was seen (or a pole), passed where every box is
        below it, else undecided; with its windows."""
        parts = done[i]
        Ls = np.concatenate([p[0] for p in parts])
        Hs = np.concatenate([p[1] for p in parts])
        Ss = np.concatenate([p[2] for p in parts]).astype(int)
        order = np.argsort(Ls, kind="stable")
        Ls, Hs, Ss = self._sharpen(i, float(L[i]), res, Ls[order], Hs[order], Ss[order])
        windows = _windows(Ls, Hs, Ss, [s.t for s in self.poles])
        above = bool(seen_above[i]) or bool((Ss == 1).any()) or bool(self.poles)
        passed: bool | None = False if above else (True if (Ss == -1).all() else None)
        return LimitCheck(float(L[i]), passed, tuple(windows), res)

    def _sharpen(
        self, i: int, limit: float, res: float, L: np.ndarray, H: np.ndarray, S: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The boxes of torque i (in order; S: -1 below, 1 above, 0 open) with each pair
        of open boxes side by side, each within ``res`` (a crossing too close to their
        common end p for the certified value there to tell), made three: where T and T'
        exclude 0 over the pair (|T| monotone there) and the certified |T| at p ∓ 0.45 res
        lies on either side of the limit, the crossing is in between (open, 0.9 res) and
        the rest of the pair on the side of its end; else the pair stays open."""
        before = np.concatenate([[0], S[:-2]])  # the states beside each pair
        after = np.concatenate([S[2:], [0]])
        pair = np.nonzero(
            (S[:-1] == 0) & (S[1:] == 0) & (H[:-1] == L[1:]) & (H[1:] - L[:-1] > res)
            & (before * after == -1)  # a crossing's bracket: above on one side, below on the other
        )[0]  # fmt: skip
        if not len(pair):
            return L, H, S
        x0, p, x2 = L[pair], H[pair], H[pair + 1]
        q1 = np.maximum(p - 0.45 * res, x0)
        q2 = np.minimum(p + 0.45 * res, x2)
        V, D = self._pass(Ball.hull(x0, x2))
        mono = (Ball._of(V.mid[i], V.rad[i]).lower_abs() > 0) & (
            Ball._of(D.mid[i], D.rad[i]).lower_abs() > 0
        )
        P = self._values(np.concatenate([q1, q2]))
        v = Ball._of(P.mid[i], P.rad[i])
        side = np.where(v.upper_abs() <= limit, -1, np.where(v.lower_abs() > limit, 1, 0))
        s1, s2 = side[: len(pair)], side[len(pair) :]
        ok = mono & (s1 * s2 == -1)
        if not ok.any():
            return L, H, S
        j = pair[ok]
        keep = np.ones(len(L), dtype=bool)
        keep[j] = keep[j + 1] = False
        new_L = np.concatenate([L[keep], x0[ok], q1[ok], q2[ok]])
        new_H = np.concatenate([H[keep], q1[ok], q2[ok], x2[ok]])
        new_S = np.concatenate([S[keep], s1[ok], np.zeros(len(j), dtype=int), s2[ok]])
        order = np.argsort(new_L, kind="stable")
        return new_L[order], new_H[order], new_S[order]

    def _limit_start(self, L: np.ndarray, res: float) -> Bounds:
        """The limit check's first pass: the first partition's (``_start``, shared with
        the peak) when the peak made it; else, without a pole, the coarse pass over the
        uniform partition (``_coarse_start``: a limit far above the torques is decided
        there); with poles, the uniform partition with the boxes within POLE_REACH boxes
        of a pole merged and cut about it (``_around_pole``, no piece wider than the
        partition's), so that the boxes beside a pole are decided in this pass, the
        pieces near the pole proven above both limits by its form without a pass
        (``poles.pole_bands``)."""
        if self._first is not None:
            return self._first
        lo, hi = partition(self.duration, START_BOXES)
        if not self.poles:  # the uniform boxes, no guess of where |T| peaks
            return self._coarse_start(lo, hi, L, res)
        reach = POLE_REACH * float(hi[0] - lo[0])
        ends = np.concatenate([lo, hi[-1:]])
        inner = np.zeros(len(ends), dtype=bool)
        for s, e in self.motion.instants:
            if not s.torque_bounded:
                inner |= np.abs(ends - e.hi) < reach
        inner[0] = inner[-1] = False
        ends = ends[~inner]  # the boxes about each pole merged: cut about it below
        lo, hi, _ = self._refine(ends[:-1], ends[1:], np.ones(len(ends) - 1, dtype=bool), 1, res,
                                 float(hi[0] - lo[0]))  # fmt: skip
        near, band = pole_bands(self.motion, self.scalars, lo, hi, L) if not self.throughs \
            else (np.zeros(len(lo), dtype=bool), None)  # fmt: skip
        if band is None:
            return self.bounds(lo, hi, need=float(L.min()), limit=L)
        return _joined(self.bounds(lo[~near], hi[~near], need=float(L.min()), limit=L), band)

    def _coarse_start(self, lo: np.ndarray, hi: np.ndarray, L: np.ndarray, res: float) -> Bounds:
        """The first pass without a pole: the values over the boxes alone (``coarse``:
        no derivative, no point), which decide a limit far above or below the torques;
        the boxes it leaves open are cut (``fan`` each) and given the full pass
        (``bounds``) at once, the others kept as the coarse pass decided them."""
        self._hull_first = True  # no zone about a bounded instant where one form will do
        try:
            B = self.coarse(lo, hi, float(L.min()))
        finally:
            self._hull_first = False
        up, floor = B.upper_abs(), B.lower_abs()
        up = np.where(np.isnan(up), np.inf, up)
        floor = np.where(floor > L[:, None], floor, 0.0)  # a bound at every time of the box
        open_ = (up > L[:, None]) & (floor == 0.0)
        keep = ~open_.any(axis=0)
        u, f = up[:, keep], floor[:, keep]  # f: a value at every time of the box (low)
        first = Bounds(lo[keep], hi[keep], f, np.broadcast_to(lo[keep], u.shape), u, f,
                       (u, u, f, f, f, f), np.zeros(u.shape, dtype=bool))  # fmt: skip
        if keep.all():
            return first
        plo, phi, _ = self._refine(lo, hi, ~keep, fan(int((~keep).sum())), res)
        return _joined(first, self.bounds(plo, phi, need=float(L.min()), limit=L))

    def _refine(
        self, lo: np.ndarray, hi: np.ndarray, which: np.ndarray, k: int, res: float,
        cap: float = math.inf,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
        """The boxes ``which`` cut for the next pass, each into k (k = 1: kept), or,
        holding a pole, into pieces about it (``_around_pole``); with the index of the
        box each new box comes from. The others are dropped."""
        pole = self._holds_pole(lo, hi) & which
        plain = np.nonzero(which & ~pole)[0]
        los, his = split(lo[plain], hi[plain], k)
        parts = [(los, his, np.repeat(plain, k))]
        for j in np.nonzero(pole)[0]:  # pieces growing away from the pole
            plo, phi = _around_pole(self.motion.instants, float(lo[j]), float(hi[j]), res, cap)
            parts.append((plo, phi, np.full(len(plo), j)))
        return tuple(np.concatenate([p[q] for p in parts]) for q in range(3))  # type: ignore[return-value]

    def _crossings(self, b: Bounds, L: np.ndarray, open_: np.ndarray) -> _Crossings:
        """The open boxes on which |T_i| is monotone (``Bounds.monotone``) with one end
        certified <= L_i and the other > L_i: each holds exactly one crossing."""
        mask = np.zeros_like(open_)
        if b.ends is not None and b.monotone is not None:
            ua, ub, la, lb, _, _ = b.ends
            Lc = L[:, None]
            rising = (ua <= Lc) & (lb > Lc)  # below at lo, above at hi
            falling = (la > Lc) & (ub <= Lc)
            mask = open_ & b.monotone & (rising | falling) & (b.hi <= self.t_last)[None, :]
        rows, cols = np.nonzero(mask)
        if not len(rows):
            return _Crossings(mask, rows, np.zeros(0), np.zeros(0), np.zeros(0, dtype=bool),
                              np.zeros(0), np.zeros(0))  # fmt: skip
        assert b.ends is not None
        va, vb = b.ends[4][rows, cols], b.ends[5][rows, cols]
        up = rising[rows, cols]
        return _Crossings(mask, rows, b.lo[cols], b.hi[cols], up, va, vb)

    def _bracket(
        self, found: list[_Crossings], L: np.ndarray, res: float,
        done: list[list[tuple[np.ndarray, np.ndarray, np.ndarray]]],
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:  # fmt: skip
        """Each crossing set aside (``_crossings``, of any round) bracketed to ``res`` by
        certified values at points, all in the same point passes (regula falsi, Illinois
        variant, to choose the points; each point's certified value decides on which
        side of the crossing it lies). A box [lo, hi] is recorded in ``done`` as three:
        below the limit up to a, open on [a, b], above from b (or the mirror image), by
        monotonicity. Returns the [a, b] still wider than ``res`` (CROSSING_STEPS
        passes did not close them) as boxes, each active for its torque (rows)."""
        rows = np.concatenate([f.rows for f in found])
        k = len(rows)
        if not k:
            return np.zeros(0), np.zeros(0), np.zeros((2, 0), dtype=bool)
        lo = np.concatenate([f.lo for f in found])
        hi = np.concatenate([f.hi for f in found])
        up = np.concatenate([f.up for f in found])  # |T| - L rises through 0
        va = np.concatenate([f.va for f in found])
        vb = np.concatenate([f.vb for f in found])
        a, z = np.where(up, lo, hi), np.where(up, hi, lo)  # below end (a), above end (z)
        lim = L[rows]
        fa = np.where(up, va, vb) - lim  # |T| - L at a and z (estimates)
        fz = np.where(up, vb, va) - lim
        c, fc = np.full(k, np.nan), np.full(k, np.nan)  # a third point, beyond a or z
        near = 0.45 * res
        reach = float(np.max(hi - lo)) / near
        spread = near * PROBE_SPREAD ** np.arange(max(1, math.ceil(math.log(reach, PROBE_SPREAD))))
        offsets = np.concatenate([-spread[::-1], [0.0], spread])
        for _ in range(CROSSING_STEPS):
            j = np.nonzero(np.abs(z - a) > res)[0]
            if not len(j):
                break
            lo_p, hi_p = np.minimum(a[j], z[j]), np.maximum(a[j], z[j])
            est = _estimate(a[j], fa[j], z[j], fz[j], c[j], fc[j], lo_p, hi_p)
            probe = np.clip(est[None, :] + offsets[:, None], lo_p, hi_p)  # rows: offsets
            V = self._values(probe.ravel())
            at = np.tile(rows[j], len(offsets)), np.arange(probe.size)
            Vi = Ball._of(V.mid[at], V.rad[at])
            lj = np.tile(lim[j], len(offsets))
            below = (Vi.upper_abs() <= lj).reshape(probe.shape)
            above = (Vi.lower_abs() > lj).reshape(probe.shape)
            f = (np.abs(Vi.mid) - lj).reshape(probe.shape)
            inside = (probe - a[j]) * (z[j] - probe) > 0
            a[j], fa[j], z[j], fz[j], c[j], fc[j] = _closer(
                probe, f, inside & below, inside & above, a[j], fa[j], z[j], fz[j], c[j], fc[j]
            )
        return _record(rows, lo, hi, up, a, z, res, done)

    def _holds_pole(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """The boxes [lo, hi] that may hold an instant with unbounded torques."""
        out = np.zeros(len(lo), dtype=bool)
        for s, e in self.motion.instants:
            if not s.torque_bounded:
                out |= (lo <= e.hi + e.err + abs(e.lo)) & (hi >= e.hi - e.err - abs(e.lo))
        return out


def _around_pole(
    instants: list[tuple[SingularInstant, Any]], lo: float, hi: float, res: float,
    cap: float = math.inf,
) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """[lo, hi] (holding a pole of order k) cut at t_p ± d q^j (d = 0.45 res, t_p the
    nearest float to the pole, q = 1 + POLE_GROWTH/k): a piece of width 2d about the
    pole (left undecided), and pieces whose widths grow with their distance to it,
    on which |T| ~ C/|t - t_s|^k changes by a factor of about e^POLE_GROWTH at most,
    so that one pass decides most of them (a uniform cut would spend most pieces far
    from the pole, and a coarser one leaves them open for another pass)."""
    s, c = min(((s, e.hi) for s, e in instants if not s.torque_bounded),
               key=lambda p: abs(p[1] - 0.5 * (lo + hi)))  # fmt: skip
    q = 1.0 + POLE_GROWTH / max(s.pole_order, 1)
    d = 0.45 * res
    width = max(hi - lo, d)
    n = math.ceil(math.log(width / d) / math.log(q)) + 1
    steps = d * q ** np.arange(n + 1)
    if cap < width:  # no piece wider than cap: beyond, steps of cap
        steps = steps[: int(np.searchsorted(steps * (q - 1), cap)) + 1]
        more = steps[-1] + cap * np.arange(1, math.ceil((width - steps[-1]) / cap) + 1)
        steps = np.concatenate([steps, more])
    cuts = np.concatenate([c - steps, c + steps])
    ends = sorted_unique(np.concatenate([[lo, hi], cuts[(cuts > lo) & (cuts < hi)]]))
    return ends[:-1], ends[1:]

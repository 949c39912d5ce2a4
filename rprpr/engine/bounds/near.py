"""The torques near singular instants, where the direct enclosure is poor (λ = μ/δ
cancels): the zone form inside a zone about an instant (``zones.Zone``), else a Taylor
form per box: the Lagrange form about a bounded t_s in the box (``taylor_lambda``), or
the box's own Taylor model (``taylor_box``), at most MAX_BOX_MODELS per task. In the
limit check's coarse pass, a bounded instant without a zone yet is first tried with one
Lagrange form over the hull of the poor boxes about it (``_over_hull``): where that
bounds T below the limit, no zone is made.
``NearForms`` is a part of ``envelope.Envelope``."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from flint import arb, ctx

from ..certified.balls import Ball, quiet
from .boxes import put_narrower

if TYPE_CHECKING:
    from ..certified.stacked import General, Stacked
    from .boxes import Polys
from ..certified.motion import CertifiedMotion
from ..certified.zones import (
    TAYLOR_PREC,
    ExactTime,
    Zone,
    taylor_at_instant,
    taylor_box,
    taylor_lambda,
)

MAX_BOX_MODELS = 400  # box Taylor models per task, at most (the work cap near an instant)
NEAR_PER_PASS = 8  # boxes given a Taylor form per pass, at most (arb, one box at a time)


class NearForms:
    """The forms of ``zones`` near singular instants, for ``Envelope`` (a part of it:
    what it reads of the envelope is declared here)."""

    motion: CertifiedMotion
    tf: float
    box_models: int  # box Taylor models left to spend (``_near_instant``)
    _coeffs: dict[int, list[list[arb]]]  # Taylor coefficients about instants
    _zones: dict[int, Zone | None]  # about the instants (``zone``)
    _pole_zones: bool  # zones about poles too, not only where points are poor
    _hull_first = False  # about a bounded instant, one Lagrange form first (``_over_hull``)

    if TYPE_CHECKING:

        @property
        def polys(self) -> Polys: ...

        @property
        def stacked(self) -> Stacked | General: ...

    def _near(
        self, pts: np.ndarray, lo: np.ndarray, hi: np.ndarray, P: Ball, B: Ball, need: float,
        settled: np.ndarray | None = None,
    ) -> tuple[Ball, Ball]:  # fmt: skip
        """P (T at the points) and B (T over the boxes) made narrower near singular
        instants: the zone form inside a zone, else a Taylor form per box (``_near_instant``)
        for the boxes whose direct enclosure is poor and whose bound matters (> need), but
        those ``settled`` (on a known side of a limit already: they keep their turn among
        the NEAR_PER_PASS, so that the other boxes get the same forms as without)."""
        if not self.motion.instants:
            return P, B
        poor_p = ~(P.rad <= np.abs(P.mid)).all(axis=0)
        poor_b = ~(B.rad <= np.abs(B.mid)).all(axis=0)
        covered = np.zeros(len(lo), dtype=bool)
        box = Ball.hull(lo, hi)
        matters = poor_b & ~(B.upper_abs() <= need).all(axis=0)  # a poor bound above need
        for k, (s, e) in enumerate(self.motion.instants):
            if not (s.torque_bounded or self._pole_zones or self._poor_beside(e, pts, poor_p)):
                continue  # beside a pole the direct form is good: no zone needed (yet)
            if self._hull_first and s.torque_bounded and k not in self._zones and not len(pts):
                hull = self._over_hull(k, lo, hi, matters, need)
                if hull is not None:  # every poor box about it proven below ``need``
                    B = put_narrower(B, hull[0], hull[1])
                    covered[hull[0]] = True
                    continue
            zone = self.zone(k)
            if zone is None:
                continue
            r = zone.r * 0.999
            ip = np.nonzero(poor_p & (np.abs(pts - zone.e.hi) <= r))[0]
            inside = (lo >= zone.e.hi - r) & (hi <= zone.e.hi + r)
            covered |= inside
            ib = np.nonzero(poor_b & inside)[0]
            if not (len(ip) or len(ib)):
                continue
            mid = np.concatenate([pts[ip], box.mid[ib]])
            rad = np.concatenate([0 * pts[ip], box.rad[ib]])
            Tz = self._zone_torques(zone, mid, rad)
            P = put_narrower(P, ip, Tz[:, : len(ip)])
            B = put_narrower(B, ib, Tz[:, len(ip) :])
        wanted = ~(B.upper_abs() <= need).all(axis=0)
        rest = ~(B.rad <= np.abs(B.mid)).all(axis=0) & wanted & ~covered
        if self.box_models <= 0 and rest.any():  # only boxes holding an instant are left
            holds = np.zeros(len(lo), dtype=bool)
            for _, e in self.motion.instants:
                holds |= (e.compare(lo) <= 0) & (e.compare(hi) >= 0)
            rest &= holds
        for j in np.nonzero(rest)[0][:NEAR_PER_PASS]:  # the others are cut further
            if settled is not None and settled[j]:
                continue
            got = self._near_instant(float(lo[j]), float(hi[j]))
            if got is not None:
                col = [g.normal() for g in got]
                B = put_narrower(B, np.array([j]), Ball._of(
                    np.array([[float(np.ravel(g.mid)[0])] for g in col]),
                    np.array([[float(np.ravel(g.rad)[0])] for g in col])))  # fmt: skip
        return P, B

    def _over_hull(
        self, k: int, lo: np.ndarray, hi: np.ndarray, poor: np.ndarray, need: float
    ) -> tuple[np.ndarray, Ball] | None:
        """The boxes ``poor`` within t_f/8 of the k-th instant (bounded) and T over their
        hull H, which holds t_s: λ by the Lagrange form about t_s over H
        (``taylor_lambda``), the rest by one evaluation over H; returned only when
        |T_i| <= ``need`` over H for both torques (then no zone is needed for a bound of
        ``need``: a zone costs a ball pass and series of 20-50 terms). T over H bounds T
        over each of its boxes."""
        s, e = self.motion.instants[k]
        idx = np.nonzero(poor & (np.abs(0.5 * lo + 0.5 * hi - e.hi) <= self.tf / 8))[0]
        if not len(idx):
            return None
        h0, h1 = float(lo[idx].min()), float(hi[idx].max())
        if not (e.compare(np.array([h0]))[0] <= 0 <= e.compare(np.array([h1]))[0]):
            return None
        lam = taylor_lambda(self.motion, s, h0, h1, self._taylor(k))
        if lam is None:
            return None
        with quiet():
            t = Ball.hull(np.array([h0]), np.array([h1]))
            x, xd, xdd, y, yd, ydd = self.polys.values(self.motion, t)
            T = self.stacked.efforts_at(x, xd, xdd, y, yd, ydd, lam)
        T = T.normal()
        if not bool((T.upper_abs() <= need).all()):
            return None
        cols = np.broadcast_to(T.mid.reshape(2, 1), (2, len(idx)))
        rads = np.broadcast_to(T.rad.reshape(2, 1), (2, len(idx)))
        return idx, Ball._of(cols.copy(), rads.copy())

    def _zone_torques(self, zone: Zone, mid: np.ndarray, rad: np.ndarray) -> Ball:
        """T (stacked) over the balls mid ± rad of time inside a zone, λ from its form."""
        with quiet():
            t = Ball._of(mid, rad)
            eps = zone.e.eps(mid) + Ball(0.0, rad)
            lam = zone.lam(eps)
            x, xd, xdd, y, yd, ydd = self.polys.values(self.motion, t)
            T = self.stacked.efforts_at(x, xd, xdd, y, yd, ydd, lam)
        return T

    def zone(self, k: int) -> Zone | None:
        """The zone form about the k-th singular instant (``make_zone``), made once."""
        if k not in self._zones:
            self._zones[k] = self.motion.zone(k)  # made once per motion
        return self._zones[k]

    def _poor_beside(self, e: ExactTime, pts: np.ndarray, poor_p: np.ndarray) -> bool:
        """Whether T at a point other than t_s within t_f/4 of t_s has a poor direct
        enclosure. Beside a pole |T| ~ C/|t - t_s|^k, and at points the direct form (λ's
        pole part without cancellation, the cancelling bounded part of relative weight
        ~ u/C) is usually good up to t_s itself: the zone about a pole is made only where
        it is not (over a box the enclosure beside a pole is wide whatever the form)."""
        ip = np.nonzero(poor_p & (np.abs(pts - e.hi) <= self.tf / 4))[0]
        return bool(len(ip)) and bool((e.compare(pts[ip]) != 0).any())

    def _taylor(self, k: int) -> list[list[arb]]:
        if k not in self._coeffs:
            s = self.motion.instants[k][0]
            self._coeffs[k] = taylor_at_instant(self.motion, s, TAYLOR_PREC)
        return self._coeffs[k]

    def _near_instant(self, lo: float, hi: float) -> tuple[Ball, Ball] | None:
        """T1, T2 over [lo, hi] by a Taylor form about the nearest singular instant: with
        the Lagrange remainder about t_s when the box holds a bounded t_s
        (``taylor_lambda``), else, for a box narrow beside its distance to t_s, by the
        box's own Taylor model (``taylor_box``)."""
        k = min(range(len(self.motion.instants)),
                key=lambda i: abs(self.motion.instants[i][1].hi - 0.5 * (lo + hi)))  # fmt: skip
        s, e = self.motion.instants[k]
        cmp_lo = int(e.compare(np.array([lo]))[0])
        cmp_hi = int(e.compare(np.array([hi]))[0])
        if cmp_lo <= 0 <= cmp_hi:  # t_s in the box
            if not s.torque_bounded:
                return None
            lam = taylor_lambda(self.motion, s, lo, hi, self._taylor(k))
            if lam is None:
                return None
            with quiet():
                t = Ball.hull(np.array([lo]), np.array([hi]))
                x, xd, xdd, y, yd, ydd = self.polys.values(self.motion, t)
                T = self.stacked.efforts_at(x, xd, xdd, y, yd, ydd, lam)
            return T[0], T[1]
        dist = min(abs(lo - e.hi), abs(hi - e.hi))
        if hi - lo > dist / 4 or self.box_models <= 0:  # too wide (bisect), or work cap
            return None
        self.box_models -= 1
        old = ctx.prec
        ctx.prec = TAYLOR_PREC
        try:
            ts = arb(e.exact) if e.exact is not None else e.at(TAYLOR_PREC)
        finally:
            ctx.prec = old
        return taylor_box(self.motion, self._taylor(k), ts, lo, hi)

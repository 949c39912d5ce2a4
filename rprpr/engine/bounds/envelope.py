"""Certified enclosures of the torques over intervals of time, and what they decide.

Over a box of time I = [a, b] (a ``Ball`` with mid c and radius h, rounded outward) the
torques are enclosed in two ways and the narrower enclosure is kept (both are proven):

* **away from singular instants**, the mean-value form: for a differentiable T on I,
  T(I) ⊆ T(c) + T'(I) [-h, h] (mean value theorem), with T(c) from the point ball pass
  and T'(I) from the same formulas run on first-order jets (value, derivative) of balls
  over I (``Jet``); plain interval evaluation T(I) as well.
* **near a singular instant**, where the direct form is poor (λ = μ/δ cancels), the
  forms of ``zones``: the instant's zone form (Taylor coefficients at t_s, the exactly
  vanishing ones dropped, with a proven remainder), the Lagrange form for a box holding
  a bounded t_s (λ_i ∈ (c_i/d) ε^(k_i - m), derived in ``zones``), or a Taylor model
  about the box's own midpoint.

What they decide (``torque_peak``, ``limit_violations``, ``saturation_windows``,
``closest_approach``) is found by branch and bound: lower bounds from certified point
values (``certified``), upper bounds from the enclosures, boxes bisected until the
bracket is within the stated tolerance. Boxes are deterministic (bisections of a fixed
partition of [0, t_f]), so no answer depends on a sampling grid.

``Envelope`` is one of the two sources of ``search`` (the peak's branch and bound), and
is made of three parts, a module each: ``near`` (the forms near singular instants),
``ladders`` (the first partition cut finer about the likely maxima) and ``limits`` (the
limit check). The closest approach comes from ``approach`` (exact critical points).
"""

from __future__ import annotations

import math
from functools import cached_property

import numpy as np
from flint import arb

from ...model.numbers import to_float
from ..certified.balls import Ball, U, quiet
from ..certified.motion import CertifiedMotion
from ..certified.shared import per_robot
from ..certified.stacked import General, Stacked, stacked_form
from ..certified.through import Through
from ..certified.zones import Zone
from ..exact.singular import SingularInstant
from . import assembly
from .approach import min_abs_delta, min_abs_y
from .boxes import (
    START_BOXES,
    Bounds,
    Polys,
    full,
    last_float,
    partition,
    poor_columns,
    put_narrower,
    sorted_unique,
    unique_ends,
)
from .ladders import Ladders
from .limits import LimitChecks, loose
from .near import MAX_BOX_MODELS, NearForms
from .search import MAX_LIVE, PEAK_REL, maximise
from .verdicts import Approach, LimitCheck, Peak, Window, around_poles


class Envelope(LimitChecks, NearForms, Ladders):
    """Grid-free torque verdicts for one task (module docstring)."""

    def __init__(self, motion: CertifiedMotion) -> None:
        self.motion = motion
        self.duration = motion.traj.duration
        self.bounded = [s for s in motion.analysis.instants if s.torque_bounded]
        self.poles = [s for s in motion.analysis.instants if not s.torque_bounded]
        self.throughs = [Through(motion, k.leg, k.time) for k in motion.kinematic]
        self.tf = to_float(self.duration)
        self.t_last = last_float(self.duration)
        self._coeffs: dict[int, list[list[arb]]] = {}  # Taylor coefficients about instants
        self._zones: dict[int, Zone | None] = {}  # about the instants (``zone``)
        self._pole_zones = False  # zones about poles too, not only where points are poor
        self.box_models = MAX_BOX_MODELS  # left to spend (``_near_instant``)
        self._first: Bounds | None = None  # the pass over the first partition
        self._peak: tuple[Peak, Peak] | None = None
        self._checks: dict[tuple[float, float], tuple[LimitCheck, LimitCheck]] = {}

    @cached_property
    def polys(self) -> Polys:
        """The motion's polynomials as balls (made for the first pass)."""
        return Polys(self.motion)

    @cached_property
    def stacked(self) -> Stacked | General:
        return per_robot(self.motion.robot, stacked_form)

    # -- one pass -------------------------------------------------------------------------
    def _pass(self, t: Ball) -> tuple[Ball, Ball]:
        """T (stacked rows) and T' over the balls of time ``t``: first-order jets."""
        with quiet():
            x, xd, xdd, y, yd, ydd = self.polys.jets(self.motion, t)
            T = self.stacked.efforts(x, xd, xdd, y, yd, ydd)
            V, D = full(T.v, len(t.mid)), full(T.d, len(t.mid))  # t-free parts too
            for th in self.throughs:
                V, D = self._through(th, t, V, D, poor_columns(V) | poor_columns(D))
        return V, D

    def _values(self, t: np.ndarray | Ball) -> Ball:
        """T (stacked rows) at the float times ``t``, or over the balls of time ``t``: the
        values of ``_pass`` without the derivatives (the factored form near t_A where the
        direct one is poor)."""
        tb = t if isinstance(t, Ball) else Ball._of(np.asarray(t, float), np.zeros(np.shape(t)))
        with quiet():
            x, xd, xdd, y, yd, ydd = self.polys.values(self.motion, tb)
            T = self.stacked.efforts(x, xd, xdd, y, yd, ydd)
            V = full(T, len(tb.mid))
            for th in self.throughs:  # rare
                V, _ = self._through(th, tb, V, V, poor_columns(V), False)
        return V

    def coarse(self, lo: np.ndarray, hi: np.ndarray, need: float) -> Ball:
        """T (stacked rows) over the boxes [lo, hi] by their values alone (no derivative,
        no point: a third of ``bounds``' cost), with the forms near singular instants
        where the direct enclosure is poor and the bound matters (> need)."""
        box = Ball.hull(lo, hi)
        B = self._values(box)
        none = np.zeros(0)
        _, B = self._near(none, lo, hi, Ball._of(np.zeros((2, 0)), np.zeros((2, 0))), B, need)
        return B

    def _through(
        self, th: Through, t: Ball, V: Ball, D: Ball, poor: np.ndarray, jets: bool = True
    ) -> tuple[Ball, Ball]:
        """V (T) and D (T') made narrower near t_A by the factored form (``Through``) on
        each side of t_A that the balls of time reach within [0, t_f] (the hull of both
        sides where a ball holds t_A: T is then bounded by either side's values), for the
        columns ``poor`` (where the direct form is poor: elsewhere it is kept); both sides
        in one evaluation (a ball each, its own sign of φ). Without ``jets``, V alone (the
        values at points: D is returned as it came)."""
        idx = np.nonzero(poor & (np.abs(t.mid - th.e.hi) <= self.tf / 4))[0]
        if not len(idx):
            return V, D
        lo, hi = t.lower()[idx], t.upper()[idx]
        eps = th.e.eps(t.mid[idx]) + Ball(0.0, t.rad[idx])
        el, eh = eps.lower(), eps.upper()
        left = th.e.compare(lo) <= 0  # reaches t <= t_A
        right = th.e.compare(hi) >= 0
        if th.e.exact is not None and th.e.exact <= 0:
            left[:] = False  # no time of [0, t_f] before t_A
        if th.e.exact is not None and th.e.exact >= self.duration:
            right[:] = False
        r, l_ = np.nonzero(right)[0], np.nonzero(left)[0]
        if not len(r) + len(l_):
            return V, D
        cols = np.concatenate([r, l_])  # the balls of ε: right sides, then left ones
        e_lo = np.concatenate([np.maximum(el[r], 0.0), np.minimum(el[l_], 0.0)])
        e = Ball.hull(e_lo, np.concatenate([np.maximum(eh[r], 0.0), np.minimum(eh[l_], 0.0)]))
        sigma = np.concatenate([np.ones(len(r)), np.full(len(l_), (-1.0) ** th.k)])
        assert isinstance(self.stacked, Stacked)  # E at A or B: the RPRPR's Type I form
        T, _ = th.torques(self.stacked, e, sigma, jets)
        some = left | right
        k = idx[some]
        where = np.cumsum(some) - 1  # the position of each column of idx among ``some``
        for q, B in enumerate((T.v, T.d) if jets else (T,)):
            lo_q, hi_q = np.full((2, len(k)), np.inf), np.full((2, len(k)), -np.inf)
            np.minimum.at(lo_q.T, where[cols], np.broadcast_to(B.lower(), (2, len(cols))).T)
            np.maximum.at(hi_q.T, where[cols], np.broadcast_to(B.upper(), (2, len(cols))).T)
            ok = np.isfinite(lo_q) & np.isfinite(hi_q)
            B = Ball.hull(np.where(ok, lo_q, 0.0), np.where(ok, hi_q, 0.0))
            B = Ball._of(np.where(ok, B.mid, np.nan), np.where(ok, B.rad, np.inf))
            if q == 0:
                V = put_narrower(V, k, B)
            else:
                D = put_narrower(D, k, B)
        return V, D

    def bounds(
        self, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray | None = None, need: float = 0.0,
        limit: np.ndarray | None = None,
    ) -> Bounds:  # fmt: skip
        """One vectorised pass over the boxes and their ends (``Bounds``), with the zone
        and Taylor forms near singular instants where the direct form is poor; with a
        ``limit`` (per torque), no box Taylor model for a box whose side of the limit the
        pass decides already (``assembly.settled``); the bounds by ``assembly.assemble``."""
        times, where = unique_ends(lo, hi)
        with quiet():
            box = Ball.hull(lo, hi)
            B, D = self._pass(box)  # T and T' over the boxes
            P = self._values(times)  # T at the ends, each once (boxes share their ends)
            settled = (
                None if limit is None else assembly.settled(P, B, D, where, box, lo, hi, limit)
            )
            P, B = self._near(times, lo, hi, P, B, need, settled)
            return assembly.assemble(P, where, B, D, box, lo, hi, self.t_last)

    def _start(self) -> Bounds:
        """The pass over the first partition, made once (shared by every verdict): the
        uniform boxes, cut finer about the likely maxima of |T| (``_ladders``) so that
        one pass often certifies the peak."""
        if self._first is None:
            lo, hi = partition(self.duration, START_BOXES)
            cuts = self._ladders(float(hi[0] - lo[0]))
            if len(cuts):
                ends = sorted_unique(np.concatenate([lo, hi[-1:], cuts]))
                lo, hi = ends[:-1], ends[1:]
            self._first = self.bounds(lo, hi)
        return self._first

    # -- the peak -------------------------------------------------------------------------
    @property
    def peak_undefined(self) -> bool:
        """Whether max |T| is undefined: the path lies on y = 0, or E meets A or B along
        AB (δ -> 0 there as well). Decided without a pass."""
        if self.motion.analysis.on_singular_line:
            return True
        return any(bool(th.db[0][0].contains_zero()) for th in self.throughs)

    def pole_peak(self) -> tuple[Peak, Peak] | None:
        """(inf, inf) at the first instant with unbounded torques, without a pass; None
        when the torques are bounded."""
        if not self.poles:
            return None
        t = self.poles[0].t
        return Peak(math.inf, t, math.inf, True), Peak(math.inf, t, math.inf, True)

    def torque_peak(self, rel: float = PEAK_REL) -> tuple[Peak, Peak] | None:
        """max |T1| and max |T2| over [0, t_f] (suprema, ``Peak``); None where undefined
        (the path lies on y = 0, or E passes A or B)."""
        if self.peak_undefined:
            return None
        if self.poles:
            return self.pole_peak()
        if rel != PEAK_REL:
            return self._maximise(rel)
        if self._peak is None:
            self._peak = self._maximise(rel)
        return self._peak

    def _maximise(self, rel: float) -> tuple[Peak, Peak]:
        """The peak by the branch and bound of ``search`` from the first partition, the
        torques' limits at bounded instants known beforehand."""
        b = self._start()
        best, best_t = np.zeros(2), np.zeros(2)
        for s in self.bounded:  # the limits at bounded instants are values of T too
            if s.torque_at_singularity is not None:
                for i in (0, 1):
                    v = abs(s.torque_at_singularity[i]) * (1 - 4 * U)
                    if v > best[i]:
                        best[i], best_t[i] = v, s.t
        idx = np.zeros(len(b.lo), dtype=int)  # one motion: every box is of piece 0
        peaks, _ = maximise(self, b, idx, best, best_t, rel, MAX_LIVE)
        return peaks

    # -- limits ---------------------------------------------------------------------------
    def limit_violations(self, limit: tuple[float, float]) -> tuple[LimitCheck, LimitCheck]:
        """Whether |T_i(t)| <= limit_i for every t in [0, t_f], per torque, certified
        (made once per limit)."""
        key = (float(limit[0]), float(limit[1]))
        if key not in self._checks:
            got = self._limits(key)
            if not self._pole_zones and self.poles and any(loose(c) for c in got):
                self._pole_zones = True  # beside a pole the direct form fell short: again,
                self.box_models = MAX_BOX_MODELS  # with the zones about the poles
                got = self._limits(key)
            self._checks[key] = got
        return self._checks[key]

    def saturation_windows(
        self, limit: tuple[float, float]
    ) -> list[tuple[SingularInstant, Window | None, Window | None]]:
        """For each unbounded instant: the windows around it in which |T1| and |T2| exceed
        their limits (``limit_violations``' windows that contain the instant)."""
        return around_poles(self.poles, self.limit_violations(limit))

    # -- near misses ------------------------------------------------------------------------
    def closest_approach(self) -> Approach | None:
        """For a motion that never meets y = 0: min |y| and min |δ| over [0, t_f], both
        exactly from the critical points (``min_abs_y``, ``min_abs_delta``). None when
        the motion meets the line."""
        a = self.motion.analysis
        if a.instants or a.kinematic or a.on_singular_line:
            return None
        dist, t_y = min_abs_y(self.motion.traj, self.duration)
        lo, hi, t_delta = min_abs_delta(self.motion.traj, self.duration)
        return Approach(dist, t_y, lo, hi, t_delta)

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
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from flint import arb, arb_poly, ctx, fmpq, fmpq_poly

from ..model.numbers import to_float
from . import equations as dyn
from .balls import Ball, U, horner, poly_balls, quiet
from .certified import CertifiedMotion, _roots
from .singular import SingularInstant
from .zones import TAYLOR_PREC, Zone, make_zone, taylor_at_instant, taylor_box, taylor_lambda

PEAK_REL = 1e-6  # torque_peak: certified to this relative width
START_BOXES = 64  # the initial partition of [0, t_f]
MAX_ROUNDS = 60  # bisection rounds, at most
MAX_LIVE = 4096  # boxes kept alive, at most
CROSSING_REL = 1e-9  # limit crossings bracketed to this fraction of t_f
MAX_BOX_MODELS = 400  # box Taylor models per task, at most (the work cap near an instant)


# -- first-order jets of balls ----------------------------------------------------------


class Jet:
    """f and f' over a box of time, both balls: the arithmetic of first-order jets."""

    __slots__ = ("d", "v")

    def __init__(self, v: Ball, d: Ball) -> None:
        self.v = v
        self.d = d

    @staticmethod
    def _of(o: Any) -> Jet:
        if isinstance(o, Jet):
            return o
        return Jet(Ball.coerce(o), Ball.exact(0.0))

    def __add__(self, o: Any) -> Jet:
        o = Jet._of(o)
        return Jet(self.v + o.v, self.d + o.d)

    __radd__ = __add__

    def __sub__(self, o: Any) -> Jet:
        o = Jet._of(o)
        return Jet(self.v - o.v, self.d - o.d)

    def __rsub__(self, o: Any) -> Jet:
        return Jet._of(o) - self

    def __neg__(self) -> Jet:
        return Jet(-self.v, -self.d)

    def __mul__(self, o: Any) -> Jet:
        if not isinstance(o, Jet):
            o = Ball.coerce(o)
            return Jet(self.v * o, self.d * o)
        return Jet(self.v * o.v, self.d * o.v + self.v * o.d)

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> Jet:
        if not isinstance(o, Jet):
            o = Ball.coerce(o)
            return Jet(self.v / o, self.d / o)
        q = self.v / o.v
        return Jet(q, (self.d - q * o.d) / o.v)

    def __rtruediv__(self, o: Any) -> Jet:
        return Jet._of(o) / self

    def sqrt(self) -> Jet:
        r = self.v.sqrt()
        return Jet(r, self.d / (r * 2.0))


def _jet_hypot(u: Jet, v: Jet) -> Jet:
    return (u * u + v * v).sqrt()


def _horner_jet(c: list[Ball], x: Jet) -> Jet:
    acc = Jet._of(c[-1])
    for ck in c[-2::-1]:
        acc = acc * x + ck
    return acc


# -- enclosures over boxes ----------------------------------------------------------------


def _torques_of(
    motion: CertifiedMotion, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any,
    lam: tuple[Any, Any] | None = None,
) -> tuple[Any, Any, Any]:  # fmt: skip
    """T1, T2 and δ from the motion (balls or jets); λ given, or μ/δ (eqs. 28-31)."""
    leg1 = dyn.leg(x, xd, xdd, y, yd, ydd, _hypot)
    leg2 = dyn.leg(x - motion.a1, xd, xdd, y, yd, ydd, _hypot)
    d = dyn.dynamics(leg1, leg2, motion.params)
    delta = -(motion.a1 * y) / (leg1.s * leg2.s)  # eq. (29), product form
    if lam is None:
        lam = (d.mu1 / delta, d.mu2 / delta)
    T1, T2 = dyn.torques(d, lam[0], lam[1])
    return T1, T2, delta


def _hypot(u: Any, v: Any) -> Any:
    return (u * u + v * v).sqrt()


class _Polys:
    """Ball coefficients of x, x', x'', x''' in t and of q, q', q'', q''' in w = x - c."""

    def __init__(self, motion: CertifiedMotion) -> None:
        x = motion.traj.x
        q = motion.traj.path(fmpq_poly([motion.center, 1]))
        self.x = [poly_balls(x)]
        self.q = [poly_balls(q)]
        for _ in range(3):
            x, q = x.derivative(), q.derivative()
            self.x.append(poly_balls(x))
            self.q.append(poly_balls(q))

    def jets(self, motion: CertifiedMotion, box: Ball) -> tuple[Jet, Jet, Jet, Jet, Jet, Jet]:
        """x, x', x'', y, y', y'' as jets over the box: (enclosure, time derivative)."""
        xv = [horner(c, box) for c in self.x]
        x, xd, xdd = Jet(xv[0], xv[1]), Jet(xv[1], xv[2]), Jet(xv[2], xv[3])
        w = xv[0] - motion.center
        qv = [horner(c, w) for c in self.q]
        q1 = Jet(qv[1], qv[2] * xv[1])
        q2 = Jet(qv[2], qv[3] * xv[1])
        y = Jet(qv[0], qv[1] * xv[1])
        return x, xd, xdd, y, q1 * xd, q2 * xd * xd + q1 * xdd


def _stack(balls: list[Ball]) -> Ball:
    """One ball vector from balls of one element each."""
    mid = np.array([np.ravel(b.mid)[0] for b in balls], dtype=float)
    return Ball(mid, np.array([np.ravel(b.rad)[0] for b in balls], dtype=float))


def _narrower(a: Ball, b: Ball) -> Ball:
    """Of two enclosures of the same set, the one with the smaller radius, elementwise."""
    pick = ~(b.rad < a.rad)
    return Ball(np.where(pick, a.mid, b.mid), np.where(pick, a.rad, b.rad))


# -- results ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Peak:
    """max |T_i| over [0, t_f] [N m]: ``value`` is attained at ``t`` (a certified lower
    bound of the maximum), ``upper`` a certified upper bound; when ``certified``,
    upper - value <= PEAK_REL value. ``value`` = ``upper`` = inf when T_i is unbounded
    (``t``: the first instant with a pole)."""

    value: float
    t: float
    upper: float
    certified: bool


@dataclass(frozen=True)
class Window:
    """An interval in which |T_i| > limit: it starts in [start_lo, start_hi] and ends in
    [end_lo, end_hi] (crossings bracketed; ``pole``: contains an unbounded instant)."""

    start_lo: float
    start_hi: float
    end_lo: float
    end_hi: float
    pole: bool = False


@dataclass(frozen=True)
class LimitCheck:
    """|T_i(t)| <= limit for every t in [0, t_f]: ``passed`` True or False, certified, or
    None when undecided at the resolution (then max |T_i| is within ``resolution`` in
    time of touching the limit); ``windows``: where the limit is exceeded, in order."""

    limit: float
    passed: bool | None
    windows: tuple[Window, ...]
    resolution: float

    @property
    def first(self) -> Window | None:
        return self.windows[0] if self.windows else None


@dataclass(frozen=True)
class Approach:
    """Closest approach of a motion that never meets y = 0: min |y| (the distance of E to
    the line AB) [m] at ``t_y``; min |δ| within [delta_lo, delta_hi] at ``t_delta``."""

    distance: float
    t_y: float
    delta_lo: float
    delta_hi: float
    t_delta: float


# -- boxes ------------------------------------------------------------------------------------


def _boxes(duration: fmpq, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A partition of [0, t_f] into n boxes with float ends (the last one reaches just
    past t_f when t_f is no float)."""
    tf = to_float(duration)
    ends = np.array([to_float(duration * fmpq(i, n)) for i in range(n + 1)])
    if fmpq(*tf.as_integer_ratio()) < duration:
        ends[-1] = np.nextafter(tf, np.inf)
    return ends[:-1], ends[1:]


def _clip(duration: fmpq, t: np.ndarray) -> np.ndarray:
    """t moved into [0, t_f] (the largest float <= t_f at the end)."""
    tf = to_float(duration)
    if fmpq(*tf.as_integer_ratio()) > duration:
        tf = float(np.nextafter(tf, -np.inf))
    return np.clip(t, 0.0, tf)


class Envelope:
    """Grid-free torque verdicts for one task (module docstring)."""

    def __init__(self, motion: CertifiedMotion) -> None:
        self.motion = motion
        self.duration = motion.traj.duration
        self.polys = _Polys(motion)
        self.bounded = [s for s in motion.analysis.instants if s.torque_bounded]
        self.poles = [s for s in motion.analysis.instants if not s.torque_bounded]
        tf = to_float(self.duration)
        self.near = tf / 16  # the Taylor form is tried within this distance of an instant
        self._coeffs: dict[int, list[list[arb]]] = {}  # Taylor coefficients about instants
        self._zones: list[Zone | None] | None = None
        self.box_models = MAX_BOX_MODELS  # left to spend (``_near_instant``)

    # -- enclosures ---------------------------------------------------------------------
    def enclose(self, lo: np.ndarray, hi: np.ndarray) -> tuple[Ball, Ball, Ball]:
        """Balls containing T1(t), T2(t), δ(t) for every t in each box [lo_j, hi_j]."""
        with quiet():
            box = Ball.hull(lo, hi)
            point = self.motion.ball_pass(box.mid)
            jets = self.polys.jets(self.motion, box)
            out = []
            for name, J in zip(("T1", "T2", "delta"), _torques_of(self.motion, *jets), strict=True):
                mean_value = point[name] + Ball(0.0, J.d.upper_abs() * box.rad)
                out.append(_narrower(mean_value, J.v))
        return out[0], out[1], out[2]

    def enclose_near(
        self, s: SingularInstant, lo: np.ndarray, hi: np.ndarray
    ) -> tuple[Ball, Ball, np.ndarray]:
        """T1, T2 over the boxes [lo_j, hi_j] with λ from the Taylor form about ``s``, and
        where that form applies (elsewhere the balls are unbounded)."""
        lams = [
            taylor_lambda(self.motion, s, float(a), float(b)) for a, b in zip(lo, hi, strict=True)
        ]
        ok = np.array([lam is not None for lam in lams])
        nan = Ball(np.nan, np.inf)
        lam1 = [lam[0] if lam is not None else nan for lam in lams]
        lam2 = [lam[1] if lam is not None else nan for lam in lams]
        with quiet():
            box = Ball.hull(lo, hi)
            x, xd, xdd, y, yd, ydd = (J.v for J in self.polys.jets(self.motion, box))
            l1, l2 = _stack(lam1), _stack(lam2)
            T1, T2, _ = _torques_of(self.motion, x, xd, xdd, y, yd, ydd, (l1, l2))
        return T1, T2, ok

    def abs_bounds(
        self, lo: np.ndarray, hi: np.ndarray, need: float = 0.0
    ) -> tuple[list[np.ndarray], list[np.ndarray]]:
        """([lower |T1|, lower |T2|], [upper |T1|, upper |T2|]) over each box. Boxes near a
        bounded instant whose direct enclosure is poor (wider than its value) and whose
        upper bound exceeds ``need`` also get the Taylor form."""
        T1, T2, _ = self.enclose(lo, hi)
        low = [T1.lower_abs(), T2.lower_abs()]
        up = [T1.upper_abs(), T2.upper_abs()]
        poor = ~((T1.rad <= np.abs(T1.mid)) & (T2.rad <= np.abs(T2.mid)))
        wanted = ~((up[0] <= need) & (up[1] <= need))
        todo = poor & wanted
        covered = np.zeros(len(lo), dtype=bool)
        for zone in self.zones():
            if zone is None:
                continue
            inside = todo & (lo >= zone.e.hi - zone.r * 0.999) & (hi <= zone.e.hi + zone.r * 0.999)
            idx = np.nonzero(inside)[0]
            covered |= inside
            if not len(idx):
                continue
            T1z, T2z = self.enclose_zone(zone, lo[idx], hi[idx])
            for i, Tz in ((0, T1z), (1, T2z)):
                u = Tz.upper_abs()
                better = u < up[i][idx]
                up[i][idx[better]] = u[better]
                low[i][idx[better]] = np.maximum(low[i][idx[better]], Tz.lower_abs()[better])
        rest = todo & ~covered
        if self.box_models <= 0 and rest.any():  # only boxes holding an instant are left
            holds = np.zeros(len(lo), dtype=bool)
            for _, e in self.motion.instants:
                holds |= (e.compare(lo) <= 0) & (e.compare(hi) >= 0)
            rest &= holds
        for j in np.nonzero(rest)[0]:
            got = self._near_instant(float(lo[j]), float(hi[j]))
            if got is None:
                continue
            for i in (0, 1):
                u1 = float(np.ravel(got[i].upper_abs())[0])
                if u1 < up[i][j]:
                    up[i][j] = u1
                    low[i][j] = max(low[i][j], float(np.ravel(got[i].lower_abs())[0]))
        return low, up

    def zones(self) -> list[Zone | None]:
        """The zone form about each singular instant (``make_zone``), made once."""
        if self._zones is None:
            self._zones = []
            for k, (s, _) in enumerate(self.motion.instants):
                if k not in self._coeffs:
                    self._coeffs[k] = taylor_at_instant(self.motion, s, TAYLOR_PREC)
                self._zones.append(make_zone(self.motion, s, self._coeffs[k]))
        return self._zones

    def enclose_zone(self, zone: Zone, lo: np.ndarray, hi: np.ndarray) -> tuple[Ball, Ball]:
        """T1, T2 over boxes inside a zone, λ from the zone form."""
        with quiet():
            box = Ball.hull(lo, hi)
            eps = zone.e.eps(box.mid) + Ball(0.0, box.rad)
            lam = zone.lam(eps)
            x, xd, xdd, y, yd, ydd = (J.v for J in self.polys.jets(self.motion, box))
            T1, T2, _ = _torques_of(self.motion, x, xd, xdd, y, yd, ydd, lam)
        return T1, T2

    def _near_instant(self, lo: float, hi: float) -> tuple[Ball, Ball] | None:
        """T1, T2 over [lo, hi] by a Taylor form about the nearest singular instant: with
        the Lagrange remainder about t_s when the box holds a bounded t_s
        (``taylor_lambda``), else, for a box narrow beside its distance to t_s, by the
        box's own Taylor model (``taylor_box``)."""
        if not self.motion.instants:
            return None
        k = min(range(len(self.motion.instants)),
                key=lambda i: abs(self.motion.instants[i][1].hi - 0.5 * (lo + hi)))  # fmt: skip
        s, e = self.motion.instants[k]
        if k not in self._coeffs:
            self._coeffs[k] = taylor_at_instant(self.motion, s, TAYLOR_PREC)
        cmp_lo = int(e.compare(np.array([lo]))[0])
        cmp_hi = int(e.compare(np.array([hi]))[0])
        if cmp_lo <= 0 <= cmp_hi:  # t_s in the box
            if not s.torque_bounded:
                return None
            T1, T2, ok = self.enclose_near(s, np.array([lo]), np.array([hi]))
            return (T1, T2) if ok[0] else None
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
        return taylor_box(self.motion, self._coeffs[k], ts, lo, hi)

    def point_abs(self, t: np.ndarray) -> list[np.ndarray]:
        """Certified lower bounds of |T1|, |T2| at the float times t (0 where undefined or
        not certified without arb: lower bounds need no refinement)."""
        c = self.motion.sample(t, refine=False)
        out = []
        for name in ("T1", "T2"):
            v, r = c.value[name], c.radius[name]
            with quiet():
                low = np.where(np.isfinite(v), (np.abs(v) - r) * (1 - 4 * U), 0.0)
            out.append(np.maximum(low, 0.0))
        return out

    # -- the peak -------------------------------------------------------------------------
    def torque_peak(self, rel: float = PEAK_REL) -> tuple[Peak, Peak] | None:
        """max |T1| and max |T2| over [0, t_f]; None where undefined (the path lies on
        y = 0, or E passes A or B)."""
        if self.motion.analysis.on_singular_line or self.motion.kinematic:
            return None
        if self.poles:
            t = self.poles[0].t
            return Peak(math.inf, t, math.inf, True), Peak(math.inf, t, math.inf, True)
        return self._maximise(0, rel), self._maximise(1, rel)

    def _maximise(self, i: int, rel: float) -> Peak:
        lo, hi = _boxes(self.duration, START_BOXES)
        best, best_t = 0.0, 0.0
        for s in self.bounded:  # the limits at bounded instants are values of T too
            if s.torque_at_singularity is not None:
                v = abs(s.torque_at_singularity[i]) * (1 - 4 * U)
                if v > best:
                    best, best_t = v, s.t
        ts = _clip(self.duration, np.concatenate([lo, hi[-1:], 0.5 * (lo + hi)]))
        best, best_t = self._raise(i, ts, best, best_t)
        up = self.abs_bounds(lo, hi, best * (1 + rel))[1][i]
        dropped = 0.0  # the largest upper bound of a box set aside
        for _ in range(MAX_ROUNDS):
            keep = up > best * (1 + rel)
            dropped = max(dropped, float(up[~keep].max(initial=0.0)))
            if not keep.any():
                return Peak(best, best_t, max(best, dropped), True)
            if keep.sum() > MAX_LIVE:
                break
            lo, hi = lo[keep], hi[keep]
            mid = 0.5 * (lo + hi)
            lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
            best, best_t = self._raise(i, _clip(self.duration, mid), best, best_t)
            up = self.abs_bounds(lo, hi, best * (1 + rel))[1][i]
        return Peak(best, best_t, max(dropped, float(up.max(initial=best))), False)

    def _raise(self, i: int, ts: np.ndarray, best: float, best_t: float) -> tuple[float, float]:
        low = self.point_abs(ts)[i]
        j = int(np.argmax(low))
        if low[j] > best:
            return float(low[j]), float(ts[j])
        return best, best_t

    # -- limits ---------------------------------------------------------------------------
    def limit_violations(self, limit: tuple[float, float]) -> tuple[LimitCheck, LimitCheck]:
        """Whether |T_i(t)| <= limit_i for every t in [0, t_f], per torque, certified."""
        return self._limit(0, float(limit[0])), self._limit(1, float(limit[1]))

    def _limit(self, i: int, limit: float) -> LimitCheck:
        tf = to_float(self.duration)
        res = CROSSING_REL * tf
        lo, hi = _boxes(self.duration, START_BOXES)
        state = np.zeros(len(lo), dtype=int)  # -1 below, +1 above (all of it), 0 open
        done_lo: list[np.ndarray] = []
        done_hi: list[np.ndarray] = []
        done_state: list[np.ndarray] = []
        seen_above = False
        for _ in range(MAX_ROUNDS):
            low, up = self.abs_bounds(lo, hi, limit)
            state = np.where(up[i] <= limit, -1, np.where(low[i] > limit, 1, 0))
            mid = 0.5 * (lo + hi)
            point = self.point_abs(_clip(self.duration, mid))[i]
            seen_above |= bool((point > limit).any())
            split = (state == 0) & (hi - lo > res)
            done_lo.append(lo[~split])
            done_hi.append(hi[~split])
            done_state.append(state[~split])
            if not split.any() or 2 * split.sum() > MAX_LIVE:
                lo, hi = lo[split], hi[split]
                break
            lo, hi = lo[split], hi[split]
            mid = mid[split]
            lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
        else:
            pass
        if len(lo):  # boxes left open by the work cap
            done_lo.append(lo)
            done_hi.append(hi)
            done_state.append(np.zeros(len(lo), dtype=int))
        L = np.concatenate(done_lo)
        H = np.concatenate(done_hi)
        S = np.concatenate(done_state)
        order = np.argsort(L)
        L, H, S = L[order], H[order], S[order]
        windows = self._windows(L, H, S)
        above = seen_above or bool((S == 1).any()) or bool(self.poles)
        if above:
            passed: bool | None = False
        elif (S == -1).all():
            passed = True
        else:
            passed = None
        return LimitCheck(limit, passed, tuple(windows), res)

    def _windows(self, L: np.ndarray, H: np.ndarray, S: np.ndarray) -> list[Window]:
        """Maximal runs of boxes not below the limit that hold a box above it (or a pole):
        the run's open boxes at its ends bracket the crossings."""
        out = []
        j = 0
        n = len(L)
        pole_times = [s.t for s in self.poles]
        while j < n:
            if S[j] == -1:
                j += 1
                continue
            k = j
            while k + 1 < n and S[k + 1] != -1:
                k += 1
            run = slice(j, k + 1)
            has_pole = any(L[j] <= t <= H[k] for t in pole_times)
            if (S[run] == 1).any() or has_pole:
                inner = np.nonzero(S[run] == 1)[0]
                first = j + (int(inner[0]) if len(inner) else 0)
                last = j + (int(inner[-1]) if len(inner) else k - j)
                out.append(Window(float(L[j]), float(L[first] if len(inner) else H[j]),
                                  float(H[last] if len(inner) else L[k]), float(H[k]),
                                  has_pole))  # fmt: skip
            j = k + 1
        return out

    def saturation_windows(
        self, limit: tuple[float, float]
    ) -> list[tuple[SingularInstant, Window | None, Window | None]]:
        """For each unbounded instant: the windows around it in which |T1| and |T2| exceed
        their limits (``limit_violations``' windows that contain the instant)."""
        checks = self.limit_violations(limit)
        out = []
        for s in self.poles:
            pair = []
            for c in checks:
                w = [w for w in c.windows if w.pole and w.start_lo <= s.t <= w.end_hi]
                pair.append(w[0] if w else None)
            out.append((s, pair[0], pair[1]))
        return out

    # -- near misses ------------------------------------------------------------------------
    def closest_approach(self, rel: float = PEAK_REL) -> Approach | None:
        """For a motion that never meets y = 0: min |y| exactly from the roots of y' and
        the ends, and min |δ| over [0, t_f] certified by branch and bound. None when the
        motion meets the line."""
        a = self.motion.analysis
        if a.instants or a.kinematic or a.on_singular_line:
            return None
        dist, t_y = self._min_abs_y()
        lo, hi = _boxes(self.duration, START_BOXES)
        ts = _clip(self.duration, np.concatenate([lo, hi[-1:], 0.5 * (lo + hi), [t_y]]))
        best, best_t = self._lower_delta(ts, math.inf, 0.0)
        floor = math.inf  # the least lower bound of a box set aside
        for _ in range(MAX_ROUNDS):
            low = self.enclose(lo, hi)[2].lower_abs()
            keep = low < best * (1 - rel)
            floor = min(floor, float(low[~keep].min(initial=math.inf)))
            if not keep.any():
                return Approach(dist, t_y, min(floor, best), best, best_t)
            if keep.sum() > MAX_LIVE:
                break
            lo, hi = lo[keep], hi[keep]
            mid = 0.5 * (lo + hi)
            lo, hi = np.concatenate([lo, mid]), np.concatenate([mid, hi])
            best, best_t = self._lower_delta(_clip(self.duration, mid), best, best_t)
        low = self.enclose(lo, hi)[2].lower_abs()
        return Approach(dist, t_y, min(floor, float(low.min(initial=best))), best, best_t)

    def _lower_delta(self, ts: np.ndarray, best: float, best_t: float) -> tuple[float, float]:
        """The smallest certified upper bound of |δ| at the times ts (and where)."""
        c = self.motion.sample(ts, refine=False)
        up = np.abs(c.value["delta"]) + c.radius["delta"]
        if np.isnan(up).all():
            return best, best_t
        j = int(np.nanargmin(up))
        if up[j] < best:
            return float(up[j]), float(ts[j])
        return best, best_t

    def _min_abs_y(self) -> tuple[float, float]:
        """min |y(t)| over [0, t_f] and where: at the ends or at a real root of y'."""
        traj = self.motion.traj
        cands: list[tuple[arb, float]] = []
        old = ctx.prec
        ctx.prec = 128
        try:
            for t in (fmpq(0), self.duration):
                cands.append((abs(arb(traj.y(t))), to_float(t)))
            for e in _roots(traj.yd, self.duration):
                tb = arb(e.exact) if e.exact is not None else e.at(128)
                cands.append((abs(arb_poly(traj.y.coeffs())(tb)), e.hi))
        finally:
            ctx.prec = old
        v, t = min(cands, key=lambda c: float(c[0].mid()))
        return float(v.mid()), t

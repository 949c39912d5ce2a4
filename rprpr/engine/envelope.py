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
from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property, partial
from typing import Any

import numpy as np
from flint import arb, arb_poly, ctx, fmpq, fmpq_poly

from ..model.actuation import PRISMATIC
from ..model.numbers import to_float
from ..model.task import Robot
from . import equations as dyn
from .balls import Ball, U, centred, horner, hypot, poly_balls, quiet, round_up, stack
from .certified import CertifiedMotion, per_robot
from .roots import real_roots_in
from .series import accurate, ball, taylor
from .singular import SingularInstant
from .trajectory import Trajectory
from .verdicts import CROSSING_REL, Approach, LimitCheck, Peak, Window, around_poles
from .zones import TAYLOR_PREC, ExactTime, Zone, taylor_at_instant, taylor_box, taylor_lambda

PEAK_REL = 1e-6  # torque_peak: certified to this relative width ...
PEAK_ABS = 1e-9  # ... or this absolute one [N m], whichever is larger (a peak of 0 N m)
START_BOXES = 512  # the initial partition of [0, t_f]
SPLIT_BUDGET = 1024  # boxes per refining pass, about (live boxes times their fan)
MAX_FAN = 512  # a live box is cut into at most this many
MAX_ROUNDS = 60  # refining passes, at most
CENTRED_DEGREE = 7  # a longer polynomial is enclosed over boxes by the centred form
MAX_LIVE = 4096  # boxes kept alive, at most
CROSSING_STEPS = 12  # point passes that bracket the crossings in monotone boxes, at most
PROBE_SPREAD = 2.0  # the points of a bracketing pass: est ± 0.45 res PROBE_SPREAD^j
POLE_GROWTH = 0.25  # pieces about a pole of order k grow by 1 + POLE_GROWTH/k outward
MAX_BOX_MODELS = 400  # box Taylor models per task, at most (the work cap near an instant)
LADDER_GRID = 2049  # doubles evaluated to guess where |T| peaks (``_ladders``)
LADDER_SPLIT = 64  # about a guessed maximum: boxes of 1/LADDER_SPLIT of the uniform width
LADDER_CORE = 32  # ... this many on either side, then boxes growing by
LADDER_RATIO = 1.15  # ... this factor
LADDER_REACH = 8  # ... out to this many uniform widths
NEAR_PER_PASS = 8  # boxes given a Taylor form per pass, at most (arb, one box at a time)


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

    def __getitem__(self, index: Any) -> Jet:
        return Jet(self.v[index], self.d[index])

    def sqrt(self) -> Jet:
        r = self.v.sqrt()
        return Jet(r, self.d / (r * 2.0))


# -- enclosures over boxes ----------------------------------------------------------------


class _Polys:
    """Ball coefficients of x, x', x'', x''' in t and of q, q', q'', q''' in w = x - c
    (q: the path recentred), or without a path q = y recentred, in w = t - c_t; and the
    fourth derivatives, which the centred form (``balls.centred``) needs where a long
    polynomial is enclosed over boxes."""

    def __init__(self, motion: CertifiedMotion) -> None:
        self.direct = motion.traj.path is None  # then q is y in w = t - c_t
        q3 = motion.y3 if self.direct else motion.q3  # up to the second derivative
        assert q3 is not None
        x, q = motion.traj.x, motion.recentred
        x3 = x.derivative().derivative().derivative()
        q3d = q.derivative().derivative().derivative()
        self.x = [*motion.x3, poly_balls(x3), *_fourth(x3)]
        self.q = [*q3, poly_balls(q3d), *_fourth(q3d)]

    @staticmethod
    def _enclose(cs: list[list[Ball]], box: Ball) -> list[Ball]:
        """The polynomial and its first three derivatives over the balls ``box``: by
        Horner's rule, or, where ``cs`` carries the fourth derivative (a degree over
        CENTRED_DEGREE), by the centred form on balls of some width (where cancellation
        makes Horner's enclosure far too wide)."""
        if len(cs) > 4 and bool(np.any(box.rad > 0)):
            return centred(cs, box)[:4]
        return [horner(c, box) for c in cs[:4]]

    def jets(self, motion: CertifiedMotion, box: Ball) -> tuple[Jet, Jet, Jet, Jet, Jet, Jet]:
        """x, x', x'', y, y', y'' as jets over the box: (enclosure, time derivative)."""
        xv = self._enclose(self.x, box)
        x, xd, xdd = Jet(xv[0], xv[1]), Jet(xv[1], xv[2]), Jet(xv[2], xv[3])
        if self.direct:
            yv = self._enclose(self.q, box - motion.t_center)
            return x, xd, xdd, Jet(yv[0], yv[1]), Jet(yv[1], yv[2]), Jet(yv[2], yv[3])
        w = xv[0] - motion.center
        qv = self._enclose(self.q, w)
        q1 = Jet(qv[1], qv[2] * xv[1])
        q2 = Jet(qv[2], qv[3] * xv[1])
        y = Jet(qv[0], qv[1] * xv[1])
        return x, xd, xdd, y, q1 * xd, q2 * xd * xd + q1 * xdd


def _fourth(third: fmpq_poly) -> list[list[Ball]]:
    """The fourth derivative's ball coefficients from the third derivative, where the
    polynomial's degree (the third's plus 3) calls for the centred form; else none."""
    return [poly_balls(third.derivative())] if third.degree() + 3 > CENTRED_DEGREE else []


def _full(b: Ball, n: int, rows: int = 2) -> Ball:
    """The ball ``b`` broadcast to ``rows`` rows (0: none) of n columns (a motion that
    does not move, x and y constant, gives balls that do not depend on t)."""
    shape = (rows, n) if rows else (n,)
    mid, rad = np.broadcast_to(b.mid, shape), np.broadcast_to(b.rad, shape)
    return Ball._of(np.array(mid), np.array(rad))


def _poor(b: Ball) -> np.ndarray:
    """The columns of a stacked ball (rows: torques) whose enclosure is wider than its
    value in some row (unbounded ones included)."""
    return np.asarray(~(b.rad <= np.abs(b.mid)).all(axis=0))


def _put(b: Ball, idx: np.ndarray, new: Ball) -> Ball:
    """b (rows by columns) with its columns ``idx`` replaced by ``new`` where narrower."""
    if not len(idx):
        return b
    mid, rad = b.mid.copy(), b.rad.copy()
    pick = ~(rad[:, idx] <= new.rad)  # NaN radii (unbounded) are replaced
    mid[:, idx] = np.where(pick, new.mid, mid[:, idx])
    rad[:, idx] = np.where(pick, new.rad, rad[:, idx])
    return Ball._of(mid, rad)


# -- results ----------------------------------------------------------------------------------


# -- the two legs stacked ------------------------------------------------------------------


def _pair(a: Any, b: Any) -> Ball:
    """The exact rationals a (leg 1, row 0) and b (leg 2, row 1) as a (2, 1) ball column."""
    return stack([Ball.of_rational(a), Ball.of_rational(b)])[:, None]


class _Stacked:
    """T1, T2 (and δ) with the two legs stacked in rows 0 and 1, on balls or jets.

    The same equations as ``equations.leg``/``dynamics``/``torques`` (eqs. 7-14, 28-33),
    written once for both legs so that each operation runs on both at once (the cost of a
    ball operation on short vectors is its call, not its length), with the constant
    parts of eqs. (7), (9), (11), (13) summed exactly in Q:
        M_i = K_i + m_i d_i²,  d_i = s_i - r_i,  K = m2 r2² + I2 + I3 (leg 2: m4, r4, I4, I5),
        N_i = 2 m_i s_i' θ_i' d_i + (G_i + m_i g s_i) cos θ_i,  G = (m2 r2 - m3 r3) g,
        F_i = m_i (s_i'' - d_i θ_i'²) + m_i g sin θ_i   (M22 s1'' + N2, M44 s2'' + N4),
        μ1 = -(sin θ2 F1 + sin θ1 F2),  μ2 = cos θ2 F1 + cos θ1 F2,  δ = -a1 y/(s1 s2),
        T_i = M_i θ_i'' + N_i ± s_i (sin θ_i λ1 - cos θ_i λ2)   (+ for T1, - for T2),
    with m_i = m3, m5 and r_i = r3, r5. Under the prismatic scheme (``equations``), with
    V_i = (M_i θ_i'' + N_i)/s_i:
        μ1 = -(cos θ2 V1 + cos θ1 V2),  μ2 = -(sin θ1 V2 + sin θ2 V1),
        F_i ∓ (cos θ_i λ1 + sin θ_i λ2)   (- for F1, + for F2) are the efforts."""

    def __init__(self, r: Robot) -> None:
        L, g = r.links, r.gravity
        self.base = _pair(0, r.a1)  # u = x - base: (x, x - a1)
        self.a1 = Ball.of_rational(r.a1)
        self.m = _pair(L[3].mass, L[5].mass)
        self.r = _pair(L[3].r, L[5].r)
        self.K = _pair(
            L[2].mass * L[2].r ** 2 + L[2].inertia + L[3].inertia,
            L[4].mass * L[4].r ** 2 + L[4].inertia + L[5].inertia,
        )
        self.G = _pair((L[2].mass * L[2].r - L[3].mass * L[3].r) * g,
                       (L[4].mass * L[4].r - L[5].mass * L[5].r) * g)  # fmt: skip
        self.mg = _pair(L[3].mass * g, L[5].mass * g)
        self.sign = Ball.exact(np.array([[1.0], [-1.0]]))
        self.prismatic = r.actuation == PRISMATIC

    def legs(self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any) -> dyn.Leg:
        """Both legs' joint values (rows 0 and 1), eqs. 41-42."""
        return dyn.leg(x - self.base, xd, xdd, y, yd, ydd, hypot)

    def torques(
        self, lg: dyn.Leg, y: Any, lam: tuple[Any, Any] | None = None, delta: Any = None
    ) -> tuple[Any, Any]:
        """(T stacked, δ) from the legs; λ given, or μ/δ (δ given, or eq. 29)."""
        d = lg.s - self.r
        M = self.K + self.m * (d * d)
        N = (self.m * 2) * (lg.s_d * lg.th_d * d) + (self.G + self.mg * lg.s) * lg.cos
        F = self.m * (lg.s_dd - d * (lg.th_d * lg.th_d)) + self.mg * lg.sin
        if delta is None:
            delta = -(self.a1 * y) / (lg.s[0] * lg.s[1])
        if self.prismatic:
            U = M * lg.th_dd + N
            if lam is None:
                V = U / lg.s
                cV, sV = lg.cos * V[::-1], lg.sin * V[::-1]
                lam = (-(cV[0] + cV[1]) / delta, -(sV[0] + sV[1]) / delta)
            return F - self.sign * (lg.cos * lam[0] + lg.sin * lam[1]), delta
        if lam is None:
            sF, cF = lg.sin * F[::-1], lg.cos * F[::-1]
            lam = (-(sF[0] + sF[1]) / delta, (cF[0] + cF[1]) / delta)
        T = M * lg.th_dd + N + self.sign * (lg.s * (lg.sin * lam[0] - lg.cos * lam[1]))
        return T, delta


# -- E at A or B: the leg through its base joint, factored ---------------------------------


def _derive(c: list[Ball]) -> list[Ball]:
    return [c[j] * float(j) for j in range(1, len(c))] or [Ball.exact(0.0)]


def _derivatives(c: list[Ball]) -> tuple[list[Ball], ...]:
    """The coefficients of f and its first three derivatives from those of f (low to
    high)."""
    out = [c]
    for _ in range(3):
        out.append(_derive(out[-1]))
    return tuple(out)


def _jets3(ds: tuple[list[Ball], ...], eps: Ball) -> tuple[Jet, Jet, Jet]:
    """f, f', f'' as jets in ε (value, derivative) over the balls ``eps``, from the
    coefficients of f and its first three derivatives (``_derivatives``): Horner's rule
    on each, every derivative made once."""
    v = [horner(c, eps) for c in ds]
    return Jet(v[0], v[1]), Jet(v[1], v[2]), Jet(v[2], v[3])


class _Through:
    """The torques near an exact instant t_A at which E is at A (leg 1) or B (leg 2).

    With ε = t - t_A, u = x - x_base and y vanish at ε = 0 to order k (at least) and
    factor as u = φ a, y = φ b with φ = ε^k and a(0) ≠ 0 (exact Taylor coefficients about
    t_A). On either side of t_A, σ = sign φ is constant and the leg's joint values are
    smooth in ε, from the leg formulas (eqs. 41-42) on (a, b), which give r = |(a, b)|,
    ã = a/r, b̃ = b/r, r', w, r'', w':
        s = σ φ r,  s' = σ (φ' r + φ r'),  s'' = σ (φ'' r + 2 φ' r' + φ r''),
        cos θ = σ ã,  sin θ = σ b̃,  θ' = w,  θ'' = w',
    and δ = -a1 y/(s1 s2) = -σ a1 b/(r s_other). Nothing divides by a ball holding 0:
    T on each side extends continuously to t_A (its one-sided limit there)."""

    def __init__(self, motion: CertifiedMotion, leg: int, e: Any) -> None:
        self.leg, self.e = leg, e
        traj = motion.traj
        base = fmpq(0) if leg == 1 else traj.a1
        u = traj.x - base
        k = self.k = _vanishing_order(u, e)
        cy = _taylor_balls(traj.y, e)
        a = _taylor_balls(u, e)[k:] or [Ball.exact(0.0)]
        b = cy[k:] or [Ball.exact(0.0)]
        phi = [Ball.exact(0.0)] * k + [Ball.exact(1.0)]  # ε^k
        with quiet():  # the coefficients of each and its first three derivatives
            self.dx, self.dy = _derivatives(_taylor_balls(traj.x, e)), _derivatives(cy)
            self.da, self.db, self.dphi = _derivatives(a), _derivatives(b), _derivatives(phi)

    def torques(self, st: _Stacked, eps: Ball, sigma: float) -> tuple[Jet, Jet]:
        """T (stacked) and δ as jets over balls of ε on one side (sign of φ: sigma)."""
        x = _jets3(self.dx, eps)
        y = _jets3(self.dy, eps)
        reg = st.legs(x[0], x[1], x[2], y[0], y[1], y[2])
        a, b, phi = _jets3(self.da, eps), _jets3(self.db, eps), _jets3(self.dphi, eps)
        f = dyn.leg(a[0], a[1], a[2], b[0], b[1], b[2], hypot)
        r, r1, r2 = f.s, f.s_d, f.s_dd
        own = dyn.Leg(
            (phi[0] * r) * sigma,
            f.cos * sigma,
            f.sin * sigma,
            (phi[1] * r + phi[0] * r1) * sigma,
            f.th_d,
            (phi[2] * r + phi[1] * r1 * 2.0 + phi[0] * r2) * sigma,
            f.th_dd,
        )
        i = self.leg - 1
        rows = [
            _jet_rows(getattr(reg, name), getattr(own, name), i, len(eps.mid))
            for name in ("s", "cos", "sin", "s_d", "th_d", "s_dd", "th_dd")
        ]
        lg = dyn.Leg(*rows)
        other = reg.s[1 - i]
        delta = -(st.a1 * b[0]) / (r * other) * sigma
        T, _ = st.torques(lg, y[0], delta=delta)
        return T, delta


def _jet_rows(reg: Jet, own: Jet, i: int, n: int) -> Jet:
    """The stacked jet ``reg`` (2 rows of n) with its row i replaced by ``own``."""
    out = []
    for part in ("v", "d"):
        R, Own = getattr(reg, part), getattr(own, part)
        mid = np.array(np.broadcast_to(R.mid, (2, n)), dtype=float)
        rad = np.array(np.broadcast_to(R.rad, (2, n)), dtype=float)
        mid[i] = np.broadcast_to(Own.mid, (n,))
        rad[i] = np.broadcast_to(Own.rad, (n,))
        out.append(Ball._of(mid, rad))
    return Jet(out[0], out[1])


def _taylor_balls(p: fmpq_poly, e: Any) -> list[Ball]:
    """The Taylor coefficients of p about the exact time e, as balls."""
    cs = taylor(p, max(p.degree(), 0) + 1)
    if e.exact is not None:
        return [Ball.of_rational(c(e.exact)) for c in cs]
    old = ctx.prec
    ctx.prec = 256
    try:
        t = e.at(256)
        return [Ball.of_arb(arb_poly(c.coeffs())(t)) if c.degree() >= 0 else Ball.exact(0.0)
                for c in cs]  # fmt: skip
    finally:
        ctx.prec = old


def _vanishing_order(p: fmpq_poly, e: Any) -> int:
    """The multiplicity of the exact time e as a root of p (exactly: an irreducible factor
    vanishing at an irrational e is found by its ball containing 0, which no other
    factor's ball does at 256 bits and more, the roots being distinct)."""
    if e.exact is not None:
        k = 0
        while not p.is_zero() and p(e.exact) == 0:
            p, k = p.derivative(), k + 1
        return k
    old = ctx.prec
    prec = 256
    try:
        while prec <= 4096:
            ctx.prec = prec
            t = e.at(prec)
            hits = [m for f, m in p.factor()[1] if arb_poly(f.coeffs())(t).contains(0)]
            if len(hits) == 1:
                return int(hits[0])
            prec *= 2
        return 1
    finally:
        ctx.prec = old


# -- boxes ------------------------------------------------------------------------------------


def _boxes(duration: fmpq, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A partition of [0, t_f] into n boxes with float ends (the last one reaches just
    past t_f when t_f is no float)."""
    tf = to_float(duration)
    step = tf / n
    if n & (n - 1) == 0 and math.isfinite(tf) and step * n == tf and step >= 2.0**-1000 \
            and fmpq(*tf.as_integer_ratio()) == duration:  # fmt: skip
        # t_f a float, n a power of 2: t_f/n is exact and i (t_f/n) the double nearest
        # t_f i/n (one correctly rounded product), as the exact line below gives
        ends = np.arange(n + 1) * step
    else:
        ends = np.array([to_float(duration * fmpq(i, n)) for i in range(n + 1)])
    if fmpq(*tf.as_integer_ratio()) < duration:
        ends[-1] = np.nextafter(tf, np.inf)
    return ends[:-1], ends[1:]


def _split(lo: np.ndarray, hi: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Each box [lo_j, hi_j] cut into k boxes that share their float ends (rounding is
    monotone, so they cover it)."""
    f = np.arange(k + 1) / k
    ends = lo[:, None] + (hi - lo)[:, None] * f[None, :]
    ends[:, 0], ends[:, -1] = lo, hi
    return ends[:, :-1].ravel(), ends[:, 1:].ravel()


def _fan(n_live: int) -> int:
    """How many boxes each live box is cut into: the pass costs its calls, not its length."""
    return int(min(MAX_FAN, max(2, SPLIT_BUDGET // max(n_live, 1))))


def _last_float(duration: fmpq) -> float:
    """The largest float <= t_f."""
    tf = to_float(duration)
    if fmpq(*tf.as_integer_ratio()) > duration:
        tf = float(np.nextafter(tf, -np.inf))
    return tf


def _clip(duration: fmpq, t: np.ndarray) -> np.ndarray:
    """t moved into [0, t_f] (the largest float <= t_f at the end)."""
    return np.clip(t, 0.0, _last_float(duration))


@dataclass
class _Bounds:
    """What one pass proves about boxes [lo_j, hi_j], per torque i (rows):
    ``low``/``low_t``: a certified value of |T_i| at a time of the box (a lower bound of
    its max there; 0 with no such value), ``up``: an upper bound of |T_i| over the box,
    ``floor``: a lower bound of |T_i| over the box."""

    lo: np.ndarray
    hi: np.ndarray
    low: np.ndarray
    low_t: np.ndarray
    up: np.ndarray
    floor: np.ndarray
    ends: tuple[np.ndarray, ...] | None = None  # |T| at the ends: bounds, values (``_crossing``)
    monotone: np.ndarray | None = None  # |T_i| monotone on the box (T' ∌ 0, T ∌ 0)


def prune(
    b: _Bounds, best: np.ndarray, best_t: np.ndarray, dropped: np.ndarray, rel: float
) -> tuple[np.ndarray, list[int | None]]:
    """One round of the peak's branch and bound: ``best``/``best_t`` (per torque) raised
    to the boxes' largest certified lower bound, and ``dropped`` to the largest upper
    bound of a box set aside (it cannot hold a value above best (1 + rel) + PEAK_ABS);
    returns the boxes kept and, per torque, the box whose lower bound became the best
    (None where the best stayed)."""
    better: list[int | None] = []
    for i in (0, 1):
        j = int(np.argmax(b.low[i]))
        better.append(j if b.low[i, j] > best[i] else None)
        if better[i] is not None:
            best[i], best_t[i] = float(b.low[i, j]), float(b.low_t[i, j])
    keep_i = b.up > (best * (1 + rel) + PEAK_ABS)[:, None]
    dropped[:] = np.maximum(dropped, np.where(keep_i, 0.0, b.up).max(axis=1))
    return np.asarray(keep_i.any(axis=0)), better


def _loose(c: LimitCheck) -> bool:
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


class Envelope:
    """Grid-free torque verdicts for one task (module docstring)."""

    def __init__(self, motion: CertifiedMotion) -> None:
        self.motion = motion
        self.duration = motion.traj.duration
        self.bounded = [s for s in motion.analysis.instants if s.torque_bounded]
        self.poles = [s for s in motion.analysis.instants if not s.torque_bounded]
        self.throughs = [_Through(motion, k.leg, k.time) for k in motion.kinematic]
        self.tf = to_float(self.duration)
        self.t_last = _last_float(self.duration)
        self._coeffs: dict[int, list[list[arb]]] = {}  # Taylor coefficients about instants
        self._zones: dict[int, Zone | None] = {}  # about the instants (``zone``)
        self._pole_zones = False  # zones about poles too, not only where points are poor
        self.box_models = MAX_BOX_MODELS  # left to spend (``_near_instant``)
        self._first: _Bounds | None = None  # the pass over the first partition
        self._peak: tuple[Peak, Peak] | None = None
        self._checks: dict[tuple[float, float], tuple[LimitCheck, LimitCheck]] = {}

    @cached_property
    def polys(self) -> _Polys:
        """The motion's polynomials as balls (made for the first pass)."""
        return _Polys(self.motion)

    @cached_property
    def stacked(self) -> _Stacked:
        return per_robot(self.motion.robot, _Stacked)

    # -- one pass -------------------------------------------------------------------------
    def _pass(self, t: Ball) -> tuple[Ball, Ball]:
        """T (stacked rows) and T' over the balls of time ``t``: first-order jets."""
        with quiet():
            x, xd, xdd, y, yd, ydd = self.polys.jets(self.motion, t)
            T, _ = self.stacked.torques(self.stacked.legs(x, xd, xdd, y, yd, ydd), y)
            V, D = _full(T.v, len(t.mid)), _full(T.d, len(t.mid))  # t-free parts too
            for th in self.throughs:
                V, D = self._through(th, t, V, D, _poor(V) | _poor(D))
        return V, D

    def _values(self, t: np.ndarray) -> Ball:
        """T (stacked rows) at the float times ``t``: the values of ``_pass`` without the
        derivatives (the factored form near t_A, on jets, where the direct one is poor)."""
        with quiet():
            x, xd, xdd, y, yd, ydd = (J.v for J in self.polys.jets(self.motion, Ball.exact(t)))
            T, _ = self.stacked.torques(self.stacked.legs(x, xd, xdd, y, yd, ydd), y)
            V = _full(T, len(t))
            for th in self.throughs:  # rare
                zero = Ball._of(np.zeros_like(V.mid), np.zeros_like(V.rad))
                V, _ = self._through(th, Ball(t, np.zeros_like(t)), V, zero, _poor(V))
        return V

    def _through(
        self, th: _Through, t: Ball, V: Ball, D: Ball, poor: np.ndarray
    ) -> tuple[Ball, Ball]:
        """V (T) and D (T') made narrower near t_A by the factored form (``_Through``) on
        each side of t_A that the balls of time reach within [0, t_f] (the hull of both
        sides where a ball holds t_A: T is then bounded by either side's values), for the
        columns ``poor`` (where the direct form is poor: elsewhere it is kept)."""
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
        m = len(idx)
        bounds = [np.full((2, m), np.inf * sign) for sign in (1, -1, 1, -1)]  # V, D: lo, hi
        for sel, side in ((right, 1), (left, -1)):
            j = np.nonzero(sel)[0]
            if not len(j):
                continue
            if side > 0:
                e = Ball.hull(np.maximum(el[j], 0.0), np.maximum(eh[j], 0.0))
            else:
                e = Ball.hull(np.minimum(el[j], 0.0), np.minimum(eh[j], 0.0))
            sigma = 1.0 if side > 0 else (-1.0) ** th.k
            T, _ = th.torques(self.stacked, e, sigma)
            for q, B in enumerate((T.v, T.d)):
                lo_q, hi_q = bounds[2 * q], bounds[2 * q + 1]
                lo_q[:, j] = np.minimum(lo_q[:, j], np.broadcast_to(B.lower(), (2, len(j))))
                hi_q[:, j] = np.maximum(hi_q[:, j], np.broadcast_to(B.upper(), (2, len(j))))
        some = left | right
        k = idx[some]
        for q in (0, 1):
            lo_q, hi_q = bounds[2 * q][:, some], bounds[2 * q + 1][:, some]
            ok = np.isfinite(lo_q) & np.isfinite(hi_q)
            B = Ball.hull(np.where(ok, lo_q, 0.0), np.where(ok, hi_q, 0.0))
            B = Ball._of(np.where(ok, B.mid, np.nan), np.where(ok, B.rad, np.inf))
            if q == 0:
                V = _put(V, k, B)
            else:
                D = _put(D, k, B)
        return V, D

    def bounds(self, lo: np.ndarray, hi: np.ndarray, need: float = 0.0) -> _Bounds:
        """One vectorised pass over the boxes and their ends (``_Bounds``), with the zone
        and Taylor forms near singular instants where the direct form is poor."""
        n = len(lo)
        times, where = np.unique(np.concatenate([lo, hi]), return_inverse=True)
        with quiet():
            box = Ball.hull(lo, hi)
            B, D = self._pass(box)  # T and T' over the boxes
            P = self._values(times)  # T at the ends, each once (boxes share their ends)
            P, B = self._near(times, lo, hi, P, B, need)
            P = Ball._of(P.mid[:, where], P.rad[:, where])
            pa, pb = P[:, :n], P[:, n:]
            ua, ub = pa.upper_abs(), pb.upper_abs()
            la, lb = pa.lower_abs(), pb.lower_abs()
            valid = np.concatenate([lo, hi]) <= self.t_last
            la = np.where(valid[:n], la, 0.0)
            lb = np.where(valid[n:], lb, 0.0)
            width = 2.0 * box.rad  # >= hi - lo
            slope = D.upper_abs()
            # |T(t)| <= min(|T(a)| + D (t - a), |T(b)| + D (b - t)) <= the mean of the two
            mean_value = round_up((ua + ub + slope * width) * 0.5)
            up = np.minimum(B.upper_abs(), mean_value)
            mono = D.lower_abs() > 0  # T monotone on the box: |T| peaks at an end
            mono_ok = mono & np.isfinite(ua) & np.isfinite(ub)
            up = np.where(mono_ok, np.minimum(up, np.maximum(ua, ub)), up)
            same = mono_ok & (pa.lower() > 0) & (pb.lower() > 0) | (
                mono_ok & (pa.upper() < 0) & (pb.upper() < 0)
            )
            around = pa + D * Ball(0.5 * width, 0.5 * width)
            floor = np.maximum(B.lower_abs(), around.lower_abs())
            floor = np.where(same, np.maximum(floor, np.minimum(la, lb)), floor)
            low = np.maximum(la, lb)
            low_t = np.where(la >= lb, lo, hi)
        up = np.where(np.isnan(up), np.inf, up)
        ends = (np.where(valid[:n], ua, np.inf), np.where(valid[n:], ub, np.inf), la, lb,
                np.abs(pa.mid), np.abs(pb.mid))  # fmt: skip
        return _Bounds(lo, hi, low, low_t, up, floor, ends, same)

    def _near(
        self, pts: np.ndarray, lo: np.ndarray, hi: np.ndarray, P: Ball, B: Ball, need: float
    ) -> tuple[Ball, Ball]:
        """P (T at the points) and B (T over the boxes) made narrower near singular
        instants: the zone form inside a zone, else a Taylor form per box (``_near_instant``)
        for the boxes whose direct enclosure is poor and whose bound matters (> need)."""
        if not self.motion.instants:
            return P, B
        poor_p = ~(P.rad <= np.abs(P.mid)).all(axis=0)
        poor_b = ~(B.rad <= np.abs(B.mid)).all(axis=0)
        covered = np.zeros(len(lo), dtype=bool)
        box = Ball.hull(lo, hi)
        for k, (s, e) in enumerate(self.motion.instants):
            if not (s.torque_bounded or self._pole_zones or self._poor_beside(e, pts, poor_p)):
                continue  # beside a pole the direct form is good: no zone needed (yet)
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
            P = _put(P, ip, Tz[:, : len(ip)])
            B = _put(B, ib, Tz[:, len(ip) :])
        wanted = ~(B.upper_abs() <= need).all(axis=0)
        rest = ~(B.rad <= np.abs(B.mid)).all(axis=0) & wanted & ~covered
        if self.box_models <= 0 and rest.any():  # only boxes holding an instant are left
            holds = np.zeros(len(lo), dtype=bool)
            for _, e in self.motion.instants:
                holds |= (e.compare(lo) <= 0) & (e.compare(hi) >= 0)
            rest &= holds
        for j in np.nonzero(rest)[0][:NEAR_PER_PASS]:  # the others are cut further
            got = self._near_instant(float(lo[j]), float(hi[j]))
            if got is not None:
                col = [g.normal() for g in got]
                B = _put(B, np.array([j]), Ball._of(
                    np.array([[float(np.ravel(g.mid)[0])] for g in col]),
                    np.array([[float(np.ravel(g.rad)[0])] for g in col])))  # fmt: skip
        return P, B

    def _zone_torques(self, zone: Zone, mid: np.ndarray, rad: np.ndarray) -> Ball:
        """T (stacked) over the balls mid ± rad of time inside a zone, λ from its form."""
        with quiet():
            t = Ball._of(mid, rad)
            eps = zone.e.eps(mid) + Ball(0.0, rad)
            lam = zone.lam(eps)
            x, xd, xdd, y, yd, ydd = (J.v for J in self.polys.jets(self.motion, t))
            T, _ = self.stacked.torques(self.stacked.legs(x, xd, xdd, y, yd, ydd), y, lam)
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
                x, xd, xdd, y, yd, ydd = (J.v for J in self.polys.jets(self.motion, t))
                T, _ = self.stacked.torques(self.stacked.legs(x, xd, xdd, y, yd, ydd), y, lam)
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

    def _start(self) -> _Bounds:
        """The pass over the first partition, made once (shared by every verdict): the
        uniform boxes, cut finer about the likely maxima of |T| (``_ladders``) so that
        one pass often certifies the peak."""
        if self._first is None:
            lo, hi = _boxes(self.duration, START_BOXES)
            cuts = self._ladders(float(hi[0] - lo[0]))
            if len(cuts):
                ends = np.unique(np.concatenate([lo, hi[-1:], cuts]))
                lo, hi = ends[:-1], ends[1:]
            self._first = self.bounds(lo, hi)
        return self._first

    def _ladders(self, h: float) -> np.ndarray:
        """Cuts about the times t* where |T1| or |T2| looks largest (the maxima of a
        double-precision evaluation on LADDER_GRID points, not within t_f/64 of an
        instant, refined by a parabola): LADDER_CORE boxes of h/LADDER_SPLIT on either
        side (h the uniform width), then boxes growing by LADDER_RATIO out to
        LADDER_REACH h. About a maximum, the mean-value form bounds |T| over a box of
        width w within ~C w² of the maximum (C: the enclosure of T' over the box, wider
        than |T''| w), and a box at a distance r from it below the maximum when w is a
        small fraction of r: the passes over the corpus of bench_many fall by a fifth
        (often the first one certifies the peak). The doubles only choose where to cut:
        every bound still comes from the ball pass (a wrong guess costs another pass,
        never a wrong value)."""
        if not self.tf > 0:
            return np.zeros(0)
        t = np.linspace(0.0, self.t_last, LADDER_GRID)
        with np.errstate(all="ignore"):
            T = np.abs(self._float_torques(t))
        T[~np.isfinite(T)] = -1.0
        for e in [e for _, e in self.motion.instants] + [th.e for th in self.throughs]:
            T[:, np.abs(t - e.hi) <= self.tf / 64] = -1.0  # the doubles cancel near t_s
        fine = h / LADDER_SPLIT
        core = fine * np.arange(1, LADDER_CORE + 1)
        far = core[-1] * LADDER_RATIO ** np.arange(1, 64)
        steps = np.concatenate([core, far[far < LADDER_REACH * h]])
        cuts = []
        for row in T:
            j = int(np.argmax(row))
            if not row[j] > 0:
                continue
            c = t[j]
            if 0 < j < len(t) - 1:  # the parabola through the three samples about the max
                a, b, e = row[j - 1], row[j], row[j + 1]
                den = a - 2 * b + e
                if den < 0:
                    c = t[j] + 0.5 * (a - e) / den * (t[1] - t[0])
            cuts.append(np.concatenate([[c], c - steps, c + steps]))
        if not cuts:
            return np.zeros(0)
        out = np.concatenate(cuts)
        return out[(out > 0.0) & (out < self.t_last)]

    def _float_torques(self, t: np.ndarray) -> np.ndarray:
        """T1, T2 (rows) at the times t in double precision, from the same formulas
        (``equations``) on the recentred polynomials: a guide for ``_ladders``, no bound."""
        m, traj = self.motion, self.motion.traj

        def values(p: fmpq_poly, at: np.ndarray) -> list[np.ndarray]:
            d1 = p.derivative()
            return [np.polynomial.polynomial.polyval(at, [to_float(c) for c in q.coeffs()] or [0.0])
                    for q in (p, d1, d1.derivative())]  # fmt: skip

        x, xd, xdd = values(traj.x, t)
        if traj.path is not None:
            q, q1, q2 = values(m.recentred, x - to_float(m.center))
            y, yd, ydd = q, q1 * xd, q2 * xd * xd + q1 * xdd
        else:
            y, yd, ydd = values(m.recentred, t - to_float(m.t_center))
        a1 = to_float(traj.a1)
        l1 = dyn.leg(x, xd, xdd, y, yd, ydd, np.hypot)
        l2 = dyn.leg(x - a1, xd, xdd, y, yd, ydd, np.hypot)
        d = dyn.dynamics(l1, l2, dyn.Params.of(m.robot, to_float))
        return np.array(dyn.efforts(d, d.mu1 / d.delta, d.mu2 / d.delta))

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
        b = self._start()
        best, best_t = np.zeros(2), np.zeros(2)
        for s in self.bounded:  # the limits at bounded instants are values of T too
            if s.torque_at_singularity is not None:
                for i in (0, 1):
                    v = abs(s.torque_at_singularity[i]) * (1 - 4 * U)
                    if v > best[i]:
                        best[i], best_t[i] = v, s.t
        dropped = np.zeros(2)  # the largest upper bound of a box set aside
        certified = False
        for _ in range(MAX_ROUNDS):
            keep, _ = prune(b, best, best_t, dropped, rel)
            n = int(keep.sum())
            if not n:
                certified = True
                break
            if n > MAX_LIVE:
                break
            lo, hi = _split(b.lo[keep], b.hi[keep], _fan(n))
            b = self.bounds(lo, hi, float(best.min() * (1 + rel)))
        out = []
        for i in (0, 1):
            up = max(best[i], dropped[i])
            if not certified:
                up = max(up, float(b.up[i].max(initial=0.0)))
            out.append(Peak(float(best[i]), float(best_t[i]), float(up), certified))
        return out[0], out[1]

    # -- limits ---------------------------------------------------------------------------
    def limit_violations(self, limit: tuple[float, float]) -> tuple[LimitCheck, LimitCheck]:
        """Whether |T_i(t)| <= limit_i for every t in [0, t_f], per torque, certified
        (made once per limit)."""
        key = (float(limit[0]), float(limit[1]))
        if key not in self._checks:
            got = self._limits(key)
            if not self._pole_zones and self.poles and any(_loose(c) for c in got):
                self._pole_zones = True  # beside a pole the direct form fell short: again,
                self.box_models = MAX_BOX_MODELS  # with the zones about the poles
                got = self._limits(key)
            self._checks[key] = got
        return self._checks[key]

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
            k = _fan(n)
            if n * k > MAX_LIVE * 4:  # the work cap: the open boxes stay undecided
                for i in (0, 1):
                    rec = act[i]
                    done[i].append((lo[rec], hi[rec], np.zeros(int(rec.sum()), dtype=int)))
                break
            lo, hi, src = self._refine(lo, hi, split, k, res)
            active = act[:, src]
            b = self.bounds(lo, hi, float(L.min()))
        if pending:  # stopped by a cap: the brackets not closed stay undecided
            lo, hi, act = self._bracket(pending, L, res, done)
            for i in (0, 1):
                done[i].append((lo[act[i]], hi[act[i]], np.zeros(int(act[i].sum()), dtype=int)))
        out = []
        for i in (0, 1):
            parts = done[i]
            Ls = np.concatenate([p[0] for p in parts])
            Hs = np.concatenate([p[1] for p in parts])
            Ss = np.concatenate([p[2] for p in parts]).astype(int)
            order = np.argsort(Ls, kind="stable")
            Ls, Hs, Ss = self._sharpen(i, float(L[i]), res, Ls[order], Hs[order], Ss[order])
            windows = self._windows(Ls, Hs, Ss)
            above = bool(seen_above[i]) or bool((Ss == 1).any()) or bool(self.poles)
            passed: bool | None = False if above else (True if (Ss == -1).all() else None)
            out.append(LimitCheck(float(L[i]), passed, tuple(windows), res))
        return out[0], out[1]

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

    def _limit_start(self, L: np.ndarray, res: float) -> _Bounds:
        """The limit check's first pass: the first partition's (``_start``, shared with
        the peak) when the peak made it; else the uniform partition (a limit needs no
        guess of where |T| peaks, and no Taylor form where the direct bound is below it:
        a limit far above the torques is decided in this one pass), with the boxes
        holding a pole cut about it already (``_around_pole``)."""
        if self._first is not None:
            return self._first
        lo, hi = _boxes(self.duration, START_BOXES)
        if not self.poles:  # no peak asked for: the uniform boxes, no guess of its maxima
            return self.bounds(lo, hi, float(L.min()))
        lo, hi, _ = self._refine(lo, hi, np.ones(len(lo), dtype=bool), 1, res)
        return self.bounds(lo, hi, float(L.min()))

    def _refine(
        self, lo: np.ndarray, hi: np.ndarray, which: np.ndarray, k: int, res: float
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The boxes ``which`` cut for the next pass, each into k (k = 1: kept), or,
        holding a pole, into pieces about it (``_around_pole``); with the index of the
        box each new box comes from. The others are dropped."""
        pole = self._holds_pole(lo, hi) & which
        plain = np.nonzero(which & ~pole)[0]
        los, his = _split(lo[plain], hi[plain], k)
        parts = [(los, his, np.repeat(plain, k))]
        for j in np.nonzero(pole)[0]:  # pieces growing away from the pole
            plo, phi = self._around_pole(float(lo[j]), float(hi[j]), res)
            parts.append((plo, phi, np.full(len(plo), j)))
        return tuple(np.concatenate([p[q] for p in parts]) for q in range(3))  # type: ignore[return-value]

    def _crossings(self, b: _Bounds, L: np.ndarray, open_: np.ndarray) -> _Crossings:
        """The open boxes on which |T_i| is monotone (``_Bounds.monotone``) with one end
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

    def _holds_pole(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        """The boxes [lo, hi] that may hold an instant with unbounded torques."""
        out = np.zeros(len(lo), dtype=bool)
        for s, e in self.motion.instants:
            if not s.torque_bounded:
                out |= (lo <= e.hi + e.err + abs(e.lo)) & (hi >= e.hi - e.err - abs(e.lo))
        return out

    def _around_pole(self, lo: float, hi: float, res: float) -> tuple[np.ndarray, np.ndarray]:
        """[lo, hi] (holding a pole of order k) cut at t_p ± d q^j (d = 0.45 res, t_p the
        nearest float to the pole, q = 1 + POLE_GROWTH/k): a piece of width 2d about the
        pole (left undecided), and pieces whose widths grow with their distance to it,
        on which |T| ~ C/|t - t_s|^k changes by a factor of about e^POLE_GROWTH at most,
        so that one pass decides most of them (a uniform cut would spend most pieces far
        from the pole, and a coarser one leaves them open for another pass)."""
        s, c = min(((s, e.hi) for s, e in self.motion.instants if not s.torque_bounded),
                   key=lambda p: abs(p[1] - 0.5 * (lo + hi)))  # fmt: skip
        q = 1.0 + POLE_GROWTH / max(s.pole_order, 1)
        d = 0.45 * res
        n = math.ceil(math.log(max(hi - lo, d) / d) / math.log(q)) + 1
        steps = d * q ** np.arange(n + 1)
        cuts = np.concatenate([c - steps, c + steps])
        ends = np.unique(np.concatenate([[lo, hi], cuts[(cuts > lo) & (cuts < hi)]]))
        return ends[:-1], ends[1:]

    def _windows(self, L: np.ndarray, H: np.ndarray, S: np.ndarray) -> list[Window]:
        """Maximal runs of boxes not below the limit that hold a box above it (or a pole):
        the run's open boxes at its ends bracket the crossings."""
        edges = np.diff(np.concatenate([[0], (S != -1).astype(int), [0]]))
        starts, ends = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0] - 1
        ones = np.nonzero(S == 1)[0]
        pole_times = [s.t for s in self.poles]
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


def min_abs_y(traj: Trajectory, duration: fmpq) -> tuple[float, float]:
    """min |y(t)| over [0, t_f] (the double nearest it) and where: at the ends or at a
    real root of y', exactly at a rational time, else in arb to 64 bits (``accurate``)."""
    cands: list[tuple[arb, float]] = []
    y = traj.y
    for t in (fmpq(0), duration):
        cands.append((ball(abs(y(t))), to_float(t)))
    for e in ExactTime.roots(traj.yd, duration):
        if e.exact is not None:
            cands.append((ball(abs(y(e.exact))), e.hi))
        else:
            cands.append((accurate(partial(_abs_at, y, e.at), 64), e.hi))
    v, t = min(cands, key=lambda c: float(c[0].mid()))
    return float(v.mid()), t


def _poly_at(p: fmpq_poly, t: arb) -> arb:
    return arb_poly(p.coeffs())(t)


def _abs_at(p: fmpq_poly, at: Callable[[int], arb], prec: int) -> arb:
    """|p| over the ball ``at(prec)`` of an exact time."""
    return abs(_poly_at(p, at(prec)))


def min_abs_delta(traj: Trajectory, duration: fmpq) -> tuple[float, float, float]:
    """(lo, hi, t): min |δ| over [0, t_f] lies in [lo, hi] (rounded outward; hi - lo is
    about 2^-64 of it, or 0 at a rational time) and is reached at about t, for a motion
    that never meets y = 0.

    δ² = a1² y²/Q with Q = s1² s2² = (x² + y²)((x - a1)² + y²) > 0, so |δ| is least at
    t = 0, t_f or a root of (δ²)' = a1² y R/Q², R = 2 y' Q - y Q', in (0, t_f) (where
    y ≠ 0): the critical times of ``_delta_critical``; |δ| at each, exactly (δ² in Q) at
    a rational one, else in arb at a precision raised until it is accurate."""
    times: list[fmpq | Callable[[int], arb]] = [fmpq(0), duration]
    for f, square_free in _delta_critical(traj):
        times += [r if r is not None else at
                  for r, at in real_roots_in(f, duration, simple=square_free)]  # fmt: skip
    lo, hi, t_min = math.inf, math.inf, 0.0
    for t in times:
        if isinstance(t, fmpq):
            x, y = traj.x(t), traj.y(t)
            q = (x * x + y * y) * ((x - traj.a1) ** 2 + y * y)
            d = ball(traj.a1**2 * y * y / q).sqrt() if q != 0 else arb("nan")
            where = to_float(t)
        else:
            d = accurate(partial(_delta_at, traj, t), 64)
            where = float(t(128).mid())
        if not d.is_finite():  # Q > 0 should be proven; else no bound from here
            lo, up = 0.0, math.inf
        else:
            lo = min(lo, max(0.0, math.nextafter(float(d.lower()), -math.inf)))
            up = math.nextafter(float(d.upper()), math.inf)
        if up < hi:
            hi, t_min = up, where
    return lo, hi, t_min


def _delta_at(traj: Trajectory, at: Callable[[int], arb], prec: int) -> arb:
    """|δ| = a1 |y|/(s1 s2) over the ball ``at(prec)`` of an exact time (eq. 29)."""
    t = at(prec)
    a1 = arb(traj.a1)
    x, y = _poly_at(traj.x, t), _poly_at(traj.y, t)
    u = x - a1
    return abs(a1 * y) / ((x * x + y * y) * (u * u + y * y)).sqrt()


def _delta_critical(traj: Trajectory) -> list[tuple[fmpq_poly, bool]]:
    """Polynomials in t whose roots in (0, t_f) hold the roots of R = 2 y' Q - y Q'
    (``min_abs_delta``), each with whether it is square-free with no rational root.

    With a path y = p(x), R(t) = x'(t) R~(x(t)) where R~ = 2 p' Q~ - p Q~' in x and Q~ =
    (x² + p²)((x - a1)² + p²) (degree 4 deg p, not 4 deg y): x' itself, and per
    irreducible factor f of R~, x(t) - r for a rational root r of f, or else the
    square-free part of f(x(t)) (no rational root: x at it would be a rational root of
    f). Without a path, R itself."""
    if traj.path is None:
        q = (traj.x**2 + traj.y**2) * ((traj.x - traj.a1) ** 2 + traj.y**2)
        return [(2 * traj.y.derivative() * q - traj.y * q.derivative(), False)]
    p, x = traj.path, traj.x
    X = fmpq_poly([0, 1])
    q = (X**2 + p**2) * ((X - traj.a1) ** 2 + p**2)
    r = 2 * p.derivative() * q - p * q.derivative()
    out: list[tuple[fmpq_poly, bool]] = [(x.derivative(), False)]
    if r.is_zero():
        return out  # δ constant along the path
    for f, _ in r.factor()[1]:
        if f.degree() == 1:
            out.append((x - (-f[0] / f[1]), False))
        elif f.degree() > 1:
            h = f(x)
            out.append((h // h.gcd(h.derivative()), True))
    return out

"""Forms of λ about a singular instant that leave no cancellation (for balls of time).

About a Type II instant t_s of order m (δ and its first m - 1 derivatives vanish there),
μ_i vanishes to order k_i (``SingularInstant.mu_valuations``), so λ_i = μ_i/δ is a quotient
of two small numbers whose digits cancel when evaluated directly. Expanded about t_s,
the vanishing coefficients are exactly zero and can be dropped:

* ``taylor_lambda``: Taylor's theorem with the Lagrange remainder: for t in a box and T
  the hull of the box and t_s, μ_i(t) = μ_i^(k_i)(ξ)/k_i! ε^k_i and δ(t) =
  δ^(m)(ξ')/m! ε^m (ε = t - t_s, ξ and ξ' between t_s and t), and flint's ``arb_series``
  evaluated on the ball T encloses f^(j)(ξ)/j! for every ξ ∈ T in its coefficient j
  (each series operation maps point Taylor coefficients to point Taylor coefficients and
  ball arithmetic contains every point case). Hence λ_i ∈ (c_i/d) ε^(k_i - m) with
  c_i ∈ coef_k_i(μ_i)(T), d ∈ coef_m(δ)(T), when d ∌ 0 and s1, s2 > 0 on T.
* ``Zone`` (``make_zone``): the same with N terms at the point t_s and a remainder bound
  valid on a whole zone |ε| <= r, evaluated on balls of ε (vectorised).
* ``taylor_box``: a Taylor model about a box's own midpoint (for boxes clear of t_s).

The Taylor coefficients of x and y at a ball are taken from their exact Taylor
coefficients about t_s (``taylor_at_instant``) by Horner in the series ε + τ: the
expanded polynomials in t, evaluated on a ball, would not stay tight.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from flint import acb, acb_poly, arb, arb_series, ctx, fmpq

from ..model.numbers import to_float
from . import equations as dyn
from .balls import ETA, Ball, U, horner, quiet, stack, two_sum
from .series import taylor
from .singular import SingularInstant


class CertifiedMotion(Protocol):
    """What the zone forms read of a certified motion (``certified.CertifiedMotion``)."""

    traj: Any
    robot: Any
    analysis: Any
    instants: Any


@dataclass
class ExactTime:
    """A time known exactly: a rational, or a real root given by certified arb balls.

    ``hi + lo`` is a double-double within ``err`` of it, so that ε = t - t_s is a ball
    of radius about u|ε| for any float t (``eps``)."""

    exact: fmpq | None
    at: Callable[[int], arb]
    hi: float = 0.0
    lo: float = 0.0
    err: float = 0.0

    def __post_init__(self) -> None:
        if self.exact is not None:
            self.hi = to_float(self.exact)
            r1 = self.exact - fmpq(*self.hi.as_integer_ratio())
            self.lo = to_float(r1)
            r2 = r1 - fmpq(*self.lo.as_integer_ratio())
            self.err = abs(to_float(r2)) * (1 + 4 * U) + ETA
        else:
            old = ctx.prec
            ctx.prec = 256
            try:
                b = self.at(256)
                self.hi = float(b.mid())
                rest = b.mid() - arb(self.hi)
                self.lo = float(rest.mid())
                e = (b - arb(self.hi) - arb(self.lo)).abs_upper()
                self.err = float(e) * (1 + 4 * U) + ETA
            finally:
                ctx.prec = old

    @property
    def t(self) -> float:
        return self.hi

    def eps(self, t: np.ndarray) -> Ball:
        """A ball containing t - t_s for each float t."""
        e1, e2 = two_sum(t, np.full_like(t, -self.hi))
        return Ball.exact(e1) + ((Ball.exact(e2) - self.lo) + Ball(0.0, self.err))

    def compare(self, t: np.ndarray) -> np.ndarray:
        """sign(t - t_s) for each float t, decided exactly."""
        e = self.eps(t)
        out = np.sign(e.mid).astype(int)
        for j in np.nonzero(e.contains_zero())[0]:
            out[j] = self.sign_at(float(t[j]))
        return out

    def sign_at(self, t: float) -> int:
        q = fmpq(*t.as_integer_ratio())
        if self.exact is not None:
            d = q - self.exact
            return (d > 0) - (d < 0)
        prec = 64
        while True:  # an irrational t_s is no float: refining decides
            d = arb(q) - self.at(prec)
            if d > 0:
                return 1
            if d < 0:
                return -1
            prec *= 2


TAYLOR_PREC = 128  # bits of the Taylor forms, to start with
ZONE_TERMS = 48  # terms of the zone form beyond the leading ones
CIRCLE_BALLS = 64  # complex balls covering the circle of a Cauchy bound
DISC_GRID = 12  # complex balls per side of the grid proving analyticity on a disc
ZONE_SLACK = 1e-9  # a zone's remainders stay below this fraction of its leading terms
TAYLOR_BOX_ORDER = 4  # degree N of the Taylor model over a box (``taylor_box``)


def _hypot(u: Any, v: Any) -> Any:
    return (u * u + v * v).sqrt()


def taylor_at_instant(motion: CertifiedMotion, s: SingularInstant, prec: int) -> list[list[arb]]:
    """The Taylor coefficients of x(t) and y(t) about t_s (exact values rounded to balls)."""
    out = []
    for p in (motion.traj.x, motion.traj.y):
        cs = taylor(p, max(p.degree(), 0) + 1)
        if s.t_rational is not None:
            out.append([arb(c(s.t_rational)) for c in cs])
        else:
            field = motion.analysis.hints(s).field
            out.append([field.evaluate(c % field.f, prec) for c in cs])
    return out


def series_at(coeffs: list[list[arb]], eps: arb, n: int) -> tuple[Any, ...]:
    """The series (n terms) of x, x', x'', y, y', y'' about every point t_s + ε, ε ∈ eps:
    Horner in the series ε + τ on the Taylor coefficients about t_s, which stays tight
    (the expanded polynomial in t would not, evaluated on a ball)."""
    var = arb_series([eps, arb(1)])
    out = []
    for cs in coeffs:
        acc = arb_series([cs[-1]])
        for c in cs[-2::-1]:
            acc = acc * var + c
        full = acc.coeffs() + [arb(0)] * (n + 2)
        out.append(arb_series(full[:n]))
        out.append(arb_series([(k + 1) * full[k + 1] for k in range(n)]))
        out.append(arb_series([(k + 1) * (k + 2) * full[k + 2] for k in range(n)]))
    return tuple(out)


def taylor_lambda(
    motion: CertifiedMotion, s: SingularInstant, lo: float, hi: float,
    coeffs: list[list[arb]] | None = None,
) -> tuple[Ball, Ball] | None:  # fmt: skip
    """Balls containing λ1(t), λ2(t) for every t in [lo, hi] by the Taylor form about the
    instant ``s`` (module docstring); None where it does not apply (d ∋ 0, s ∋ 0).
    ``coeffs``: the Taylor coefficients of x and y about t_s, when already computed."""
    e = motion.instants[motion.analysis.instants.index(s)][1]
    m = s.order
    ks = [
        min(v, m + 1) for v in motion.analysis.hints(s).mu_valuations
    ]  # μ_i's first k_i coefficients vanish
    n = max(*ks, m) + 1
    old_prec, old_cap = ctx.prec, ctx.cap
    ctx.prec, ctx.cap = TAYLOR_PREC, n + 2
    try:
        ts = arb(e.exact) if e.exact is not None else e.at(TAYLOR_PREC)
        E = (arb(lo) - ts).union(arb(hi) - ts).union(arb(0))  # ξ - t_s for ξ in hull
        if coeffs is None:
            coeffs = taylor_at_instant(motion, s, TAYLOR_PREC)
        X, Xd, Xdd, Y, Yd, Ydd = series_at(coeffs, E, n)
        ctx.cap = n
        a1 = arb(motion.traj.a1)
        l1 = dyn.leg(X, Xd, Xdd, Y, Yd, Ydd, _hypot)
        l2 = dyn.leg(X - a1, Xd, Xdd, Y, Yd, Ydd, _hypot)
        d = dyn.dynamics(l1, l2, dyn.Params.of(motion.robot, arb))
        dm = _coef(-(Y * a1) / (l1.s * l2.s), m)  # δ^(m)(ξ)/m!, eq. (29)
        if not dm.is_finite() or dm.contains(0):
            return None
        eps = Ball.hull(np.array([lo]), np.array([hi])) - Ball.of_arb(ts)
        out = []
        with quiet():
            for mu, k in ((d.mu1, ks[0]), (d.mu2, ks[1])):
                c = _coef(mu, k) / dm
                if not c.is_finite():
                    return None
                power = Ball.exact(1.0)
                for _ in range(abs(k - m)):
                    power = power * eps
                ratio = Ball.of_arb(c)
                out.append(ratio * power if k >= m else ratio / power)
        return out[0], out[1]
    except (ValueError, ZeroDivisionError):  # a square root of a ball reaching below 0
        return None
    finally:
        ctx.prec, ctx.cap = old_prec, old_cap


def _coef(s: Any, k: int) -> arb:
    c = s.coeffs()
    return c[k] if k < len(c) else arb(0)


def _torque_series(motion: CertifiedMotion, ser: tuple[Any, ...]) -> tuple[Any, Any]:
    """T1, T2 as series from the series of x, x', x'', y, y', y'' (eqs. 28-31)."""
    X, Xd, Xdd, Y, Yd, Ydd = ser
    a1 = arb(motion.traj.a1)
    l1 = dyn.leg(X, Xd, Xdd, Y, Yd, Ydd, _hypot)
    l2 = dyn.leg(X - a1, Xd, Xdd, Y, Yd, Ydd, _hypot)
    d = dyn.dynamics(l1, l2, dyn.Params.of(motion.robot, arb))
    delta = -(Y * a1) / (l1.s * l2.s)  # eq. (29), product form
    T1, T2 = dyn.torques(d, d.mu1 / delta, d.mu2 / delta)
    return T1, T2


def taylor_box(
    motion: CertifiedMotion, coeffs: list[list[arb]], ts: arb, lo: float, hi: float
) -> tuple[Ball, Ball] | None:
    """T1, T2 over [lo, hi] (clear of singular instants) by a Taylor model about the
    box's midpoint c: T(c + e) ∈ Σ_{j<N} T_j(c) e^j + T_N(box) e^N for |e| <= h, with
    T_j(c) from series at the point c (precision raised until they are tight: near a
    high-order instant μ/δ cancels) and T_N enclosing T^(N)(ξ)/N! over the box (the
    Lagrange remainder). The series of x and y come from their Taylor coefficients about
    the nearest exact instant t_s (``coeffs``, ``ts``), which stay tight on a ball."""
    n = TAYLOR_BOX_ORDER + 1
    old_prec, old_cap = ctx.prec, ctx.cap
    try:
        ctx.prec, ctx.cap = TAYLOR_PREC, n + 2
        c = arb(0.5 * lo + 0.5 * hi)
        box = arb(lo).union(arb(hi))
        e = (arb(lo) - c).union(arb(hi) - c)
        far = _torque_series(motion, series_at(coeffs, box - ts, n))
        prec = TAYLOR_PREC
        while True:
            ctx.prec = prec
            near = _torque_series(motion, series_at(coeffs, c - ts, n))
            v0 = [_coef(T, 0) for T in near]
            if all(v.rad() <= 1e-12 * (1 + abs(v.mid())) for v in v0) or prec >= 2048:
                break
            prec *= 2
        out = []
        for T_near, T_far in zip(near, far, strict=True):
            acc = _coef(T_far, n - 1)
            for j in range(n - 2, -1, -1):
                acc = acc * e + _coef(T_near, j)
            if not acc.is_finite():
                return None
            out.append(Ball.of_arb(acc))
        return out[0], out[1]
    except (ValueError, ZeroDivisionError):
        return None
    finally:
        ctx.prec, ctx.cap = old_prec, old_cap


@dataclass
class Zone:
    """λ about a singular instant t_s for |t - t_s| <= r, with bounded remainders:
        λ_i = ε^(k_i - m) A_i(ε)/B(ε),
        A_i = Σ_{j=k_i}^{N-1} μ_i,j ε^(j-k_i) + R_i ε^(N-k_i),
        B = Σ_{j=m}^{N-1} δ_j ε^(j-m) + R_δ ε^(N-m),
    where μ_i,j and δ_j are the Taylor coefficients at t_s (their lower ones vanish
    exactly) and R_i, R_δ bound the tails (``make_zone``). No cancellation is left: it
    is evaluated on balls of ε directly."""

    e: ExactTime
    r: float
    shift: tuple[int, int]
    num: tuple[list[Ball], list[Ball]]
    den: list[Ball]
    stacked: list[Ball] | None = field(default=None, repr=False)  # (``lam``)

    def lam(self, eps: Ball) -> tuple[Ball, Ball]:
        """λ1, λ2 on balls of ε: A_1, A_2 and B by one Horner pass, stacked (the shorter
        polynomials padded with exact zeros at the top)."""
        if self.stacked is None:
            n = max(len(self.num[0]), len(self.num[1]), len(self.den))
            self.stacked = []
            for k in range(n):
                parts = [p[k] if k < len(p) else Ball.exact(0.0) for p in (*self.num, self.den)]
                b = stack(parts)
                self.stacked.append(Ball._of(b.mid.reshape(3, 1), b.rad.reshape(3, 1)))
        v = horner(self.stacked, eps)
        out = []
        for i in (0, 1):
            lam = v[i] / v[2]
            for _ in range(abs(self.shift[i])):
                lam = lam * eps if self.shift[i] > 0 else lam / eps
            out.append(lam)
        return out[0], out[1]


def _series_parts(
    motion: CertifiedMotion, coeffs: list[list[arb]], eps: arb, n: int
) -> tuple[Any, Any, Any]:
    """μ1, μ2 and δ (product form) as series about t_s + ε for every ε in ``eps``."""
    X, Xd, Xdd, Y, Yd, Ydd = series_at(coeffs, eps, n)
    a1 = arb(motion.traj.a1)
    l1 = dyn.leg(X, Xd, Xdd, Y, Yd, Ydd, _hypot)
    l2 = dyn.leg(X - a1, Xd, Xdd, Y, Yd, Ydd, _hypot)
    d = dyn.dynamics(l1, l2, dyn.Params.of(motion.robot, arb))
    return d.mu1, d.mu2, -(Y * a1) / (l1.s * l2.s)


def _on_ball(
    motion: CertifiedMotion, coeffs: list[list[arb]], z: acb
) -> tuple[arb, arb, arb] | None:
    """Upper bounds of |μ1|, |μ2|, |δ| at t_s + z for every z of the complex ball, or None
    unless Re s² > 0 there for both legs (then the principal square root is the analytic
    continuation of the real one)."""
    vals = []
    for cs in coeffs:  # x, x', x'' and y, y', y'' about t_s
        d1 = [k * cs[k] for k in range(1, len(cs))] or [arb(0)]
        d2 = [k * d1[k] for k in range(1, len(d1))] or [arb(0)]
        for c in (cs, d1, d2):
            acc = acb(c[-1])
            for ck in c[-2::-1]:
                acc = acc * z + ck
            vals.append(acc)
    x, xd, xdd, y, yd, ydd = vals
    a1 = arb(motion.traj.a1)
    for u in (x, x - a1):
        if not (u * u + y * y).real > 0:
            return None
    l1 = dyn.leg(x, xd, xdd, y, yd, ydd, _hypot)
    l2 = dyn.leg(x - a1, xd, xdd, y, yd, ydd, _hypot)
    d = dyn.dynamics(l1, l2, dyn.Params.of(motion.robot, arb))
    out = (abs(d.mu1).upper(), abs(d.mu2).upper(), abs(-(y * a1) / (l1.s * l2.s)).upper())
    return out if all(v.is_finite() for v in out) else None


def _analytic_on_disc(motion: CertifiedMotion, coeffs: list[list[arb]], rho: float) -> bool:
    """True when Re s_i² > 0 on the whole disc |t - t_s| <= rho for both legs, proven on
    DISC_GRID² complex balls covering it: then s_i² has no zero there, the principal
    square root is analytic on it and continues the real one, and so are μ and δ."""
    x = acb_poly([acb(c) for c in coeffs[0]])
    y = acb_poly([acb(c) for c in coeffs[1]])
    polys = [x * x + y * y, (x - acb(arb(motion.traj.a1))) ** 2 + y * y]
    n = DISC_GRID
    half = rho / n * 1.01
    for i in range(n):
        for j in range(n):
            re, im = -rho + (2 * i + 1) * rho / n, -rho + (2 * j + 1) * rho / n
            if math.hypot(abs(re) - rho / n, abs(im) - rho / n) > rho:
                continue  # this ball lies outside the disc
            z = acb(arb(re, half), arb(im, half))
            if not all(p(z).real > 0 for p in polys):
                return False
    return True


def _disc_bound(motion: CertifiedMotion, coeffs: list[list[arb]], rho: float) -> list[arb] | None:
    """Upper bounds M of |μ1|, |μ2|, |δ| on the disc |t - t_s| <= rho: where μ and δ are
    analytic on the disc (``_analytic_on_disc``), by the maximum modulus principle |f|
    there is at most its maximum on the circle |z| = rho, bounded on CIRCLE_BALLS complex
    balls covering the circle; one ball covering the whole disc bounds it as well."""
    if not _analytic_on_disc(motion, coeffs, rho):
        return None
    whole = _on_ball(motion, coeffs, acb(arb(0, rho), arb(0, rho)))
    n = CIRCLE_BALLS
    half = rho * math.sin(math.pi / n) * 1.01  # each ball covers its arc of the circle
    best = list(whole) if whole is not None else None
    circle: list[arb] = [arb(0), arb(0), arb(0)]
    for j in range(n):
        th = 2 * math.pi * j / n
        got = _on_ball(
            motion, coeffs, acb(arb(rho * math.cos(th), half), arb(rho * math.sin(th), half))
        )
        if got is None:
            return best
        circle = [c if c > g else g for c, g in zip(circle, got, strict=True)]
    if best is None:
        return circle
    return [c if c < b else b for c, b in zip(circle, best, strict=True)]


def make_zone(motion: CertifiedMotion, s: SingularInstant, coeffs: list[list[arb]]) -> Zone | None:
    """The widest zone r = t_f/2^j (j = 2..20) whose remainders stay below ZONE_SLACK of
    the leading terms; None when there is none.

    The remainder R (tail Σ_{j>=N} μ_j ε^j = R ε^N for |ε| <= r) is bounded twice, and
    the smaller bound kept: by Taylor's theorem, R = μ^(N)(ξ)/N! for some ξ in t_s +
    [-r, r], enclosed by series arithmetic on that ball; and by Cauchy's estimate: μ is
    analytic on the disc |ε| <= ρ = 2r with |μ| <= M there (``_disc_bound``), so
    |μ_j| <= M/ρ^j and |R| <= M/ρ^N Σ_i 2^-i = 2M/ρ^N. The same for δ."""
    e = motion.instants[motion.analysis.instants.index(s)][1]
    m = s.order
    ks = [min(v, m + 1) for v in motion.analysis.hints(s).mu_valuations]
    N = max(*ks, m) + ZONE_TERMS
    old_prec, old_cap = ctx.prec, ctx.cap
    ctx.prec, ctx.cap = TAYLOR_PREC, N + 3
    try:
        point = _series_parts(motion, coeffs, arb(0), N + 1)
        lead = [_coef(point[0], ks[0]), _coef(point[1], ks[1]), _coef(point[2], m)]
        if lead[2].contains(0):
            return None
        tf = to_float(motion.traj.duration)
        for j in range(2, 21):
            r = tf * 2.0**-j
            bounds = _disc_bound(motion, coeffs, 2 * r)
            rem = [2 * M / arb(2 * r) ** N for M in bounds] if bounds else [arb("inf")] * 3
            try:  # Taylor's theorem: the N-th coefficients over t_s + [-r, r]
                hull = arb(0).union(arb(r)).union(arb(-r))
                lagrange = [
                    abs(_coef(f, N)).upper() for f in _series_parts(motion, coeffs, hull, N + 1)
                ]
                rem = [b if not a.is_finite() or (b.is_finite() and b < a) else a
                       for a, b in zip(rem, lagrange, strict=True)]  # fmt: skip
            except (ValueError, ZeroDivisionError):
                pass
            ok = all(R.is_finite() for R in rem)
            for R, c, k in zip(rem, lead, (ks[0], ks[1], m), strict=True):
                size = R * arb(r) ** (N - k)
                scale = abs(c).lower() if not c.contains(0) else arb(1)
                ok &= bool(size < ZONE_SLACK * scale)
            if ok:
                num = tuple(
                    [Ball.of_arb(_coef(point[i], j)) for j in range(ks[i], N)]
                    + [Ball(0.0, float(rem[i].upper()) * (1 + 4 * U))]
                    for i in (0, 1)
                )
                den = [Ball.of_arb(_coef(point[2], j)) for j in range(m, N)]
                den.append(Ball(0.0, float(rem[2].upper()) * (1 + 4 * U)))
                return Zone(e, r, (ks[0] - m, ks[1] - m), (num[0], num[1]), den)
        return None
    except (ValueError, ZeroDivisionError):
        return None
    finally:
        ctx.prec, ctx.cap = old_prec, old_cap

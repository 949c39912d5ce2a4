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
from flint import acb, acb_poly, arb, arb_poly, arb_series, ctx, fmpq

from ..model.numbers import to_float
from . import equations as dyn
from .balls import ETA, Ball, U, horner, quiet, two_sum
from .mechanism import Mechanism, of
from .series import taylor
from .singular import SingularInstant


class CertifiedMotion(Protocol):
    """What the zone forms read of a certified motion (``certified.CertifiedMotion``)."""

    traj: Any
    robot: Any
    analysis: Any
    instants: Any

    def ball_pass(self, t: Any) -> dict[str, Ball]: ...


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
ZONE_TERMS = 160  # terms of the zone form beyond the leading ones, at most
CIRCLE_BALLS = 32  # complex balls covering the circle of a Cauchy bound (then twice)
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
        mech, p = _arb_params(motion)
        l1, l2 = mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, _hypot)
        d = mech.dynamics(l1, l2, p)
        dm = _coef(mech.delta(p, Y, l1, l2), m)  # δ^(m)(ξ)/m!, eq. (29)
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


def _coefs(s: Any, n: int) -> list[arb]:
    """The first n coefficients of a series (zeros beyond its length)."""
    c = s.coeffs()[:n]
    return c + [arb(0)] * (n - len(c))


def _coef(s: Any, k: int) -> arb:
    c = s.coeffs()
    return c[k] if k < len(c) else arb(0)


def _arb_params(motion: CertifiedMotion) -> tuple[Mechanism, dyn.Params]:
    """The motion's mechanism and its parameters as arb (at the working precision)."""
    mech = of(motion.robot)
    return mech, mech.params(motion.robot, arb)


def _torque_series(motion: CertifiedMotion, ser: tuple[Any, ...]) -> tuple[Any, Any]:
    """T1, T2 as series from the series of x, x', x'', y, y', y'' (eqs. 28-31)."""
    X, Xd, Xdd, Y, Yd, Ydd = ser
    mech, p = _arb_params(motion)
    l1, l2 = mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, _hypot)
    d = mech.dynamics(l1, l2, p)
    delta = mech.delta(p, Y, l1, l2)  # product form
    T1, T2 = mech.efforts(d, d.mu1 / delta, d.mu2 / delta)
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
            polys = (*self.num, self.den)
            n = max(len(p) for p in polys)
            mid, rad = np.zeros((n, 3, 1)), np.zeros((n, 3, 1))
            for i, p in enumerate(polys):
                mid[: len(p), i, 0] = [float(b.mid) for b in p]
                rad[: len(p), i, 0] = [float(b.rad) for b in p]
            self.stacked = [Ball._of(mid[k], rad[k]) for k in range(n)]
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
    mech, p = _arb_params(motion)
    l1, l2 = mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, _hypot)
    d = mech.dynamics(l1, l2, p)
    return d.mu1, d.mu2, mech.delta(p, Y, l1, l2)


def _on_ball(
    motion: CertifiedMotion, coeffs: list[list[arb]], z: acb, r: arb | None = None
) -> tuple[arb, arb, arb] | None:
    """Upper bounds of |μ1|, |μ2|, |δ| at t_s + z for every z of the complex ball and
    every choice of the square roots s1, s2 (±, on either side of the principal branch's
    cut: the analytic continuation of the real functions is one of those choices at each
    z), or None unless s1², s2² ≠ 0 on the ball. ``r``: the disc |ε - mid z| <= r instead
    (``_on_disc``)."""
    vals = _on_disc(coeffs, z, r)
    x, xd, xdd, y, yd, ydd = vals
    a1 = arb(motion.traj.a1)
    for u in (x, x - a1):
        if (u * u + y * y).contains(0):
            return None
    out = [arb(0), arb(0), arb(0)]
    mech, params = _arb_params(motion)
    one, two = mech.legs(params, x, xd, xdd, y, yd, ydd, _branch(1))
    first, second = (one, _other_root(one)), (two, _other_root(two))
    for l1, l2 in ((a, b) for a in first for b in second):  # every branch of s1, s2
        d = mech.dynamics(l1, l2, params)
        got = (abs(d.mu1).upper(), abs(d.mu2).upper(), abs(mech.delta(params, y, l1, l2)).upper())
        out = [o if o > g else g for o, g in zip(out, got, strict=True)]
    return (out[0], out[1], out[2]) if all(v.is_finite() for v in out) else None


def _other_root(g: dyn.Leg) -> dyn.Leg:
    """The leg with -s for s (exactly: s, cos, sin, s', s'' change sign, θ' and θ''
    depend on s² and s s' only)."""
    return dyn.Leg(-g.s, -g.cos, -g.sin, -g.s_d, g.th_d, -g.s_dd, g.th_dd)


def _branch(sign: int) -> Callable[[Any, Any], Any]:
    """A root of u² + v² times ``sign`` (complex balls): with both signs, both roots of
    every point of the ball (``_root``)."""
    return lambda u, v: _root(u * u + v * v) * sign


def _root(w: acb) -> acb:
    """A ball holding one square root of each point of the complex ball w (the other is
    its negative), by polar form: where w holds no 0 and lies clear of the negative reals,
    arg is continuous on it and ranges between the args of its corners (a rectangle's
    directions from a point outside it are spanned by its corners), so √z = ρ e^(iφ)
    with ρ² between the least and the largest |z| and 2φ in that range; where it lies
    on the negative reals, i √(-w). The principal √w of a ball of ball arithmetic
    would reach 0 once the ball is wide, and a quotient by it would be unbounded."""
    direct = w.sqrt()
    if w.contains(0) or not w.is_finite() or _width(direct) < ROOT_NARROW * _size(direct):
        return direct  # a narrow ball: the principal root is as tight
    re, im = w.real, w.imag
    if im.contains(0) and not re > 0:  # on the cut: -w lies on the positive reals
        return _root(-w) * acb(0, 1)
    corners = [
        arb.atan2(y, x)
        for x in (arb(re.mid() - re.rad()), arb(re.mid() + re.rad()))
        for y in (arb(im.mid() - im.rad()), arb(im.mid() + im.rad()))
    ]
    phi = corners[0]
    for c in corners[1:]:
        phi = phi.union(c)
    phi = phi / 2
    least = re.abs_lower() ** 2 + im.abs_lower() ** 2  # |z|² over the rectangle
    most = re.abs_upper() ** 2 + im.abs_upper() ** 2
    rho = least.sqrt().sqrt().union(most.sqrt().sqrt())  # √|z|
    polar = acb(rho * phi.cos(), rho * phi.sin())
    return direct if _width(direct) < _width(polar) else polar


ROOT_NARROW = 0.01  # ``_root``: a ball this narrow beside its size takes √w directly


def _width(z: acb) -> float:
    return float(z.real.rad() + z.imag.rad()) if z.is_finite() else math.inf


def _size(z: acb) -> float:
    return float(abs(z.real.mid()) + abs(z.imag.mid()))


def _analytic_on_disc(
    motion: CertifiedMotion, coeffs: list[list[arb]], rho: float, grid: bool = True
) -> bool:
    """True when s_i² ≠ 0 on the whole disc |t - t_s| <= rho for both legs, proven on
    one ball (the centred form about t_s) or, unless ``grid`` is False, DISC_GRID² complex
    balls covering it: then (the disc being simply connected) s_i has an analytic
    continuation from the real segment over the disc, and so have μ and δ."""
    a1 = arb(motion.traj.a1)
    x, _, _, y, _, _ = _on_disc(coeffs, acb(0), arb(rho))
    if not any((u * u + y * y).contains(0) for u in (x, x - a1)):
        return True  # one ball (the centred form about t_s) proves it
    if not grid:
        return False
    n = DISC_GRID
    half = rho / n * 1.01
    for i in range(n):
        for j in range(n):
            re, im = -rho + (2 * i + 1) * rho / n, -rho + (2 * j + 1) * rho / n
            if math.hypot(abs(re) - rho / n, abs(im) - rho / n) > rho:
                continue  # this ball lies outside the disc
            x, _, _, y, _, _ = _on_disc(coeffs, acb(arb(re, half), arb(im, half)))
            if any((u * u + y * y).contains(0) for u in (x, x - a1)):
                return False
    return True


def _on_disc(coeffs: list[list[arb]], z: acb, r: arb | None = None) -> list[acb]:
    """x, x', x'', y, y', y'' at t_s + ε for every ε with |ε - z0| <= r (z0 the midpoint
    of the complex ball z; r its half-diagonal unless given): by the centred form, from the
    Taylor coefficients q_j of each polynomial about z0 (composition with z0 + h in ball
    arithmetic), |p^(i)(z0 + h)/i! - q_i| <= Σ_{j>i} C(j, i) |q_j| |h|^(j-i). Horner's rule
    on a complex ball would wrap (each product of rectangles grows by up to √2: 10^9
    after 60 of them)."""
    z0 = acb(z.real.mid(), z.imag.mid())
    if r is None:
        r = (z.real.rad() * z.real.rad() + z.imag.rad() * z.imag.rad()).sqrt()
    shift = acb_poly([z0, acb(1)])
    out = []
    for cs in coeffs:  # x and y about t_s
        q = acb_poly([acb(c) for c in cs])(shift).coeffs() + [acb(0)] * 3
        size = arb_poly([abs(v) for v in q])  # Σ |q_j| h^j, a majorant
        for i, fact in ((0, 1), (1, 1), (2, 2)):  # p, p', p'' = i! (the i-th coefficient)
            rad = ((size(arb(r)) - abs(q[i])) if i == 0 else _tail(size, i, arb(r))).upper()
            out.append((q[i] + acb(arb(0, rad), arb(0, rad))) * fact)
    return out


def _tail(size: arb_poly, i: int, r: arb) -> arb:
    """Σ_{j>i} C(j, i) a_j r^(j-i) for the majorant Σ a_j h^j: its i-th derivative at r
    over i!, less the constant term a_i."""
    d = size
    for _ in range(i):
        d = d.derivative()
    a = size.coeffs()
    return d(r) / math.factorial(i) - (a[i] if i < len(a) else arb(0))


def _disc_bound(
    motion: CertifiedMotion, coeffs: list[list[arb]], rho: float, proven: bool = False,
    balls: int = CIRCLE_BALLS,
) -> list[arb] | None:  # fmt: skip
    """Upper bounds M of |μ1|, |μ2|, |δ| on the disc |t - t_s| <= rho: where μ and δ are
    analytic on the disc (``_analytic_on_disc``), by the maximum modulus principle |f|
    there is at most its maximum on the circle |z| = rho, bounded on ``balls`` complex
    balls covering the circle; one ball covering the whole disc bounds it as well.
    ``proven``: the disc is already known to be analytic; ``balls`` = 0: the one ball
    only (cheap, looser)."""
    if not proven and not _analytic_on_disc(motion, coeffs, rho):
        return None
    whole = _on_ball(motion, coeffs, acb(0), arb(rho))
    if not balls:
        return None if whole is None else list(whole)
    n = balls
    half = rho * math.sin(math.pi / n) * 1.01  # each ball covers its arc of the circle
    best = list(whole) if whole is not None else None
    most: list[arb] = [arb(0), arb(0), arb(0)]
    for j in range(n):
        th = 2 * math.pi * j / n
        got = _on_ball(
            motion, coeffs, acb(arb(rho * math.cos(th), half), arb(rho * math.sin(th), half))
        )
        if got is None:
            return best
        most = [c if c > g else g for c, g in zip(most, got, strict=True)]
    if best is None:
        return most
    return [c if c < b else b for c, b in zip(most, best, strict=True)]


def make_zone(motion: CertifiedMotion, s: SingularInstant, coeffs: list[list[arb]]) -> Zone | None:
    """A zone |ε| <= r (r <= t_f) whose remainders stay below ZONE_SLACK of the leading
    terms, as wide as the ball pass needs (``_needed``: WANT_FACTOR times that, at least
    ZONE_FLOOR of the widest analytic disc) with as few terms as will do, or else the
    widest; None when there is none.

    The remainder R (tail Σ_{j>=N} μ_j ε^j = R ε^N for |ε| <= r) is bounded by Cauchy's
    estimate: μ is analytic on the disc |ε| <= ρ with |μ| <= M there (``_disc_bound``),
    so |μ_j| <= M/ρ^j and |R| <= M/ρ^N Σ_i (r/ρ)^i = M/(ρ^N (1 - r/ρ)); the same for δ.
    ρ: first 2^j r with M from one ball over the disc (``_small_disc``: cheap, and few
    terms while r/ρ is small), then a fraction DISC_FRACTIONS of the widest disc proven
    analytic (``_widest_disc``) with M from the circle (``_choose``); N the fewest terms
    (<= max(k, m) + ZONE_TERMS) that meet the slack. Where no disc gives a zone, Taylor's
    theorem on t_s + [-r, r], r = t_f/2^j: R = μ^(N)(ξ)/N! for some ξ there, enclosed by
    series arithmetic on that ball (``_lagrange_zone``)."""
    e = motion.instants[motion.analysis.instants.index(s)][1]
    m = s.order
    ks = [min(v, m + 1) for v in motion.analysis.hints(s).mu_valuations]
    orders = (ks[0], ks[1], m)
    top = max(orders)
    old_prec, old_cap = ctx.prec, ctx.cap
    ctx.prec = TAYLOR_PREC
    try:
        head = _point_series(motion, coeffs, top)  # the leading coefficients only
        lead = [_coef(head[0], ks[0]), _coef(head[1], ks[1]), _coef(head[2], m)]
        if lead[2].contains(0):
            return None
        tf = to_float(motion.traj.duration)
        widest = _widest_disc(motion, coeffs, 2 * tf)
        target = _needed(motion, e, widest) if widest else 0.0
        want = min(max(WANT_FACTOR * target, ZONE_FLOOR * widest), tf)
        best = None
        for r in dict.fromkeys((want, max(target, ZONE_FLOOR * widest)) if widest else ()):
            best = best or _small_disc(motion, coeffs, widest, r, lead, orders)
        for f in DISC_FRACTIONS if widest and best is None else ():
            rho = f * widest
            for balls in (CIRCLE_BALLS, 2 * CIRCLE_BALLS):  # tighter M, at a cost
                if balls == CIRCLE_BALLS and target >= ZONE_FRACTIONS[0] * rho:
                    continue  # out of reach: the tighter M (fewer terms) at once
                bounds = _disc_bound(motion, coeffs, rho, proven=True, balls=balls)
                got = None
                if bounds is not None:
                    got = _choose(bounds, rho, lead, orders, tf, (want, min(target, want)))
                if got is not None and (best is None or got[0] > best[0]):
                    best = got
                if best is not None and best[0] >= min(target, tf):
                    break
            if best is not None:  # the next disc is narrower: no wider zone
                break
        if best is None:
            point = _point_series(motion, coeffs, top + LAGRANGE_TERMS)
            return _lagrange_zone(motion, s, e, coeffs, point, lead, orders)
        r, n, rem = best
        point = _point_series(motion, coeffs, n)
        return _zone(e, r, n, rem, point, orders)
    except (ValueError, ZeroDivisionError):
        return None
    finally:
        ctx.prec, ctx.cap = old_prec, old_cap


ZONE_BASE = 48  # terms beyond the leading ones of a zone as wide as wanted, at most
ZONE_FRACTIONS = (
    *(0.9, 0.85, 0.8, 0.75, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1),
    *(10.0 ** (-j / 2) for j in range(3, 19)),
)  # r/ρ, from the widest
DISC_STEPS = 40  # discs 2 t_f 2^(-i/2), i < DISC_STEPS, tried for analyticity
DISC_FINE = 8  # ... and between the widest two, at steps of 2^(-1/(2 DISC_FINE))
DISC_FRACTIONS = (0.9, 0.75)  # fractions of the widest analytic disc tried, in turn
WANT_FACTOR = 2.0  # a zone reaches this many times as far as the ball pass needs
ZONE_FLOOR = 0.125  # ... and at least this fraction of the widest analytic disc
DIRECT_REL = 1e-13  # the relative error of λ the ball pass should reach outside a zone


def _point_series(motion: CertifiedMotion, coeffs: list[list[arb]], n: int) -> tuple[Any, ...]:
    """μ1, μ2, δ as series of n + 1 terms about t_s."""
    ctx.cap = n + 3
    return _series_parts(motion, coeffs, arb(0), n + 1)


def _needed(motion: CertifiedMotion, e: ExactTime, rho: float) -> float:
    """The |ε| beyond which the ball pass gives λ1, λ2 to DIRECT_REL at the probes
    t_s ± ρ 10^(-j/4) (j < PROBES) inside [0, t_f], times 1.1: a measurement (one
    vectorised pass) that only chooses how wide a zone to make."""
    d = rho * 10.0 ** (-np.arange(PROBES) / 4)
    tf = to_float(motion.traj.duration)
    t = np.concatenate([e.hi + d, e.hi - d])
    inside = (t >= 0) & (t <= tf)
    with quiet():
        b = motion.ball_pass(t)
    good = b["lambda1"].certified(DIRECT_REL) & b["lambda2"].certified(DIRECT_REL)
    poor = np.concatenate([d, d])[inside & ~good]
    return 1.1 * float(poor.max()) if len(poor) else 0.0


PROBES = 48  # probes of ``_needed``, from ρ down to ρ 10^-12


def _widest_disc(motion: CertifiedMotion, coeffs: list[list[arb]], start: float) -> float:
    """The widest disc |ε| <= ρ, ρ = start 2^(-i/2) refined between the widest two,
    proven analytic (``_analytic_on_disc``: by one ball, else by grids); 0 when none."""
    for grid in (False, True):  # one ball at each step first (cheap), then the grids
        for i in range(DISC_STEPS):
            rho = start * 2.0 ** (-i / 2)
            if _analytic_on_disc(motion, coeffs, rho, grid):
                break
        else:
            continue
        step = 2.0 ** (1 / (2 * DISC_FINE))
        for _ in range(DISC_FINE - 1 if i else 0):
            if not _analytic_on_disc(motion, coeffs, rho * step, grid):
                break
            rho *= step
        return rho
    return 0.0


def _small_disc(
    motion: CertifiedMotion, coeffs: list[list[arb]], widest: float, want: float,
    lead: list[arb], orders: tuple[int, int, int],
) -> tuple[float, int, list[arb]] | None:  # fmt: skip
    """The zone r = ``want`` with M from one ball over a disc ρ = 2^j r (inside the widest
    analytic one, j from SMALL_DISCS, the widest that gives M first): cheap, and a few
    terms suffice while ρ/r is large; None when no such disc meets the slack with at most
    k + ZONE_BASE terms."""
    for j in SMALL_DISCS:
        rho = want * 2.0**j
        if rho > DISC_FRACTIONS[0] * widest:
            continue
        bounds = _disc_bound(motion, coeffs, rho, proven=True, balls=0)
        if bounds is None:
            continue
        got = _fewest(bounds, rho, want, lead, orders, max(orders) + ZONE_BASE)
        return None if got is None else (want, got[0], got[1])
    return None


SMALL_DISCS = (4, 3, 2, 1)  # ρ/r = 2^j of ``_small_disc``, tried in turn


def _choose(
    bounds: list[arb], rho: float, lead: list[arb], orders: tuple[int, int, int], tf: float,
    wants: tuple[float, float],
) -> tuple[float, int, list[arb]] | None:  # fmt: skip
    """(r, N, remainders) of a zone about t_s whose Cauchy remainders R ε^N, |R| <=
    M/(ρ^N (1 - r/ρ)), stay below ZONE_SLACK of the leading terms |c| r^k with the
    fewest terms N: r = ``wants`` [0] (the zone wanted) with N <= k + ZONE_BASE, else r =
    ``wants`` [1] (the zone the ball pass needs) with N <= k + ZONE_TERMS; where that is
    out of this disc's reach, the widest r = f ρ (f in ZONE_FRACTIONS, r <= t_f) with N <=
    k + ZONE_TERMS (the ball pass is poor up to there), else with N <= k + ZONE_BASE."""
    top = max(orders)
    for r, most in ((wants[0], ZONE_BASE), (wants[1], ZONE_TERMS)):
        if 0 < r < ZONE_FRACTIONS[0] * rho:
            terms = _fewest(bounds, rho, r, lead, orders, top + most)
            if terms is not None:
                return r, terms[0], terms[1]
    base = None if wants[1] > 0 else _widest_of(bounds, rho, lead, orders, top + ZONE_BASE, tf)
    return base or _widest_of(bounds, rho, lead, orders, top + ZONE_TERMS, tf)


def _widest_of(
    bounds: list[arb], rho: float, lead: list[arb], orders: tuple[int, int, int], n_max: int,
    tf: float,
) -> tuple[float, int, list[arb]] | None:  # fmt: skip
    """The widest zone r = f ρ (f in ZONE_FRACTIONS, r <= t_f) of at most n_max terms."""
    for f in ZONE_FRACTIONS:
        r = min(f * rho, tf)
        n = _fewest(bounds, rho, r, lead, orders, n_max)
        if n is not None:
            return r, n[0], n[1]
    return None


def _fewest(
    bounds: list[arb], rho: float, r: float, lead: list[arb], orders: tuple[int, int, int],
    n_max: int,
) -> tuple[int, list[arb]] | None:  # fmt: skip
    """The fewest terms N <= n_max (in steps of 4) for which the zone r meets the slack,
    with its remainders: the bound M q^N/(1 - q) r^-k (q = r/ρ < 1) falls with N, so by
    bisection over the steps."""
    q = arb(r) / arb(rho)

    def meets(n: int) -> list[arb] | None:
        rem = [M / (arb(rho) ** n * (1 - q)) for M in bounds]
        for R, c, k in zip(rem, lead, orders, strict=True):
            scale = abs(c).lower() if not c.contains(0) else arb(1)
            if not R * arb(r) ** (n - k) < ZONE_SLACK * scale:
                return None
        return rem

    first = max(orders) + 1
    lo, hi = 0, (n_max - first) // 4  # steps: N = first + 4 j
    if hi < 0 or meets(first + 4 * hi) is None:
        return None
    while lo < hi:
        j = (lo + hi) // 2
        if meets(first + 4 * j) is None:
            lo = j + 1
        else:
            hi = j
    n = first + 4 * lo
    rem = meets(n)
    return None if rem is None else (n, rem)


def _zone(
    e: ExactTime, r: float, n: int, rem: list[arb], point: tuple[Any, Any, Any],
    orders: tuple[int, int, int],
) -> Zone:  # fmt: skip
    """The zone |ε| <= r with the first n Taylor coefficients and the remainders ``rem``."""
    parts = [
        [Ball.of_arb(c) for c in _coefs(point[i], n)[orders[i] :]]
        + [Ball(0.0, float(rem[i].upper()) * (1 + 4 * U))]
        for i in (0, 1, 2)
    ]
    m = orders[2]
    return Zone(e, r, (orders[0] - m, orders[1] - m), (parts[0], parts[1]), parts[2])


def _lagrange_zone(
    motion: CertifiedMotion, s: SingularInstant, e: ExactTime, coeffs: list[list[arb]],
    point: tuple[Any, Any, Any], lead: list[arb], orders: tuple[int, int, int],
) -> Zone | None:  # fmt: skip
    """The widest zone r = t_f/2^j (j = 2..20) whose Lagrange remainders (the N-th
    coefficients over t_s + [-r, r] by series arithmetic) meet the slack."""
    n = max(orders) + LAGRANGE_TERMS
    tf = to_float(motion.traj.duration)
    for j in range(2, 21):
        r = tf * 2.0**-j
        try:
            hull = arb(0).union(arb(r)).union(arb(-r))
            rem = [abs(_coef(f, n)).upper() for f in _series_parts(motion, coeffs, hull, n + 1)]
        except (ValueError, ZeroDivisionError):
            continue
        ok = all(R.is_finite() for R in rem)
        for R, c, k in zip(rem, lead, orders, strict=True):
            scale = abs(c).lower() if not c.contains(0) else arb(1)
            ok &= bool(R * arb(r) ** (n - k) < ZONE_SLACK * scale)
        if ok:
            return _zone(e, r, n, rem, point, orders)
    return None


LAGRANGE_TERMS = 48  # terms of a zone bounded by Taylor's theorem beyond the leading ones

"""The zone form of λ about a singular instant: no cancellation left, for balls of time.

About a Type II instant t_s of order m, μ_i vanishes to order k_i and δ to order m, so
λ_i = μ_i/δ cancels digits when evaluated directly. ``Zone`` (``make_zone``) expands both
about t_s with the vanishing coefficients dropped: N terms at the point t_s and a remainder
bound valid on a whole zone |ε| <= r (by Cauchy's estimate on a disc proven analytic,
``discs``, else by Taylor's theorem), evaluated on balls of ε (vectorised). The Taylor
forms over a box (``taylor_lambda``, ``taylor_box``) are in ``taylor_forms``; ``ExactTime``
gives ε = t - t_s as a tight ball for every float t.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import field
from typing import Any

import numpy as np
from flint import arb, ctx, fmpq, fmpq_poly

from ...model.dataclass import dataclass
from ...model.numbers import to_float
from ..exact.roots import real_roots_in
from ..exact.singular import SingularInstant
from .balls import ETA, Ball, U, horner, hypot, quiet, two_sum
from .discs import CIRCLE_BALLS, analytic_on_disc, disc_bound
from .taylor_forms import (
    TAYLOR_PREC,
    CertifiedMotion,
    coef,
    coefs,
    series_parts,
    taylor_at_instant,
    taylor_box,
    taylor_lambda,
)


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

    @staticmethod
    def roots(poly: fmpq_poly, duration: fmpq) -> list[ExactTime]:
        """The real roots of ``poly`` in [0, t_f] (``roots.real_roots_in``), in increasing
        order."""
        return sorted((ExactTime(*r) for r in real_roots_in(poly, duration)), key=lambda e: e.hi)

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


ZONE_TERMS = 160  # terms of the zone form beyond the leading ones, at most
ZONE_SLACK = 1e-9  # a zone's remainders stay below this fraction of its leading terms


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

    def stack(self) -> list[Ball]:
        """A_1, A_2 and B stacked for one Horner pass (the shorter polynomials padded with
        exact zeros at the top), made once."""
        if self.stacked is None:
            polys = (*self.num, self.den)
            n = max(len(p) for p in polys)
            mid, rad = np.zeros((n, 3, 1)), np.zeros((n, 3, 1))
            for i, p in enumerate(polys):
                mid[: len(p), i, 0] = [float(b.mid) for b in p]
                rad[: len(p), i, 0] = [float(b.rad) for b in p]
            self.stacked = [Ball._of(mid[k], rad[k]) for k in range(n)]
        return self.stacked

    def lam(self, eps: Ball) -> tuple[Ball, Ball]:
        """λ1, λ2 on balls of ε: A_1, A_2 and B by one Horner pass (``stack``)."""
        v = horner(self.stack(), eps)
        out = []
        for i in (0, 1):
            lam = v[i] / v[2]
            for _ in range(abs(self.shift[i])):
                lam = lam * eps if self.shift[i] > 0 else lam / eps
            out.append(lam)
        return out[0], out[1]


def make_zone(motion: CertifiedMotion, s: SingularInstant, coeffs: list[list[arb]]) -> Zone | None:
    """A zone |ε| <= r (r <= t_f) whose remainders stay below ZONE_SLACK of the leading
    terms, as wide as the ball pass needs (``_needed``: WANT_FACTOR times that, at least
    ZONE_FLOOR of the widest analytic disc) with as few terms as will do, or else the
    widest; None when there is none.

    The remainder R (tail Σ_{j>=N} μ_j ε^j = R ε^N for |ε| <= r) is bounded by Cauchy's
    estimate: μ is analytic on the disc |ε| <= ρ with |μ| <= M there (``disc_bound``),
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
        lead = [coef(head[0], ks[0]), coef(head[1], ks[1]), coef(head[2], m)]
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
                bounds = disc_bound(motion, coeffs, rho, proven=True, balls=balls)
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
    return series_parts(motion, coeffs, arb(0), n + 1)


def _needed(motion: CertifiedMotion, e: ExactTime, rho: float) -> float:
    """The |ε| beyond which the ball pass gives λ1, λ2 to DIRECT_REL at the probes
    t_s ± ρ 10^(-j/4) (j < PROBES) inside [0, t_f], times 1.1: a measurement (one
    vectorised pass) that only chooses how wide a zone to make."""
    d = rho * 10.0 ** (-np.arange(PROBES) / 4)
    tf = to_float(motion.traj.duration)
    t = np.concatenate([e.hi + d, e.hi - d])
    inside = (t >= 0) & (t <= tf)
    with quiet():  # λ alone, as ``ball_pass`` has it (no angle, no torque)
        x, xd, xdd, y, yd, ydd = motion.end_point(t)
        p, mech = motion.params, motion.mech
        leg1, leg2 = mech.legs(p, x, xd, xdd, y, yd, ydd, hypot)
        dyn, delta = mech.dynamics(leg1, leg2, p), mech.delta(p, y, leg1, leg2)
        lam1, lam2 = dyn.mu1 / delta, dyn.mu2 / delta
    good = lam1.certified(DIRECT_REL) & lam2.certified(DIRECT_REL)
    poor = np.concatenate([d, d])[inside & ~good]
    return 1.1 * float(poor.max()) if len(poor) else 0.0


PROBES = 48  # probes of ``_needed``, from ρ down to ρ 10^-12


def _widest_disc(motion: CertifiedMotion, coeffs: list[list[arb]], start: float) -> float:
    """The widest disc |ε| <= ρ, ρ = start 2^(-i/2) refined between the widest two,
    proven analytic (``analytic_on_disc``: by one ball, else by grids); 0 when none."""
    for grid in (False, True):  # one ball at each step first (cheap), then the grids
        for i in range(DISC_STEPS):
            rho = start * 2.0 ** (-i / 2)
            if analytic_on_disc(motion, coeffs, rho, grid):
                break
        else:
            continue
        step = 2.0 ** (1 / (2 * DISC_FINE))
        for _ in range(DISC_FINE - 1 if i else 0):
            if not analytic_on_disc(motion, coeffs, rho * step, grid):
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
        bounds = disc_bound(motion, coeffs, rho, proven=True, balls=0)
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
        [Ball.of_arb(c) for c in coefs(point[i], n)[orders[i] :]]
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
            rem = [abs(coef(f, n)).upper() for f in series_parts(motion, coeffs, hull, n + 1)]
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


__all__ = [  # the Taylor forms stay importable from here, as before
    "TAYLOR_PREC", "CertifiedMotion", "ExactTime", "Zone", "make_zone", "taylor_at_instant",
    "taylor_box", "taylor_lambda",
]  # fmt: skip

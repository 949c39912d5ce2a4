"""Certified values of a 5R motion (one polynomial piece) in ball arithmetic (``flint.arb``).

The 5R's formulas (``exact.five_bar``) are written once for any number type; here they run
on ``arb`` (a value at one time) and on ``arb_series`` (the Taylor coefficients at a time
or over a box of time), the legs' square roots being the balls' (``D.sqrt()``). Three
enclosures of the torques T1, T2 come out of them, each proven:

* **at a time t**: T(t) as balls (``point``); at an exact Type II instant, the limit of
  the Taylor form below (bounded) or no value (a pole).
* **over a box I** away from Type II instants, the Taylor form of order 2 about the box's
  midpoint c: T(I) ⊆ T(c) + T'(c) [-h, h] + (T''(I)/2) [0, h²] (Lagrange remainder), and
  the plain enclosure T(I); the narrower is kept (``box``).
* **near a Type II instant t_s** of order m, where T = A/δ is 0/0 or a pole: with
  A_i = T_i δ = T_i(α=0) δ + ν ∂T_i/∂α (affine in the axial force α = ν/δ) and the
  exact analysis' count k of the conditions met (A vanishes to order k at t_s, δ to order
  m), T_i = g_i(t) / ((t - t_s)^(m - k) q(t)) with g_i = A_i/(t - t_s)^k and
  q = δ/(t - t_s)^m, each a Taylor polynomial about t_s with a Lagrange remainder over the
  box (``zone``). The coefficients below k and m are dropped: they are zero, decided
  exactly by the analysis (a ball that does not hold 0 there is an internal error). t_s is
  exact, or an isolated root as a ball of 128 bits; (t - t_s) is then a ball too.

Nothing here rounds a double into a proof: every bound is read from a ball, outward.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

from flint import arb, arb_series, ctx, fmpq, fmpq_poly

from ..exact import five_bar as fb
from ..exact.five_bar_instants import FiveBarInstant

PREC = 96  # bits of the branch and bound's balls
TERMS = 4  # Taylor terms kept about a Type II instant beyond the ones divided out
NEAR = 0.02  # the instant's Taylor form is tried over boxes this close (a fraction of t_f)
_NAN = arb("nan")


def lower(b: arb) -> float:
    """A double below every member of the ball ``b`` (-inf when it is not finite)."""
    if not b.is_finite():
        return -math.inf
    m, r = float(b.mid()), float(b.rad())
    return m - r - 4 * math.ulp(abs(m) + r)


def upper(b: arb) -> float:
    """A double above every member of the ball ``b`` (inf when it is not finite)."""
    if not b.is_finite():
        return math.inf
    m, r = float(b.mid()), float(b.rad())
    return m + r + 4 * math.ulp(abs(m) + r)


def abs_bounds(b: arb) -> tuple[float, float]:
    """(lower, upper) bounds of |v| over the members v of ``b``."""
    lo, hi = lower(b), upper(b)
    top = max(abs(lo), abs(hi))
    return (lo if lo > 0 else -hi if hi < 0 else 0.0), top


def exact_ball(q: fmpq) -> arb:
    """The rational ``q`` as a ball at the working precision."""
    return arb(q)


def _root(D: Any, i: int) -> Any:
    return D.sqrt()


def _horner(cs: Sequence[arb], u: Any) -> Any:
    out: Any = arb(0)
    for c in reversed(cs):
        out = out * u + c
    return out


class Evaluation:
    """What one pass of the formulas gives at a time or over a box (any number type):
    the dynamics ``d``, T at α = 0 (``base``), ∂T/∂α (``slope``) and A = T δ."""

    def __init__(self, d: fb.FiveBarDynamics, base: tuple[Any, Any], slope: tuple[Any, Any]):
        self.d = d
        self.base = base
        self.slope = slope
        self.A = (base[0] * d.delta + d.nu * slope[0], base[1] * d.delta + d.nu * slope[1])

    def torques(self) -> tuple[Any, Any]:
        """T_i = T_i(α = 0) + α ∂T_i/∂α with α = ν/δ (δ must exclude 0)."""
        alpha = self.d.nu / self.d.delta
        return self.base[0] + alpha * self.slope[0], self.base[1] + alpha * self.slope[1]


class Zone:
    """The Taylor form about one Type II instant (module docstring): ``a[i]`` the
    coefficients k.. of A_i at t_s, ``q`` those m.. of δ, ``nu`` those m.. of ν,
    ``pole`` = m - k."""

    def __init__(
        self, s: FiveBarInstant, t_s: arb, a: list[list[arb]], q: list[arb], nu: list[arb]
    ) -> None:
        self.s = s
        self.lo, self.hi = exact_ends(t_s)  # exact rationals about t_s
        self.nu = nu  # ν's coefficients m.. (α's limit at a bounded instant: ν_m/δ_m)
        self.t_s = t_s
        self.k = s.conditions_met
        self.m = s.order
        self.pole = self.m - self.k
        self.a = a
        self.q = q


class FiveBarMotion:
    """A 5R motion of one piece (x(t), y(t), 0 <= t <= ``duration``) in its working modes,
    with its exact Type II instants, evaluated in balls (module docstring); for a piece of
    a piecewise motion, t is its local time and ``start`` the absolute time of t = 0
    (the samples' times are absolute: ``five_bar_samples``)."""

    def __init__(
        self, five_bar: Any, gravity: Any, x: fmpq_poly, y: fmpq_poly, duration: fmpq,
        instants: Sequence[FiveBarInstant], start: fmpq | None = None,
    ) -> None:  # fmt: skip
        self.five_bar, self.gravity = five_bar, gravity
        self.start = fmpq(0) if start is None else start  # the absolute time of t = 0
        self.modes: tuple[int, int] = five_bar.modes
        xd, yd = x.derivative(), y.derivative()
        self.polys = (x, xd, xd.derivative(), y, yd, yd.derivative())
        self.duration = duration
        self.instants = tuple(instants)
        self.exact = fb.params(five_bar, gravity)
        self._prec: dict[int, tuple[fb.FiveBarParams, list[list[arb]]]] = {}
        self._zones: dict[int, Zone] = {}

    def _at_prec(self) -> tuple[fb.FiveBarParams, list[list[arb]]]:
        bits = ctx.prec
        if bits not in self._prec:
            p = fb.params(self.five_bar, self.gravity, arb)
            self._prec[bits] = (p, [[arb(c) for c in q.coeffs()] for q in self.polys])
        return self._prec[bits]

    def evaluate(self, t: arb, terms: int = 0, cs: list[list[arb]] | None = None) -> Evaluation:
        """The formulas at the ball ``t`` (``terms`` 0: values; else ``terms`` Taylor
        coefficients at ``t``, an ``arb_series``); ``cs``: the path's coefficients in
        the variable of ``t`` (by default in t itself)."""
        p, own = self._at_prec()
        cs = own if cs is None else cs
        u: Any = t if terms == 0 else arb_series([t, 1], prec=terms)
        x, xd, xdd, y, yd, ydd = (_horner(c, u) for c in cs)
        l1, l2 = fb.legs(p, self.modes, x, xd, xdd, y, yd, ydd, _root)
        d = fb.dynamics(l1, l2, p)
        T0 = fb.efforts(d, 0)
        T1 = fb.efforts(d, 1)
        return Evaluation(d, T0, (T1[0] - T0[0], T1[1] - T0[1]))

    def evaluate_span(self, lo: fmpq, hi: fmpq, terms: int) -> Evaluation:
        """The formulas over the box [lo, hi] (``terms`` Taylor coefficients): the path
        taken about the box's exact midpoint c, in u = t - c over [-h, h] (a centred
        form: the path's large coefficients do not widen the box's values)."""
        c = (lo + hi) / 2
        shift = fmpq_poly([c, 1])
        cs = [[arb(v) for v in q(shift).coeffs()] for q in self.polys]
        return self.evaluate(arb(0, upper(arb(hi - c))), terms, cs)

    def point(self, t: fmpq) -> tuple[arb, arb]:
        """(T1, T2) at the time ``t``: direct where δ(t) excludes 0, else by the Taylor
        form of the nearest instant (NaN balls where a pole or undecided)."""
        ball = exact_ball(t)
        e = self.evaluate(ball)
        if not e.d.delta.contains(0):
            return e.torques()
        s = self.nearest(ball)
        if s is None:
            return _NAN, _NAN
        return self.zone_values(s, ball, (t, t))

    def box(self, lo: fmpq, hi: fmpq) -> tuple[arb, arb]:
        """(T1, T2) enclosed over the box [lo, hi] (module docstring): the Taylor form
        about its midpoint or the plain enclosure, the narrower; near an instant, its zone
        form where narrower (NaN balls where none is finite)."""
        box = exact_ball(lo).union(exact_ball(hi))
        c = exact_ball((lo + hi) / 2)
        h = upper(box - c)
        out = [_NAN, _NAN]
        try:
            over = self.evaluate_span(lo, hi, 3)
            at = self.evaluate(c, 2)
            T_over = _centred(over, at, arb(0, h))
            T_at = at.torques()
            U2 = arb(h * h / 2, h * h / 2)
            for i in (0, 1):
                v, dv = T_at[i].coeffs()[:2]
                taylor = v + dv * arb(0, h) + T_over[i].coeffs()[2] * U2
                out[i] = _narrower(taylor, T_over[i].coeffs()[0])
        except (ValueError, ZeroDivisionError):  # δ over the box not proven nonzero
            pass
        s = self.nearest(box)
        if s is not None and (self._near(s, box) or not all(v.is_finite() for v in out)):
            zone = self.zone_values(s, box, (lo, hi))
            out = [_narrower(out[i], zone[i]) for i in (0, 1)]
        return out[0], out[1]

    def _near(self, s: FiveBarInstant, box: arb) -> bool:
        """The box lies within NEAR of the duration of the instant ``s``."""
        return upper(abs(box - s.t_ball)) < NEAR * float(self.duration)

    def nearest(self, t: arb) -> FiveBarInstant | None:
        """The Type II instant nearest the ball ``t`` (None without one)."""
        if not self.instants:
            return None
        mid = float(t.mid())
        return min(self.instants, key=lambda s: abs(s.t - mid))

    def zone(self, s: FiveBarInstant) -> Zone:
        """The Taylor coefficients of A and δ at the instant ``s`` (made once)."""
        i = self.instants.index(s)
        if i not in self._zones:
            t_s = exact_ball(s.t_exact) if s.t_exact is not None else s.t_ball
            k, m = s.conditions_met, s.order
            e = self.evaluate(t_s, m + TERMS)
            n = m + TERMS
            A = [_padded(e.A[j].coeffs(), n) for j in (0, 1)]
            q = _padded(e.d.delta.coeffs(), n)
            nu = _padded(e.d.nu.coeffs(), n)
            zero = [*A[0][:k], *A[1][:k], *q[:m], *(nu[:m] if s.bounded else [])]
            if any(not v.contains(0) for v in zero):  # ν too where α = ν/δ stays bounded
                raise AssertionError("a coefficient the exact analysis proves zero is not")
            self._zones[i] = Zone(s, t_s, [A[0][k:], A[1][k:]], q[m:], nu[m:])
        return self._zones[i]

    def zone_values(self, s: FiveBarInstant, t: arb, span: tuple[fmpq, fmpq]) -> tuple[arb, arb]:
        """(T1, T2) over the ball of time ``t`` by the instant's Taylor form, its remainder
        taken over ``span`` (exact ends, holding ``t``) joined with t_s. Where the box
        holds a pole, no enclosure: NaN balls (``pole_lower`` bounds |T| below there)."""
        z = self.zone(s)
        u = t - z.t_s
        try:
            g, q = self._forms(z, u, span)
        except (ValueError, ZeroDivisionError):  # a leading term not proven nonzero
            return _NAN, _NAN
        if u.contains(0) and z.pole:
            return _NAN, _NAN
        den = q * u**z.pole if z.pole else q
        if den.contains(0):
            return _NAN, _NAN
        return g[0] / den, g[1] / den

    def pole_lower(self, s: FiveBarInstant, lo: fmpq, hi: fmpq) -> tuple[float, float]:
        """Lower bounds of |T1|, |T2| over the box [lo, hi] (t_s excluded) about an
        instant with a pole: |g| / (max |t - t_s|^p |q|) (0 where not proven)."""
        z = self.zone(s)
        u = exact_ball(lo).union(exact_ball(hi)) - z.t_s
        try:
            g, q = self._forms(z, u, (lo, hi))
        except (ValueError, ZeroDivisionError):  # a leading term not proven nonzero
            return 0.0, 0.0
        reach = upper(abs(u)) ** z.pole * abs_bounds(q)[1]
        out = []
        for i in (0, 1):
            lo = abs_bounds(g[i])[0]
            out.append(lo / reach * (1 - 1e-12) if reach > 0 and math.isfinite(reach) else 0.0)
        return out[0], out[1]

    def _forms(self, z: Zone, u: arb, span: tuple[fmpq, fmpq]) -> tuple[tuple[arb, arb], arb]:
        """g_i = A_i/u^k and q = δ/u^m over u = t - t_s, remainders over span ∪ t_s."""
        n = z.m + TERMS
        r = self.evaluate_span(min(span[0], z.lo), max(span[1], z.hi), n + 1)
        rA = [r.A[i].coeffs()[n] if len(r.A[i].coeffs()) > n else arb(0) for i in (0, 1)]
        rq = r.d.delta.coeffs()
        rq_n = rq[n] if len(rq) > n else arb(0)
        g = tuple(_horner([*z.a[i], rA[i]], u) for i in (0, 1))
        q = _horner([*z.q, rq_n], u)
        return (g[0], g[1]), q

    def limit_at(self, s: FiveBarInstant) -> tuple[arb, arb]:
        """(T1, T2) at a bounded instant: a_k/δ_m (the form at u = 0)."""
        z = self.zone(s)
        return z.a[0][0] / z.q[0], z.a[1][0] / z.q[0]


def _centred(over: Evaluation, at: Evaluation, U: arb) -> tuple[Any, Any]:
    """T's Taylor coefficients over a box from ``over`` (the series over the box), each
    part's value (δ, ν, T at α = 0, ∂T/∂α) over the box first narrowed by its mean-value
    form v(c) + v'(box) U (``at``: the series at the midpoint c; U = [-h, h]): near a
    Type II instant δ's plain enclosure spans 0 where δ itself does not. Every
    coefficient still holds the true one at each t of the box, so the series' division
    by δ stays proven."""

    def narrow(s: Any, p: Any) -> Any:
        cs = s.coeffs()
        mv = p.coeffs()[0] + cs[1] * U
        first = cs[0].intersection(mv) if cs[0].overlaps(mv) else mv
        return arb_series([first, *cs[1:]], prec=len(cs))

    delta, nu = narrow(over.d.delta, at.d.delta), narrow(over.d.nu, at.d.nu)
    base = [narrow(over.base[i], at.base[i]) for i in (0, 1)]
    slope = [narrow(over.slope[i], at.slope[i]) for i in (0, 1)]
    alpha = nu / delta
    return base[0] + alpha * slope[0], base[1] + alpha * slope[1]


def exact_ends(b: arb) -> tuple[fmpq, fmpq]:
    """Exact rationals below and above every member of the ball ``b``."""
    m, e = b.mid().man_exp()
    r, f = b.rad().man_exp()
    mid = fmpq(int(m)) * _two(int(e))
    rad = fmpq(int(r)) * _two(int(f))
    return mid - rad, mid + rad


def _two(e: int) -> fmpq:
    return fmpq(2**e) if e >= 0 else fmpq(1, 2**-e)


def _padded(cs: list[arb], n: int) -> list[arb]:
    """The first ``n`` coefficients of a series (those it leaves out are zero)."""
    return (cs + [arb(0)] * n)[:n]


def _narrower(a: arb, b: arb) -> arb:
    """The narrower of two enclosures of one value (a finite one over a NaN)."""
    if not b.is_finite():
        return a
    if not a.is_finite():
        return b
    return a if a.rad() <= b.rad() else b

"""The Taylor forms of λ and of the torques about a singular instant, for balls of time.

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
* ``taylor_box``: a Taylor model about a box's own midpoint (for boxes clear of t_s).

The zone form (``zones``) uses the same series about t_s (``series_parts``). The Taylor
coefficients of x and y at a ball are taken from their exact Taylor coefficients about t_s
(``taylor_at_instant``) by Horner in the series ε + τ: the expanded polynomials in t,
evaluated on a ball, would not stay tight.
"""

from __future__ import annotations

from typing import Any, Protocol

import numpy as np
from flint import arb, arb_series, ctx

from ..exact import equations as dyn
from ..exact.mechanism import Mechanism, of
from ..exact.series import taylor
from ..exact.singular import SingularInstant
from .balls import Ball, hypot, quiet


class CertifiedMotion(Protocol):
    """What the zone forms read of a certified motion (``certified.CertifiedMotion``)."""

    traj: Any
    robot: Any
    analysis: Any
    instants: Any
    mech: Any  # the robot's formulas (``mechanism``)

    @property
    def params(self) -> Any: ...

    def ball_pass(self, t: Any) -> dict[str, Ball]: ...

    def end_point(self, t: Any) -> tuple[Ball, ...]: ...


TAYLOR_PREC = 128  # bits of the Taylor forms, to start with
TAYLOR_BOX_ORDER = 4  # degree N of the Taylor model over a box (``taylor_box``)


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
        mech, p = arb_params(motion)
        l1, l2 = mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, hypot)
        d = mech.dynamics(l1, l2, p)
        dm = coef(mech.delta(p, Y, l1, l2), m)  # δ^(m)(ξ)/m!, eq. (29)
        if not dm.is_finite() or dm.contains(0):
            return None
        eps = Ball.hull(np.array([lo]), np.array([hi])) - Ball.of_arb(ts)
        out = []
        with quiet():
            for mu, k in ((d.mu1, ks[0]), (d.mu2, ks[1])):
                c = coef(mu, k) / dm
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


def coefs(s: Any, n: int) -> list[arb]:
    """The first n coefficients of a series (zeros beyond its length)."""
    c = s.coeffs()[:n]
    return c + [arb(0)] * (n - len(c))


def coef(s: Any, k: int) -> arb:
    c = s.coeffs()
    return c[k] if k < len(c) else arb(0)


def arb_params(motion: CertifiedMotion) -> tuple[Mechanism, dyn.Params]:
    """The motion's mechanism and its parameters as arb (at the working precision)."""
    mech = of(motion.robot)
    return mech, mech.params(motion.robot, arb)


def _torque_series(motion: CertifiedMotion, ser: tuple[Any, ...]) -> tuple[Any, Any]:
    """T1, T2 as series from the series of x, x', x'', y, y', y'' (eqs. 28-31)."""
    X, Xd, Xdd, Y, Yd, Ydd = ser
    mech, p = arb_params(motion)
    l1, l2 = mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, hypot)
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
            v0 = [coef(T, 0) for T in near]
            if all(v.rad() <= 1e-12 * (1 + abs(v.mid())) for v in v0) or prec >= 2048:
                break
            prec *= 2
        out = []
        for T_near, T_far in zip(near, far, strict=True):
            acc = coef(T_far, n - 1)
            for j in range(n - 2, -1, -1):
                acc = acc * e + coef(T_near, j)
            if not acc.is_finite():
                return None
            out.append(Ball.of_arb(acc))
        return out[0], out[1]
    except (ValueError, ZeroDivisionError):
        return None
    finally:
        ctx.prec, ctx.cap = old_prec, old_cap


def series_parts(
    motion: CertifiedMotion, coeffs: list[list[arb]], eps: arb, n: int
) -> tuple[Any, Any, Any]:
    """μ1, μ2 and δ (product form) as series about t_s + ε for every ε in ``eps``."""
    X, Xd, Xdd, Y, Yd, Ydd = series_at(coeffs, eps, n)
    mech, p = arb_params(motion)
    l1, l2 = mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, hypot)
    d = mech.dynamics(l1, l2, p)
    return d.mu1, d.mu2, mech.delta(p, Y, l1, l2)

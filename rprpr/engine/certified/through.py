"""E at A or B: the leg through its base joint, factored (``Through``), and the torques
made narrower near t_A by that form (``narrowed``)."""

from __future__ import annotations

from typing import Any

import numpy as np
from flint import arb_poly, ctx, fmpq, fmpq_poly

from ..exact import equations as dyn
from ..exact.series import taylor
from .balls import Ball, full, horner, hypot, quiet
from .jets import Jet
from .motion import CertifiedMotion
from .stacked import Stacked


def _derive(c: list[Ball]) -> list[Ball]:
    return [c[j] * float(j) for j in range(1, len(c))] or [Ball.exact(0.0)]


def _derivatives(c: list[Ball]) -> tuple[list[Ball], ...]:
    """The coefficients of f and its first three derivatives from those of f (low to
    high)."""
    out = [c]
    for _ in range(3):
        out.append(_derive(out[-1]))
    return tuple(out)


def _jets3(ds: tuple[list[Ball], ...], eps: Ball, jets: bool = True) -> tuple[Any, Any, Any]:
    """f, f', f'' as jets in ε (value, derivative) over the balls ``eps``, from the
    coefficients of f and its first three derivatives (``_derivatives``): Horner's rule
    on each, every derivative made once; without ``jets``, f, f', f'' as balls (the
    third derivative not evaluated)."""
    if not jets:
        return horner(ds[0], eps), horner(ds[1], eps), horner(ds[2], eps)
    v = [horner(c, eps) for c in ds]
    return Jet(v[0], v[1]), Jet(v[1], v[2]), Jet(v[2], v[3])


class Through:
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

    def torques(
        self, st: Stacked, eps: Ball, sigma: float | np.ndarray, jets: bool = True
    ) -> tuple[Any, Any]:
        """T (stacked) and δ as jets over balls of ε, each ball on one side (the sign of φ
        there: ``sigma``, one for all or one per ball); without ``jets``, as balls (the
        values alone: points need no derivative)."""
        x = _jets3(self.dx, eps, jets)
        y = _jets3(self.dy, eps, jets)
        reg = st.legs(x[0], x[1], x[2], y[0], y[1], y[2])
        a, b, phi = (_jets3(d, eps, jets) for d in (self.da, self.db, self.dphi))
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


def _jet_rows(reg: Any, own: Any, i: int, n: int) -> Any:
    """The stacked jet (or ball) ``reg`` (2 rows of n) with its row i replaced by ``own``."""
    if isinstance(reg, Ball):
        return _rows(reg, own, i, n)
    return Jet(_rows(reg.v, own.v, i, n), _rows(reg.d, own.d, i, n))


def _rows(R: Ball, Own: Ball, i: int, n: int) -> Ball:
    mid, rad = full(R.mid, (2, n)), full(R.rad, (2, n))
    mid[i] = Own.mid  # broadcast to the row
    rad[i] = Own.rad
    return Ball._of(mid, rad)


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

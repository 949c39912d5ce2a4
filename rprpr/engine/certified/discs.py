"""Cauchy bounds of μ and δ on complex discs about a singular instant (for ``zones``).

μ and δ continue analytically from the real line over a disc |ε| <= ρ about t_s where
s1² and s2² stay clear of 0 on it (``analytic_on_disc``); there the maximum modulus
principle bounds |μ| and |δ| by their maximum on the circle |ε| = ρ (``disc_bound``),
enclosed on complex balls over every branch of the square roots s1, s2.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from flint import acb, acb_poly, arb, arb_poly

from ..exact import equations as dyn
from .taylor_forms import CertifiedMotion, arb_params

CIRCLE_BALLS = 32  # complex balls covering the circle of a Cauchy bound (then twice)
DISC_GRID = 12  # complex balls per side of the grid proving analyticity on a disc


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
    mech, params = arb_params(motion)
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


def analytic_on_disc(
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


def disc_bound(
    motion: CertifiedMotion, coeffs: list[list[arb]], rho: float, proven: bool = False,
    balls: int = CIRCLE_BALLS,
) -> list[arb] | None:  # fmt: skip
    """Upper bounds M of |μ1|, |μ2|, |δ| on the disc |t - t_s| <= rho: where μ and δ are
    analytic on the disc (``analytic_on_disc``), by the maximum modulus principle |f|
    there is at most its maximum on the circle |z| = rho, bounded on ``balls`` complex
    balls covering the circle; one ball covering the whole disc bounds it as well.
    ``proven``: the disc is already known to be analytic; ``balls`` = 0: the one ball
    only (cheap, looser)."""
    if not proven and not analytic_on_disc(motion, coeffs, rho):
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

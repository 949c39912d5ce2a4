"""The closest approach of a motion that never meets y = 0: min |y| and min |δ| over
[0, t_f], both exactly from the critical points (real roots of y' and of (δ²)', by
``roots.real_roots_in``), not by boxes."""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial

from flint import arb, arb_poly, fmpq, fmpq_poly

from ...model.numbers import to_float
from ..certified.zones import ExactTime
from ..exact.kept import Kept, exact_key
from ..exact.roots import real_roots_in
from ..exact.series import accurate, ball
from ..exact.trajectory import Trajectory


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
    for f in _factors(r):
        if f.degree() == 1:
            out.append((x - (-f[0] / f[1]), False))
        elif f.degree() > 1:
            h = f(x)
            out.append((h // h.gcd(h.derivative()), True))
    return out


def _factors(r: fmpq_poly) -> list[fmpq_poly]:
    """The irreducible factors of R~ (``_delta_critical``), in flint's order. R~ is made of
    the path and a1 alone, so tasks of one path and robot (several timings of it, a
    repair's candidates) share its factorisation, the costly step (tens of ms at degree
    60): kept by R~'s exact coefficients (``exact.kept``), as coefficients, each caller
    given polynomials of its own."""

    def factored() -> tuple[tuple[tuple[int, ...], int], ...]:
        return tuple(
            (tuple(int(c) for c in f.numer().coeffs()), int(f.denom())) for f, _ in r.factor()[1]
        )

    got = _FACTORED.get(exact_key(r), factored)
    return [fmpq_poly(list(c), d) for c, d in got]


FACTORED_KEPT = 64
_FACTORED: Kept[tuple[tuple[tuple[int, ...], int], ...]] = Kept(FACTORED_KEPT)

"""λ near a Type II singular instant, where the direct quotient λ = μ/δ loses its digits.

Near t_s, λ = μ/δ (eqs. 30-31) is a quotient of two small numbers. Two ways around the
cancellation, both in ball arithmetic (flint's arb) and both the paper's formulas
(``equations``):

* ``lambda_series``: the Laurent series of λ1 and λ2 in ε = t - t_s, from the exact Taylor
  coefficients of x and y at t_s, with the orders of μ that vanish exactly (``singular``)
  removed; rounded to floats once per instant (``Laurent``), it is evaluated at every
  sample near t_s with the error estimate: the size of the last two terms kept, plus
  16 u times the sum of the absolute values of all terms (u the unit roundoff);
* ``lambda_ball``: λ at one sample's own time by the direct formulas, the precision
  doubled until both values are known to double precision (slow: the last resort).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from flint import arb, arb_poly, arb_series, ctx, fmpq_poly

from ..model.numbers import to_float
from ..model.task import Robot
from . import equations as dyn
from .series import taylor
from .singular import SingularInstant, _SamplerHints
from .trajectory import Trajectory

EPS = float(np.finfo(float).eps) / 2  # the unit roundoff u of a double
EXTRA_TERMS = 12  # terms of the λ series kept beyond the pole/shift, for samples near t_s
SERIES_PREC = 128  # bits of the ball arithmetic behind λ, to start with
MAX_PREC = 4096  # ... doubled up to this while a value is not certified


@dataclass
class Laurent:
    """λ_j(t_s + ε) = ε^lead Σ c_i (ε/h)^i, i = 0..len(c)-1: the coefficients are those of
    the series in ε scaled by h^i (h = t_f), so that they stay within the double range
    for any time scale."""

    t: float
    c: np.ndarray
    lead: int
    h: float

    def evaluate(self, eps: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Value and error estimate at each ε (NaN at ε = 0 when lead < 0: a pole)."""
        c = self.c
        n = len(c)
        u = eps / self.h
        value = np.full_like(u, c[-1])
        for ck in c[-2::-1]:  # Horner
            value = value * u + ck
        absum = np.polynomial.polynomial.polyval(np.abs(u), np.abs(c))
        last = np.abs(c[-1]) * np.abs(u) ** (n - 1) + np.abs(c[-2]) * np.abs(u) ** (n - 2)
        err = last + 16 * EPS * absum
        if self.lead:
            factor = np.where(eps == 0, np.nan, eps) ** float(self.lead)
            value, err = value * factor, err * np.abs(factor)
        return value, err


def lambda_series(
    traj: Trajectory, robot: Robot, s: SingularInstant, hints: _SamplerHints
) -> tuple[Laurent, Laurent] | None:
    """Laurent series of λ1 and λ2 about the singular instant ``s``, rounded to floats.

    Computed in ball arithmetic (flint's arb_series) from the exact Taylor coefficients of
    x and y at t_s, with the coefficients of μ below its exact order dropped (they are
    exactly zero); the same formulas as everywhere (``equations``). The precision is
    doubled until every coefficient is known to about 53 bits; None when even MAX_PREC
    bits do not certify them (then the samples fall back on ``lambda_ball``).
    """
    prec = SERIES_PREC
    while prec <= MAX_PREC:
        try:
            out = _lambda_series_at(traj, robot, s, hints, prec)
        except (ValueError, ZeroDivisionError):  # a leading coefficient not yet nonzero
            out = None
        if out is not None:
            return out
        prec *= 2
    return None


def _lambda_series_at(
    traj: Trajectory, robot: Robot, s: SingularInstant, hints: _SamplerHints, prec: int
) -> tuple[Laurent, Laurent] | None:
    m = s.order
    n = m + EXTRA_TERMS + 1
    old_prec, old_cap = ctx.prec, ctx.cap
    ctx.prec, ctx.cap = prec, n
    try:
        X, Xd, Xdd, Y, Yd, Ydd = _motion_series(traj, s, hints, n, prec)
        l1 = dyn.leg(X, Xd, Xdd, Y, Yd, Ydd, _arb_hypot)
        l2 = dyn.leg(X - traj.a1, Xd, Xdd, Y, Yd, Ydd, _arb_hypot)
        d = dyn.dynamics(l1, l2, dyn.Params.of(robot))
        den = arb_series(d.delta.coeffs()[m:])
        out = []
        for mu, v in ((d.mu1, hints.mu_valuations[0]), (d.mu2, hints.mu_valuations[1])):
            shift = min(v, m)
            lam = arb_series(mu.coeffs()[shift:]) / den  # exact zeros below the shift dropped
            h = arb(traj.duration)
            coeffs = [a * h**i for i, a in enumerate(lam.coeffs()[: n - m])]  # in ε/h
            scale = max((abs(float(a.mid())) for a in coeffs), default=0.0)
            if any(float(a.rad()) > 1e-16 * scale for a in coeffs):
                return None  # not certified to double precision at this working precision
            c = np.array([float(a.mid()) for a in coeffs])
            c = np.concatenate([c, np.zeros(max(0, n - m - len(c)))])
            out.append(Laurent(s.t, c, shift - m, to_float(traj.duration)))
        return out[0], out[1]
    finally:
        ctx.prec, ctx.cap = old_prec, old_cap


def _motion_series(
    traj: Trajectory, s: SingularInstant, hints: _SamplerHints, n: int, prec: int
) -> list[Any]:
    """x, x', x'', y, y', y'' as arb series (n terms) in ε about t_s."""

    def value(ck: fmpq_poly) -> arb:
        if s.t_exact is not None:
            return arb(ck(s.t_exact))
        return hints.field.evaluate(ck % hints.field.f, prec)

    ser = []
    for p in (traj.x, traj.y):
        tc = [value(ck) for ck in taylor(p, n + 2)]
        ser.append(arb_series(tc[:n]))
        ser.append(arb_series([(k + 1) * tc[k + 1] for k in range(n)]))
        ser.append(arb_series([(k + 1) * (k + 2) * tc[k + 2] for k in range(n)]))
    return ser


def _arb_hypot(u: Any, v: Any) -> Any:
    """s = |(u, v)| for arb numbers or series (s > 0 away from A and B)."""
    return (u * u + v * v).sqrt()


def lambda_ball(traj: Trajectory, robot: Robot, t: float) -> tuple[float, float] | None:
    """λ1, λ2 at the time t (a float, taken exactly) by the direct formulas (27)-(33) in
    ball arithmetic, the precision doubled until both are known to double precision;
    None when δ cannot be told from zero even at MAX_PREC bits."""
    coefficients = traj.motion_coefficients
    params = dyn.Params.of(robot)
    prec = SERIES_PREC
    old = ctx.prec
    try:
        while prec <= MAX_PREC:
            ctx.prec = prec
            tb = arb(t)
            x, xd, xdd, y, yd, ydd = (arb_poly(c)(tb) for c in coefficients)
            if not ((x * x + y * y) > 0 and ((x - traj.a1) ** 2 + y * y) > 0):
                return None
            l1 = dyn.leg(x, xd, xdd, y, yd, ydd, _arb_hypot)
            l2 = dyn.leg(x - traj.a1, xd, xdd, y, yd, ydd, _arb_hypot)
            d = dyn.dynamics(l1, l2, params)
            if d.delta != 0 and not d.delta.contains(0):
                lam = (d.mu1 / d.delta, d.mu2 / d.delta)
                if all(float(v.rad()) <= 1e-16 * abs(float(v.mid())) for v in lam):
                    return float(lam[0].mid()), float(lam[1].mid())
            prec *= 2
        return None
    finally:
        ctx.prec = old

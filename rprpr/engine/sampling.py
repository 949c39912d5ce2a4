"""The motion and its inverse dynamics on a grid of times, in floating point (numpy).

Away from the singular instants every quantity is the paper's formula evaluated directly
(``dynamics``), with δ taken in its product form δ = -a1 y/(s1 s2) (no cancellation).
Near a Type II singular instant t_s, λ = μ/δ (eqs. 30-31) is a quotient of two small
numbers and the direct formula loses digits to cancellation; there λ is taken from its
Laurent series in ε = t - t_s, computed in 128-bit ball arithmetic from the exact Taylor
coefficients of x and y at t_s, with the orders that vanish exactly (``singular``)
removed. Each sample uses whichever of the two has the smaller error estimate:

* direct:  16 u S_μ/|δ| + |λ| e_δ/|δ|, where u is the unit roundoff, S_μ the sum of the
  absolute values of the terms of μ (the size of the terms that cancel), and e_δ the
  rounding bound of δ (Horner's bound for y, relative to Σ|p_i||x|^i);
* series:  the size of the last two terms kept, plus 16 u times the sum of the absolute
  values of all terms.

A sample exactly at an instant where λ has a pole (conditions not met) is NaN: the torque
is unbounded there, never a large finite number.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from flint import arb, arb_poly, arb_series, ctx, fmpq, fmpq_poly

from ..model.numbers import to_float
from ..model.task import Robot
from . import equations as dyn
from .series import taylor
from .singular import SingularAnalysis, SingularInstant
from .trajectory import Trajectory

EXTRA_TERMS = 12  # terms of the λ series kept beyond the pole/shift, for samples near t_s
EPS = float(np.finfo(float).eps) / 2

# the export columns, in order (SI units, angles in radians, θ continuous)
COLUMNS = (
    "t", "x", "y", "x_dot", "y_dot", "theta1", "s1", "theta2", "s2",
    "theta1_dot", "s1_dot", "theta2_dot", "s2_dot", "delta", "delta_dot",
    "lambda1", "lambda2", "T1", "T2",
)  # fmt: skip


@dataclass(frozen=True)
class Samples:
    """Sampled motion: one numpy array per quantity, all of the length of ``t``."""

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    x_dot: np.ndarray
    y_dot: np.ndarray
    x_ddot: np.ndarray
    y_ddot: np.ndarray
    theta1: np.ndarray
    s1: np.ndarray
    theta2: np.ndarray
    s2: np.ndarray
    theta1_dot: np.ndarray
    s1_dot: np.ndarray
    theta2_dot: np.ndarray
    s2_dot: np.ndarray
    theta1_ddot: np.ndarray
    s1_ddot: np.ndarray
    theta2_ddot: np.ndarray
    s2_ddot: np.ndarray
    delta: np.ndarray
    delta_dot: np.ndarray
    lambda1: np.ndarray
    lambda2: np.ndarray
    T1: np.ndarray
    T2: np.ndarray

    def column(self, name: str) -> np.ndarray:
        return getattr(self, name)

    def rows(self) -> np.ndarray:
        """The export columns as a 2-D array, one row per sample."""
        return np.column_stack([self.column(c) for c in COLUMNS])


def grid(duration: fmpq, n: int) -> np.ndarray:
    """n sample times t_i = i t_f/(n-1), i = 0..n-1, each the float nearest the exact value."""
    if n < 2:
        raise ValueError("at least 2 samples are needed")
    num, den = int(duration.p), int(duration.q)
    if num * (n - 1) < 2**53 and den * (n - 1) < 2**53:  # exact products, one rounding
        return np.arange(n) * float(num) / float((n - 1) * den)
    return np.array([(i * num) / ((n - 1) * den) for i in range(n)])


def _coeffs(p: fmpq_poly) -> np.ndarray:
    c = [to_float(q) for q in p.coeffs()]
    return np.array(c or [0.0])


def _polyval(c: np.ndarray, x: np.ndarray) -> np.ndarray:
    return np.polynomial.polynomial.polyval(x, c)


@dataclass
class _Laurent:
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
        absum = _polyval(np.abs(c), np.abs(u))
        last = np.abs(c[-1]) * np.abs(u) ** (n - 1) + np.abs(c[-2]) * np.abs(u) ** (n - 2)
        err = last + 16 * EPS * absum
        if self.lead:
            factor = np.where(eps == 0, np.nan, eps) ** float(self.lead)
            value, err = value * factor, err * np.abs(factor)
        return value, err


SERIES_PREC = 128  # bits of the ball arithmetic behind the λ series, to start with
MAX_PREC = 4096  # ... doubled up to this while a coefficient is not certified
TOLERANCE = 1e-9  # relative error estimate a sample of λ must meet (else ball arithmetic)
MAX_BALL_SAMPLES = 2000  # samples evaluated in ball arithmetic per task, at most


def lambda_series(
    traj: Trajectory, robot: Robot, s: SingularInstant
) -> tuple[_Laurent, _Laurent] | None:
    """Laurent series of λ1 and λ2 about the singular instant ``s``, rounded to floats.

    Computed in ball arithmetic (flint's arb_series) from the exact Taylor coefficients of
    x and y at t_s, with the coefficients of μ below its exact order dropped (they are
    exactly zero); the same formulas as everywhere (``dynamics``). The precision is
    doubled until every coefficient is known to about 53 bits; None when even MAX_PREC
    bits do not certify them (then the samples fall back on ball arithmetic).
    """
    prec = SERIES_PREC
    while prec <= MAX_PREC:
        try:
            out = _lambda_series_at(traj, robot, s, prec)
        except (ValueError, ZeroDivisionError):  # a leading coefficient not yet nonzero
            out = None
        if out is not None:
            return out
        prec *= 2
    return None


def _lambda_series_at(
    traj: Trajectory, robot: Robot, s: SingularInstant, prec: int
) -> tuple[_Laurent, _Laurent] | None:
    m = s.order
    n = m + EXTRA_TERMS + 1
    old_prec, old_cap = ctx.prec, ctx.cap
    ctx.prec, ctx.cap = prec, n
    try:

        def value(ck: fmpq_poly) -> arb:
            if s.t_exact is not None:
                return arb(ck(s.t_exact))
            return s.field.evaluate(ck % s.field.f, prec)

        ser = []
        for p in (traj.x, traj.y):
            tc = [value(ck) for ck in taylor(p, n + 2)]
            ser.append(arb_series(tc[:n]))
            ser.append(arb_series([(k + 1) * tc[k + 1] for k in range(n)]))
            ser.append(arb_series([(k + 1) * (k + 2) * tc[k + 2] for k in range(n)]))
        X, Xd, Xdd, Y, Yd, Ydd = ser
        l1 = dyn.leg(X, Xd, Xdd, Y, Yd, Ydd, _arb_hypot)
        l2 = dyn.leg(X - traj.a1, Xd, Xdd, Y, Yd, Ydd, _arb_hypot)
        d = dyn.dynamics(l1, l2, dyn.Params.of(robot))
        den = arb_series(d.delta.coeffs()[m:])
        out = []
        for mu, v in ((d.mu1, s.mu_valuations[0]), (d.mu2, s.mu_valuations[1])):
            shift = min(v, m)
            lam = arb_series(mu.coeffs()[shift:]) / den  # exact zeros below the shift dropped
            h = arb(traj.duration)
            coeffs = [a * h**i for i, a in enumerate(lam.coeffs()[: n - m])]  # in ε/h
            scale = max((abs(float(a.mid())) for a in coeffs), default=0.0)
            if any(float(a.rad()) > 1e-16 * scale for a in coeffs):
                return None  # not certified to double precision at this working precision
            c = np.array([float(a.mid()) for a in coeffs])
            c = np.concatenate([c, np.zeros(max(0, n - m - len(c)))])
            out.append(_Laurent(s.t, c, shift - m, _float(traj.duration)))
        return out[0], out[1]
    finally:
        ctx.prec, ctx.cap = old_prec, old_cap


def _arb_hypot(u: Any, v: Any) -> Any:
    """s = |(u, v)| for arb numbers or series (s > 0 away from A and B)."""
    return (u * u + v * v).sqrt()


def _lambda_ball(traj: Trajectory, robot: Robot, t: float) -> tuple[float, float] | None:
    """λ1, λ2 at the time t (a float, taken exactly) by the direct formulas (27)-(33) in
    ball arithmetic, the precision doubled until both are known to double precision;
    None when δ cannot be told from zero even at MAX_PREC bits."""
    polys = [traj.x, traj.x.derivative(), traj.x.derivative().derivative()]
    polys += [traj.y, traj.y.derivative(), traj.y.derivative().derivative()]
    params = dyn.Params.of(robot)
    prec = SERIES_PREC
    old = ctx.prec
    try:
        while prec <= MAX_PREC:
            ctx.prec = prec
            tb = arb(t)
            x, xd, xdd, y, yd, ydd = (arb_poly(p.coeffs())(tb) for p in polys)
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


def _float(q: fmpq) -> float:
    return to_float(q)


def _continuous_angle(
    raw: np.ndarray, t: np.ndarray, cuts: list[tuple[float, int, bool]]
) -> np.ndarray:
    """θ made continuous: atan2 jumps by 2π where the leg's line crosses its branch cut
    (y = 0 on the far side of its base joint). ``cuts`` = (t_c, sign of y after, crossing?)
    for each singular instant on the cut; the crossings are known exactly, so no
    threshold on sample spacing is involved. A sample at t_c takes the limit from the left.
    """
    out = raw.copy()
    width = 64 * EPS * max(1.0, float(t[-1]) if len(t) else 1.0)
    for tc, after, crossing in cuts:  # samples on the cut: atan2's value from the left
        out[np.abs(t - tc) <= width] = -np.pi * after if crossing else np.pi * after
    for tc, after, crossing in cuts:  # past a crossing, the branch is 2π further on
        if crossing:
            out[t > tc + width] -= 2 * np.pi * after
    return out


def sample(traj: Trajectory, robot: Robot, analysis: SingularAnalysis, t: np.ndarray) -> Samples:
    """The motion, joints, δ, λ and torques at the times ``t`` (seconds)."""
    p = dyn.Params.of(robot, _float)
    xc = _coeffs(traj.x)
    pc = _coeffs(traj.path)
    with np.errstate(all="ignore"):
        x = _polyval(xc, t)
        xd = _polyval(np.polynomial.polynomial.polyder(xc), t)
        xdd = _polyval(np.polynomial.polynomial.polyder(xc, 2), t)
        y = _polyval(pc, x)
        p1 = _polyval(np.polynomial.polynomial.polyder(pc), x)
        p2 = _polyval(np.polynomial.polynomial.polyder(pc, 2), x)
        yd = p1 * xd
        ydd = p2 * xd * xd + p1 * xdd
        # near a singular instant y(t) is small and Horner's rule on the path loses its
        # digits: there y, y', y'' come from y's exact Taylor polynomial about t_s
        ycond = _polyval(np.abs(pc), np.abs(x))
        near = _nearest(t, analysis)
        for i, s in enumerate(analysis.instants):
            zone = (near == i) & (np.abs(y) < 1e6 * len(pc) * EPS * ycond)
            if np.any(zone):
                _recentered(traj, s, t[zone] - s.t, zone, y, yd, ydd, ycond)
        leg1 = dyn.leg(x, xd, xdd, y, yd, ydd, np.hypot)
        leg2 = dyn.leg(x - p.a1, xd, xdd, y, yd, ydd, np.hypot)
        d = dyn.dynamics(leg1, leg2, p)
        delta = -p.a1 * y / (leg1.s * leg2.s)  # eq. (29) in product form
        lam1 = d.mu1 / delta
        lam2 = d.mu2 / delta
        # error estimate of the direct quotient (module docstring)
        f1 = p.m3 * (xd * xd + yd * yd + np.abs(x * xdd) + np.abs(y * ydd) + leg1.s_d**2) / leg1.s
        f1 += p.m3 * (np.abs(leg1.s - p.r3) * leg1.th_d**2 + p.g)
        f2 = (
            p.m5
            * (xd * xd + yd * yd + np.abs((x - p.a1) * xdd) + np.abs(y * ydd) + leg2.s_d**2)
            / leg2.s
        )
        f2 += p.m5 * (np.abs(leg2.s - p.r5) * leg2.th_d**2 + p.g)
        degree = max(len(pc), traj.y.degree() + 1)
        e_delta = np.abs(delta) * (3 * EPS + 2 * degree * EPS * ycond / np.abs(y)) + 4 * EPS
        e_mu = 16 * EPS * (f1 + f2)
        ad = np.abs(delta)
        err1 = e_mu / ad + np.abs(lam1) * e_delta / ad
        err2 = e_mu / ad + np.abs(lam2) * e_delta / ad
        err1 = np.where(np.isfinite(err1), err1, np.inf)
        err2 = np.where(np.isfinite(err2), err2, np.inf)
        for i, s in enumerate(analysis.instants):
            inaccurate = ~(err1 <= 1e-9 * (1 + np.abs(lam1))) | ~(err2 <= 1e-9 * (1 + np.abs(lam2)))
            if not np.any(inaccurate & (near == i)):
                continue  # the direct formula is accurate near this instant
            series = lambda_series(traj, robot, s)
            if series is None:
                continue  # no certified series here: the ball-arithmetic fallback below
            eps_t = t - s.t
            for lam, err, L in zip((lam1, lam2), (err1, err2), series, strict=True):
                v, e = L.evaluate(eps_t)
                better = (near == i) & ((e < err) | (eps_t == 0))
                lam[better] = v[better]
                err[better] = e[better]
        # where neither estimate is good enough, evaluate λ in ball arithmetic at the
        # sample's own time (slow, so only there); a pole or a base joint stays non-finite
        poles = np.zeros(len(t), dtype=bool)
        for s in analysis.instants:
            if not s.torque_bounded:
                poles |= t == s.t
        doubtful = (
            ~((err1 <= TOLERANCE * (1 + np.abs(lam1))) & (err2 <= TOLERANCE * (1 + np.abs(lam2))))
            & ~poles
            & (leg1.s > 0)
            & (leg2.s > 0)
        )
        if not analysis.on_singular_line:
            for j in np.nonzero(doubtful)[0][:MAX_BALL_SAMPLES]:
                ball = _lambda_ball(traj, robot, float(t[j]))
                if ball is not None:
                    lam1[j], lam2[j] = ball
        T1, T2 = dyn.torques(d, lam1, lam2)
        theta1 = _continuous_angle(np.arctan2(y, x), t, _cuts(analysis, 1))
        theta2 = _continuous_angle(np.arctan2(y, x - p.a1), t, _cuts(analysis, 2))
        theta1[leg1.s == 0] = np.nan  # E at A: θ1 undefined
        theta2[leg2.s == 0] = np.nan  # E at B: θ2 undefined
        delta_dot = np.cos(theta1 - theta2) * (leg1.th_d - leg2.th_d)
    return Samples(
        t=t, x=x, y=y, x_dot=xd, y_dot=yd, x_ddot=xdd, y_ddot=ydd,
        theta1=theta1, s1=leg1.s, theta2=theta2, s2=leg2.s,
        theta1_dot=leg1.th_d, s1_dot=leg1.s_d, theta2_dot=leg2.th_d, s2_dot=leg2.s_d,
        theta1_ddot=leg1.th_dd, s1_ddot=leg1.s_dd, theta2_ddot=leg2.th_dd, s2_ddot=leg2.s_dd,
        delta=delta, delta_dot=delta_dot, lambda1=lam1, lambda2=lam2, T1=T1, T2=T2,
    )  # fmt: skip


def _nearest(t: np.ndarray, analysis: SingularAnalysis) -> np.ndarray:
    """Index of the singular instant nearest each sample (-1 when there is none)."""
    if not analysis.instants:
        return np.full(len(t), -1)
    ts = np.array([s.t for s in analysis.instants])
    return np.argmin(np.abs(t[:, None] - ts[None, :]), axis=1)


def _recentered(
    traj: Trajectory, s: SingularInstant, eps: np.ndarray, zone: np.ndarray,
    y: np.ndarray, yd: np.ndarray, ydd: np.ndarray, ycond: np.ndarray,
) -> None:  # fmt: skip
    """y, y', y'' at t_s + ε from the Taylor polynomial of y(t) about t_s (exact
    coefficients, the first ``order`` of them zero), written into the zone, with the
    matching rounding scale Σ|c_k||ε|^k in ``ycond``."""
    # in u = ε/h (h = t_f) the coefficients c_k h^k stay within the double range
    h = traj.duration
    taylor_c = taylor(traj.y, traj.y.degree() + 1)
    c = np.array([s.field.to_float((ck % s.field.f) * h**k) for k, ck in enumerate(taylor_c)])
    u = eps / _float(h)
    y[zone] = _polyval(c, u)
    ycond[zone] = _polyval(np.abs(c), np.abs(u))
    dc = np.polynomial.polynomial.polyder(c)
    yd[zone] = _polyval(dc, u) / _float(h)
    ydd[zone] = _polyval(np.polynomial.polynomial.polyder(dc), u) / _float(h) ** 2


def _cuts(analysis: SingularAnalysis, leg: int) -> list[tuple[float, int, bool]]:
    """Instants at which y = 0 on leg ``leg``'s branch cut (the far side of its base
    joint): Type II instants behind A (case 2) for leg 1; behind B (cases 2 and 3) for
    leg 2, and also E passing A (a kinematic singularity of leg 1 only)."""
    on_cut = (2,) if leg == 1 else (2, 3)
    cuts = [
        (s.t, s.y_leading_sign, s.order % 2 == 1)
        for s in analysis.instants
        if s.case.number in on_cut
    ]
    if leg == 2:
        cuts += [
            (k.t, k.y_leading_sign, k.order % 2 == 1) for k in analysis.kinematic if k.leg == 1
        ]
    return sorted(cuts)

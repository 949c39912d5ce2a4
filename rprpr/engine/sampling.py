"""The motion and its inverse dynamics on a grid of times, in floating point (numpy).

``sample`` runs these stages, one function each:

1. the motion: x, y and their derivatives; near a singular instant, where y is small and
   Horner's rule on the path loses its digits, y from its exact Taylor polynomial about t_s;
2. the legs: both legs' joint values (inverse kinematics);
3. the dynamics: the paper's equations, with δ in its product form δ = -a1 y/(s1 s2)
   (no cancellation);
4. λ = μ/δ directly (eqs. 30-31), with the error estimate 16 u S_μ/|δ| + |λ| e_δ/|δ|,
   where u is the unit roundoff, S_μ the sum of the absolute values of the terms of μ (the
   size of the terms that cancel), and e_δ the rounding bound of δ (Horner's bound for y,
   relative to Σ|p_i||x|^i);
5. near a Type II singular instant, where that quotient loses digits to cancellation, λ
   from its Laurent series in ε = t - t_s (``near_pole``) wherever its error estimate is
   the smaller;
6. where neither meets TOLERANCE, λ in ball arithmetic at the sample's own time;
7. the torques (eq. 28), and the angles θ1, θ2 made continuous across the branch cuts.

A sample exactly at an instant where λ has a pole (conditions not met) is NaN: the torque
is unbounded there, never a large finite number.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from flint import fmpq, fmpq_poly

from ..model.numbers import to_float
from ..model.task import Robot
from . import equations as dyn
from .near_pole import EPS, lambda_ball, lambda_series
from .series import NumberField, taylor
from .singular import SingularAnalysis
from .trajectory import Trajectory

TOLERANCE = 1e-9  # relative error estimate a sample of λ must meet (else ball arithmetic)
MAX_BALL_SAMPLES = 2000  # samples evaluated in ball arithmetic per task, at most

Pair = tuple[np.ndarray, np.ndarray]  # (λ1, λ2), or their error estimates

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


def sample(traj: Trajectory, robot: Robot, analysis: SingularAnalysis, t: np.ndarray) -> Samples:
    """The motion, joints, δ, λ and torques at the times ``t`` (seconds)."""
    p = dyn.Params.of(robot, to_float)
    with np.errstate(all="ignore"):
        m = _motion(traj, analysis, t)
        leg1, leg2 = _legs(m, p)
        d, delta = _dynamics(m, leg1, leg2, p)
        lam, err = _direct_lambda(traj, m, d, delta, p)
        lam, err = _near_pole(traj, robot, analysis, m, lam, err)
        lam1, lam2 = _ball_fallback(traj, robot, analysis, m, d, lam, err)
        T1, T2 = dyn.torques(d, lam1, lam2)
        theta1, theta2 = _angles(analysis, m, d, p)
        delta_dot = np.cos(theta1 - theta2) * (leg1.th_d - leg2.th_d)  # of δ = sin(θ1 - θ2)
    return Samples(
        t=t, x=m.x, y=m.y, x_dot=m.x_dot, y_dot=m.y_dot, x_ddot=m.x_ddot, y_ddot=m.y_ddot,
        theta1=theta1, s1=leg1.s, theta2=theta2, s2=leg2.s,
        theta1_dot=leg1.th_d, s1_dot=leg1.s_d, theta2_dot=leg2.th_d, s2_dot=leg2.s_d,
        theta1_ddot=leg1.th_dd, s1_ddot=leg1.s_dd, theta2_ddot=leg2.th_dd, s2_ddot=leg2.s_dd,
        delta=delta, delta_dot=delta_dot, lambda1=lam1, lambda2=lam2, T1=T1, T2=T2,
    )  # fmt: skip


# -- 1. the motion ----------------------------------------------------------------------------


@dataclass(frozen=True)
class _Motion:
    """x, y and their first two derivatives at the times ``t``; ``y_scale`` is the rounding
    scale of y (Σ|p_i||x|^i, or Σ|c_k||ε|^k where y was recentred); ``near`` the index of
    the singular instant nearest each sample (-1 when there is none)."""

    t: np.ndarray
    x: np.ndarray
    x_dot: np.ndarray
    x_ddot: np.ndarray
    y: np.ndarray
    y_dot: np.ndarray
    y_ddot: np.ndarray
    y_scale: np.ndarray
    near: np.ndarray


def _motion(traj: Trajectory, analysis: SingularAnalysis, t: np.ndarray) -> _Motion:
    """x(t) and y = p(x(t)) with their derivatives; near a singular instant, where y is
    small and Horner's rule on the path loses its digits, y, y', y'' come from y's exact
    Taylor polynomial about t_s instead."""
    P = np.polynomial.polynomial
    xc = _coeffs(traj.x)
    pc = _coeffs(traj.path)
    x = _polyval(xc, t)
    xd = _polyval(P.polyder(xc), t)
    xdd = _polyval(P.polyder(xc, 2), t)
    y = _polyval(pc, x)
    p1 = _polyval(P.polyder(pc), x)
    p2 = _polyval(P.polyder(pc, 2), x)
    yd = p1 * xd
    ydd = p2 * xd * xd + p1 * xdd
    y_scale = _polyval(np.abs(pc), np.abs(x))
    near = _nearest(t, analysis)
    for i, (s, hints) in enumerate(zip(analysis.instants, analysis._hints, strict=True)):
        zone = (near == i) & (np.abs(y) < 1e6 * len(pc) * EPS * y_scale)
        if np.any(zone):
            _recentered(traj, hints.field, t[zone] - s.t, zone, y, yd, ydd, y_scale)
    return _Motion(t, x, xd, xdd, y, yd, ydd, y_scale, near)


def _nearest(t: np.ndarray, analysis: SingularAnalysis) -> np.ndarray:
    """Index of the singular instant nearest each sample (-1 when there is none)."""
    if not analysis.instants:
        return np.full(len(t), -1)
    ts = np.array([s.t for s in analysis.instants])
    return np.argmin(np.abs(t[:, None] - ts[None, :]), axis=1)


def _recentered(
    traj: Trajectory, field: NumberField, eps: np.ndarray, zone: np.ndarray,
    y: np.ndarray, yd: np.ndarray, ydd: np.ndarray, y_scale: np.ndarray,
) -> None:  # fmt: skip
    """y, y', y'' at t_s + ε from the Taylor polynomial of y(t) about t_s (exact
    coefficients in ``field``, the first ``order`` of them zero), written into the zone,
    with the matching rounding scale Σ|c_k||ε|^k in ``y_scale``."""
    # in u = ε/h (h = t_f) the coefficients c_k h^k stay within the double range
    h = traj.duration
    taylor_c = taylor(traj.y, traj.y.degree() + 1)
    c = np.array([field.to_float((ck % field.f) * h**k) for k, ck in enumerate(taylor_c)])
    u = eps / to_float(h)
    y[zone] = _polyval(c, u)
    y_scale[zone] = _polyval(np.abs(c), np.abs(u))
    dc = np.polynomial.polynomial.polyder(c)
    yd[zone] = _polyval(dc, u) / to_float(h)
    ydd[zone] = _polyval(np.polynomial.polynomial.polyder(dc), u) / to_float(h) ** 2


# -- 2. the legs, 3. the dynamics -------------------------------------------------------------


def _legs(m: _Motion, p: dyn.Params) -> tuple[dyn.Leg, dyn.Leg]:
    """Both legs' joint values: leg 1 from A at the origin, leg 2 from B at (a1, 0)."""
    leg1 = dyn.leg(m.x, m.x_dot, m.x_ddot, m.y, m.y_dot, m.y_ddot, np.hypot)
    leg2 = dyn.leg(m.x - p.a1, m.x_dot, m.x_ddot, m.y, m.y_dot, m.y_ddot, np.hypot)
    return leg1, leg2


def _dynamics(
    m: _Motion, leg1: dyn.Leg, leg2: dyn.Leg, p: dyn.Params
) -> tuple[dyn.Dynamics, np.ndarray]:
    """The paper's equations on the samples, and δ in its product form (no cancellation)."""
    d = dyn.dynamics(leg1, leg2, p)
    delta = -p.a1 * m.y / (leg1.s * leg2.s)  # eq. (29) in product form
    return d, delta


# -- 4. λ directly, 5. near a pole, 6. in ball arithmetic --------------------------------------


def _direct_lambda(
    traj: Trajectory, m: _Motion, d: dyn.Dynamics, delta: np.ndarray, p: dyn.Params
) -> tuple[Pair, Pair]:
    """λ1, λ2 = μ/δ (eqs. 30-31) and their error estimates (module docstring; inf where
    the estimate is not finite)."""
    lam1 = d.mu1 / delta
    lam2 = d.mu2 / delta
    s_mu = _mu_terms(m, m.x, d.leg1, p.m3, p.r3, p.g)
    s_mu += _mu_terms(m, m.x - p.a1, d.leg2, p.m5, p.r5, p.g)
    degree = max(len(_coeffs(traj.path)), traj.y.degree() + 1)
    e_delta = np.abs(delta) * (3 * EPS + 2 * degree * EPS * m.y_scale / np.abs(m.y)) + 4 * EPS
    e_mu = 16 * EPS * s_mu
    ad = np.abs(delta)
    err1 = e_mu / ad + np.abs(lam1) * e_delta / ad
    err2 = e_mu / ad + np.abs(lam2) * e_delta / ad
    err1 = np.where(np.isfinite(err1), err1, np.inf)
    err2 = np.where(np.isfinite(err2), err2, np.inf)
    return (lam1, lam2), (err1, err2)


def _mu_terms(
    m: _Motion, u: np.ndarray, leg: dyn.Leg, mass: float, r: float, g: float
) -> np.ndarray:
    """The sum of the absolute values of the terms of F = M s'' + N of one leg (eqs. 8-14,
    u = x - x_base), a bound on the size of the terms that cancel in μ."""
    ud2 = m.x_dot * m.x_dot + m.y_dot * m.y_dot
    f = mass * (ud2 + np.abs(u * m.x_ddot) + np.abs(m.y * m.y_ddot) + leg.s_d**2) / leg.s
    return f + mass * (np.abs(leg.s - r) * leg.th_d**2 + g)


def _accurate(lam: Pair, err: Pair) -> np.ndarray:
    """Where both error estimates meet TOLERANCE, relative to 1 + |λ|."""
    ok1 = err[0] <= TOLERANCE * (1 + np.abs(lam[0]))
    return ok1 & (err[1] <= TOLERANCE * (1 + np.abs(lam[1])))


def _near_pole(
    traj: Trajectory, robot: Robot, analysis: SingularAnalysis, m: _Motion, lam: Pair, err: Pair
) -> tuple[Pair, Pair]:
    """λ and its error estimate with, near each singular instant at which the direct
    quotient is not accurate, the Laurent series' value wherever its estimate is smaller
    (and at t_s itself)."""
    lam1, lam2, err1, err2 = lam[0].copy(), lam[1].copy(), err[0].copy(), err[1].copy()
    for i, (s, hints) in enumerate(zip(analysis.instants, analysis._hints, strict=True)):
        mine = m.near == i
        if not np.any(~_accurate((lam1, lam2), (err1, err2)) & mine):
            continue  # the direct formula is accurate near this instant
        series = lambda_series(traj, robot, s, hints)
        if series is None:
            continue  # no certified series here: the ball-arithmetic fallback
        eps = m.t - s.t
        for lam_j, err_j, L in zip((lam1, lam2), (err1, err2), series, strict=True):
            v, e = L.evaluate(eps)
            better = mine & ((e < err_j) | (eps == 0))
            lam_j[better] = v[better]
            err_j[better] = e[better]
    return (lam1, lam2), (err1, err2)


def _ball_fallback(
    traj: Trajectory, robot: Robot, analysis: SingularAnalysis, m: _Motion,
    d: dyn.Dynamics, lam: Pair, err: Pair,
) -> Pair:  # fmt: skip
    """λ with, where neither estimate meets TOLERANCE, its value in ball arithmetic at the
    sample's own time (slow, so only there, at most MAX_BALL_SAMPLES); a pole or a base
    joint stays non-finite."""
    if analysis.on_singular_line:
        return lam
    poles = np.zeros(len(m.t), dtype=bool)
    for s in analysis.instants:
        if not s.torque_bounded:
            poles |= m.t == s.t
    doubtful = ~_accurate(lam, err) & ~poles & (d.leg1.s > 0) & (d.leg2.s > 0)
    lam1, lam2 = lam[0].copy(), lam[1].copy()
    for j in np.nonzero(doubtful)[0][:MAX_BALL_SAMPLES]:
        ball = lambda_ball(traj, robot, float(m.t[j]))
        if ball is not None:
            lam1[j], lam2[j] = ball
    return lam1, lam2


# -- 7. the continuous angles -----------------------------------------------------------------


def _angles(
    analysis: SingularAnalysis, m: _Motion, d: dyn.Dynamics, p: dyn.Params
) -> tuple[np.ndarray, np.ndarray]:
    """θ1, θ2 continuous along the motion (NaN where E is at the leg's base joint)."""
    theta1 = _continuous_angle(np.arctan2(m.y, m.x), m.t, _cuts(analysis, 1))
    theta2 = _continuous_angle(np.arctan2(m.y, m.x - p.a1), m.t, _cuts(analysis, 2))
    theta1[d.leg1.s == 0] = np.nan  # E at A: θ1 undefined
    theta2[d.leg2.s == 0] = np.nan  # E at B: θ2 undefined
    return theta1, theta2


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


def _cuts(analysis: SingularAnalysis, leg: int) -> list[tuple[float, int, bool]]:
    """Instants at which y = 0 on leg ``leg``'s branch cut (the far side of its base
    joint): Type II instants behind A (case 2) for leg 1; behind B (cases 2 and 3) for
    leg 2, and also E passing A (a kinematic singularity of leg 1 only)."""
    on_cut = (2,) if leg == 1 else (2, 3)
    cuts = [
        (s.t, h.y_leading_sign, s.order % 2 == 1)
        for s, h in zip(analysis.instants, analysis._hints, strict=True)
        if s.case.number in on_cut
    ]
    if leg == 2:
        cuts += [
            (k.t, sign, k.order % 2 == 1)
            for k, sign in zip(analysis.kinematic, analysis._kinematic_signs, strict=True)
            if k.leg == 1
        ]
    return sorted(cuts)

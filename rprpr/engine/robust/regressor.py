"""The regressor of the efforts over the box of ``docs/robust.md`` (``robust.windows``,
``robust.worst``): both schemes' efforts are linear forms in the links' inertial
parameters π (``BASIS``) and affine in the acceleration error e; each link's largest
value over its box in closed form, in doubles (``link_max_float``) and proven in balls
(``link_max_ball``)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from flint import arb

from ...model.task import Robot
from ..exact import equations as dyn
from ..exact.mechanism import of

# the links' inertial parameters (π above): (link, what), what one of m, mr, J
BASIS = ((2, "mr"), (2, "J"), (3, "m"), (3, "mr"), (3, "J"),
         (4, "mr"), (4, "J"), (5, "m"), (5, "mr"), (5, "J"))  # fmt: skip
# the (m, r, I) settings whose efforts give the regressor: setting k has π = SETTINGS_PI[k]
SETTING = {"m": (1, 0, 0), "mr": (1, 1, -1), "J": (0, 0, 1)}


# -- the regressor: efforts as linear forms in π, affine in e ----------------------------


def setting_params(robot: Robot, k: int, convert: Callable[[Any], Any]) -> dyn.Params:
    """The parameters whose π is the k-th setting: one link's (m, r, I) from ``SETTING``,
    every other link zero."""
    link, what = BASIS[k]
    m, r, i = SETTING[what]
    z = convert(0)
    vals = dict.fromkeys((2, 3, 4, 5), (z, z, z))
    vals[link] = (convert(m), convert(r), convert(i))
    return dyn.Params(
        convert(robot.a1), convert(robot.gravity),
        vals[2][0], vals[2][2], vals[2][1], vals[3][0], vals[3][2], vals[3][1],
        vals[4][0], vals[4][2], vals[4][1], vals[5][0], vals[5][2], vals[5][1],
        of(robot),
    )  # fmt: skip


def settings_array(robot: Robot) -> dyn.Params:
    """All the settings at once: each link parameter a double array over ``BASIS``."""
    cols = [setting_params(robot, k, float) for k in range(len(BASIS))]
    names = ("m2", "I2", "r2", "m3", "I3", "r3", "m4", "I4", "r4", "m5", "I5", "r5")
    arrays = {n: np.array([getattr(c, n) for c in cols]) for n in names}
    return dyn.Params(float(robot.a1), float(robot.gravity), **arrays, mechanism=of(robot))


def to_basis(values: list[Any]) -> list[Any]:
    """From the efforts at the settings to the coefficients of π: the "mr" setting has
    π = (m, mr) = (1, 1), so its coefficient is its value less the "m" setting's (links 3,
    5); links 2, 4 have no m coefficient."""
    out = list(values)
    for k, (link, what) in enumerate(BASIS):
        if what == "mr" and (link, "m") in BASIS:
            out[k] = values[k] - values[BASIS.index((link, "m"))]
    return out


def legs_about(
    c: Sequence[Sequence[Any]], h: Any, p: dyn.Params, ex: Any, ey: Any, hyp: Any
) -> Any:
    """The legs at t_s + h from the Taylor coefficients ``c`` (x, x', x'', y, y', y''
    about t_s), the acceleration error (ex, ey) added (the mechanism's inverse kinematics)."""
    x, xd, xdd, y, yd, ydd = (horner_at(q, h) for q in c)
    return p.mechanism.legs(p, x, xd, xdd + ex, y, yd, ydd + ey, hyp)


def horner_at(p: Sequence[Any], h: Any) -> Any:
    v = p[-1] * 1 if p else 0 * h
    for c in reversed(p[:-1]):
        v = v * h + c
    return v + 0 * h


def efforts_of(legs: Any, p: dyn.Params) -> tuple[Any, Any]:
    """(T1, T2) of the scheme at the legs (λ = μ/δ, eqs. 30-31)."""
    d = dyn.dynamics(legs[0], legs[1], p)
    return dyn.efforts(d, d.mu1 / d.delta, d.mu2 / d.delta)


# -- the exact maximum of a link's linear form over its box ------------------------------


def link_max_float(A: Any, B: Any, C: Any, box: Any) -> Any:
    """max over (m, r, I) in the box of A m + B m r + C (m r² + I), elementwise."""
    (mlo, mhi), (rlo, rhi), (ilo, ihi) = box
    glo = A + B * rlo + C * rlo * rlo
    ghi = A + B * rhi + C * rhi * rhi
    G = np.maximum(glo, ghi)
    with np.errstate(divide="ignore", invalid="ignore"):
        rs = -B / (2 * C)
        inside = (C < 0) & (rs > rlo) & (rs < rhi)
        G = np.where(inside, np.maximum(G, A - B * B / (4 * C)), G)
    return np.maximum(mlo * G, mhi * G) + np.maximum(C * ilo, C * ihi)


Pair = tuple[arb, arb]  # (a lower bound, an upper bound): exact points, never one wide ball


def pair(b: arb) -> Pair:
    return b.lower(), b.upper()


def pair_max(pairs: Sequence[Pair]) -> Pair:
    """Bounds on the largest of values bounded by ``pairs``."""
    lo, hi = pairs[0][0].lower(), pairs[0][1].upper()
    for a, b in pairs[1:]:
        a, b = a.lower(), b.upper()
        if a > lo:
            lo = a
        if b > hi:
            hi = b
    return lo, hi


def link_max_ball(A: arb, B: arb, C: arb, box: Any) -> Pair:
    """``link_max_float`` in ball arithmetic: bounds on the maximum."""
    (mlo, mhi), (rlo, rhi), (ilo, ihi) = box
    g0 = A + B * rlo + C * rlo * rlo
    g = [pair(g0), pair(A + B * rhi + C * rhi * rhi)]
    if not (C > 0) and not C.is_zero():  # an interior maximum in r is possible
        if C < 0:
            rs = -B / (2 * C)
            if not (rs <= rlo or rs >= rhi):
                top = A - B * B / (4 * C)
                if rs > rlo and rs < rhi:
                    g.append(pair(top))
                else:  # maybe inside: it bounds the maximum from above only
                    g.append((g0.lower(), top.upper()))
        else:  # C's sign undecided: the quadratic's range over [r_lo, r_hi]
            r = (arb(rlo) + arb(rhi)) / 2 + (arb(rhi) - arb(rlo)) / 2 * arb("0 +/- 1")
            g.append((g0.lower(), (A + B * r + C * r * r).upper()))
    Glo, Ghi = pair_max(g)
    mG = pair_max([(mlo * Glo, mlo * Ghi), (mhi * Glo, mhi * Ghi)])
    cI = pair_max([pair(C * ilo), pair(C * ihi)])
    return (mG[0] + cI[0]).lower(), (mG[1] + cI[1]).upper()


LINKS = ((2, None, 0, 1), (3, 2, 3, 4), (4, None, 5, 6), (5, 7, 8, 9))  # link, m, mr, J


def form_max(Y: Sequence[Any], box: Any, ball: bool) -> Any:
    """max over the box's links of Σ_k Y_k π_k (Y indexed as ``BASIS``)."""
    total: Any = 0
    lo, hi = arb(0), arb(0)
    for link, km, kmr, kj in LINKS:
        A = Y[km] if km is not None else Y[kmr] * 0
        b = box[link]
        if ball:
            pl, ph = link_max_ball(A, Y[kmr], Y[kj], b)
            lo, hi = (lo + pl).lower(), (hi + ph).upper()
        else:
            total = total + link_max_float(A, Y[kmr], Y[kj], b)
    return (lo, hi) if ball else total

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
from ..certified.kernel import INDEX, KERNEL
from ..exact import equations as dyn
from ..exact.mechanism import of
from ..exact.regressor_form import BASIS as BASIS
from ..exact.regressor_form import LINKS as LINKS
from ..exact.regressor_form import closed_form as closed_form
from ..exact.regressor_form import regressor_columns as regressor_columns

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


def regressor_balls(robot: Robot, kin: Sequence[Any], jets: bool = False) -> Any:
    """The regressor [effort, ``BASIS``, e = 0 / per unit e_x / per unit e_y, time] as
    one ball array (``regressor_columns``; ``closed_form`` robots) from the end point's
    balls ``kin``; with ``jets`` (``kin`` first-order jets over boxes of time), the pair
    (values, derivatives), each enclosing its quantity at every time of its box."""
    from ..certified.balls import Ball, hypot

    p = _ball_params(robot)
    if KERNEL is not None:
        got = _compiled(p, kin, jets)
        if got is not None:
            return got
    hyp = (lambda u, v: (u * u + v * v).sqrt()) if jets else hypot
    cols = regressor_columns(p, kin, hyp)
    shape = np.broadcast_shapes(*(np.shape((k.v if jets else k).mid) for k in kin))
    out = []
    for which in ("v", "d") if jets else (None,):
        mid = np.zeros((2, len(BASIS), 3, *shape))
        rad = np.zeros((2, len(BASIS), 3, *shape))
        for j, row in enumerate(cols):
            for k, entry in enumerate(row):
                for e, b in enumerate(entry):
                    if b is None:
                        continue
                    if which is not None:  # a jet's part (a ball: a constant's)
                        if isinstance(b, Ball) and which == "d":
                            continue
                        b = b if isinstance(b, Ball) else getattr(b, which)
                    mid[j, k, e], rad[j, k, e] = b.mid, b.rad
        out.append(Ball._of(mid, rad))
    return tuple(out) if jets else out[0]


def _compiled(p: dyn.Params, kin: Sequence[Any], jets: bool) -> Any:
    """``regressor_balls`` in one call of the compiled kernel (``kernel_gen``: traced from
    ``regressor_columns``, the same doubles), or None where it does not apply (the
    arguments not all balls or all jets of vectors of one length, or a shape the kernel
    does not take): numpy's path then runs."""
    from ..certified.balls import Ball
    from ..certified.jets import Jet

    spec = INDEX.get(f"regressor_{'jet' if jets else 'ball'}_{p.mechanism.name}")
    if spec is None:
        return None
    kind = Jet if jets else Ball
    if not all(type(k) is kind for k in kin):
        return None
    parts = [b for k in kin for b in ((k.v, k.d) if jets else (k,))]
    shape = np.broadcast_shapes(*(np.shape(b.mid) for b in parts))
    if len(shape) != 1:
        return None
    n = shape[0]
    flat = (*_consts(p), *(np.asarray(a, dtype=float) for b in parts for a in (b.mid, b.rad)))
    out = np.empty((spec[1], n))
    if not KERNEL.run(spec[0], flat, out, n):
        return None
    size = 2 * len(BASIS) * 3
    parts_out = out.reshape(2 if jets else 1, size, 2, n)  # [value/derivative, entry, mid/rad]
    got = [Ball._of(o[:, 0].reshape(2, len(BASIS), 3, n), o[:, 1].reshape(2, len(BASIS), 3, n))
           for o in parts_out]  # fmt: skip
    return tuple(got) if jets else got[0]


def _consts(p: dyn.Params) -> tuple[np.ndarray, ...]:
    """a1's and g's mids and radii as the kernel reads them (``_ball_params``' own)."""
    return tuple(np.asarray(a, dtype=float) for b in (p.a1, p.g) for a in (b.mid, b.rad))


_PARAMS: dict[Any, dyn.Params] = {}


def _ball_params(robot: Robot) -> dyn.Params:
    """The robot's a1 and g as balls, and its scheme (what ``regressor_columns`` reads)."""
    from ..certified.balls import Ball

    key = (robot.a1, robot.gravity, of(robot))
    got = _PARAMS.get(key)
    if got is None:
        z = None
        got = _PARAMS[key] = dyn.Params(
            Ball.of_rational(robot.a1), Ball.of_rational(robot.gravity),
            z, z, z, z, z, z, z, z, z, z, z, z, of(robot),
        )  # fmt: skip
    return got


def regressor_floats(robot: Robot, kin: Sequence[Any], hyp: Any = np.hypot) -> np.ndarray:
    """``regressor_balls`` in doubles (not proven: a guide), from the end point's x, ẋ,
    ẍ, y, ẏ, ÿ as double arrays: [effort, ``BASIS``, error part, time]; ``hyp`` is the
    closed form's √(u² + v²)."""
    mech = of(robot)
    shape = np.broadcast_shapes(*(np.shape(k) for k in kin))
    if not closed_form(mech):  # the equations at every setting and error part
        x, xd, xdd, y, yd, ydd = (np.broadcast_to(np.asarray(k, dtype=float), shape)[:, None, None]
                                  for k in kin)  # fmt: skip
        ex = np.array([0.0, 1.0, 0.0])[None, :, None]
        ey = np.array([0.0, 0.0, 1.0])[None, :, None]
        params = settings_array(robot)
        legs = mech.legs(params, x, xd, xdd + ex, y, yd, ydd + ey, np.hypot)
        T = np.stack(np.broadcast_arrays(*efforts_of(legs, params)))  # (2, n, 3, 10)
        T = np.stack(to_basis([T[..., k] for k in range(len(BASIS))]), axis=1)  # (2, 10, n, 3)
        T = np.moveaxis(T, 3, 2)  # (2, 10, 3, n)
        return np.concatenate([T[:, :, :1], T[:, :, 1:] - T[:, :, :1]], axis=2)
    p = dyn.Params(float(robot.a1), float(robot.gravity), *(None,) * 12, mech)
    cols = regressor_columns(p, kin, hyp)
    out = np.zeros((2, len(BASIS), 3, *shape))
    for j, row in enumerate(cols):
        for k, entry in enumerate(row):
            for e, v in enumerate(entry):
                if v is not None:
                    out[j, k, e] = v
    return out


def regressor_doubles(robot: Robot, kin: Sequence[np.ndarray]) -> np.ndarray:
    """``regressor_floats`` (a guide, not proven) for the end point's x, ẋ, ẍ, y, ẏ, ÿ as
    double vectors of one length: through the compiled kernel where it applies (the mids
    of ``regressor_balls`` at balls of radius zero: the closed form's operations in
    doubles), else numpy's closed form with the kernel's operations (√(u·u + v·v), not
    ``np.hypot``: the same doubles, so the window ends do not depend on the build), or the
    equations at the settings."""
    if KERNEL is not None and closed_form(of(robot)):
        from ..certified.balls import Ball

        vs = [np.asarray(k, dtype=float) for k in kin]
        if all(v.ndim == 1 and len(v) == len(vs[0]) for v in vs):
            zero = np.zeros(len(vs[0]))
            got = _compiled(_ball_params(robot), [Ball._of(v, zero) for v in vs], False)
            if got is not None:
                return np.asarray(got.mid)
    return regressor_floats(robot, kin, _root_of_squares)


def doubles_call(robot: Robot) -> Callable[[Sequence[np.ndarray]], np.ndarray | None] | None:
    """``regressor_doubles`` for ``robot`` as one call of the compiled kernel on the end
    point's x, ẋ, ẍ, y, ẏ, ÿ as float64 vectors of one length (the same call, so the same
    doubles; None from it where the kernel declines), its constants looked up once; None
    where the kernel does not apply (not built, not the closed form)."""
    kernel = KERNEL  # the kernel as it is now, whatever the module's name holds later
    if kernel is None or not closed_form(of(robot)):
        return None
    p = _ball_params(robot)
    spec = INDEX.get(f"regressor_ball_{p.mechanism.name}")
    if spec is None:
        return None
    consts = _consts(p)
    size = 2 * len(BASIS) * 3

    def run(kin: Sequence[np.ndarray]) -> np.ndarray | None:
        n = len(kin[0])
        zero = np.zeros(n)
        out = np.empty((spec[1], n))
        if not kernel.run(spec[0], (*consts, *(a for v in kin for a in (v, zero))), out, n):
            return None
        return out.reshape(size, 2, n)[:, 0].reshape(2, len(BASIS), 3, n)

    return run


def _root_of_squares(u: Any, v: Any) -> Any:
    """√(u·u + v·v) in doubles: the mids of the ball operations of ``equations.hypot``."""
    return np.sqrt(u * u + v * v)


def form_worst(Y: np.ndarray, corners: Sequence[tuple[Any, Any]], box: Any) -> np.ndarray:
    """[effort, time]: the largest |Σ_k Y_k π_k| over the box (``corners``: the error's,
    ``box``: the links' as doubles), the error e at the corners (the efforts are affine
    in it), in doubles, from ``regressor_floats``' Y. Through the compiled kernel's
    ``box_max`` where it is built (the sign s = -1 from the same operations on -Y, which
    give exactly the negated doubles: the same doubles, ``windows.box_max``)."""
    if KERNEL is not None and np.ndim(Y) == 4:
        plus = np.array([(float(ex), float(ey), 1.0) for ex, ey in corners])
        ends = box_ends(box)
        out = np.empty((np.shape(Y)[3], 2))
        if KERNEL.box_max(np.asarray(Y, dtype=float).transpose(2, 3, 0, 1), plus, ends, out):
            return out.T
    k = np.array([(s * float(ex), s * float(ey), s) for ex, ey in corners for s in (1.0, -1.0)])
    Yc = (k[:, 2, None, None, None] * Y[None, :, :, 0] + k[:, 0, None, None, None]
          * Y[None, :, :, 1] + k[:, 1, None, None, None] * Y[None, :, :, 2])  # fmt: skip
    return form_max([Yc[:, :, j] for j in range(len(BASIS))], box, False).max(axis=0)


def box_ends(box: Any) -> np.ndarray:
    """The links' box as the compiled kernel takes it (``box_max``, ``form_bounds``): (6, 4)
    doubles, rows m_lo, m_hi, r_lo, r_hi, I_lo, I_hi, a column per link of ``LINKS``."""
    return np.array([[float(box[link][q][e]) for link, *_ in LINKS] for q in (0, 1, 2)
                     for e in (0, 1)])  # fmt: skip


# -- the largest effort over the box from the regressor's balls, in doubles, proven -------
#
# With every coefficient Y_k in [y_k - ρ_k, y_k + ρ_k] (a ball), at a corner e of the
# error's square and a sign s, s E = Σ_k π_k s (y0_k + e_x yx_k + e_y yy_k) + Σ_k π_k η_k
# with |η_k| <= ρ0_k + |e_x| ρx_k + |e_y| ρy_k. So
#     max over the box of s E  <=  max over the box of Σ_k π_k x_k  +  Σ_k |π_k|max ρ_k
# and >= the same first term less the second (at the box's point where the first is
# largest), x_k = s (y0_k + e_x yx_k + e_y yy_k). The first term is ``link_max_float``'s
# closed form evaluated in doubles: every candidate there is a sum of at most a few tens
# of products of the box's ends and the x_k, so its rounding error (and that of the box's
# ends and of e as doubles, each within one unit in the last place of the exact ones) is
# at most ``SLACK`` times the same sum with every term's absolute value,
#     S = Σ_links M (|A| + |B| R + |C| R²) + |C| I_max   (M, R, I_max >= |m|, |r|, |I|),
# a vertex -B/2C counted only where it lies within [r_lo, r_hi] (a lower bound: surely
# inside, by a margin far above its rounding), so |B²/4C| = |B| |r*|/2 <= |B| R there.

SLACK = 1e-12  # the doubles' rounding, relative to S: tens of units of 2^-53, and room

# Counted, in units u = 2^-53 of S (to first order): x_k carries at most 4 roundings (e's
# double, two products, two sums); a candidate's terms at most 5 more (the ends' doubles,
# entering C r r squared, B r, C r r, the sums; the vertex's A + B r*/2 as many, with
# |r*| <= R plus the margin); m G and C I one each; the sum over the links 3; S itself
# and the final best ± slack one each: under 20 u. So 2^-46 (128 u) is room enough
# (``TIGHT_SLACK``: the windows' quick proofs, ``proofs.quick_verdicts``).
TIGHT_SLACK = 2.0**-46


def form_bounds(Y: Any, box: Any, corners: Sequence[tuple[Any, Any]], upper: bool,
                slack_rel: float = SLACK) -> np.ndarray:  # fmt: skip
    """[effort, column]: an upper bound (``upper``) or a lower bound of the largest
    |E_j| over the box and the error's ``corners`` for efforts whose coefficients lie in
    the balls ``Y`` [effort, ``BASIS``, e = 0 / per e_x / per e_y, column], proven (see
    above); ±inf where a ball is not finite. ``box``: {link: ((m_lo, m_hi), (r_lo, r_hi),
    (I_lo, I_hi))} exact (fmpq). In one call of the compiled kernel where it is built
    (``kernel_c.FORM_BOUNDS``: the numpy operations below and ``_link_max``'s, in their
    order, so the same doubles; a change to one is a change to both)."""
    mid, rad = np.asarray(Y.mid, dtype=float), np.asarray(Y.rad, dtype=float)
    mid, rad = np.broadcast_arrays(mid, rad)
    if KERNEL is not None and mid.ndim == 4:  # these operations in one call, the same doubles
        es = np.array([(float(ex), float(ey)) for ex, ey in corners])
        ends = box_ends(box)
        out = np.empty((2, mid.shape[3]))
        if KERNEL.form_bounds(mid, rad, es, ends, slack_rel, upper, out):
            return out
    finite = np.isfinite(mid).all(axis=(1, 2)) & np.isfinite(rad).all(axis=(1, 2))
    mid = np.where(np.isfinite(mid), mid, 0.0)
    rad = np.where(np.isfinite(rad), rad, 0.0)
    es = np.array([(float(ex), float(ey)) for ex, ey in corners])  # [corner, 2]
    ea = np.abs(es).max(axis=0)  # |e_x|, |e_y| at most
    # x_k at every corner and sign: [combination, effort, BASIS, column]
    comb = [(s * ex, s * ey, s) for ex, ey in es for s in (1.0, -1.0)]
    X = np.stack([s * mid[:, :, 0] + cx * mid[:, :, 1] + cy * mid[:, :, 2] for cx, cy, s in comb])
    # X: [combination, effort, BASIS, column]
    ab = np.abs(mid[:, :, 0]) + ea[0] * np.abs(mid[:, :, 1]) + ea[1] * np.abs(mid[:, :, 2])
    rho = rad[:, :, 0] + ea[0] * rad[:, :, 1] + ea[1] * rad[:, :, 2]  # [effort, BASIS, col]
    total = np.zeros((X.shape[0], X.shape[1], X.shape[3]))
    S = np.zeros(ab.shape[:1] + ab.shape[2:])
    spread = np.zeros_like(S)
    for link, km, kmr, kj in LINKS:
        (mlo, mhi), (rlo, rhi), (ilo, ihi) = (tuple(float(v) for v in pair) for pair in box[link])
        R, Imax, M = max(abs(rlo), abs(rhi)), max(abs(ilo), abs(ihi)), max(abs(mlo), abs(mhi))
        A = X[:, :, km] if km is not None else 0.0 * X[:, :, kmr]  # [comb, effort, col]
        B, C = X[:, :, kmr], X[:, :, kj]
        total = total + _link_max(A, B, C, (mlo, mhi), (rlo, rhi), (ilo, ihi), upper)
        aA = ab[:, km] if km is not None else 0.0
        S = S + M * (aA + ab[:, kmr] * R + ab[:, kj] * R * R) + ab[:, kj] * Imax
        spread = spread + rho[:, kmr] * (M * R) + rho[:, kj] * (M * R * R + Imax)
        if km is not None:
            spread = spread + rho[:, km] * M
    best = total.max(axis=0)  # [effort, column]
    slack = (S * slack_rel + spread) * (1 + slack_rel) + 1e-300
    out = best + slack if upper else best - slack
    return np.where(finite, out, np.inf if upper else -np.inf)


Span = tuple[float, float]


def _link_max(A: np.ndarray, B: np.ndarray, C: np.ndarray, m: Span, r: Span, i: Span,
              upper: bool) -> np.ndarray:  # fmt: skip
    """``link_max_float`` with the vertex counted where it may lie inside r's interval
    (``upper``: an upper bound) or only where it surely does (a lower bound: a value the
    box reaches), both within a margin far above the doubles' rounding."""
    (mlo, mhi), (rlo, rhi), (ilo, ihi) = m, r, i
    G = np.maximum(A + B * rlo + C * rlo * rlo, A + B * rhi + C * rhi * rhi)
    margin = 1e-9 * (max(abs(rlo), abs(rhi)) + (rhi - rlo))
    with np.errstate(divide="ignore", invalid="ignore"):
        rs = -B / (2 * C)
        if upper:
            inside = (C < 0) & (rs >= rlo - margin) & (rs <= rhi + margin)
        else:
            inside = (C < 0) & (rs >= rlo + margin) & (rs <= rhi - margin)
        # the value at the vertex, A - B²/4C, as A + B r*/2: B² can underflow, and /4C
        # would magnify that past any slack relative to the terms; B r*/2 cannot
        G = np.where(inside, np.maximum(G, A + B * (0.5 * rs)), G)
    return np.maximum(mlo * G, mhi * G) + np.maximum(C * ilo, C * ihi)

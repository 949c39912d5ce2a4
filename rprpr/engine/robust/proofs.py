"""Robust verdicts: the proofs in ball arithmetic (``docs/robust.md``) — the consistency
residual over the box at t_s, and at a window's ends the upper bound of the largest |T_i|
over the box (at most the limit: the window cannot reach past it) or |T_i| at one point of
the box (above the limit: the window reaches there), from the regressor of
``robust.windows``' closed form written out per coefficient of π."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from flint import arb, ctx, fmpq

from ...model.numbers import to_float
from ...model.task import Robot, Uncertainty
from ..certified.balls import Ball, horner
from ..exact import equations as dyn
from ..exact.mechanism import of
from .regressor import (
    BASIS,
    LINKS,
    TIGHT_SLACK,
    closed_form,
    form_bounds,
    horner_at,
    legs_about,
    regressor_balls,
    regressor_columns,
    to_basis,
)
from .windows import (
    PREC,
    About,
    Box,
    ball_box,
    box_arrays,
    combos_of,
    float_box,
    form_float,
    regressor_float,
    to_ball,
)


def _regressor_ball(ab: About, h: arb, at_ts: bool = False) -> list[list[list[Any]]]:
    """The regressor at t_s + h in ball arithmetic, for the error parts e = 0, per unit
    e_x, per unit e_y: [part][joint][``BASIS``]; at t_s (``at_ts``) the residual's
    coefficients as the one "joint"."""
    c, params = ab.balls()
    if not at_ts and closed_form(params[0].mechanism):  # the RPRPR's schemes
        return _regressor_closed(c, params[0], h)
    if type(params[0].mechanism).dynamics is dyn.Rprpr.dynamics:  # the RPRPR's terms
        return _regressor_direct(ab, c, params[0], h, at_ts)
    out = []
    for ex, ey in ((0, 0), (1, 0), (0, 1)):
        legs = legs_about(c, h, params[0], arb(ex), arb(ey), dyn.hypot)
        values: list[tuple[Any, ...]] = []
        for p in params:
            d = dyn.dynamics(legs[0], legs[1], p)
            if at_ts:
                num, den = dyn.consistency(d, _sigma(legs), lambda v: v)
                values.append((num if den is None else num / den,))
            else:
                values.append(dyn.efforts(d, d.mu1 / d.delta, d.mu2 / d.delta))
        out.append([to_basis([v[j] for v in values]) for j in range(len(values[0]))])
    return [[[y - y0 if i else y for y, y0 in zip(row, row0, strict=True)]
             for row, row0 in zip(out[i], out[0], strict=True)] for i in range(3)]  # fmt: skip


def _regressor_closed(c: list[list[arb]], p: dyn.Params, h: arb) -> list[list[list[arb]]]:
    """``_regressor_ball`` from the closed form (``regressor_columns``, the efforts' columns
    a handful of ball products each, the columns per unit e_x, e_y written out, δ in its
    product form) on the end point's balls at t_s + h."""
    kin = [horner_at(q, h) for q in c]
    cols = regressor_columns(p, kin, dyn.hypot)
    return [[[ZERO if entry[e] is None else entry[e] for entry in row] for row in cols]
            for e in range(3)]  # fmt: skip


def _regressor_direct(ab: About, c: list[list[arb]], p: dyn.Params, h: arb, at_ts: bool
                      ) -> list[list[list[Any]]]:  # fmt: skip
    """``_regressor_ball`` for the RPRPR's equations of motion (``equations.Rprpr``,
    eqs. 7-14, shared by its schemes), each coefficient of π written out: with d = s - r
    and J = m r² + I, the θ and s rows' terms U1 = M11 θ1'' + N1 and F1 = M22 s1'' + N2

        U1:  J2, J3: θ1'';  m3: θ1'' s1² + 2 s1' θ1' s1 + g cos θ1 s1;
             m3 r3: -2 θ1'' s1 - 2 s1' θ1' - g cos θ1;  m2 r2: g cos θ1
        F1:  m3: s1'' - θ1'² s1 + g sin θ1;  m3 r3: θ1'²

    (U2, F2 alike with links 4, 5 and leg 2) are linear in π, and the scheme's efforts
    and consistency residual are linear in (U1, U2, F1, F2): each column through the
    scheme's own μ, efforts and consistency (``Rprpr._mu``, ``efforts``, ``consistency``)
    at the unit terms (M11 = M33 = 0, N1 = U1, N3 = U2), λ = μ/δ with δ in its product
    form (``delta``, eq. 29), then each column from them. Far fewer operations than the
    equations at each of the ten settings."""
    mech = p.mechanism
    x, xd, xdd, y, yd, ydd = (horner_at(q, h) for q in c)  # ``legs_about``'s, once
    out = []
    unit: list[tuple[Any, ...]] = []
    for ex, ey in ((0, 0), (1, 0), (0, 1)):
        l1, l2 = mech.legs(p, x, xd, xdd + arb(ex), y, yd, ydd + arb(ey), dyn.hypot)
        # (the map reads the legs' s, cos θ, sin θ, which the error does not move)
        unit = unit or _unit_map(p, y, l1, l2, at_ts)
        rows: list[list[Any]] = [[] for _ in unit[0]]
        for col in _terms(p.g, l1, l2):
            terms = [(u, v) for u, v in zip(unit, col, strict=True) if v is not ZERO]
            for j, row in enumerate(rows):
                acc = terms[0][0][j] * terms[0][1]
                for u, v in terms[1:]:
                    acc = acc + u[j] * v
                row.append(acc)
        out.append(rows)
    return [[[y - y0 if i else y for y, y0 in zip(row, row0, strict=True)]
             for row, row0 in zip(out[i], out[0], strict=True)] for i in range(3)]  # fmt: skip


def _terms(g: arb, l1: dyn.Leg, l2: dyn.Leg) -> list[tuple[arb, arb, arb, arb]]:
    """Per coefficient of π (``BASIS``), its (U1, U2, F1, F2) (``_regressor_direct``)."""
    n = len(BASIS)
    U1, U2, F1, F2 = ([ZERO] * n for _ in range(4))
    for (k_mr, k_j2, k_m, k_mr3, k_j3), leg, U, F in (
        ((0, 1, 2, 3, 4), l1, U1, F1), ((5, 6, 7, 8, 9), l2, U2, F2)
    ):  # fmt: skip
        gc = g * leg.cos
        sd_thd = leg.s_d * leg.th_d
        thd2 = leg.th_d * leg.th_d
        U[k_mr] = gc
        U[k_j2] = U[k_j3] = leg.th_dd
        U[k_m] = (leg.th_dd * leg.s + 2 * sd_thd + gc) * leg.s
        U[k_mr3] = -2 * (leg.th_dd * leg.s + sd_thd) - gc
        F[k_m] = leg.s_dd - thd2 * leg.s + g * leg.sin
        F[k_mr3] = thd2
    return list(zip(U1, U2, F1, F2, strict=True))


def _unit_map(p: dyn.Params, y: arb, l1: dyn.Leg, l2: dyn.Leg, at_ts: bool
              ) -> list[tuple[Any, ...]]:  # fmt: skip
    """The scheme's efforts (at t_s, ``at_ts``: its consistency residual), linear in
    (U1, U2, F1, F2) on the legs: their values at each unit term."""
    mech = p.mechanism
    sigma = _sigma((l1, l2)) if at_ts else 0
    delta = None if at_ts else mech.delta(p, y, l1, l2)
    unit: list[tuple[Any, ...]] = []
    for k in range(4):
        t = [ONE if i == k else ZERO for i in range(4)]
        mu1, mu2, u1, u2 = mech._mu(l1, l2, ZERO, ZERO, *t)
        d = dyn.Dynamics(l1, l2, ZERO, ZERO, t[0], t[1], t[2], t[3], mu1, mu2, delta, mech, u1, u2)
        if at_ts:
            num, den = mech.consistency(d, sigma, lambda v: v)
            unit.append((num if den is None else num / den,))
        else:
            unit.append(mech.efforts(d, mu1 / delta, mu2 / delta))
    return unit


def _sigma(legs: Any) -> int:
    """σ = cos θ1 cos θ2 at t_s (Table 2): the sign of x (x - a1)."""
    return 1 if (legs[0].cos * legs[1].cos) > 0 else -1


def phi_ball(ab: About, h: float, box: Box, bbox: Any, width: float = 0.0,
             limits: tuple[float, float] | None = None, prec: int = PREC
             ) -> tuple[arb, arb] | None:  # fmt: skip
    """Upper bounds (exact points) of the largest |T1|, |T2| over the box at t_s + h
    (with ``width``: over every time between t_s + h and t_s + h + ``width``), in balls
    of ``prec`` bits; with ``limits``, None as soon as one of them exceeds its limit."""
    with ctx.workprec(prec):
        Ys = _regressor_ball(ab, arb(h) if not width else arb(h).union(arb(h) + arb(width)))
        out = []
        for j in (0, 1):
            best = None
            for form in _corner_forms(Ys, box, j):
                for up in signed_uppers(form, bbox):
                    if limits is not None and not up <= limits[j]:
                        return None
                    best = up if best is None or up > best else best
            out.append(best)
        return out[0], out[1]


def _corner_forms(Ys: list[list[list[Any]]], box: Box, j: int) -> list[list[Any]]:
    """Y0 + ex Yx + ey Yy for joint j at each corner (ex, ey) of the error's square
    (``Box.corners``' order): the products by the bound a made once."""
    y0 = Ys[0][j]
    if box.a == 0:
        return [list(y0)]
    a = arb(box.a)
    bx = [v * a for v in Ys[1][j]]
    cy = [v * a for v in Ys[2][j]]
    out = []
    for part in ([u - b for u, b in zip(y0, bx, strict=True)],
                 [u + b for u, b in zip(y0, bx, strict=True)]):  # fmt: skip
        out.append([u - c for u, c in zip(part, cy, strict=True)])
        out.append([u + c for u, c in zip(part, cy, strict=True)])
    return out


ZERO, ONE = arb(0), arb(1)


def _top(a: arb, b: arb) -> arb:
    """The larger of two exact points."""
    return a if a > b else b


def signed_uppers(Y: Sequence[arb], bbox: Any) -> tuple[arb, arb]:
    """Upper bounds (exact points) of max over the box of s Σ_k Y_k π_k (Y indexed as
    ``BASIS``) for s = +1 and s = -1: ``regressor.form_max``'s upper bound in ball
    arithmetic (each link's candidates: the ends of r's interval, the vertex of the
    quadratic in r where it is concave and may lie inside, r's whole interval where the
    sign of its r² coefficient is not decided; the larger of m's ends, of I's), both signs
    from the same balls: s = -1 negates every candidate's ball exactly (its upper end is
    minus the lower end of the ball for s = +1)."""
    t0 = t1 = ZERO  # s = +1, s = -1 (``_top`` written out: one call per link, not 24)
    for link, km, kmr, kj in LINKS:
        (mlo, mhi), (rlo, rhi), (ilo, ihi) = bbox[link]
        A = Y[km] if km is not None else ZERO
        B, C = Y[kmr], Y[kj]
        g0 = A + B * rlo + C * rlo * rlo
        g1 = A + B * rhi + C * rhi * rhi
        a, b = g0.upper(), g1.upper()
        G0 = a if a > b else b
        a, b = -g0.lower(), -g1.lower()
        G1 = a if a > b else b
        if not C.is_zero():
            pos, neg = C > 0, C < 0
            if pos or neg:  # concave for the sign s with s C < 0
                rs = -B / (2 * C)
                if not (rs <= rlo or rs >= rhi):
                    top = A - B * B / (4 * C)
                    if neg:
                        a = top.upper()
                        G0 = G0 if a < G0 else a
                    else:
                        a = -top.lower()
                        G1 = G1 if a < G1 else a
            else:  # C's sign not decided: the quadratic's range over [r_lo, r_hi]
                r = (rlo + rhi) / 2 + (rhi - rlo) / 2 * arb("0 +/- 1")
                q = A + B * r + C * r * r
                a, b = q.upper(), -q.lower()
                G0 = G0 if a < G0 else a
                G1 = G1 if b < G1 else b
        c_lo, c_hi = C * ilo, C * ihi
        a, b = c_lo.upper(), c_hi.upper()
        cI0 = a if a > b else b
        a, b = -c_lo.lower(), -c_hi.lower()
        cI1 = a if a > b else b
        a, b = (mlo * G0).upper(), (mhi * G0).upper()
        t0 = (t0 + ((a if a > b else b) + cI0).upper()).upper()
        a, b = (mlo * G1).upper(), (mhi * G1).upper()
        t1 = (t1 + ((a if a > b else b) + cI1).upper()).upper()
    return t0, t1


def residual(ab: About, box: Box) -> tuple[arb, arb]:
    """A lower bound on the least and an upper bound on the largest consistency residual
    over the box [N] (exact points)."""
    with ctx.workprec(PREC):
        bbox = ball_box(box)
        Ys = _regressor_ball(ab, arb(0), at_ts=True)
        hi = lo = None
        for form in _corner_forms(Ys, box, 0):
            up, down = signed_uppers(form, bbox)  # down: an upper bound of -min
            hi = up if hi is None or up > hi else hi
            lo = down if lo is None or down > lo else lo
        assert hi is not None and lo is not None
        return -lo, hi


def residual_at(robot: Robot, u: Uncertainty, state: Sequence[fmpq]) -> tuple[arb, arb]:
    """``residual`` at a Type II state given directly: ``state`` = (x, ẋ, ẍ, ẏ, ÿ) at
    y = 0, exact (the repair's aim, ``repair.middle``), over the box of ``u``."""
    x, xd, xdd, yd, ydd = state
    ab = About([[x], [xd], [xdd], [fmpq(0)], [yd], [ydd]], 0.0, 0.0, robot, 0.0)
    return residual(ab, Box.of(robot, u))


CLEAR = 1e-12  # a double value of |T_j| this fraction of the limit below it: clear of it


def _inward(h: float) -> list[float]:
    """The candidates for a proven inner end: h, then a little nearer t_s."""
    return [g for shrink in (0.0, 1e-12, 1e-9, 1e-6) if (g := h * (1 - shrink)) > 0]


QUICK = 64  # bits of a first attempt at a proof where the doubles leave a margin


def below(ab: About, box: Box, bbox: Any, limits: tuple[float, float], h: float,
          width: float = 0.0, quick: bool = True) -> bool:  # fmt: skip
    """Both max |T_j| <= their limits proven at t_s + h (over [h, h + ``width``]): in
    ``QUICK``-bit balls first (with ``quick``: where the doubles put the bound clear of
    the limit), then where they do not decide it in ``PREC``-bit balls (a proof either
    way; the box's ends are ``bbox``'s balls in both)."""
    if quick and phi_ball(ab, h, box, bbox, width, limits, QUICK) is not None:
        return True
    return phi_ball(ab, h, box, bbox, width, limits) is not None


def quick_verdicts(ab: About, box: Box, limits: tuple[float, float], hs: Sequence[float],
                    joints: Sequence[int | None]) -> list[bool]:  # fmt: skip
    """At each time t_s + ``hs[i]``, whether, proven: with ``joints[i]`` None, both max
    |T_j| <= their limits (``below``); else max |T_j| > its limit for j = ``joints[i]``
    (``prove_in``). All at once, from the regressor's balls in double precision
    (``regressor_balls``) and their proven bounds over the box (``form_bounds``), through
    the compiled kernel where it is built (numpy's path otherwise: the same doubles, so
    the same verdicts): a quick first attempt, False where it does not decide (or for
    another scheme than the RPRPR's); ``below`` and ``prove_in`` then decide in ``arb``."""
    if not closed_form(of(ab.robot)) or not hs:
        return [False] * len(hs)
    cs = ab.__dict__.get("_coefficient_balls")
    if cs is None:  # the Taylor coefficients as balls (made once per instant)
        cs = ab.__dict__["_coefficient_balls"] = [
            [Ball.of_rational(v) if isinstance(v, fmpq) else Ball.of_arb(arb(v)) for v in q]
            for q in ab.coeffs
        ]
    x = Ball(np.asarray(hs, dtype=float), 0.0)
    with np.errstate(all="ignore"):
        kin = [horner(q, x) if len(q) > 1 else q[0] + x * 0.0 for q in cs]
        Y = regressor_balls(ab.robot, kin)
        up = form_bounds(Y, box.links, box.corners(), True, TIGHT_SLACK)
        low = form_bounds(Y, box.links, box.corners(), False, TIGHT_SLACK)
    out = []
    for i, j in enumerate(joints):
        if j is None:
            out.append(bool(up[0, i] <= limits[0] and up[1, i] <= limits[1]))
        else:
            out.append(bool(low[j, i] > limits[j]))
    return out


def prove_in(ab: About, box: Box, bbox: Any, lim: float, j: int, d: int, h: float,
             quick: bool = False) -> float:  # fmt: skip
    """h, or a little nearer t_s, at which max |T_j| > lim is proven (0 when none is):
    |T_j| at the box's worst point there (found in doubles), in ball arithmetic (with
    ``quick``, where the doubles put it clear of the limit: ``QUICK`` bits first)."""

    def above(g: float) -> bool:
        return bool((quick and _worst_ball(ab, d * g, box, j, QUICK) > lim)
                    or _worst_ball(ab, d * g, box, j) > lim)  # fmt: skip

    return next((g for g in _inward(h) if above(g)), 0.0)


def _worst_ball(ab: About, h: float, box: Box, j: int, prec: int = PREC) -> arb:
    """|T_j| at t_s + h at one point of the box, the largest the doubles find (its
    corners of e, and per link the maximiser of ``link_max_float``), as a ball. (Any
    point of the box gives a lower bound of the largest |T_j| there; the doubles at a
    time 1e-9 |h| from t_s + h, when evaluated already, choose it as well.)"""
    fbox = ab.__dict__.get("_fbox")
    if fbox is None or fbox[0] is not box:  # (made once per instant and box)
        fbox = ab.__dict__["_fbox"] = (box, float_box(box))
    fbox = fbox[1]
    got = ab.row(h, 1e-9)
    Ys = (got if got is not None else regressor_float(ab, np.array([h]))[:, 0])[:, j, :]  # (3, 10)
    combos, _, k = combos_of(ab, box)  # (c, 3): (e_x, e_y, s)
    Yc = k[:, 2, None] * (Ys[0] + k[:, 0, None] * Ys[1] + k[:, 1, None] * Ys[2])  # (c, 10)
    v = form_float(Yc, box_arrays(ab, box, fbox, Yc.ndim))
    found = np.nonzero(v > -math.inf)[0]  # (NaN: not a candidate)
    assert len(found)
    best = int(found[np.argmax(v[found])])  # the first of the largest
    ex, ey, _ = combos[best]
    Y = Yc[best]
    values = {}
    for link, km, kmr, kj in LINKS:
        A = Y[km] if km is not None else 0.0
        values[link] = _argmax(A, Y[kmr], Y[kj], box.links[link])
    with ctx.workprec(prec):
        c, params = ab.balls()
        if closed_form(params[0].mechanism):  # the regressor's columns at that point
            cols = _regressor_closed(c, params[0], arb(h))
            bx, by = arb(ex), arb(ey)
            total = ZERO
            for q, pi in enumerate(_pi(values)):
                total += pi * (cols[0][j][q] + bx * cols[1][j][q] + by * cols[2][j][q])
            return abs(total)
        L = box.robot_links(values)
        p = dyn.Params(to_ball(ab.robot.a1), to_ball(ab.robot.gravity), *L, of(ab.robot))  # type: ignore[call-arg]
        legs = legs_about(c, arb(h), p, arb(ex), arb(ey), dyn.hypot)
        d = dyn.dynamics(legs[0], legs[1], p)
        return abs(dyn.efforts(d, d.mu1 / d.delta, d.mu2 / d.delta)[j])


def _pi(values: dict[int, tuple[fmpq, fmpq, fmpq]]) -> list[arb]:
    """π (``BASIS``: m r, J = m r² + I, m) at the links' (m, r, I), each rounded once."""
    out = []
    for link, what in BASIS:
        m, r, inertia = values[link]
        out.append(arb(m * r if what == "mr" else m * r * r + inertia if what == "J" else m))
    return out


def _argmax(A: float, B: float, C: float, box: Any) -> tuple[fmpq, fmpq, fmpq]:
    """A point (m, r, I) of the link's box at which A m + B m r + C (m r² + I) is largest
    (in doubles; r exact at an end, or the rational nearest the interior maximiser)."""
    (mlo, mhi), (rlo, rhi), (ilo, ihi) = box
    cands = [rlo, rhi]
    if C < 0:
        rs = -B / (2 * C)
        if to_float(rlo) < rs < to_float(rhi):
            cands.append(fmpq(*rs.as_integer_ratio()))
    r = max(cands, key=lambda v: A + B * to_float(v) + C * to_float(v) ** 2)
    g = A + B * to_float(r) + C * to_float(r) ** 2
    return (mhi if g >= 0 else mlo), r, (ihi if C >= 0 else ilo)

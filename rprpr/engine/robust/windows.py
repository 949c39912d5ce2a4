"""Robust verdicts: the consistency residual and the saturation window at each singular
instant over a box of link parameters and acceleration tracking errors (``docs/robust.md``).

The perturbation model. The end point follows the planned position and velocity; its
acceleration is the planned one plus a tracking error e(t) with |e_x(t)|, |e_y(t)| <= a,
chosen anew at every instant; the links' masses m_i, inertias I_i and r_i lie each in
its own relative interval. The inverse dynamics at one instant depends only on the state
there, so the efforts that the box allows at time t are the set over (parameters, e) of
the efforts of eq. (28) (revolute) or of the legs (prismatic) at that t.

Both schemes' efforts are linear in the inertial parameters
    π = (m2 r2, J2, m3, m3 r3, J3, m4 r4, J4, m5, m5 r5, J5),   J_i = m_i r_i² + I_i
and affine in e (``equations``: every term is a mass-weighted product of the joint
values; e enters the legs' s'', θ'' linearly). So at a time t, with the regressor Y(t, e)
(T = Y π), the largest |T_i| over the box is

    max over s = ±1 and the corners of e of  Σ_links  max over the link's (m, r, I) of
    s (A m + B m r + C (m r² + I)),

each link's maximum in closed form (linear in I and, for r fixed, in m; a quadratic in
r). That is exact, not sampled. The residual of the consistency condition at t_s is such
a linear form too. The saturation window around t_s is the connected set of times around
t_s where that largest |T_i| exceeds the limit; its ends are found on double-precision
evaluations about t_s (the motion's polynomials shifted exactly to t_s, so that times
next to t_s lose nothing) and then proven in ball arithmetic: at the reported end the
upper bound of the largest |T_i| is at most the limit, so the window cannot reach past it.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from fractions import Fraction
from typing import Any

import numpy as np
from flint import arb, ctx, fmpq, fmpq_poly

from ...model.dataclass import dataclass
from ...model.numbers import to_float
from ...model.task import Robot, Uncertainty
from ..exact import equations as dyn
from ..exact.mechanism import of
from ..exact.series import taylor
from .regressor import (
    BASIS,
    LINKS,
    efforts_of,
    horner_at,
    legs_about,
    link_max_float,
    setting_params,
    settings_array,
    to_basis,
)

PREC = 160  # bits of the proofs at the window's ends


@dataclass(frozen=True)
class Robust:
    """The robust analysis of one singular instant (``docs/robust.md``).

    ``residual`` = [lo, hi]: the consistency residual [N] over the box (outward rounded;
    the exact residual twice when the box has radius zero). ``window`` [s]: a proven
    upper bound on the width of the time span around t_s in which some |T_i| may exceed
    its limit (0 when it cannot, or when no limit is given); ``window_lo`` a lower bound
    (shown exceeded at both ends, 0 when not shown); ``joint`` (1 or 2) the effort that
    reaches furthest from t_s, ``span`` the span's proven outer ends [s] (absolute time);
    ``window_lo`` <= the window's true width <= ``window``."""

    residual: tuple[float, float]
    window: float
    window_lo: float = 0.0
    joint: int | None = None
    span: tuple[float, float] | None = None


@dataclass(frozen=True)
class Box:
    """The parameter box: for each link i, ([m_lo, m_hi], [r_lo, r_hi], [I_lo, I_hi]) as
    exact rationals, and the acceleration bound a [m/s²]."""

    links: dict[int, tuple[tuple[fmpq, fmpq], tuple[fmpq, fmpq], tuple[fmpq, fmpq]]]
    a: fmpq

    @staticmethod
    def of(robot: Robot, u: Uncertainty) -> Box:
        out = {}
        for i, link in robot.links.items():
            rm, ri, rr = u.links.get(i, (fmpq(0), fmpq(0), fmpq(0)))
            out[i] = (_interval(link.mass, rm), _interval(link.r, rr), _interval(link.inertia, ri))
        return Box(out, _q(u.acceleration))

    def robot_links(self, values: dict[int, tuple[fmpq, fmpq, fmpq]]) -> list[arb]:
        """``Params``' link fields (m2, I2, r2, ..., m5, I5, r5) from (m, r, I) per link."""
        out = []
        for i in (2, 3, 4, 5):
            m, r, inertia = values[i]
            out += [_ball(m), _ball(inertia), _ball(r)]
        return out

    @property
    def zero(self) -> bool:
        return self.a == 0 and all(lo == hi for b in self.links.values() for lo, hi in b)

    def corners(self) -> list[tuple[fmpq, fmpq]]:
        """The corners of the acceleration error's square (one point when a = 0)."""
        a = self.a
        return [(fmpq(0), fmpq(0))] if a == 0 else [(sx * a, sy * a) for sx in (-1, 1)
                                                    for sy in (-1, 1)]  # fmt: skip


def _q(v: Any) -> fmpq:
    """An exact rational from an fmpq, a Fraction, an int or a float (its binary value)."""
    if isinstance(v, fmpq):
        return v
    n, d = Fraction(v).as_integer_ratio()
    return fmpq(n, d)


def _interval(v: fmpq, rel: Any) -> tuple[fmpq, fmpq]:
    w = abs(v) * _q(rel)
    return (v - w, v + w)


# -- one instant ---------------------------------------------------------------------------


@dataclass
class About:
    """The motion about one t_s on one piece: Taylor coefficients of x, x', x'', y, y',
    y'' in h = t - t_s (exact rationals or balls; y(t_s) = 0 exactly), the span of h on
    the piece, and the robot."""

    coeffs: list[list[Any]]
    h_min: float  # <= 0: how far back the piece reaches
    h_max: float  # >= 0
    robot: Robot
    t_s: float  # absolute

    def floats(self) -> list[list[float]]:
        """The coefficients as doubles (made once: every evaluation in doubles reads them)."""
        got = self.__dict__.get("_floats")
        if got is None:
            got = self.__dict__["_floats"] = [
                [float(arb(c).mid()) if not isinstance(c, float) else c for c in p]
                for p in self.coeffs
            ]
        return got

    def rows(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """The times t_s + h at which ``phi_float`` evaluated the regressor in doubles, and
        the regressor there (h, ``_regressor_float``'s array)."""
        return self.__dict__.setdefault("_rows", [])

    def row(self, h: float, near: float = 0.0) -> np.ndarray | None:
        """The regressor in doubles at t_s + h, (3, 2, 10), when ``phi_float`` has
        evaluated it there (with ``near``: at the time it evaluated nearest t_s + h, when
        within ``near`` |h| of it)."""
        best, gap = None, near * abs(h)
        for hs, Ys in reversed(self.rows()):
            dist = np.abs(hs - h)
            k = int(np.argmin(dist)) if len(dist) else -1
            if k >= 0 and (dist[k] < gap or (best is None and dist[k] <= gap)):
                best, gap = Ys[:, k], dist[k]
                if gap == 0:
                    break
        return best

    def balls(self) -> tuple[list[list[arb]], list[dyn.Params]]:
        """The coefficients and the settings of ``BASIS`` (``regressor.setting_params``)
        as balls at the working precision (made once per precision)."""
        key = f"_balls{ctx.prec}"
        got = self.__dict__.get(key)
        if got is None:
            got = self.__dict__[key] = (
                [[_ball(v) for v in p] for p in self.coeffs],
                [setting_params(self.robot, k, _ball) for k in range(len(BASIS))],
            )
        return got

    def settings(self) -> Any:
        """``regressor.settings_array`` of the robot (made once)."""
        got = self.__dict__.get("_settings")
        if got is None:
            got = self.__dict__["_settings"] = settings_array(self.robot)
        return got


def shifted(poly: fmpq_poly, t_s: fmpq | None, ball: arb | None, field: Any) -> list[Any]:
    """The Taylor coefficients of ``poly`` at t_s (exact when t_s is rational)."""
    if t_s is not None:
        return list(poly(fmpq_poly([t_s, 1])).coeffs()) or [fmpq(0)]
    n = max(poly.degree() + 1, 1)
    return [field.evaluate(c, PREC + 64) for c in taylor(poly, n)]


def about(traj: Any, robot: Robot, t_local: fmpq | None, field: Any, t_abs: float) -> About:
    """The motion of the piece ``traj`` (local time) about its instant t_local (or the
    root of ``field`` when irrational)."""
    polys = (traj.x, traj.xd, traj.xdd, traj.y, traj.yd, traj.ydd)
    coeffs = [shifted(p, t_local, None, field) for p in polys]
    coeffs[3][0] = fmpq(0)  # y(t_s) = 0 exactly
    ts = (
        float(t_local)
        if t_local is not None
        else float(field.evaluate(fmpq_poly([0, 1]), 64).mid())
    )
    lead = to_float(traj.lead)
    return About(coeffs, min(0.0, lead - ts), max(0.0, to_float(traj.duration) - ts), robot, t_abs)


def _regressor_float(ab: About, h: np.ndarray) -> np.ndarray:
    """The regressor at the times t_s + h (doubles): (3, n, 2, 10) for the error parts
    e = 0, per unit e_x, per unit e_y; joints T1, T2; ``BASIS``."""
    c = ab.floats()
    hh = np.asarray(h, dtype=float)[:, None, None]  # (n, 1, 1)
    ex = np.array([0.0, 1.0, 0.0])[None, :, None]
    ey = np.array([0.0, 0.0, 1.0])[None, :, None]
    params = ab.settings()
    legs = legs_about(c, hh, params, ex, ey, np.hypot)
    with np.errstate(divide="ignore", invalid="ignore"):
        T1, T2 = efforts_of(legs, params)  # (n, 3, 10)
    shape = (len(hh), 3, len(BASIS))
    Y = np.empty((3, len(hh), 2, len(BASIS)))
    for j, T in enumerate((T1, T2)):
        Y[:, :, j, :] = (T.transpose(1, 0, 2) if np.ndim(T) == 3
                         else np.moveaxis(np.broadcast_to(T, shape), 1, 0))  # fmt: skip
    for k, m in _TO_BASIS:  # ``to_basis`` in place
        Y[..., k] -= Y[..., m]
    Y[1] -= Y[0]  # per unit e_x, e_y
    Y[2] -= Y[0]
    return Y


# ``to_basis``: the "mr" column less the "m" column of the same link (links 3, 5)
_TO_BASIS = [(k, BASIS.index((link, "m"))) for k, (link, what) in enumerate(BASIS)
             if what == "mr" and (link, "m") in BASIS]  # fmt: skip


def phi_float(ab: About, h: np.ndarray, box: Box, fbox: Any) -> np.ndarray:
    """The largest |T_i| over the box at t_s + h, (n, 2), in doubles. The regressor at
    each of these times is kept (``About.rows``, for ``prove_in``)."""
    Ys = _regressor_float(ab, h)
    ab.rows().append((np.asarray(h, dtype=float), Ys))
    k = _combos(ab, box)[1][::2]  # (corners, 3): (e_x, e_y, 1)
    Y = (
        k[:, 2, None, None, None] * Ys[0][None]
        + k[:, 0, None, None, None] * Ys[1][None]
        + (k[:, 1, None, None, None] * Ys[2][None])
    )  # (corners, n, 2, 10); for s = -1 exactly -Y (rounding to nearest is symmetric)
    up, down = _form_both(Y, _box_arrays(ab, box, fbox, Y.ndim))
    return np.maximum(up.max(axis=0), down.max(axis=0))


def _combos(ab: About, box: Box) -> tuple[list[tuple[fmpq, fmpq, float]], np.ndarray, np.ndarray]:
    """The corners of e with each sign s: (e_x, e_y, s), and as doubles (s e_x, s e_y, s)
    and (e_x, e_y, s), (c, 3) (made once per instant and box)."""
    got = ab.__dict__.get("_combos")
    if got is None or got[0] is not box:
        combos = [(ex, ey, s) for ex, ey in box.corners() for s in (1.0, -1.0)]
        signed = np.array([(s * float(ex), s * float(ey), s) for ex, ey, s in combos])
        plain = np.array([(float(ex), float(ey), s) for ex, ey, s in combos])
        got = ab.__dict__["_combos"] = (box, combos, signed, plain)
    return got[1], got[2], got[3]


_MR, _J, _M = [0, 3, 5, 8], [1, 4, 6, 9], [0, 2, 5, 7]  # per link of ``LINKS``: its columns


def _form_float(Y: np.ndarray, bounds: Any) -> np.ndarray:
    """``regressor.form_max`` in doubles (the same operations on the same numbers, so the
    same doubles) with ``BASIS`` on the last axis of ``Y``: every link at once."""
    axes = (Y.ndim - 1, *range(Y.ndim - 1))  # the links' axis first
    B = Y[..., _MR].transpose(axes)
    C = Y[..., _J].transpose(axes)
    A = Y[..., _M].transpose(axes)
    for i, (_, km, _, _) in enumerate(LINKS):
        if km is None:
            A[i] = B[i] * 0
    L = link_max_float(A, B, C, bounds)
    total = L[0]
    for i in range(1, len(LINKS)):
        total = total + L[i]
    return total


def _form_both(Y: np.ndarray, bounds: Any) -> tuple[np.ndarray, np.ndarray]:
    """``_form_float`` of Y and of -Y from one set of operations (``_link_max_both``)."""
    axes = (Y.ndim - 1, *range(Y.ndim - 1))  # the links' axis first
    B = Y[..., _MR].transpose(axes)
    C = Y[..., _J].transpose(axes)
    A = Y[..., _M].transpose(axes)
    for i, (_, km, _, _) in enumerate(LINKS):
        if km is None:
            A[i] = B[i] * 0
    up, down = _link_max_both(A, B, C, bounds)
    tot_up, tot_down = up[0], down[0]
    for i in range(1, len(LINKS)):
        tot_up = tot_up + up[i]
        tot_down = tot_down + down[i]
    return tot_up, tot_down


def _link_max_both(A: Any, B: Any, C: Any, box: Any) -> tuple[Any, Any]:
    """``regressor.link_max_float`` of (A, B, C) and of (-A, -B, -C): every operation
    there on the negated operands gives the negated double (rounding to nearest is
    symmetric), so the second is read off the first's intermediate values (a maximum of
    negated values is minus their minimum, the vertex -B/2C is the same)."""
    (mlo, mhi), (rlo, rhi), (ilo, ihi) = box
    glo = A + B * rlo + C * rlo * rlo
    ghi = A + B * rhi + C * rhi * rhi
    G = np.maximum(glo, ghi)
    Gn = -np.minimum(glo, ghi)
    with np.errstate(divide="ignore", invalid="ignore"):
        rs = -B / (2 * C)
        placed = (rs > rlo) & (rs < rhi)
        top = A - B * B / (4 * C)
        G = np.where((C < 0) & placed, np.maximum(G, top), G)
        Gn = np.where((C > 0) & placed, np.maximum(Gn, -top), Gn)
    c_lo, c_hi = C * ilo, C * ihi
    up = np.maximum(mlo * G, mhi * G) + np.maximum(c_lo, c_hi)
    down = np.maximum(mlo * Gn, mhi * Gn) + (-np.minimum(c_lo, c_hi))
    return up, down


def _box_arrays(ab: About, box: Box, fbox: Any, ndim: int) -> Any:
    """The box's (m, r, I) ends (``fbox``, ``box`` in doubles) as arrays over ``LINKS``
    (then ``ndim`` - 1 unit axes), made once per instant, box and ``ndim``."""
    key = f"_bounds{ndim}"
    got = ab.__dict__.get(key)
    if got is None or got[0] is not box:
        shape = (len(LINKS),) + (1,) * (ndim - 1)
        arrays = tuple(tuple(np.array([fbox[link][q][e] for link, *_ in LINKS]).reshape(shape)
                             for e in (0, 1)) for q in (0, 1, 2))  # fmt: skip
        got = ab.__dict__[key] = (box, arrays)
    return got[1]


def _regressor_ball(ab: About, h: arb, at_ts: bool = False) -> list[list[list[Any]]]:
    """The regressor at t_s + h in ball arithmetic, for the error parts e = 0, per unit
    e_x, per unit e_y: [part][joint][``BASIS``]; at t_s (``at_ts``) the residual's
    coefficients as the one "joint"."""
    c, params = ab.balls()
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
    with those terms (M11 = M33 = 0, N1 = U1, N3 = U2), λ = μ/δ with δ in its product
    form (``delta``, eq. 29). Far fewer operations than the equations at each of the ten
    settings."""
    g = p.g
    mech = p.mechanism
    n = len(BASIS)
    x, xd, xdd, y, yd, ydd = (horner_at(q, h) for q in c)  # ``legs_about``'s, once
    out = []
    for ex, ey in ((0, 0), (1, 0), (0, 1)):
        l1, l2 = mech.legs(p, x, xd, xdd + arb(ex), y, yd, ydd + arb(ey), dyn.hypot)
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
        sigma = _sigma((l1, l2)) if at_ts else 0
        delta = None if at_ts else mech.delta(p, y, l1, l2)
        rows: list[list[Any]] = []
        done: dict[tuple[int, ...], tuple[Any, ...]] = {}
        for col in zip(U1, U2, F1, F2, strict=True):
            key = tuple(id(v) for v in col)  # (J2 and J3, J4 and J5: the same column)
            got = done.get(key)
            if got is None:
                mu1, mu2, u1, u2 = mech._mu(l1, l2, ZERO, ZERO, col[0], col[1], col[2], col[3])
                d = dyn.Dynamics(l1, l2, ZERO, ZERO, col[0], col[1], col[2], col[3], mu1, mu2,
                                 delta, mech, u1, u2)  # fmt: skip
                if at_ts:
                    num, den = mech.consistency(d, sigma, lambda v: v)
                    got = (num if den is None else num / den,)
                else:
                    got = mech.efforts(d, mu1 / delta, mu2 / delta)
                done[key] = got
            rows.append(list(got))
        out.append([[r[j] for r in rows] for j in range(len(rows[0]))])
    return [[[y - y0 if i else y for y, y0 in zip(row, row0, strict=True)]
             for row, row0 in zip(out[i], out[0], strict=True)] for i in range(3)]  # fmt: skip


def _at_corner(Ys: list[list[list[Any]]], ex: fmpq, ey: fmpq, j: int, s: int) -> list[Any]:
    """s (Y0 + ex Yx + ey Yy) for joint j."""
    return [s * (a + b * ex + c * ey) for a, b, c in zip(Ys[0][j], Ys[1][j], Ys[2][j], strict=True)]


def _sigma(legs: Any) -> int:
    """σ = cos θ1 cos θ2 at t_s (Table 2): the sign of x (x - a1)."""
    return 1 if (legs[0].cos * legs[1].cos) > 0 else -1


def _ball(v: Any) -> arb:
    if isinstance(v, arb):
        return v
    if isinstance(v, fmpq):
        return arb(v)
    return arb(v)


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


ZERO = arb(0)


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
    tot = [ZERO, ZERO]
    for link, km, kmr, kj in LINKS:
        (mlo, mhi), (rlo, rhi), (ilo, ihi) = bbox[link]
        A = Y[km] if km is not None else ZERO
        B, C = Y[kmr], Y[kj]
        g0 = A + B * rlo + C * rlo * rlo
        g1 = A + B * rhi + C * rhi * rhi
        G = [_top(g0.upper(), g1.upper()), _top(-g0.lower(), -g1.lower())]
        if not C.is_zero():
            pos, neg = C > 0, C < 0
            if pos or neg:  # concave for the sign s with s C < 0
                s = 0 if neg else 1
                rs = -B / (2 * C)
                if not (rs <= rlo or rs >= rhi):
                    top = A - B * B / (4 * C)
                    G[s] = _top(G[s], top.upper() if s == 0 else -top.lower())
            else:  # C's sign not decided: the quadratic's range over [r_lo, r_hi]
                r = (rlo + rhi) / 2 + (rhi - rlo) / 2 * arb("0 +/- 1")
                q = A + B * r + C * r * r
                G = [_top(G[0], q.upper()), _top(G[1], -q.lower())]
        c_lo, c_hi = C * ilo, C * ihi
        cI = [_top(c_lo.upper(), c_hi.upper()), _top(-c_lo.lower(), -c_hi.lower())]
        for s in (0, 1):
            mG = _top((mlo * G[s]).upper(), (mhi * G[s]).upper())
            tot[s] = (tot[s] + (mG + cI[s]).upper()).upper()
    return tot[0], tot[1]


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


def ball_box(box: Box) -> dict[int, Any]:
    return {i: tuple((arb(lo), arb(hi)) for lo, hi in b) for i, b in box.links.items()}


def float_box(box: Box) -> dict[int, Any]:
    return {i: tuple((to_float(lo), to_float(hi)) for lo, hi in b) for i, b in box.links.items()}


def round_down(x: arb) -> float:
    """The largest double <= the exact point ``x``."""
    f = float(x.lower().mid())
    return f if arb(f) <= x.lower() else math.nextafter(f, -math.inf)


def round_up(x: arb) -> float:
    """The smallest double >= the exact point ``x``."""
    f = float(x.upper().mid())
    return f if arb(f) >= x.upper() else math.nextafter(f, math.inf)


# -- the window on one side ----------------------------------------------------------------


def side(ab: About, box: Box, limits: tuple[float, float], direction: int
         ) -> tuple[float, float, int]:  # fmt: skip
    """The window on one side of t_s (``sides`` for that side alone)."""
    return sides(ab, box, limits, (direction,))[direction]


# the initial scan looks at reach 2^-k, k = 0..159: every k up to DENSE, every 8th beyond
DENSE = 40
SCAN = np.array(sorted(set(range(0, 160 - DENSE, 8)) | set(range(160 - DENSE - 1, 160))))


def sides(ab: About, box: Box, limits: tuple[float, float], directions: Sequence[int]
          ) -> dict[int, tuple[float, float, int]]:  # fmt: skip
    """The window on each side of t_s in ``directions`` (-1, +1), as distances |h| [s]:
    (a proven outer end, an inner end at which the limit is proven exceeded (0 when not
    shown), the joint (0, 1) that reaches furthest). The doubles bracket each joint's
    first crossing of its limit outward from t_s (``_scan``, then ``_refine``); when even
    the nearest time looked at (2^-159 of the piece's reach) shows no excess, the window
    is too narrow for doubles (a residual of the order of the input's rounding) and a
    proven outer end is found by halving in ball arithmetic (``_halving``). Every side
    and joint is evaluated at once at each step (an evaluation costs its call more than
    its points)."""
    out: dict[int, tuple[float, float, int]] = {}
    live = []
    for d in directions:
        reach = ab.h_max if d > 0 else -ab.h_min
        if reach <= 0:
            out[d] = (0.0, 0.0, 0)
        else:
            live.append((d, reach, reach * np.exp2(-np.arange(0, 160, 1.0))[::-1]))
    if not live:
        return out
    bbox = ball_box(box)
    fbox = float_box(box)
    lim = np.array(limits)
    brackets, narrow = _scan(ab, box, fbox, lim, live)
    for d, reach in narrow:
        out[d] = (_halving(ab, box, bbox, limits, d, reach), 0.0, 0)
    _refine(ab, box, fbox, lim, brackets)
    for d, bs in brackets.items():
        j = 0 if bs[0][1] >= bs[1][1] else 1
        reach = next(r for dd, r, _ in live if dd == d)
        # the window cannot reach past the first candidate at which it is proven to end
        # (at the bracket's far end itself, the quick attempt only where the doubles put
        # the largest |T_j| there clear of the limit: else it is often just over it)
        clear = bs[j][3] < -CLEAR * limits[j]
        outer = next((h for k, h in enumerate(_outward(bs[j][1], reach))
                      if below(ab, box, bbox, limits, d * h, quick=k > 0 or clear)),
                     reach)  # fmt: skip
        # (a bracket narrower than the doubles' error at its ends: from a little inside)
        near = min(bs[j][0], bs[j][1] * (1 - 2e-12))
        inner = prove_in(ab, box, bbox, limits[j], j, d, near,
                         near == bs[j][0] and bs[j][2] > CLEAR * limits[j])  # fmt: skip
        out[d] = (outer, inner, j)
    return out


Bracket = tuple[float, float, float, float]  # lo, hi, and the largest |T_j| less the limit there


def _scan(ab: About, box: Box, fbox: Any, lim: np.ndarray, live: list[tuple[int, float, Any]]
          ) -> tuple[dict[int, list[Bracket]], list[tuple[int, float]]]:  # fmt: skip
    """Each side's brackets of each joint's first crossing (``live``: the sides, their
    reach and times reach 2^-k, k = 159..0) from the doubles at those times: every k
    down to 2^-(DENSE - 1) of the reach and every 8th below (a dip below the limit
    narrower than that, at under 1e-12 of the reach, is not looked for; the points
    between the first 8th found below and the one before are); and the sides too narrow
    for doubles (the limit not exceeded at the nearest time), with their reach."""
    n = len(SCAN)
    phi = phi_float(ab, np.concatenate([d * hs[SCAN] for d, _, hs in live]), box, fbox)
    brackets: dict[int, list[Bracket]] = {}
    narrow = []
    for m, (d, reach, hs) in enumerate(live):
        p = phi[n * m : n * (m + 1)]
        if not (p[0] > lim).any():
            narrow.append((d, reach))
            continue
        firsts = []
        for j in (0, 1):
            below = np.nonzero(p[:, j] <= lim[j])[0]
            firsts.append(int(SCAN[below[0]]) if len(below) else None)
        # the points skipped before each first 8th found below: looked at now
        gaps = sorted({i for k in firsts if k is not None
                       for i in range(int(SCAN[k > SCAN].max(initial=-1)) + 1, k)})  # fmt: skip
        seen = dict(zip(SCAN.tolist(), p, strict=True))  # the values looked at, by k
        if gaps:
            q = phi_float(ab, d * hs[gaps], box, fbox)
            seen.update(zip(gaps, q, strict=True))
            for j in (0, 1):
                fine = [g for g, v in zip(gaps, q[:, j], strict=True) if v <= lim[j]]
                k = firsts[j]
                if fine and k is not None and fine[0] < k:
                    firsts[j] = fine[0]
        bs = []
        for j, k in enumerate(firsts):
            if k is None:
                bs.append((reach, reach, math.nan, math.nan))  # beyond the limit to the end
            else:
                flo = seen[k - 1][j] - lim[j] if k > 0 else math.nan
                bs.append((float(hs[k - 1]) if k > 0 else 0.0, float(hs[k]), flo,
                           seen[k][j] - lim[j]))  # fmt: skip
        brackets[d] = bs
    return brackets, narrow


TIGHT = 2.0**-30  # a crossing's bracket is refined to this width relative to its far end


def _refine(ab: About, box: Box, fbox: Any, lim: np.ndarray,
            brackets: dict[int, list[Bracket]]) -> None:  # fmt: skip
    """Each joint's bracket of its first crossing (``brackets[d][j]`` = (lo, hi, and
    the largest |T_j| less the limit there, NaN when not known): the limit exceeded at
    lo, not at hi) narrowed in place to ``TIGHT``, every bracket at once at each step.
    With the values at both ends known: the regula falsi's estimate in 1/h (next to a
    pole |T| is about C/|h| + a slowly varying part, so nearly linear in 1/h) and points
    about it at 2^-4, 2^-8, ..., 2^-24 of the bracket on either side, the first of them
    found below the limit (the estimate's error sets how far the bracket shrinks); else
    16 points across it. A joint whose bracket lies wholly nearer t_s than the other's
    cannot reach furthest: not refined."""
    offsets = np.concatenate([-(2.0 ** -np.arange(4, 25, 4)), [0.0], 2.0 ** -np.arange(24, 3, -4)])
    state = {(d, j): bs[j] for d, bs in brackets.items() for j in (0, 1)}
    for _ in range(8):
        todo = []
        for (d, j), (lo, hi, flo, fhi) in state.items():
            other = state[(d, 1 - j)]
            if lo == hi or hi < other[0] or hi - lo <= TIGHT * hi:
                continue
            if lo > 0 and flo > 0 >= fhi and math.isfinite(flo) and math.isfinite(fhi):
                u = 1 / lo + (1 / hi - 1 / lo) * (flo / (flo - fhi))  # in 1/h
                est = min(max(1 / u, lo), hi)
                xs = np.unique(np.clip(est + (hi - lo) * offsets, lo, hi))
                xs = xs[(xs > lo) & (xs < hi)]
                if not len(xs):
                    xs = np.array([0.5 * lo + 0.5 * hi])
            else:
                xs = np.linspace(lo, hi, 17)[1:-1]
            todo.append(((d, j), xs))
        if not todo:
            break
        p = phi_float(ab, np.concatenate([d * xs for (d, _), xs in todo]), box, fbox)
        at = 0
        for (d, j), xs in todo:
            f = p[at : at + len(xs), j] - lim[j]
            at += len(xs)
            lo, hi, flo, fhi = state[(d, j)]
            below = np.nonzero(f <= 0)[0]  # NaN: not below (as above the limit)
            i = int(below[0]) if len(below) else len(xs)
            xs_all = np.concatenate([[lo], xs, [hi]])
            fs_all = np.concatenate([[flo], f, [fhi]])
            # the first point at or below the limit is xs_all[i + 1], the one before above
            state[(d, j)] = (float(xs_all[i]), float(xs_all[i + 1]), float(fs_all[i]),
                             float(fs_all[i + 1]))  # fmt: skip
    for (d, j), got in state.items():
        brackets[d][j] = got


CLEAR = 1e-12  # a double value of |T_j| this fraction of the limit below it: clear of it


def _outward(h: float, reach: float) -> list[float]:
    """The candidates for a proven outer end from h: h, h (1 + 1e-12), h (1 + 1e-12)
    (1 + 1e-10), ..., each below ``reach`` (the window cannot reach past the first at
    which both max |T_j| <= their limits are proven; ``reach`` when none is)."""
    out, step = [], 1e-12
    while h < reach:
        out.append(h)
        h, step = min(h * (1 + step), reach), step * 100
    return out


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
    fbox = float_box(box)
    got = ab.row(h, 1e-9)
    Ys = (got if got is not None else _regressor_float(ab, np.array([h]))[:, 0])[:, j, :]  # (3, 10)
    combos, _, k = _combos(ab, box)  # (c, 3): (e_x, e_y, s)
    Yc = k[:, 2, None] * (Ys[0] + k[:, 0, None] * Ys[1] + k[:, 1, None] * Ys[2])  # (c, 10)
    v = _form_float(Yc, _box_arrays(ab, box, fbox, Yc.ndim))
    found = np.nonzero(v > -math.inf)[0]  # (NaN: not a candidate)
    assert len(found)
    best = int(found[np.argmax(v[found])])  # the first of the largest
    ex, ey, _ = combos[best]
    Y = Yc[best]
    values = {}
    for link, km, kmr, kj in LINKS:
        A = Y[km] if km is not None else 0.0
        values[link] = _argmax(A, Y[kmr], Y[kj], box.links[link])
    L = box.robot_links(values)
    old = ctx.prec
    ctx.prec = prec
    try:
        c = ab.balls()[0]
        p = dyn.Params(_ball(ab.robot.a1), _ball(ab.robot.gravity), *L, of(ab.robot))  # type: ignore[call-arg]
        legs = legs_about(c, arb(h), p, arb(ex), arb(ey), dyn.hypot)
        d = dyn.dynamics(legs[0], legs[1], p)
        return abs(dyn.efforts(d, d.mu1 / d.delta, d.mu2 / d.delta)[j])
    finally:
        ctx.prec = old


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


def _halving(ab: About, box: Box, bbox: Any, limits: tuple[float, float], d: int,
             reach: float) -> float:  # fmt: skip
    """A proven outer end for a window too narrow for doubles: from the piece's end
    towards t_s by factors of 16, then of 2, the nearest h at which both max |T_j| <=
    their limits are proven (down to 1e-30 of the piece's reach: a window narrower
    is reported as that bound)."""

    best, h = reach, reach / 2
    for factor in (16.0, 2.0):
        # (a window under 1e-30 of the piece: 0)
        while h > reach * 1e-30 and below(ab, box, bbox, limits, d * h):
            best, h = h, h / factor
        h = best / 2
    return best

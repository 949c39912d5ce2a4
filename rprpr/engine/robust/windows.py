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
next to t_s lose nothing; ``robust.ends``) and then proven in ball arithmetic
(``robust.proofs``): at the reported end the upper bound of the largest |T_i| is at most
the limit, so the window cannot reach past it. Here: the instant's data (``About``,
``Box``, ``Robust``) and the evaluation in doubles (``phi_float``).
"""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

import numpy as np
from flint import arb, ctx, fmpq, fmpq_poly

from ...model.dataclass import dataclass
from ...model.numbers import to_float
from ...model.task import Robot, Uncertainty
from ..certified.kernel import KERNEL
from ..exact import equations as dyn
from ..exact.mechanism import of
from ..exact.series import taylor
from .regressor import (
    BASIS,
    LINKS,
    box_ends,
    closed_form,
    doubles_call,
    efforts_of,
    horner_at,
    legs_about,
    link_max_float,
    regressor_doubles,
    setting_params,
    settings_array,
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
            out += [to_ball(m), to_ball(inertia), to_ball(r)]
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
        the regressor there (h, ``regressor_float``'s array)."""
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
                [[to_ball(v) for v in p] for p in self.coeffs],
                [setting_params(self.robot, k, to_ball) for k in range(len(BASIS))],
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


def regressor_float(ab: About, h: np.ndarray) -> np.ndarray:
    """The regressor at the times t_s + h (doubles): (3, n, 2, 10) for the error parts
    e = 0, per unit e_x, per unit e_y; joints T1, T2; ``BASIS``. For the RPRPR's own
    schemes the closed form (``regressor_doubles``: a handful of products per column,
    and no difference of large efforts near t_s); another scheme's equations at the ten
    settings of ``settings_array``. A guide to the window's ends, never a proof."""
    c = ab.floats()
    hh = np.asarray(h, dtype=float)
    if closed_form(of(ab.robot)):
        kin = [np.asarray(horner_at(q, hh), dtype=float) for q in c]
        if "_call" not in ab.__dict__:
            ab.__dict__["_call"] = doubles_call(ab.robot)
        call = ab.__dict__["_call"]
        got = call(kin) if call is not None and hh.ndim == 1 else None
        if got is not None:  # (``regressor_doubles``' kernel call, its constants once)
            return got.transpose(2, 3, 0, 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            return regressor_doubles(ab.robot, kin).transpose(2, 3, 0, 1)
    hh = hh[:, None, None]  # (n, 1, 1)
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
    Ys = regressor_float(ab, h)
    ab.rows().append((np.asarray(h, dtype=float), Ys))
    return box_max(Ys, *_kernel_box(ab, box, fbox))


def box_max(Ys: np.ndarray, corners: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """The largest |T_i| over the box, (n, 2), in doubles, from the regressor ``Ys`` (3, n,
    2, 10) (``regressor_float``), the error's ``corners`` (c, 3): (e_x, e_y, 1), and the
    box's ``bounds`` (6, ``LINKS``): m_lo, m_hi, r_lo, r_hi, I_lo, I_hi. In one call of
    the compiled kernel where it is built (``kernel_c.BOX_MAX``: these operations in this
    order, the same doubles; a change to one is a change to both), else numpy's operations
    below."""
    if KERNEL is not None:
        out = np.empty((Ys.shape[1], 2))
        if KERNEL.box_max(Ys, corners, bounds, out):
            return out
    k = corners
    Y = (
        k[:, 2, None, None, None] * Ys[0][None]
        + k[:, 0, None, None, None] * Ys[1][None]
        + (k[:, 1, None, None, None] * Ys[2][None])
    )  # (corners, n, 2, 10); for s = -1 exactly -Y (rounding to nearest is symmetric)
    shape = (len(LINKS),) + (1,) * (Y.ndim - 1)
    ends = [row.reshape(shape) for row in bounds]
    up, down = _form_both(Y, ((ends[0], ends[1]), (ends[2], ends[3]), (ends[4], ends[5])))
    return np.maximum(up.max(axis=0), down.max(axis=0))


def _kernel_box(ab: About, box: Box, fbox: Any) -> tuple[np.ndarray, np.ndarray]:
    """``box_max``'s corners (e_x, e_y, 1) and the box's ends (m, r, I; low, high) over
    ``LINKS``, C-contiguous as the kernel reads them (made once per instant and box)."""
    got = ab.__dict__.get("_kernel_box")
    if got is None or got[0] is not box:
        corners = np.ascontiguousarray(combos_of(ab, box)[1][::2])
        bounds = box_ends(fbox)
        got = ab.__dict__["_kernel_box"] = (box, corners, bounds)
    return got[1], got[2]


def combos_of(ab: About, box: Box) -> tuple[list[tuple[fmpq, fmpq, float]], np.ndarray, np.ndarray]:
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


def _links(Y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``link_max_float``'s (A, B, C) for every link of ``LINKS``: ``Y``'s columns ``_M``,
    ``_MR``, ``_J`` (``BASIS`` on its last axis), the links' axis first; A is 0 for a link
    whose mass is not in the box (no ``km``)."""
    axes = (Y.ndim - 1, *range(Y.ndim - 1))
    B = Y[..., _MR].transpose(axes)
    C = Y[..., _J].transpose(axes)
    A = Y[..., _M].transpose(axes)
    for i, (_, km, _, _) in enumerate(LINKS):
        if km is None:
            A[i] = B[i] * 0
    return A, B, C


def form_float(Y: np.ndarray, bounds: Any) -> np.ndarray:
    """``regressor.form_max`` in doubles (the same operations on the same numbers, so the
    same doubles) with ``BASIS`` on the last axis of ``Y``: every link at once."""
    L = link_max_float(*_links(Y), bounds)
    total = L[0]
    for i in range(1, len(LINKS)):
        total = total + L[i]
    return total


def _form_both(Y: np.ndarray, bounds: Any) -> tuple[np.ndarray, np.ndarray]:
    """``form_float`` of Y and of -Y from one set of operations (``_link_max_both``)."""
    up, down = _link_max_both(*_links(Y), bounds)
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


def box_arrays(ab: About, box: Box, fbox: Any, ndim: int) -> Any:
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


def to_ball(v: Any) -> arb:
    if isinstance(v, arb):
        return v
    if isinstance(v, fmpq):
        return arb(v)
    return arb(v)


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

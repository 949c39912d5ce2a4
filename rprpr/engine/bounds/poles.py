"""The torques about an unbounded instant in one form: T_i = A_i + S_i/ε^k, over a whole
band about t_s, in arb scalars (``pole_form``), and the band it proves above a limit.

About a Type II instant t_s of order m with unbounded torques (a pole of order k = m -
min k_j, μ_j vanishing to order k_j), Taylor's theorem with the Lagrange remainder gives,
for every t = t_s + ε of a band and its hull E (holding 0): μ_j(t) = c_j ε^k_j, δ(t) = d
ε^m, with c_j the k_j-th coefficient of μ_j's series over E and d the m-th of δ's
(flint's ``arb_series`` on the ball E encloses f^(j)(ξ)/j! for every ξ ∈ E, as in
``taylor_forms.taylor_lambda``). So λ_j = Λ_j/ε^k with Λ_j ∈ (c_j/d) E^(k_j - m + k), and
the efforts, affine in λ (eq. 28 and the prismatic scheme's), are T_i = A_i + S_i/ε^k:
A_i the efforts with λ = 0 and S_i = Σ_j B_ij Λ_j, both over E, evaluated apart
(``_Affine``: no dependency between A_i and S_i). Hence, for 0 < |ε| <= h (h the largest
|ε| of the band), |T_i| >= |S_i|/h^k - |A_i|: one evaluation proves |T_i| above a limit
over the whole band, where the boxes of a ball pass would need ~10 pieces per factor of
e in |ε| (the direct form over a box holding t_s is unbounded).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from flint import arb, ctx

from ..certified.balls import hypot
from ..certified.motion import CertifiedMotion
from ..certified.taylor_forms import TAYLOR_PREC, coef, series_at
from .boxes import Bounds

if TYPE_CHECKING:
    from .scalars import Scalars


class _Affine:
    """a + b w, w a symbol (1/ε^k): the efforts, affine in λ, with λ_j = Λ_j w split into
    the part without λ (a) and the part with it (b), each evaluated once."""

    __slots__ = ("a", "b")

    def __init__(self, a: Any, b: Any) -> None:
        self.a, self.b = a, b

    def __add__(self, o: Any) -> _Affine:
        if isinstance(o, _Affine):
            return _Affine(self.a + o.a, self.b + o.b)
        return _Affine(self.a + o, self.b)

    __radd__ = __add__

    def __sub__(self, o: Any) -> _Affine:
        if isinstance(o, _Affine):
            return _Affine(self.a - o.a, self.b - o.b)
        return _Affine(self.a - o, self.b)

    def __rsub__(self, o: Any) -> _Affine:
        return _Affine(o - self.a, -self.b)

    def __neg__(self) -> _Affine:
        return _Affine(-self.a, -self.b)

    def __mul__(self, o: Any) -> _Affine:
        if isinstance(o, _Affine):
            raise TypeError("the efforts are affine in λ")
        return _Affine(self.a * o, self.b * o)

    __rmul__ = __mul__


TERMS = 3  # Taylor terms of μ_j/ε^k_j and δ/ε^m beyond the first, before the remainder


def _quotients(
    motion: CertifiedMotion, k: int, t0: arb, coeffs: list[list[arb]], lo: float, hi: float,
    point: tuple[Any, Any, Any],
) -> tuple[arb, Any, list[arb], list[int], int] | None:  # fmt: skip
    """(E, the dynamics over the hull, [q_1, q_2], [k_1, k_2], m) about the ``k``-th
    instant over [lo, hi] (E: the hull of [lo, hi] - t_s and 0): λ_j(t) ∈ q_j ε^(k_j - m)
    for every t of [lo, hi], q_j = (μ_j/ε^k_j)/(δ/ε^m) by Taylor forms about t_s (their
    coefficients at t_s, ``point``, up to TERMS beyond the first, and the next over the
    hull: the Lagrange remainder), by Horner in E. None where d ∋ 0 or a formula fails."""
    s, _ = motion.instants[k]
    m = s.order
    ks = [min(v, m + 1) for v in motion.analysis.hints(s).mu_valuations]
    n = max(*ks, m) + TERMS + 1
    E = (arb(lo) - t0).union(arb(hi) - t0).union(arb(0))  # ξ - t_s for ξ in the hull
    X, Xd, Xdd, Y, Yd, Ydd = series_at(coeffs, E, n + 1)
    ctx.cap = n + 1
    mech = motion.mech
    p = mech.params(motion.robot, arb)
    l1, l2 = mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, hypot)
    d = mech.dynamics(l1, l2, p)
    far = (d.mu1, d.mu2, mech.delta(p, Y, l1, l2))
    reduced = []
    for near, wide, v in zip(point, far, (ks[0], ks[1], m), strict=True):
        acc = coef(wide, n)  # f^(n)(ξ)/n!, ξ in the hull
        for j in range(n - 1, v - 1, -1):
            acc = acc * E + coef(near, j)
        reduced.append(acc)  # f(t_s + ε)/ε^v for every ε in E
    dm = reduced[2]
    if not dm.is_finite() or dm.contains(0):
        return None
    qs = [c / dm for c in reduced[:2]]
    if not all(q.is_finite() for q in qs):
        return None
    return E, d, qs, ks, m


def pole_form(
    motion: CertifiedMotion, k: int, t0: arb, coeffs: list[list[arb]], lo: float, hi: float,
    point: tuple[Any, Any, Any] | None = None,
) -> tuple[int, list[arb], list[arb], arb] | None:  # fmt: skip
    """(k, [S_1, S_2], [A_1, A_2], h) about the ``k``-th instant (a pole; t0: t_s,
    ``coeffs``: the Taylor coefficients of x and y about it) over the band [lo, hi]
    (holding t_s): for every t of the band other than t_s, T_i(t) = A_i(t) + S_i(t)/(t -
    t_s)^k with A_i(t) ∈ A_i, S_i(t) ∈ S_i, and |t - t_s| <= h (module docstring);
    ``point``: μ1, μ2, δ as series at t_s (``point_series``), when made already. None
    where the form does not apply (d ∋ 0, a square root or a quotient over a ball reaching
    0, a bounded instant).

    μ_j/ε^k_j and δ/ε^m are Taylor forms about t_s (``_quotients``): the series over the
    hull alone would enclose them far too wide (μ_j cancels digits)."""
    s, _ = motion.instants[k]
    if s.torque_bounded:
        return None
    if point is None:
        point = point_series(motion, t0, coeffs, k)
        if point is None:
            return None
    old_prec, old_cap = ctx.prec, ctx.cap
    ctx.prec = TAYLOR_PREC
    try:
        got = _quotients(motion, k, t0, coeffs, lo, hi, point)
        if got is None:
            return None
        E, d, qs, ks, m = got
        order = m - min(ks)
        if order < 1:
            return None
        lam = []
        for q, kj in zip(qs, ks, strict=True):
            for _ in range(kj - m + order):  # E**n: flint's power of a ball holding 0 is nan
                q = q * E
            lam.append(_Affine(arb(0), q))
        T = motion.mech.efforts(d, lam[0], lam[1])
        S = [coef(Ti.b, 0) for Ti in T]
        A = [coef(Ti.a, 0) for Ti in T]
        if not all(v.is_finite() for v in (*S, *A)):
            return None
        return order, S, A, arb(abs(E).upper())
    except (ValueError, ZeroDivisionError):  # a square root of a ball reaching below 0
        return None
    finally:
        ctx.prec, ctx.cap = old_prec, old_cap


def point_series(
    motion: CertifiedMotion, t0: arb, coeffs: list[list[arb]], k: int
) -> _PointSeries | None:
    """μ1, μ2, δ as series at the ``k``-th instant t_s (``pole_form``'s terms), with the
    dynamics there (``_PointSeries``)."""
    s, _ = motion.instants[k]
    m = s.order
    ks = [min(v, m + 1) for v in motion.analysis.hints(s).mu_valuations]
    n = max(*ks, m) + TERMS + 1
    old_prec, old_cap = ctx.prec, ctx.cap
    ctx.prec, ctx.cap = TAYLOR_PREC, n + 2
    try:
        X, Xd, Xdd, Y, Yd, Ydd = series_at(coeffs, arb(0), n)
        ctx.cap = n
        mech = motion.mech
        p = mech.params(motion.robot, arb)
        l1, l2 = mech.legs(p, X, Xd, Xdd, Y, Yd, Ydd, hypot)
        d = mech.dynamics(l1, l2, p)
        return _PointSeries((d.mu1, d.mu2, mech.delta(p, Y, l1, l2)), d)
    except (ValueError, ZeroDivisionError):
        return None
    finally:
        ctx.prec, ctx.cap = old_prec, old_cap


class _PointSeries(tuple):  # type: ignore[type-arg]
    """μ1, μ2, δ as series at t_s (``point_series``), with the dynamics there (``dyn``),
    from which ``_at_pole`` reads the form at t_s without evaluating the formulas again."""

    dyn: Any

    def __new__(cls, items: tuple[Any, Any, Any], dyn: Any) -> _PointSeries:
        out = super().__new__(cls, items)
        out.dyn = dyn
        return out


def _at_pole(
    motion: CertifiedMotion, k: int, point: _PointSeries
) -> tuple[int, list[arb], list[arb], arb] | None:
    """S_i and A_i of the form at t_s itself (``pole_form`` over the band [t_s, t_s]) from
    the series at t_s (``point_series``): the leading coefficients' quotients, the
    efforts on the dynamics at t_s. Only for ``estimate`` (where to try a band: each
    band is proven by its own ``pole_form``), so the time's enclosure (t_s a real root)
    is not carried."""
    s, _ = motion.instants[k]
    m = s.order
    ks = [min(v, m + 1) for v in motion.analysis.hints(s).mu_valuations]
    order = m - min(ks)
    if order < 1:
        return None
    with ctx.workprec(TAYLOR_PREC):
        try:
            dm = coef(point[2], m)
            if not dm.is_finite() or dm.contains(0):
                return None
            lam = []
            for j, kj in enumerate(ks):
                q = coef(point[j], kj) / dm if kj - m + order == 0 else arb(0)
                lam.append(_Affine(arb(0), q))
            T = motion.mech.efforts(point.dyn, lam[0], lam[1])
            S = [coef(Ti.b, 0) for Ti in T]
            A = [coef(Ti.a, 0) for Ti in T]
        except (ValueError, ZeroDivisionError):
            return None
    if not all(v.is_finite() for v in (*S, *A)):
        return None
    return order, S, A, arb(0)


def band_floor(form: tuple[int, list[arb], list[arb], arb], i: int) -> float:
    """A lower bound of |T_i| at every time of the band of ``form`` (``pole_form``) other
    than t_s: |S_i|/h^k - |A_i| rounded down (0 when that is not above 0)."""
    order, S, A, h = form
    with ctx.workprec(TAYLOR_PREC):
        if S[i].contains(0):
            return 0.0
        hk = arb(1)
        for _ in range(order):
            hk = hk * h
        low = (arb(abs(S[i]).lower()) / hk - arb(abs(A[i]).upper())).lower()
        if not low.is_finite() or not low > 0:
            return 0.0
        return max(0.0, math.nextafter(float(low), -math.inf))


def estimate(form: tuple[int, list[arb], list[arb], arb], i: int, limit: float) -> float:
    """Where |T_i| = limit about t_s by the form at t_s alone (|ε|^k = |S_i|/(limit +
    |A_i|)): only a choice of where to try the band (``band_floor`` proves it)."""
    order, S, A, _ = form
    s, a = abs(float(S[i].mid())), abs(float(A[i].mid()))
    return float((s / (limit + a)) ** (1.0 / order)) if s > 0 else 0.0


BAND_SHARES = (0.5, 0.2)  # a pole's band reaches these shares of the distance to a crossing


def pole_bands(
    motion: CertifiedMotion, scalars: Scalars, lo: np.ndarray, hi: np.ndarray, L: np.ndarray
) -> tuple[np.ndarray, Bounds | None]:
    """The pieces about each pole (``limits._around_pole``) within a share (BAND_SHARES,
    the widest proven) of the distance at which |T_i| falls to L_i (``estimate``), but
    the piece holding the pole, merged into a box on each side proven above both limits
    by the pole's form over their hull (``pole_form``: |T_i| >= |S_i|/h^k - |A_i|), so
    that no pass is spent on them (~10 pieces per factor of e in |t - t_s|): (the pieces
    merged, the boxes that replace them); (no piece, None) where no band is proven."""
    inner = np.zeros(len(lo), dtype=bool)
    blo, bhi, floors = [], [], []
    for k, (s, e) in enumerate(motion.instants):
        if s.torque_bounded:
            continue
        t0, coeffs = scalars._origin(e.hi)
        point = point_series(motion, t0, coeffs, k)
        at = None if point is None else _at_pole(motion, k, point)
        if at is None:
            continue
        reach = min(estimate(at, i, float(L[i])) for i in (0, 1))
        for share in BAND_SHARES:  # the widest band proven
            got = _pole_band(motion, k, t0, coeffs, point, share * reach, lo, hi, inner, L)
            if got is not None:
                break
        if got is None:
            continue
        near, pieces = got
        inner |= near
        for x0, x1, f in pieces:
            blo.append(x0)
            bhi.append(x1)
            floors.append(f)
    if not blo:
        return inner, None
    lo_b, hi_b = np.array(blo), np.array(bhi)
    fl = np.array(floors).T  # rows: torques; 0 about the pole (open there)
    up = np.full(fl.shape, np.inf)
    band = Bounds(lo_b, hi_b, fl, np.broadcast_to(lo_b, fl.shape).copy(), up, fl,
                  (up, up, fl, fl, fl, fl), np.zeros(fl.shape, dtype=bool))  # fmt: skip
    return inner, band


def _pole_band(
    motion: CertifiedMotion, k: int, t0: Any, coeffs: Any, point: Any, h: float, lo: np.ndarray,
    hi: np.ndarray, inner: np.ndarray, L: np.ndarray,
) -> tuple[np.ndarray, list[tuple[float, float, list[float]]]] | None:  # fmt: skip
    """The pieces within h of the k-th instant (a pole) but the one holding it, merged
    on each side and proven above both limits by the pole's form over their hull, with
    the floors of |T1|, |T2| there; and the piece holding the pole, when it is the
    narrow one that ``limits._around_pole`` leaves about it, as a box open for both
    torques with floors 0 (the torques are unbounded in it: a pass over it would
    decide nothing, and the point values at its ends are the poorest of all, which
    would ask for the pole's zone): (the pieces, the boxes that replace them); None
    where no band is proven."""
    e = motion.instants[k][1]
    near = (lo >= e.hi - h) & (hi <= e.hi + h) & ~inner
    centre = (lo <= e.hi) & (hi >= e.hi)  # the piece about the pole stays as it was
    near &= ~centre
    left, right = near & (hi <= e.hi), near & (lo >= e.hi)
    if not ((left.any() or right.any()) and centre.any()):
        return None
    c_lo, c_hi = float(lo[centre].min()), float(hi[centre].max())
    a = float(lo[left].min()) if left.any() else c_lo
    z = float(hi[right].max()) if right.any() else c_hi
    if np.count_nonzero(near) != np.count_nonzero((lo >= a) & (hi <= z) & ~centre):
        return None  # the pieces are not one run about the pole's piece
    form = pole_form(motion, k, t0, coeffs, a, z, point)
    if form is None:
        return None
    f = [band_floor(form, i) for i in (0, 1)]
    if not (f[0] > L[0] and f[1] > L[1]):
        return None
    pieces = [(x0, x1, f) for side, x0, x1 in ((left, a, c_lo), (right, c_hi, z)) if side.any()]
    if c_hi - c_lo < z - a:  # the piece about the pole: open, and no pass for it
        near |= centre
        pieces.append((c_lo, c_hi, [0.0, 0.0]))
    return near, pieces

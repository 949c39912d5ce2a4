"""The worst case of each effort over the box of ``docs/robust.md``, at given times,
proven: per time t, an upper bound of max |E_i(t)| over every link parameter in the box
and every acceleration tracking error within the bound (``rprpr export``'s ``T1_worst``,
``T2_worst`` columns, ``F1_worst``, ``F2_worst`` under linear actuators).

The closed form of ``robust.windows`` (its module docstring), evaluated in ball arithmetic
(``balls.Ball``, every sample at once): the efforts are linear in the inertial parameters
π (``robust.BASIS``) and affine in the error e, so with the regressor Y(t, e) (E = Y π)

    max |E_i(t)| = max over s = ±1 and the corners of e of Σ_links max over the link's
                   (m, r, I) of s (A m + B m r + C (m r² + I)),

each link's maximum in closed form: at an end of r's interval, or (C < 0) at the
parabola's vertex -B/(2C) when it may lie inside; then the larger of m's ends, and of I's.
Every candidate is an upper bound of a value the box reaches (or, where the sign of C is
not decided, of r's whole interval), so the result is a proven upper bound and, where the
candidates are decided, within the balls' rounding of the true maximum. Not sampled: the
maximum over the box at each t is exact; the times are the caller's grid.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from ...model.numbers import to_float
from ...model.task import Task
from ..certified.balls import Ball, hypot, quiet, stack
from ..certified.jets import Jet
from ..exact import equations as dyn
from .regressor import BASIS, LINKS, setting_params
from .windows import Box

ERRORS = ((0, 0), (1, 0), (0, 1))  # the error parts of the regressor: e = 0, unit e_x, e_y


def worst_efforts(task: Task, parts: Sequence[Any], t: np.ndarray) -> tuple[np.ndarray, ...]:
    """Per time of ``t`` [s] (absolute), proven upper bounds of max |E1|, max |E2| over
    ``task.uncertainty``'s box (+inf where unbounded: at a pole). ``parts``: the audit's
    pieces (``AuditResult.parts``)."""
    (lo1, hi1), (lo2, hi2) = effort_bands(task, parts, t)
    return np.maximum(hi1, -lo1), np.maximum(hi2, -lo2)


def effort_bands(
    task: Task, parts: Sequence[Any], t: np.ndarray
) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """Per time of ``t`` [s] (absolute), for E1 and E2 a proven (lower, upper) bound of
    the effort over ``task.uncertainty``'s box: every effort the box allows at that time
    lies in [lower, upper] (∓inf where unbounded: at a pole)."""
    from ..pieces import which

    u = task.uncertainty
    assert u is not None
    box = Box.of(task.robot, u)
    t = np.asarray(t, dtype=float)
    out = np.full((2, 2, len(t)), np.inf)
    out[:, 0] = -np.inf
    idx = which(list(parts), t) if len(parts) > 1 else np.zeros(len(t), dtype=int)
    with quiet():
        for i in np.unique(idx):
            p = parts[int(i)]
            sel = np.nonzero(idx == i)[0]
            kin = p.motion.end_point(t[sel] - to_float(p.origin))
            for j, (lo, hi) in enumerate(bands_at(task, kin, box)):
                out[j, 0, sel], out[j, 1, sel] = lo, hi
    return (out[0, 0], out[0, 1]), (out[1, 0], out[1, 1])


def bands_at(
    task: Task, kin: Sequence[Ball], box: Box, lower: bool | np.ndarray = False
) -> list[tuple[np.ndarray, np.ndarray]]:
    """(lower, upper) of E_j over the box, j = 1, 2, from the end point's balls ``kin``:
    the upper bound of max s E_j for s = +1, and minus it for s = -1. With ``lower``,
    the same from lower bounds of the maxima (a band inside the true one); an array:
    per ball of ``kin``.

    Every effort, basis parameter, error part and corner at once: the balls carry them
    as leading axes [effort, ``BASIS``, corner, time] (a ball operation costs its call
    more than its length), each element the operations it would have alone; both signs
    from the same balls (``_link_bounds``)."""
    return bands_of(_regressor(task, kin), box, lower)


def bands_of(
    Y: Ball, box: Box, lower: bool | np.ndarray = False
) -> list[tuple[np.ndarray, np.ndarray]]:
    """``bands_at`` from the regressor's balls ``Y`` [effort, ``BASIS``, error part, time]:
    every effort whose coefficients lie in ``Y``, over the box."""
    corners = box.corners()
    ex = _column([c[0] for c in corners], 2)  # [corner, time]
    ey = _column([c[1] for c in corners], 2)
    a, b, c = (Ball._of(Y.mid[:, :, i, None], Y.rad[:, :, i, None]) for i in range(3))
    form = (a + b * ex + c * ey) * 1.0  # [effort, BASIS, corner, time]; s = +1 (s E: * s)
    links = {i: [[Ball.of_rational(v) for v in pair] for pair in b] for i, b in box.links.items()}
    bound = _form_bound(form, links, lower)  # [sign, effort, corner, time]
    best = np.full(bound.shape[:2] + bound.shape[3:], -np.inf)
    for k in range(len(corners)):  # the corners in order (np.maximum keeps NaN)
        best = np.maximum(best, bound[:, :, k])
    ends = np.where(np.isnan(best), np.where(lower, -np.inf, np.inf), best)  # [sign, effort]
    return [(-ends[1, j], ends[0, j]) for j in (0, 1)]


def _column(values: Sequence[Any], dims: int) -> Ball:
    """The exact rationals ``values`` as one ball array along the first of ``dims`` axes."""
    parts = [Ball.of_rational(v) for v in values]
    shape = (len(parts),) + (1,) * (dims - 1)
    return Ball._of(np.array([p.mid for p in parts]).reshape(shape),
                    np.array([p.rad for p in parts]).reshape(shape))  # fmt: skip


def _regressor(task: Task, kin: Sequence[Ball]) -> Ball:
    """[effort, ``BASIS``, error part, time]: the efforts' coefficients of π for e = 0,
    and their change per unit e_x, per unit e_y. The settings ([``BASIS``] leading the
    parameters' balls) and the error parts ([e = 0, unit e_x, unit e_y] leading the
    accelerations) in one evaluation."""
    values = _efforts(task, kin, hypot)
    shape = (len(BASIS), len(ERRORS), *np.broadcast_shapes(*(np.shape(b.mid) for b in kin)))
    return _to_regressor(stack([full(v, shape) for v in values]))


def regressor_jet(task: Task, kin: Sequence[Jet]) -> tuple[Ball, Ball]:
    """``_regressor`` and its time derivative over the boxes of time the jets ``kin`` (x,
    ẋ, ẍ, y, ẏ, ÿ and their derivatives) are taken over: every coefficient, and its
    derivative, at every time of its box lies in the ball."""
    values = _efforts(task, kin, lambda u, v: (u * u + v * v).sqrt())
    shape = (len(BASIS), len(ERRORS), *np.broadcast_shapes(*(np.shape(j.v.mid) for j in kin)))
    return (_to_regressor(stack([full(v.v, shape) for v in values])),
            _to_regressor(stack([full(v.d, shape) for v in values])))  # fmt: skip


def _efforts(task: Task, kin: Sequence[Any], hyp: Any) -> tuple[Any, Any]:
    """Both efforts at every setting of ``BASIS`` and error part (balls or jets)."""
    x, xd, xdd, y, yd, ydd = kin
    cols = [setting_params(task.robot, k, Ball.of_rational) for k in range(len(BASIS))]
    names = ("m2", "I2", "r2", "m3", "I3", "r3", "m4", "I4", "r4", "m5", "I5", "r5")
    p = dyn.Params(cols[0].a1, cols[0].g, mechanism=cols[0].mechanism,
                   **{n: _stacked([getattr(c, n) for c in cols]) for n in names})  # fmt: skip
    mech = p.mechanism
    ex = Ball.exact(np.array([float(e) for e, _ in ERRORS])[:, None])
    ey = Ball.exact(np.array([float(e) for _, e in ERRORS])[:, None])
    leg1, leg2 = mech.legs(p, x, xd, xdd + ex, y, yd, ydd + ey, hyp)
    delta = mech.delta(p, y, leg1, leg2)  # the product form (no cancellation)
    d = mech.dynamics(leg1, leg2, p)
    return mech.efforts(d, d.mu1 / delta, d.mu2 / delta)


def _to_regressor(E: Ball) -> Ball:
    """From the efforts at the settings and error parts [effort, ``BASIS``, error part,
    time] to the coefficients of π for e = 0, per unit e_x, per unit e_y (linear)."""
    for k, (link, what) in enumerate(BASIS):  # ``to_basis``: the "mr" setting less the "m"
        if what == "mr" and (link, "m") in BASIS:
            m = BASIS.index((link, "m"))
            diff = Ball._of(E.mid[:, k], E.rad[:, k]) - Ball._of(E.mid[:, m], E.rad[:, m])
            E.mid[:, k], E.rad[:, k] = diff.mid, diff.rad
    e0 = Ball._of(E.mid[:, :, :1], E.rad[:, :, :1])
    per = Ball._of(E.mid[:, :, 1:], E.rad[:, :, 1:]) - e0  # per unit e_x, e_y
    return Ball._of(np.concatenate([e0.mid, per.mid], axis=2),
                    np.concatenate([e0.rad, per.rad], axis=2))  # fmt: skip


def _stacked(balls: Sequence[Ball]) -> Ball:
    """Scalar balls as one ball array along a leading axis (then two unit axes)."""
    return Ball._of(np.array([b.mid for b in balls]).reshape(-1, 1, 1),
                    np.array([b.rad for b in balls]).reshape(-1, 1, 1))  # fmt: skip


def full(b: Ball, shape: tuple[int, ...]) -> Ball:
    """The ball ``b`` broadcast to ``shape`` (a new array)."""
    mid, rad = np.broadcast_to(b.mid, shape), np.broadcast_to(b.rad, shape)
    return Ball._of(np.array(mid), np.array(rad))


def _form_bound(
    form: Ball, links: dict[int, list[list[Ball]]], lower: bool | np.ndarray
) -> np.ndarray:
    """[sign s = +1, -1, ...]: an upper bound (``lower``: a lower bound) of max over the
    box of s Σ_k form_k π_k (``BASIS`` on the form's second axis)."""

    def at(k: int) -> Ball:
        return Ball._of(form.mid[:, k], form.rad[:, k])

    total = Ball.exact(0.0)
    for link, km, kmr, kj in LINKS:
        A = at(km) if km is not None else at(kmr) * 0.0
        total = total + Ball.exact(_link_bounds(A, at(kmr), at(kj), links[link], lower))
    return np.where(lower, total.lower(), total.upper())


def _link_bounds(
    A: Ball, B: Ball, C: Ball, box: list[list[Ball]], lower: bool | np.ndarray
) -> np.ndarray:
    """[sign s = +1, -1, ...]: an upper bound of max over the link's (m, r, I) of
    s (A m + B m r + C (m r² + I)); with ``lower`` (per element where an array), a lower
    bound of it (only the candidates the balls decide).

    Both signs from one set of ball operations: every operation below, given -A, -B, -C,
    gives the negated ball exactly (midpoints negated, the same radii: rounding to nearest
    is symmetric), whose upper end is minus the lower end (``Ball.upper``, ``lower``);
    so s = -1 reads the other end of each ball, the concavity from C's other end, and
    the vertex -B/2C is the same."""
    (mlo, mhi), (rlo, rhi), (ilo, ihi) = box
    low = np.asarray(lower)

    def ends(b: Ball) -> tuple[np.ndarray, np.ndarray]:
        """The bound each sign reads of the ball b (of s b for s = -1)."""
        lo, hi = b.lower(), b.upper()
        return np.where(lower, lo, hi), -np.where(lower, hi, lo)

    def end(b: Ball) -> np.ndarray:
        return np.where(lower, b.lower(), b.upper())

    e_lo = ends(A + B * rlo + C * rlo * rlo)
    e_hi = ends(A + B * rhi + C * rhi * rhi)
    G = [np.maximum(e_lo[s], e_hi[s]) for s in (0, 1)]
    c_lo, c_hi = C.lower(), C.upper()
    concave = (c_hi < 0, -c_lo < 0)  # s C's upper end below 0
    vertex = -B / (C * 2.0)
    surely = (vertex.lower() > rlo.upper()) & (vertex.upper() < rhi.lower())
    maybe = (vertex.upper() > rlo.lower()) & (vertex.lower() < rhi.upper())
    placed = np.where(lower, surely, maybe)  # lower: only where surely inside
    top = list(ends(A - B * B / (C * 4.0)))
    if not np.all(lower):
        r = Ball.hull(rlo.lower(), rhi.upper())
        q = A + B * r + C * r * r  # the quadratic over r's whole interval
        over = (q.upper(), -q.lower())
        negative = (c_lo < 0, -c_hi < 0)  # s C's lower end below 0
        for s in (0, 1):
            # an upper bound of the vertex's value too where the vertex lies in r's
            # interval: the narrower of the two (a vertex ball too wide to place, C near
            # 0, makes A - B²/4C a vast bound where the quadratic itself is small)
            top[s] = np.where(lower, top[s], np.minimum(top[s], over[s]))
            undecided = ~concave[s] & negative[s] & ~low  # C's sign unknown
            G[s] = np.where(undecided, np.maximum(G[s], over[s]), G[s])
    for s in (0, 1):
        G[s] = np.where(concave[s] & placed, np.maximum(G[s], top[s]), G[s])
    g = Ball.exact(np.stack(G))  # [sign, ...]
    m_part = np.maximum(end(g * mlo), end(g * mhi))  # m > 0: linear in m
    i_lo, i_hi = ends(C * ilo), ends(C * ihi)
    i_part = np.stack([np.maximum(i_lo[s], i_hi[s]) for s in (0, 1)])
    return end(Ball.exact(m_part) + Ball.exact(i_part))

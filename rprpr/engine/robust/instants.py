"""The robust analysis of a singular instant from its pieces (``docs/robust.md``): the
residual over the box and the saturation window, each side measured by ``ends.sides``
on the piece that holds t_s and, when it reaches that piece's end, continued across the
knot into the pieces beyond (``beyond``) until one proves where it ends."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
from flint import arb, ctx, fmpq, fmpq_poly

from ...model.numbers import to_float
from ...model.task import Robot, Task
from ..pieces import shift
from .ends import sides
from .proofs import below, prove_in, residual
from .windows import (
    PREC,
    About,
    Box,
    Robust,
    about,
    ball_box,
    float_box,
    phi_float,
    round_down,
    round_up,
    shifted,
)

GAP = 1e-12  # [s] past a knot, a dip below the limit shorter than this does not end a window


# -- across knots: the window continued into the neighbouring pieces -------------------


def about_knot(traj: Any, robot: Robot, u: fmpq, t_abs: float) -> About:
    """The motion of the piece ``traj`` about its end at local time ``u`` (a knot, exact):
    Taylor coefficients in h = t - knot, h's span on the piece."""
    polys = (traj.x, traj.xd, traj.xdd, traj.y, traj.yd, traj.ydd)
    coeffs = [shifted(p, u, None, None) for p in polys]
    lo, hi = to_float(traj.lead - u), to_float(traj.duration - u)
    return About(coeffs, min(0.0, lo), max(0.0, hi), robot, t_abs)


def beyond(ab: About, box: Box, limits: tuple[float, float], direction: int
           ) -> tuple[float, float, int] | None:  # fmt: skip
    """Where, going from the knot ``ab`` is taken about into its piece (``direction``),
    the largest |T_i| over the box is proven at most its limit for both joints: (h, an
    h' at which the limit is proven exceeded (0 when not shown), the joint (0, 1) that
    reaches furthest), distances from the knot [s]; None when that is not
    proven before the piece's far end (the window goes on into the next piece). The
    doubles look at distances reach·2^-k (k = 0..159) and on a uniform grid of 256, from
    ``GAP`` on, bracket the first time where both joints are at most their limits, refine
    the bracket, and the end h is proven in ball arithmetic (``_prove_from``): over the
    whole span [h, h + GAP], both max |T_j| <= their limits. A dip below the limit shorter
    than ``GAP`` does not end a window: at a knot the pieces' states differ by the
    rounding a tolerance closed, and next to a pole that can make one piece's efforts
    small for 1e-15 s (a plan that arrives at y = 0 with ẏ = ÿ = 0 in doubles)."""
    reach = ab.h_max if direction > 0 else -ab.h_min
    fbox, bbox = float_box(box), ball_box(box)
    lim = np.array(limits)
    hs = np.unique(np.concatenate([reach * np.exp2(-np.arange(0, 160, 1.0)),
                                   np.linspace(0.0, reach, 257)[1:]]))  # fmt: skip
    hs = hs[hs >= min(GAP, reach)]
    phi = phi_float(ab, direction * hs, box, fbox)
    below = np.nonzero((phi <= lim).all(axis=1))[0]
    if len(below) == 0:
        if _prove_from(ab, bbox, box, limits, direction, reach, reach) is None:
            return None
        return reach, 0.0, int(np.argmax(phi[-1] / lim))
    k = int(below[0])
    lo, hi = (float(hs[k - 1]) if k > 0 else 0.0), float(hs[k])
    joint = int(np.argmax(phi[k - 1] / lim)) if k > 0 else 0
    for _ in range(4):
        if lo == hi:
            break
        grid = np.linspace(lo, hi, 65)
        p = phi_float(ab, direction * grid[1:], box, fbox)
        idx = np.nonzero((p <= lim).all(axis=1))[0]
        i = int(idx[0]) if len(idx) else 63
        lo, hi = float(grid[i]), float(grid[i + 1])
    h = _prove_from(ab, bbox, box, limits, direction, hi, reach)
    if h is None:
        return None
    return h, prove_in(ab, box, bbox, limits[joint], joint, direction, lo), joint


def _prove_from(ab: About, bbox: Any, box: Box, limits: tuple[float, float], d: int, h: float,
                reach: float) -> float | None:  # fmt: skip
    """The nearest of h, h + s, h + 101 s, ... (s = 1e-12 max(h, 1e-9 reach), the step
    growing a hundredfold), up to ``reach``, such that both max |T_j| <= their limits is
    proven over the span from it ``GAP`` further (towards the piece's far end); None when
    none is."""
    step = 1e-12 * max(h, 1e-9 * reach)
    while True:
        if below(ab, box, bbox, limits, d * h, d * min(GAP, reach - h)):
            return h
        if h >= reach:
            return None
        h, step = min(h + step, reach), step * 100


def analyse(ab_sides: Sequence[tuple[About, int]], box: Box, limits: tuple[float, float] | None,
            nominal: Any, onward: Any = None) -> Robust:  # fmt: skip
    """The robust analysis of one instant from its pieces (``ab_sides``: the motion about
    t_s and the sides, -1, +1 or 0 for both, that this piece covers); ``nominal`` the
    instant's exact analysis (``singular.SingularInstant``). ``onward(k, d)``, when
    given: where the window goes on past the end (``d`` = -1, +1) of the piece of
    ``ab_sides[k]`` — (a proven upper bound of the distance |t - t_s| at which it ends,
    the joint), the motion's end's distance when it reaches it."""
    if box.zero:
        r = nominal.consistency_residual
        res = (r, r)
        lo_b = hi_b = None
    else:
        balls = [residual(ab, box) for ab, _ in ab_sides]
        lo_b = min((b[0] for b in balls), key=lambda v: float(v.mid()))
        hi_b = max((b[1] for b in balls), key=lambda v: float(v.mid()))
        res = (round_down(lo_b), round_up(hi_b))
    pole = not (box.zero and nominal.torque_bounded)
    if limits is None or not pole:
        return Robust(res, 0.0)
    ends = {-1: (0.0, 0.0, 0), 1: (0.0, 0.0, 0)}
    covered = set()
    for k, (ab, which) in enumerate(ab_sides):
        dirs = [d for d in (-1, 1) if which in (0, d)]
        got = sides(ab, box, limits, dirs)
        for d in dirs:
            covered.add(d)
            ends[d] = got[d]
            reach = ab.h_max if d > 0 else -ab.h_min
            if onward is not None and ends[d][0] >= reach:
                far, near, j = onward(k, d)  # the window reaches the knot: it goes on
                ends[d] = (max(far, ends[d][0]), max(near, ends[d][1]), j)
    for d in {-1, 1} - covered:  # t_s on a knot, the piece beyond without a record
        edge = [k for k, (ab, _) in enumerate(ab_sides) if (ab.h_max if d > 0 else -ab.h_min) == 0]
        if onward is not None and edge:
            ends[d] = onward(edge[0], d)
    left, right = ends[-1][0], ends[1][0]
    window = left + right
    if window == 0:
        return Robust(res, 0.0)
    joint = 1 + (ends[-1][2] if left >= right else ends[1][2])
    t = ab_sides[0][0].t_s
    span = (math.nextafter(t - left, -math.inf), math.nextafter(t + right, math.inf))
    inner = ends[-1][1] + ends[1][1] if ends[-1][1] and ends[1][1] else 0.0
    return Robust(res, shift(fmpq(*left.as_integer_ratio()), right, up=True), inner, joint, span)


def robust(
    task: Task,
    parts: Sequence[Any],
    instants: Sequence[Any],
    sources: Sequence[Sequence[tuple[int, Any]]],
) -> list[Robust]:
    """The robust analysis of each singular instant of the audited ``task``
    (``instants``: the joined analysis, absolute times; ``parts``: the pieces with
    their local analyses; ``sources[i]``: the (piece index, local instant) pairs
    ``instants[i]`` was joined from, two at a knot)."""
    u = task.uncertainty
    assert u is not None
    box = Box.of(task.robot, u)
    limit = task.checks.torque_limit
    limits = None if limit is None else (to_float(limit[0]), to_float(limit[1]))
    out = []
    for s, origin in zip(instants, sources, strict=True):
        ab_sides = []
        for j, loc in origin:
            p = parts[j]
            field = p.analysis.hints(loc).field
            ab = about(p.traj, task.robot, loc.t_rational, field, s.t)
            which = 0
            if s.knot and len(task.motion) > 1:
                which = 1 if ab.h_min == 0 else (-1 if ab.h_max == 0 else 0)
            ab_sides.append((ab, which))
        if not ab_sides:
            out.append(Robust((s.consistency_residual, s.consistency_residual), 0.0))
            continue
        pieces = [j for j, _ in origin]
        ts = [_absolute(parts[j], loc) for j, loc in origin]

        def onward(k: int, d: int, pieces: list[int] = pieces, ts: list[arb] = ts) -> Any:
            assert limits is not None
            return _onward(task, parts, pieces[k], d, ts[k], box, limits)

        out.append(analyse(ab_sides, box, limits, s, onward))
    return out


def _absolute(p: Any, loc: Any) -> arb:
    """The instant ``loc`` of the piece ``p`` in absolute time, a ball (exact when
    rational)."""
    old = ctx.prec
    ctx.prec = PREC + 64
    try:
        if loc.t_rational is not None:
            return arb(p.origin + loc.t_rational)
        field = p.analysis.hints(loc).field
        return arb(p.origin) + field.evaluate(fmpq_poly([0, 1]), PREC + 64)
    finally:
        ctx.prec = old


def _onward(task: Task, parts: Sequence[Any], j: int, d: int, ts: arb, box: Box,
            limits: tuple[float, float]) -> tuple[float, float, int]:  # fmt: skip
    """The window past the end (``d``) of piece ``j``: the pieces beyond, one after
    another, until one proves the end (``beyond``); (a proven upper bound of its distance
    from t_s [s], a lower bound of the distance at which the limit is proven exceeded (0
    when not shown), the joint). At the motion's end: that end's distance."""
    k = j + d
    knot = parts[j].end if d > 0 else parts[j].start
    joint = 0
    while 0 <= k < len(parts):
        p = parts[k]
        u = p.start - p.origin if d > 0 else p.end - p.origin  # the knot, local
        knot = p.start if d > 0 else p.end
        ab = about_knot(p.traj, task.robot, u, to_float(knot))
        got = beyond(ab, box, limits, d)
        if got is not None:
            h, inner, joint = got
            near = round_down(abs(arb(knot) + d * arb(inner) - ts)) if inner > 0 else 0.0
            return round_up(abs(arb(knot) + d * arb(h) - ts)), near, joint
        knot = p.end if d > 0 else p.start
        k += d
    return round_up(abs(arb(knot) - ts)), 0.0, joint

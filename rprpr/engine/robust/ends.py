"""Robust verdicts: the saturation window's ends on each side of t_s (``docs/robust.md``),
found on the doubles of ``robust.windows`` (a scan outward from t_s, then the regula
falsi in 1/h) and proven in ball arithmetic (``robust.proofs``)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .proofs import CLEAR, below, prove_in, quick_verdicts
from .windows import About, Box, ball_box, float_box, phi_float

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
    plan = {}
    for d, bs in brackets.items():
        j = 0 if bs[0][1] >= bs[1][1] else 1
        reach = next(r for dd, r, _ in live if dd == d)
        # (a bracket narrower than the doubles' error at its ends: from a little inside)
        plan[d] = (j, reach, min(bs[j][0], bs[j][1] * (1 - 2e-12)))
    # the first candidates of both ends of every side, proven at once where the balls in
    # double precision decide (``quick_verdicts``); the others in arb, one by one
    firsts: list[tuple[float, int | None]] = [
        (d * brackets[d][j][1], None) for d, (j, reach, _) in plan.items()
    ]
    firsts += [(d * near, j) for d, (j, _, near) in plan.items()]
    quick = quick_verdicts(ab, box, limits, [h for h, _ in firsts], [j for _, j in firsts])
    for k, (d, (j, reach, near)) in enumerate(plan.items()):
        bs = brackets[d]
        # the window cannot reach past the first candidate at which it is proven to end
        # (at the bracket's far end itself, the quick attempt only where the doubles put
        # the largest |T_j| there clear of the limit: else it is often just over it)
        clear = bs[j][3] < -CLEAR * limits[j]
        outer = next((h for i, h in enumerate(_outward(bs[j][1], reach))
                      if (i == 0 and quick[k])
                      or below(ab, box, bbox, limits, d * h, quick=i > 0 or clear)),
                     reach)  # fmt: skip
        inner = (near if near > 0 and quick[len(plan) + k] else
                 prove_in(ab, box, bbox, limits[j], j, d, near,
                          near == bs[j][0] and bs[j][2] > CLEAR * limits[j]))  # fmt: skip
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


def _outward(h: float, reach: float) -> list[float]:
    """The candidates for a proven outer end from h: h, h (1 + 1e-12), h (1 + 1e-12)
    (1 + 1e-10), ..., each below ``reach`` (the window cannot reach past the first at
    which both max |T_j| <= their limits are proven; ``reach`` when none is)."""
    out, step = [], 1e-12
    while h < reach:
        out.append(h)
        h, step = min(h * (1 + step), reach), step * 100
    return out


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

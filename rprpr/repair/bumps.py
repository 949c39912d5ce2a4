"""The changes themselves: local bumps and blends, exact polynomials in rational windows.

At a first-order crossing (ẏ(t_s) != 0) eq. (34) is the only condition for bounded
torques (one condition for order 1). So a failing instant is repaired by local bumps of
half-width w about t_s, u = (t - t_s)/w, W = (1 - u²)³ on |u| <= 1 (zero outside; W and
its first two derivatives vanish at u = ±1, so the motion stays C2 and its torques
continuous):

* timing, Δx = (t - t_s)(b1 + a (t - t_s)) W: keeps x(t_s), changes ẋ(t_s) by b1 (a zero
  speed made nonzero) and ẍ(t_s) by 2a (to the consistent value);
* path, Δy = b (t - t_s) W: keeps the crossing point, changes ẏ(t_s) by b (a zero slope
  made b/ẋ); a touch (even order) is lifted clear of AB instead, Δy = h W.

A knot where the velocity or the acceleration jumps (RPR203, RPR204: impulsive or
jumping torques) is smoothed by blending the two pieces over [t_k - w, t_k + w]:
x_B = x_L + (x_R - x_L) S(σ), σ = (t - t_k + w)/(2w), S = 10σ³ - 15σ⁴ + 6σ⁵ (the
quintic smoothstep: S and its first two derivatives are 0 at σ = 0 and match 1, 0, 0 at
σ = 1), so x_B continues x_L and x_R with two derivatives at the window's ends; y alike
(or y = p(x_B) when the task gives its path). At a C1 knot x_R - x_L = O((t - t_k)²),
so the change is of order Δẍ w².
"""

from __future__ import annotations

import itertools
from dataclasses import replace
from typing import TYPE_CHECKING

from flint import fmpq, fmpq_poly

from ..engine.roots import isolate
from ..model.task import Piece, Task

if TYPE_CHECKING:
    from .plan import Plan


def bump(t_s: fmpq, w: fmpq) -> fmpq_poly:
    """W(t) = (1 - ((t - t_s)/w)²)³, the window of every local change."""
    u = fmpq_poly([-t_s / w, 1 / w])
    return (1 - u * u) ** 3


def smoothstep(lo: fmpq, hi: fmpq) -> fmpq_poly:
    """S(σ) = 10σ³ - 15σ⁴ + 6σ⁵, σ = (t - lo)/(hi - lo): 0 at lo and 1 at hi, with zero
    first and second derivatives at both."""
    sig = fmpq_poly([-lo / (hi - lo), 1 / (hi - lo)])
    return sig**3 * (10 - 15 * sig + 6 * sig * sig)


def blended(task: Task, widths: dict[int, fmpq]) -> Task | None:
    """The task with the pieces blended at the knots after pieces ``widths`` (index ->
    half-width); None when a blend makes x non-monotone where the path is kept."""
    out: list[Piece] = []
    motion = task.motion
    for j, p in enumerate(motion):
        start = p.start + widths.get(j - 1, fmpq(0))
        end = p.end - widths.get(j, fmpq(0))
        out.append(replace(p, start=start, end=end, line=0, file=""))
        if j in widths:
            r, w = motion[j + 1], widths[j]
            lo, hi = p.end - w, p.end + w
            S = smoothstep(lo, hi)
            x = p.x + (r.x - p.x) * S
            if task.path is not None and p.path is not None:
                if not monotone(x, lo, hi):
                    return None
                y = task.path(x)
            else:
                y = p.y + (r.y - p.y) * S
            out.append(Piece(lo, hi, x, y, p.path))
    name = renamed(task.name)
    if task.path is not None and all(q.path is not None for q in out):
        return replace(task, name=name, x_of_t=None, pieces=tuple(out), law="pieces", lines={})
    pieces = tuple(replace(q, path=None) for q in out)
    return replace(task, name=name, path=None, x_of_t=None, pieces=pieces, law="motion", lines={})


def apply(task: Task, plans: list[Plan]) -> Task | None:
    """The task with every plan's bumps; None when a timing change makes x non-monotone."""
    pieces = list(task.motion)
    path = task.path
    path_changed = any(p.b != 0 or p.h != 0 or p.ay != 0 for p in plans)
    out: list[Piece] = []
    for piece in pieces:
        cuts = sorted(
            {piece.start, piece.end}
            | {e for p in plans for e in (p.t - p.w, p.t + p.w) if piece.start < e < piece.end}
        )
        for lo, hi in itertools.pairwise(cuts):
            x, dy = piece.x, fmpq_poly([0])
            for p in plans:
                if p.t - p.w <= lo and hi <= p.t + p.w:
                    tau, W = fmpq_poly([-p.t, 1]), bump(p.t, p.w)
                    x = x + (tau * (p.b1 + p.a * tau) + p.x0) * W
                    dy = dy + (p.b * tau + p.h + p.ay * tau * tau) * W
                    if x != piece.x and not monotone(x, lo, hi):
                        return None
            y = (path(x) if path is not None else piece.y) + dy
            keep_path = path is not None and not path_changed
            out.append(Piece(lo, hi, x, y, path if keep_path else None))
    if path is not None and not path_changed:
        return replace(task, name=renamed(task.name), x_of_t=None, pieces=tuple(out),
                       law="pieces", lines={})  # fmt: skip
    return replace(task, name=renamed(task.name), path=None, x_of_t=None, pieces=tuple(out),
                   law="motion", lines={})  # fmt: skip


def renamed(name: str) -> str:
    """The repaired task's name: the old one marked, so that reports and overlays tell
    the two apart."""
    return name if name.endswith(" (repaired)") else f"{name} (repaired)"


def monotone(x: fmpq_poly, lo: fmpq, hi: fmpq) -> bool:
    """ẋ keeps one sign on (lo, hi) (exactly: no root of odd multiplicity inside)."""
    d = x.derivative()
    if d == 0:
        return False
    mid = (lo + hi) / 2
    for f, e in d.factor()[1]:
        if e % 2 == 0:
            continue
        if f.degree() == 1:
            r = -f[0] / f[1]
            if lo < r < hi:
                return False
            continue
        g = f(fmpq_poly([lo, 1]))
        if isolate(g, hi - lo):
            return False
    return bool(d(mid) != 0) or _monotone_far(d, lo, hi)


def _monotone_far(d: fmpq_poly, lo: fmpq, hi: fmpq) -> bool:
    return any(d(lo + (hi - lo) * fmpq(k, 7)) != 0 for k in range(1, 7))

"""The certified layers of a 5R motion of several pieces (pure): each piece on its closed
span [start, end] in its local time u = t - start (its ``local`` polynomials where given,
else x, y composed with t = start + u, exactly), with its own one-sided Type II instants
(those its exact analysis found: an instant at a knot is given to the piece on each side
of it), then joined as the RPRPR's pieces are (``pieces``):

* **peak**: max |T_i| over the pieces (its time back in absolute time, ``pieces.shift``;
  infinite at the first pole; certified when every piece's is);
* **limit**: failed if one piece fails, undecided if one is; each piece's windows in
  absolute time (outward), a window that runs to a knot joined with the next piece's that
  starts there (``pieces.limits``);
* **samples**: each time from the piece holding it (the later one exactly at a knot,
  ``pieces.which``), the motors' angles moved by 2πk per piece so that they are continuous
  across every knot (the multiple of 2π nearest the jump between doubles just before and
  just after it, as the RPRPR's ``pieces.theta_offsets``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from functools import cached_property

import numpy as np
from flint import arb, ctx, fmpq, fmpq_poly

from ..model.numbers import to_float
from ..model.task import Piece, Robot
from .bounds.verdicts import LimitCheck, Peak
from .certified.five_bar import FiveBarMotion
from .certified.five_bar_samples import FIELDS, FiveBarSamples, at_time
from .exact.five_bar_instants import FiveBarAnalysis, FiveBarInstant
from .five_bar_certified import limit_check, torque_peak
from .pieces import limits, peaks, which
from .pieces import theta_offsets as shared_offsets


def local(s: FiveBarInstant, origin: fmpq) -> FiveBarInstant:
    """The instant ``s`` (absolute time) in the local time of a piece starting at ``origin``."""
    if origin == 0:
        return s
    with ctx.workprec(128):
        if s.t_exact is not None:
            u = s.t_exact - origin
            return replace(s, t=to_float(u), t_exact=u, t_ball=arb(u))
        ball = s.t_ball - arb(origin)
        return replace(s, t=float(ball.mid()), t_ball=ball)


class FiveBarPart:
    """One piece [start, end] (absolute, exact) of a 5R motion in its local time, with the
    Type II instants of its own analysis; its certified motion is made when first read."""

    def __init__(self, piece: Piece, robot: Robot, analysis: FiveBarAnalysis) -> None:
        self.piece = piece
        self.robot = robot
        self.analysis = analysis
        self.start: fmpq = piece.start
        self.end: fmpq = piece.end
        self.origin: fmpq = piece.start
        self.theta_offset: tuple[float, float] = (0.0, 0.0)  # 2πk per leg

    @cached_property
    def motion(self) -> FiveBarMotion:
        p = self.piece
        if p.local is not None:
            x, y = p.local
        else:
            t = fmpq_poly([p.start, 1])  # t = start + u
            x, y = p.x(t), p.y(t)
        r = self.robot
        instants = [local(s, self.origin) for s in self.analysis.instants]
        return FiveBarMotion(
            r.five_bar, r.gravity, x, y, self.end - self.start, instants, start=self.origin
        )

    @cached_property
    def crossings(self) -> tuple[list, list]:  # type: ignore[type-arg]
        from .certified.five_bar_angles import crossings

        return crossings(self.motion, 1), crossings(self.motion, 2)


def five_bar_parts(
    pieces: Sequence[Piece], robot: Robot, analyses: Sequence[FiveBarAnalysis]
) -> list[FiveBarPart]:
    return [FiveBarPart(p, robot, a) for p, a in zip(pieces, analyses, strict=True)]


def torque_peak_pieces(parts: Sequence[FiveBarPart]) -> tuple[Peak, Peak]:
    """max |T1|, max |T2| over every piece (module docstring)."""
    got: list[tuple[Peak, Peak] | None] = [torque_peak(p.motion) for p in parts]
    out = peaks([p.origin for p in parts], got)
    assert out is not None
    return out


def limit_check_pieces(
    parts: Sequence[FiveBarPart], limit: tuple[float, float], peak: tuple[Peak, Peak] | None
) -> tuple[LimitCheck, LimitCheck]:
    """The limit check of every piece, joined (module docstring); a certified peak of the
    whole motion below a limit decides it on every piece."""
    got = [limit_check(p.motion, limit, peak) for p in parts]
    return limits(list(parts), got)  # type: ignore[arg-type]


def _theta(p: FiveBarPart, t: float) -> tuple[float, float]:
    v, _ = at_time(p.motion, t, p.crossings)
    return v["theta1"], v["theta2"]


def theta_offsets(parts: Sequence[FiveBarPart]) -> None:
    """Each piece's 2πk per leg, so that θ is continuous across every knot (the RPRPR's
    ``pieces.theta_offsets``, with the 5R's angles)."""
    shared_offsets(parts, _theta)


def sample_pieces(parts: Sequence[FiveBarPart], t: np.ndarray) -> FiveBarSamples:
    """Certified samples at the absolute times ``t``, each from the piece holding it."""
    t = np.asarray(t, dtype=float)
    out = {n: np.full(len(t), math.nan) for n in FIELDS}
    reason = np.zeros(len(t), dtype=int)
    idx = which(list(parts), t)  # type: ignore[arg-type]
    for j, tj in enumerate(t.tolist()):
        p = parts[int(idx[j])]
        values, code = at_time(p.motion, tj, p.crossings)
        for n, v in values.items():
            out[n][j] = v
        out["theta1"][j] += p.theta_offset[0]
        out["theta2"][j] += p.theta_offset[1]
        reason[j] = code
    return FiveBarSamples(t=t, reason=reason, **out)

"""What the torque verdicts are (pure): the certified peak, the limit check and its
windows, the closest approach; and the saturation windows read from a limit check.

The branch and bound that proves them is ``envelope``'s; these plain records are all the
findings and the report read, so a task that needs no pass (unbounded or unasked torques)
imports none of the ball machinery.
"""

from __future__ import annotations

from collections.abc import Iterable

from ...model.dataclass import dataclass
from ..exact.singular import SingularInstant

CROSSING_REL = 1e-9  # limit crossings bracketed to this fraction of t_f


@dataclass(frozen=True)
class Peak:
    """sup |T_i| over the times of [0, t_f] where T_i is defined [N m]: ``value`` is a
    certified lower bound of it, attained at ``t`` or, when ``t`` is an instant at which
    E is at A or B (T undefined there), the one-sided limit of |T_i| as t is approached;
    ``upper`` a certified upper bound; when ``certified``, upper - value <= PEAK_REL value
    + PEAK_ABS.
    ``value`` = ``upper`` = inf when T_i is unbounded (``t``: the first instant with a
    pole)."""

    value: float
    t: float
    upper: float
    certified: bool


@dataclass(frozen=True)
class Window:
    """An interval in which |T_i| > limit: it starts in [start_lo, start_hi] and ends in
    [end_lo, end_hi] (crossings bracketed; ``pole``: contains an unbounded instant)."""

    start_lo: float
    start_hi: float
    end_lo: float
    end_hi: float
    pole: bool = False


@dataclass(frozen=True)
class LimitCheck:
    """|T_i(t)| <= limit for every t in [0, t_f]: ``passed`` True or False, certified, or
    None when undecided at the resolution (then max |T_i| is within ``resolution`` in
    time of touching the limit); ``windows``: where the limit is exceeded, in order."""

    limit: float
    passed: bool | None
    windows: tuple[Window, ...]
    resolution: float

    @property
    def first(self) -> Window | None:
        return self.windows[0] if self.windows else None


@dataclass(frozen=True)
class Approach:
    """Closest approach of a motion that never meets y = 0: min |y| (the distance of E to
    the line AB) [m] at ``t_y``; min |δ| within [delta_lo, delta_hi] at ``t_delta``."""

    distance: float
    t_y: float
    delta_lo: float
    delta_hi: float
    t_delta: float


def around_poles(
    instants: Iterable[SingularInstant], checks: tuple[LimitCheck, LimitCheck]
) -> list[tuple[SingularInstant, Window | None, Window | None]]:
    """For each unbounded instant of ``instants``, the windows of the limit checks in
    which |T1|, |T2| exceed their limits around it (None where a limit is not exceeded
    there)."""
    out = []
    for s in instants:
        if s.torque_bounded:
            continue
        pair = []
        for c in checks:
            w = [w for w in c.windows if w.pole and w.start_lo <= s.t <= w.end_hi]
            pair.append(w[0] if w else None)
        out.append((s, pair[0], pair[1]))
    return out

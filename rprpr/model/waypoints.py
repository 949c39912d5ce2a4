"""Waypoints to pieces, exactly as ros2_controllers' joint_trajectory_controller
interpolates between consecutive points (``Trajectory::interpolate_between_points``):
linear when the points give positions only (C0), the cubic Hermite segment when they give
positions and velocities (C1), the quintic Hermite segment when they give positions,
velocities and accelerations (C2).

Each coordinate of a segment from (t0, p0, v0, a0) to (t1, p1, v1, a1), T = t1 - t0, is
the controller's polynomial in the local time u = t - t0 (its formulas, exact over the
rationals), composed with u = t - t0 into a polynomial in absolute time t; each piece
keeps the controller's polynomials too (``Piece.local``).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise

from flint import fmpq, fmpq_poly

from .task import Piece


@dataclass(frozen=True)
class Waypoint:
    """A planner's point: time t [s], position p = (x, y) [m], and optionally velocity v
    [m/s] and acceleration a [m/s^2]; every point of a motion gives the same fields."""

    t: fmpq
    p: tuple[fmpq, fmpq]
    v: tuple[fmpq, fmpq] | None = None
    a: tuple[fmpq, fmpq] | None = None
    line: int = 0


def segment(
    T: fmpq,
    p0: fmpq,
    p1: fmpq,
    v0: fmpq | None = None,
    v1: fmpq | None = None,
    a0: fmpq | None = None,
    a1: fmpq | None = None,
) -> list[fmpq]:
    """The controller's coefficients c0, c1, ... (ascending powers of u = t - t0) of one
    coordinate on a segment of length T."""
    if v0 is None or v1 is None:
        return [p0, (p1 - p0) / T]
    if a0 is None or a1 is None:
        return [
            p0,
            v0,
            (-3 * p0 + 3 * p1 - 2 * v0 * T - v1 * T) / T**2,
            (2 * p0 - 2 * p1 + v0 * T + v1 * T) / T**3,
        ]
    T2 = T * T
    d, A, B, C, D = p1 - p0, v0 * T, v1 * T, a0 * T2, a1 * T2
    h3 = 1 / (2 * T2 * T)
    h4 = h3 / T
    return [
        p0,
        v0,
        a0 / 2,
        (20 * d - 12 * A - 8 * B - 3 * C + D) * h3,
        (-30 * d + 16 * A + 14 * B + 3 * C - 2 * D) * h4,
        (12 * d - 6 * A - 6 * B - C + D) * (h4 / T),
    ]


def interpolate(points: list[Waypoint]) -> list[tuple[fmpq, fmpq, fmpq_poly, fmpq_poly, int]]:
    """Consecutive pieces (start, end, x(t), y(t), line of the end point) through
    ``points`` (at least two, strictly increasing t), polynomials in absolute time t."""
    return [(p.start, p.end, p.x, p.y, p.line) for p in pieces(points)]


def pieces(points: list[Waypoint], file: str = "") -> list[Piece]:
    """The pieces through ``points`` (at least two, strictly increasing t): x(t), y(t) in
    absolute time, and the controller's polynomials in u = t - t0 as their ``local``
    form; ``line`` the end point's, ``file`` the CSV's name (or "")."""
    out = []
    for w0, w1 in pairwise(points):
        T = w1.t - w0.t
        shift = fmpq_poly([-w0.t, 1])  # u = t - t0
        local = []
        for i in (0, 1):
            v0, v1 = (w0.v[i], w1.v[i]) if w0.v and w1.v else (None, None)
            a0, a1 = (w0.a[i], w1.a[i]) if w0.a and w1.a else (None, None)
            local.append(fmpq_poly(segment(T, w0.p[i], w1.p[i], v0, v1, a0, a1)))
        x, y = local[0](shift), local[1](shift)
        out.append(Piece(w0.t, w1.t, x, y, None, w1.line, file, (local[0], local[1])))
    return out

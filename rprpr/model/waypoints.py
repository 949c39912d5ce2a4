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

import math
from dataclasses import dataclass

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


def _ratio(q: fmpq) -> tuple[int, int]:
    return int(q.p), int(q.q)


def _ratios(w: Waypoint) -> tuple[tuple[int, int], list[tuple[int, int]]]:
    """t and p (then v, then a, where given) of ``w`` as (numerator, denominator)."""
    values = [_ratio(w.p[0]), _ratio(w.p[1])]
    if w.v is not None:
        values += [_ratio(w.v[0]), _ratio(w.v[1])]
        if w.a is not None:
            values += [_ratio(w.a[0]), _ratio(w.a[1])]
    return _ratio(w.t), values


def _difference(b: tuple[int, int], a: tuple[int, int]) -> tuple[int, int]:
    """b - a for (numerator, denominator) pairs, in lowest terms: a segment's T, the
    shortest integers its powers are formed on."""
    d = math.lcm(a[1], b[1])
    n = b[0] * (d // b[1]) - a[0] * (d // a[1])
    g = math.gcd(n, d)
    return n // g, d // g


def _coefficients(T: tuple[int, int], ends: list[tuple[int, int]]) -> fmpq_poly:
    """``segment``'s polynomial on integers: T = Tn/Td > 0 and the ends (p0, p1[, v0, v1[,
    a0, a1]]) as (numerator, denominator) pairs, put over their least common denominator
    D (one power of ten for a planner's decimals); every coefficient is then formed over
    one common denominator and the polynomial made once (flint reduces it): the same
    rationals as ``segment``'s, without a rational operation per term."""
    Tn, Td = T
    D = math.lcm(*(q for _, q in ends))
    P0, P1, *rest = (n * (D // q) for n, q in ends)
    if not rest:  # c1 = (p1 - p0) / T
        return fmpq_poly([P0 * Tn, (P1 - P0) * Td], D * Tn)
    d = (P1 - P0) * Td  # d, A = v0 T, B = v1 T over D Td (cubic), D Td^2 (quintic)
    V0, V1, *acc = rest
    if not acc:  # over D Tn^3: c2 = (3d - 2A - B) / T^2, c3 = (-2d + A + B) / T^3
        A, B, T3 = V0 * Tn, V1 * Tn, Tn**3
        return fmpq_poly(
            [P0 * T3, V0 * T3, (3 * d - 2 * A - B) * Td * Tn, (A + B - 2 * d) * Td * Td],
            D * T3,
        )
    A0, A1 = acc
    d *= Td
    A, B = V0 * Tn * Td, V1 * Tn * Td
    C, E = A0 * Tn * Tn, A1 * Tn * Tn  # a0 T^2, a1 T^2
    T5 = Tn**5
    return fmpq_poly(
        [
            2 * P0 * T5,
            2 * V0 * T5,
            A0 * T5,
            (20 * d - 12 * A - 8 * B - 3 * C + E) * Td * Tn * Tn,
            (-30 * d + 16 * A + 14 * B + 3 * C - 2 * E) * Td * Td * Tn,
            (12 * d - 6 * A - 6 * B - C + E) * Td * Td * Td,
        ],
        2 * D * T5,
    )


def pieces(points: list[Waypoint], file: str = "") -> list[Piece]:
    """The pieces through ``points`` (at least two, strictly increasing t): the
    controller's polynomials in u = t - t0 as their ``local`` form (``segment``'s, made on
    integers: ``_coefficients``), x(t), y(t) in absolute time made from them when read;
    ``line`` the end point's, ``file`` the CSV's name (or ""); ``smooth`` the derivatives
    each segment continues from the one before by construction (it ends at its
    waypoint's p, v, a exactly, where the next one starts)."""
    out: list[Piece] = []
    prev = 0
    w0, (t0, r0) = points[0], _ratios(points[0])
    for w1 in points[1:]:  # each point's integers made once, held while its segments are
        t1, r1 = _ratios(w1)
        T = _difference(t1, t0)
        fields = min(len(r0), len(r1)) // 2  # 1: p; 2: p, v; 3: p, v, a
        x, y = (
            _coefficients(T, [r for k in range(0, 2 * fields, 2) for r in (r0[k + i], r1[k + i])])
            for i in (0, 1)
        )
        # derivatives 1 .. smooth of both segments meet w0's v, a at the knot t0
        smooth = max(min(prev, fields) - 1, 0) if out else 0
        out.append(Piece(w0.t, w1.t, None, None, None, w1.line, file, (x, y), smooth=smooth))
        prev = fields
        w0, t0, r0 = w1, t1, r1
    return out

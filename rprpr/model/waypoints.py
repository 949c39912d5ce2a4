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
from dataclasses import field
from typing import Any, overload

from flint import fmpq, fmpq_poly

from .dataclass import dataclass
from .task import Piece


class _Unread:
    """A pair of a row (``Waypoint.row``) not yet made from its numbers (one object,
    itself again when unpickled)."""

    def __reduce__(self) -> str:
        return "_UNREAD"


_UNREAD = _Unread()


class _Pair:
    """``Waypoint.p``, ``.v`` or ``.a``: the pair given, or, for a reader's row
    (``Waypoint.row``), the exact rationals made from its ``numbers`` when first read."""

    def __init__(self, index: int) -> None:
        self.index = index  # 0: p, 1: v, 2: a

    def __set_name__(self, owner: type, name: str) -> None:
        self.name, self.slot = name, "_" + name

    def value(self, obj: Waypoint) -> tuple[fmpq, fmpq] | None:
        got = getattr(obj, self.slot)
        if got is _UNREAD:
            n, k = obj.numbers, 3 + 2 * self.index
            assert n is not None
            got = (fmpq(n[k], n[2]), fmpq(n[k + 1], n[2])) if len(n) > k else None
            object.__setattr__(obj, self.slot, got)
        return got

    def __set__(self, obj: Waypoint, value: tuple[fmpq, fmpq] | None) -> None:
        object.__setattr__(obj, self.slot, None if isinstance(value, _Pair) else value)


class _Position(_Pair):
    @overload
    def __get__(self, obj: None, owner: Any = None) -> _Position: ...
    @overload
    def __get__(self, obj: Waypoint, owner: Any = None) -> tuple[fmpq, fmpq]: ...
    def __get__(self, obj: Waypoint | None, owner: Any = None) -> Any:
        if obj is None:
            raise AttributeError(self.name)  # no default: the field is required
        return self.value(obj)


class _Optional(_Pair):
    @overload
    def __get__(self, obj: None, owner: Any = None) -> None: ...
    @overload
    def __get__(self, obj: Waypoint, owner: Any = None) -> tuple[fmpq, fmpq] | None: ...
    def __get__(self, obj: Waypoint | None, owner: Any = None) -> Any:
        return None if obj is None else self.value(obj)


@dataclass(frozen=True)
class Waypoint:
    """A planner's point: time t [s], position p = (x, y) [m], and optionally velocity v
    [m/s] and acceleration a [m/s^2]; every point of a motion gives the same fields.

    ``numbers``, when given, are the same numbers on integers: (tn, td, D, x, y[, vx,
    vy[, ax, ay]]), t = tn/td and the others over their common denominator D (any, not
    only lowest terms); a reader that has them hands them on (``row``), and the
    interpolation reads them instead of the rationals."""

    t: fmpq
    p: _Position = _Position(0)
    v: _Optional = _Optional(1)
    a: _Optional = _Optional(2)
    line: int = 0
    numbers: tuple[int, ...] | None = field(default=None, compare=False, repr=False)

    @classmethod
    def row(cls, t: fmpq, numbers: tuple[int, ...], line: int) -> Waypoint:
        """A reader's point from its ``numbers`` alone (and t, as a rational): p, v and a
        are made from them where read."""
        w = object.__new__(cls)
        for name, value in (("t", t), ("_p", _UNREAD), ("_v", _UNREAD), ("_a", _UNREAD),
                            ("line", line), ("numbers", numbers)):  # fmt: skip
            object.__setattr__(w, name, value)  # no __dict__ made: one object a point
        return w

    @property
    def given(self) -> str:
        """What the point gives: "p", "p, v" or "p, v, a" (without making them)."""
        if self.numbers is not None:
            return ("p", "p, v", "p, v, a")[(len(self.numbers) - 5) // 2]
        return ", ".join(k for k, v in (("p", 1), ("v", self.v), ("a", self.a)) if v is not None)


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


def _ratios(w: Waypoint) -> tuple[tuple[int, int], tuple[int, ...]]:
    """t of ``w`` as (numerator, denominator), and (D, x, y[, vx, vy[, ax, ay]]): its
    other numbers over their common denominator D (``Waypoint.numbers``, made from the
    rationals where the point has none)."""
    n = w.numbers
    if n is not None:
        return (n[0], n[1]), n[2:]
    values = [*w.p, *(w.v or ()), *(w.a or ())] if w.v is not None else [*w.p]
    pairs = [(int(q.p), int(q.q)) for q in values]
    D = math.lcm(*(d for _, d in pairs))
    return (int(w.t.p), int(w.t.q)), (D, *(k * (D // d) for k, d in pairs))


def _difference(b: tuple[int, int], a: tuple[int, int]) -> tuple[int, int]:
    """b - a for (numerator, denominator) pairs, in lowest terms: a segment's T, the
    shortest integers its powers are formed on."""
    if a[1] == b[1]:  # a planner's times: one power of ten, most often
        n, d = b[0] - a[0], a[1]
    else:
        d = math.lcm(a[1], b[1])
        n = b[0] * (d // b[1]) - a[0] * (d // a[1])
    g = math.gcd(n, d)
    return n // g, d // g


class Segment:
    """One segment of the controller's interpolation held on integers (a
    ``task.LocalForm``): its length ``T`` = (Tn, Td) in lowest terms, and its end
    points' numbers ``r0``, ``r1`` (D, x, y, ...: ``_ratios``, shared with the segments
    before and after), of which the first ``fields`` (1: p; 2: p, v; 3: p, v, a) are
    interpolated. Its polynomials (``polys``) are made where read; what reads all the
    segments of a long motion (``bounds.batch``) takes their ``integers`` instead."""

    __slots__ = ("T", "fields", "r0", "r1")

    def __init__(
        self, T: tuple[int, int], r0: tuple[int, ...], r1: tuple[int, ...], fields: int
    ) -> None:
        self.T, self.r0, self.r1, self.fields = T, r0, r1, fields

    def __reduce__(self) -> tuple[type, tuple[Any, ...]]:
        return Segment, (self.T, self.r0, self.r1, self.fields)

    def polys(self) -> tuple[fmpq_poly, fmpq_poly]:
        """x(u) and y(u), exactly: ``segment``'s polynomials."""
        return fmpq_poly(*self.integers(0)), fmpq_poly(*self.integers(1))

    def integers(self, i: int) -> tuple[list[int], int]:
        """``segment``'s polynomial of coordinate i (0: x, 1: y) in u = t - t0 on
        integers: the numerators of its ascending powers and their one denominator (not
        in lowest terms). The ends' numbers are put over one denominator D (one power of
        ten for a planner's decimals), the coefficients formed over 2 D Tn^5 (quintic),
        D Tn^3 (cubic) or D Tn (linear): the same rationals as ``segment``'s, without a
        rational operation per term."""
        (Tn, Td), r0, r1, fields = self.T, self.r0, self.r1, self.fields
        D = r0[0]
        P0, P1 = r0[1 + i], r1[1 + i]
        if fields > 1:
            V0, V1 = r0[3 + i], r1[3 + i]
        if fields > 2:
            A0, A1 = r0[5 + i], r1[5 + i]
        if r1[0] != D:
            D = math.lcm(D, r1[0])
            s0, s1 = D // r0[0], D // r1[0]
            P0, P1 = P0 * s0, P1 * s1
            if fields > 1:
                V0, V1 = V0 * s0, V1 * s1
            if fields > 2:
                A0, A1 = A0 * s0, A1 * s1
        if fields == 1:  # c1 = (p1 - p0) / T
            return [P0 * Tn, (P1 - P0) * Td], D * Tn
        if fields == 2:  # over D Tn^3: c2 = (3d - 2A - B) / T^2, c3 = (-2d + A + B) / T^3
            T3, d = Tn * Tn * Tn, (P1 - P0) * Td  # d, A = v0 T, B = v1 T over D Td
            A, B = V0 * Tn, V1 * Tn
            return [
                P0 * T3, V0 * T3, (3 * d - 2 * A - B) * Td * Tn, (A + B - 2 * d) * Td * Td
            ], D * T3  # fmt: skip
        # over 2 D Tn^5: d = p1 - p0, A = v0 T, B = v1 T, C = a0 T^2, E = a1 T^2 over D Td^2
        Tn2, Td2, TnTd = Tn * Tn, Td * Td, Tn * Td
        T5 = Tn2 * Tn2 * Tn
        d = (P1 - P0) * Td2
        A, B, C, E = V0 * TnTd, V1 * TnTd, A0 * Tn2, A1 * Tn2
        return [
            2 * P0 * T5,
            2 * V0 * T5,
            A0 * T5,
            (20 * d - 12 * A - 8 * B - 3 * C + E) * Td * Tn2,  # c3 = (...) / (2 T^3)
            (-30 * d + 16 * A + 14 * B + 3 * C - 2 * E) * Td2 * Tn,  # c4 = (...) / (2 T^4)
            (12 * d - 6 * A - 6 * B - C + E) * Td2 * Td,  # c5 = (...) / (2 T^5)
        ], 2 * D * T5


def pieces(points: list[Waypoint], file: str = "") -> list[Piece]:
    """The pieces through ``points`` (at least two, strictly increasing t): the
    controller's polynomials in u = t - t0 as their ``local`` form (``segment``'s, held
    on integers until read: ``Segment``), x(t), y(t) in absolute time made from them
    when read; ``line`` the end point's, ``file`` the CSV's name (or ""); ``smooth`` the
    derivatives each segment continues from the one before by construction (it ends at
    its waypoint's p, v, a exactly, where the next one starts)."""
    out: list[Piece] = []
    prev = 0
    w0, (t0, r0) = points[0], _ratios(points[0])
    for w1 in points[1:]:  # each point's integers made once, shared by its two segments
        t1, r1 = _ratios(w1)
        fields = (min(len(r0), len(r1)) - 1) // 2  # 1: p; 2: p, v; 3: p, v, a
        # derivatives 1 .. smooth of both segments meet w0's v, a at the knot t0
        smooth = max(min(prev, fields) - 1, 0) if out else 0
        form = Segment(_difference(t1, t0), r0, r1, fields)
        out.append(Piece(w0.t, w1.t, None, None, None, w1.line, file, form, smooth=smooth))
        prev = fields
        w0, t0, r0 = w1, t1, r1
    return out

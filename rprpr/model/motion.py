"""A piecewise-polynomial motion of the end point built from arrays: a planner's output
(scipy's ``PPoly``/``CubicSpline``, TOPP-RA, Ruckig) in one line, exactly.

The layout is scipy's ``PPoly``: ``breaks`` (m + 1 increasing times, from 0) and, per
coordinate, coefficients ``c[j][i]`` of the power k - 1 - j (highest power first) on the
interval i, in the local variable t - breaks[i] (``local=False``: in absolute time t).
Any nested sequences work (lists, numpy arrays); scipy is not needed. Every number is
taken exactly: a float (or a numpy float) as the binary value it is,
``fmpq(*f.as_integer_ratio())``, so 0.1 is 3602879701896397/36028797018963968, not 1/10.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import field, replace
from fractions import Fraction
from typing import Any

from flint import fmpq, fmpq_poly

from .dataclass import dataclass
from .task import Piece, Task
from .waypoints import Segment, Waypoint
from .waypoints import pieces as waypoint_pieces


def exact(value: Any) -> fmpq:
    """``value`` as an exact rational: an integer, a Fraction, an fmpq, or a float-like
    number (float, numpy float, Decimal) as the binary (or decimal) value it is. Raises
    ValueError for NaN and infinities, TypeError for anything else (text, booleans)."""
    if isinstance(value, fmpq):
        return value
    if isinstance(value, (bool, str | bytes)):
        raise TypeError(f"expected a number, found {value!r}")
    if isinstance(value, Fraction):
        return fmpq(value.numerator, value.denominator)
    if hasattr(value, "__index__"):  # int, numpy integers, fmpz
        return fmpq(int(value.__index__()))
    ratio = getattr(value, "as_integer_ratio", None)
    if ratio is None:
        raise TypeError(f"expected a number, found {type(value).__name__} {value!r}")
    try:
        n, d = ratio()
    except (ValueError, OverflowError):
        raise ValueError(f"expected a finite number, found {value!r}") from None
    return fmpq(int(n), int(d))


def position_jump(
    before: Sequence[fmpq_poly], after: Sequence[fmpq_poly], t: fmpq
) -> tuple[tuple[fmpq, ...], tuple[fmpq, ...]] | None:
    """The position at the knot ``t`` on each side, (before, after), when the pieces
    ``before`` and ``after`` (their coordinates) disagree there; None when continuous."""
    left = tuple(p(t) for p in before)
    right = tuple(p(t) for p in after)
    return None if left == right else (left, right)


@dataclass(frozen=True)
class Motion:
    """The end point's motion: consecutive pieces from t = 0 (``Piece``: x(t), y(t) in
    absolute time), position continuous at every knot (checked exactly).

    Build it with ``from_pieces`` (arrays in scipy's PPoly layout), ``from_ppoly`` (a
    scipy PPoly or CubicSpline of the 2-D position) or ``from_waypoints``; give it to a
    robot and its checks with ``with_motion(task, motion)``.
    """

    pieces: tuple[Piece, ...]
    tolerance: fmpq = field(default_factory=fmpq)  # 0: exactly continuous
    snapped: fmpq = field(default_factory=fmpq)  # the largest change made by closing jumps [m]

    def __post_init__(self) -> None:
        if not self.pieces:
            raise ValueError("a motion needs at least one piece")
        if self.pieces[0].start != 0:
            raise ValueError(f"a motion starts at t = 0, found t = {self.pieces[0].start}")
        for i, p in enumerate(self.pieces):
            if not p.start < p.end:
                raise ValueError(f"piece {i}: from t = {p.start} to {p.end}: not increasing")
        for i, (a, b) in enumerate(zip(self.pieces, self.pieces[1:], strict=False)):
            if a.end != b.start:
                raise ValueError(f"piece {i + 1} starts at t = {b.start}, not at {a.end}")
            if _shared_waypoint(a, b):
                continue
            jump = position_jump((a.x, a.y), (b.x, b.y), a.end)
            if jump is not None and max(abs(u - v) for u, v in zip(*jump, strict=True)) > (
                self.tolerance
            ):
                (x0, y0), (x1, y1) = jump
                raise ValueError(
                    f"the position jumps at the knot t = {a.end} (breaks[{i + 1}]):"
                    f" ({float(x0)}, {float(y0)}) before, ({float(x1)}, {float(y1)}) after;"
                    f" difference ({float(x1 - x0):.3g}, {float(y1 - y0):.3g})"
                )

    @property
    def duration(self) -> fmpq:
        """t_f [s]: the end of the last piece."""
        return self.pieces[-1].end

    @property
    def knots(self) -> tuple[fmpq, ...]:
        """The interior break times."""
        return tuple(p.end for p in self.pieces[:-1])

    @classmethod
    def from_pieces(
        cls,
        breaks: Sequence[Any],
        x_coeffs: Sequence[Sequence[Any]],
        y_coeffs: Sequence[Sequence[Any]],
        *,
        local: bool = True,
        tolerance: Any = 0,
    ) -> Motion:
        """The motion of scipy's PPoly layout: ``breaks[0] = 0 < breaks[1] < ...``, and
        ``x_coeffs[j][i]``, ``y_coeffs[j][i]`` the coefficients of the power k - 1 - j on
        the interval i (highest first), in t - breaks[i] (``local=False``: in t).

        Floats are taken as their exact binary value, so a float spline is continuous
        at its knots only to rounding (about 1e-16). Position must be continuous at every
        knot: a jump larger than ``tolerance`` [m] in x or y (default 0: exactly
        continuous) raises ValueError. A jump no larger than ``tolerance`` in position,
        velocity [m/s] or acceleration [m/s^2] is *closed*: the later piece gains the
        exact polynomial d0 + d1 u + d2 u^2 (u = t - knot) that makes it continue the
        one before, so a C2 spline audits as C2 and not as a chain of rounding jumps; a
        larger velocity or acceleration jump is kept (the audit reports it). ``snapped``
        bounds the largest change so made to x or y over any piece [m] (0: none).
        """
        ts = [exact(b) for b in breaks]
        m = len(ts) - 1
        xs, ys = _columns(x_coeffs, m, "x_coeffs"), _columns(y_coeffs, m, "y_coeffs")
        tol = exact(tolerance)
        pieces: list[Piece] = []
        change = fmpq(0)
        for i in range(m):
            shift = fmpq_poly([-ts[i], 1]) if local else fmpq_poly([0, 1])
            x, y = fmpq_poly(xs[i])(shift), fmpq_poly(ys[i])(shift)
            if pieces and tol > 0:
                before, span = pieces[-1], ts[i + 1] - ts[i]
                (x, dx), (y, dy) = (_closed(before.x, x, ts[i], span, tol),
                                    _closed(before.y, y, ts[i], span, tol))  # fmt: skip
                change = max(change, dx, dy)
            pieces.append(Piece(ts[i], ts[i + 1], x, y, None, i + 1))
        return cls(tuple(pieces), tol, change)

    @classmethod
    def from_ppoly(cls, ppoly: Any, *, tolerance: Any = 0) -> Motion:
        """The motion of a scipy ``PPoly`` (``CubicSpline``, ``Akima1DInterpolator``,
        ``make_interp_spline(...).to_ppoly()`` ...) of the 2-D position: ``ppoly.c`` of
        shape (k, m, 2), ``ppoly.x`` the breaks; see ``from_pieces``."""
        c = ppoly.c
        x = [[row[i][0] for i in range(len(row))] for row in c]
        y = [[row[i][1] for i in range(len(row))] for row in c]
        return cls.from_pieces(ppoly.x, x, y, tolerance=tolerance)

    @classmethod
    def from_waypoints(
        cls,
        t: Sequence[Any],
        p: Sequence[Sequence[Any]],
        v: Sequence[Sequence[Any]] | None = None,
        a: Sequence[Sequence[Any]] | None = None,
    ) -> Motion:
        """The motion through waypoints (times ``t`` from 0, positions ``p[i] = (x, y)``,
        optionally velocities ``v`` and accelerations ``a`` alike), interpolated as
        ros2_controllers' joint_trajectory_controller does: linear, cubic or quintic
        Hermite segments (``waypoints.pieces``)."""

        def pair(q: Sequence[Any]) -> tuple[fmpq, fmpq]:
            return exact(q[0]), exact(q[1])

        if len(t) < 2 or len(p) != len(t):
            raise ValueError(
                f"expected at least two waypoints, one position each: {len(t)} times,"
                f" {len(p)} positions"
            )
        if a is not None and v is None:
            raise ValueError("accelerations need velocities (p; p, v; or p, v, a)")
        points = [
            Waypoint(
                exact(t[i]),
                pair(p[i]),
                pair(v[i]) if v is not None else None,
                pair(a[i]) if a is not None and v is not None else None,
                line=i + 1,
            )
            for i in range(len(t))
        ]
        for i, (w0, w1) in enumerate(itertools.pairwise(points)):
            if not w0.t < w1.t:
                raise ValueError(f"waypoint {i + 1}: t = {w1.t} does not follow t = {w0.t}")
        pieces = tuple(waypoint_pieces(points))
        return cls(pieces)


def _shared_waypoint(a: Piece, b: Piece) -> bool:
    """Whether ``b`` is the waypoint segment that starts at the waypoint where the
    segment ``a`` ends (``waypoints.pieces``: both hold that waypoint's numbers): then
    the position is continuous there by construction (a segment ends at its end
    point's p exactly), without evaluating x(t), y(t) in absolute time."""
    fa, fb = a.form, b.form
    return isinstance(fa, Segment) and isinstance(fb, Segment) and fa.r1 is fb.r0


def _closed(
    before: fmpq_poly, after: fmpq_poly, t: fmpq, span: fmpq, tol: fmpq
) -> tuple[fmpq_poly, fmpq]:
    """``after`` continuing ``before`` at the knot ``t`` in value, first and second
    derivative wherever they differ by at most ``tol``: plus d0 + d1 u + d2 u^2/2
    (u = t - knot, exact), and a bound on that change over the piece's ``span``."""
    d = []
    a, b = before, after
    for _ in range(3):
        jump = a(t) - b(t)
        d.append(jump if abs(jump) <= tol else fmpq(0))
        a, b = a.derivative(), b.derivative()
    if not any(d):
        return after, fmpq(0)
    u = fmpq_poly([-t, 1])
    correction = fmpq_poly([d[0], d[1], d[2] / 2])
    bound = abs(d[0]) + abs(d[1]) * span + abs(d[2]) / 2 * span**2
    return after + correction(u), bound


def _columns(coeffs: Sequence[Sequence[Any]], m: int, name: str) -> list[list[fmpq]]:
    """Per interval i, the coefficients in ascending powers (fmpq_poly's order)."""
    k = len(coeffs)
    if k == 0 or any(len(row) != m for row in coeffs):
        shape = [len(row) for row in coeffs]
        raise ValueError(f"{name}: expected shape (k, {m}) for {m + 1} breaks, found rows {shape}")
    return [[exact(coeffs[j][i]) for j in reversed(range(k))] for i in range(m)]


def with_motion(task: Task, motion: Motion, *, name: str | None = None) -> Task:
    """``task``'s robot and checks with ``motion`` as its motion (law "motion"): the path
    and timing of ``task`` (and their lines in its file) are dropped."""
    own = ("path", "timing", "motion")
    return replace(
        task,
        name=task.name if name is None else name,
        path=None,
        x_of_t=None,
        duration=motion.duration,
        pieces=motion.pieces,
        law="motion",
        lines={k: v for k, v in task.lines.items() if k.split(".", 1)[0] not in own},
    )

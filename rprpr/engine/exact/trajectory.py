"""The planned motion as exact polynomials: x_E(t), y_E(t) and their derivatives, one
``Trajectory`` per piece of the motion (the timing laws themselves are ``model.timing``).

Each piece is audited in its own local time u = t - origin, the polynomials shifted
exactly. ``origin`` is the piece's start rounded down to a multiple of a power of two q
no smaller than the spacing of the doubles at the piece's end (the start itself when it
is such a dyadic number, 0 for the first piece): then u = t - origin is exact in double
arithmetic for every double t of the piece, so samples at absolute times are certified
at those very times. The local span is [0, end - origin]; when the start is no dyadic
number, it begins a sliver of less than q (about 1e-15 s) before the piece's start, in
which the piece's polynomials extend it (``lead``: the start in local time). Instants
found in that sliver belong to the previous piece and are dropped by the audit.
"""

from __future__ import annotations

import math

from flint import fmpq, fmpq_poly

from ...model.dataclass import dataclass
from ...model.numbers import to_float
from ...model.task import Piece, Task

ZERO = fmpq(0)


@dataclass(frozen=True)
class Trajectory:
    """Exact end-point motion of one piece: ``x``, ``y`` and their first two time
    derivatives (polynomials in the local time u = t - ``origin``, SI units), ``a1``, the
    local span [0, ``duration``], ``path`` (y = path(x), or None when the task gives
    y(t) directly) and ``lead`` (the piece's start in local time, 0 unless the start is
    no dyadic number)."""

    x: fmpq_poly
    y: fmpq_poly
    path: fmpq_poly | None  # y = path(x), None for the end point's motion given directly
    a1: fmpq
    duration: fmpq
    origin: fmpq = ZERO
    lead: fmpq = ZERO

    @property
    def slope(self) -> fmpq_poly:
        """dy/dx along a path, p'(x(t)) (polynomial in t; only with a ``path``)."""
        assert self.path is not None
        return self.path.derivative()(self.x)

    @property
    def xd(self) -> fmpq_poly:
        return self.x.derivative()

    @property
    def yd(self) -> fmpq_poly:
        return self.y.derivative()

    @property
    def xdd(self) -> fmpq_poly:
        return self.x.derivative().derivative()

    @property
    def ydd(self) -> fmpq_poly:
        return self.y.derivative().derivative()


def origin_of(start: fmpq, end: fmpq) -> fmpq:
    """The local origin of a piece [start, end] (module docstring): ``start`` rounded down
    to a multiple of q = 2^(e - 51), end's double in [2^(e-1), 2^e)."""
    if start == 0:
        return fmpq(0)
    e = math.frexp(to_float(end))[1]
    q = fmpq(2) ** (e - 51) if e >= 51 else fmpq(1, 2 ** (51 - e))
    return fmpq(int((start / q).floor())) * q


def piece_trajectory(piece: Piece, a1: fmpq) -> Trajectory:
    """The exact trajectory of one piece, in its local time (module docstring)."""
    origin = origin_of(piece.start, piece.end)
    if piece.local is not None and piece.path is None:  # the same polynomials, shorter work
        lead = piece.start - origin  # t - start = u - lead
        x, y = piece.local
        if lead != 0:
            x, y = x(fmpq_poly([-lead, 1])), y(fmpq_poly([-lead, 1]))
    else:
        shift = fmpq_poly([origin, 1])  # t = origin + u
        x = piece.x(shift) if origin != 0 else piece.x
        y = piece.y(shift) if origin != 0 else piece.y
    return Trajectory(
        x=x, y=y, path=piece.path, a1=a1, duration=piece.end - origin, origin=origin,
        lead=piece.start - origin,
    )  # fmt: skip


def trajectory(task: Task) -> Trajectory:
    """The exact trajectory of ``task``'s first piece (the whole motion in the paper's
    form): y(t) = p(x(t)) by composition."""
    return piece_trajectory(task.motion[0], task.robot.a1)

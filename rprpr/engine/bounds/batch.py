"""The envelope of many plain pieces at once: one branch and bound over the boxes of all
of them (pure).

A piece is *plain* when its motion holds no singular instant, no instant at which E is
at A or B, and does not lie on y = 0: then its torques over a box are enclosed by the
direct forms of ``envelope`` alone (the mean-value form and plain interval evaluation,
no zone or Taylor form). Those forms are the same operations for every piece; only the
ball coefficients of x(t) and y(t) (or of the path) differ. Here every box carries the
index of its piece and the coefficients become arrays indexed by box (Horner's rule
works elementwise), so one pass of ball operations encloses every box of every piece:
the cost of a pass is its operations' calls, not its length.

The proofs are those of ``Envelope.bounds`` box by box (each box is evaluated with its
own piece's exact coefficients, rounded outward); only the pruning is shared: a box is
set aside when its upper bound of |T_i| is below the best certified value of any piece
(the peak), or its lower bound of |δ| above the least certified |δ| of any piece (the
closest approach). The answers are the same suprema and infima over all the pieces
that ``pieces.peaks`` and ``pieces.approach`` would make from one envelope per piece.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import Any

import numpy as np
from flint import fmpq, fmpq_poly

from ...model.numbers import to_float
from ...model.task import Piece, Robot
from ...model.waypoints import Segment
from ..certified.balls import ETA, Ball, U, horner, quiet, round_up
from ..certified.jets import Jet
from ..certified.motion import CertifiedMotion, dyadic_middle
from ..certified.shared import per_robot
from ..certified.stacked import stacked_form
from ..exact.trajectory import Trajectory
from .approach import min_abs_y
from .boxes import Bounds, full, last_float, partition, y_chain
from .search import MAX_LIVE, MAX_ROUNDS, PEAK_REL, cut, maximise
from .verdicts import Approach, Peak

START_PER_PIECE = 2  # the initial partition: boxes per piece (short pieces, smooth torques)
LEVELS = 4  # a polynomial and its first three derivatives: what the jets read


def plain(motion: CertifiedMotion) -> bool:
    """Whether the piece's torques need no form but the direct ones (module docstring)."""
    a = motion.analysis
    return not (a.instants or a.kinematic or a.on_singular_line or motion.kinematic)


def _balls(qs: list[fmpq]) -> tuple[np.ndarray, np.ndarray]:
    """Exact rationals as balls (what ``Ball.of_rational`` makes of each, in one array):
    the double m nearest each, radius 0 when m is the rational itself (only a dyadic
    rational can be), else u|m| + η/2 rounded up; unbounded beyond the double range."""
    mid = np.empty(len(qs))
    exact = np.zeros(len(qs), dtype=bool)
    for i, q in enumerate(qs):
        d = int(q.q)
        try:
            m = int(q.p) / d
        except OverflowError:
            m = math.inf
        mid[i] = m
        if d & (d - 1) == 0 and math.isfinite(m):
            exact[i] = fmpq(*m.as_integer_ratio()) == q
    bad = ~np.isfinite(mid)
    with quiet():
        rad = np.where(exact, 0.0, round_up(U * np.abs(mid) + ETA))
    return np.where(bad, np.nan, mid), np.where(bad, np.inf, rad)


def _poly_balls(polys: list[fmpq_poly]) -> tuple[np.ndarray, np.ndarray]:
    """``_balls`` of the coefficients of ``polys``, as (mid, rad) arrays of shape
    (degree + 1, pieces) padded with exact zeros: each polynomial read as integers over
    its one denominator (flint's form; ``_integer_balls``)."""
    return _integer_balls([([int(c) for c in p.numer().coeffs()], int(p.denom())) for p in polys])


def _integer_balls(polys: list[tuple[list[int], int]]) -> tuple[np.ndarray, np.ndarray]:
    """``_balls`` of the coefficients of polynomials given as the integer numerators of
    their ascending powers over one denominator each (``_Rounded``)."""
    r = _Rounded()
    for nums, den in polys:
        r.add(nums, den)
    return r.balls()


class _Rounded:
    """``_balls`` of the coefficients of polynomials given one by one (``add``) as the
    integer numerators of their ascending powers over one denominator each (any, not
    only lowest terms), as (mid, rad) arrays of shape (degree + 1, pieces) padded with
    exact zeros (``balls``): each n/d rounded to the nearest double m by Python's exact
    division, radius 0 exactly when m = n/d (then n/d is dyadic, which it is exactly
    when d's odd part divides n, as ``_balls`` asks). The degree is that of the
    polynomial: zero numerators at the top are dropped. Only floats are kept: a long
    motion's integers are not held."""

    def __init__(self) -> None:
        self.mids: list[float] = []
        self.exact: list[bool] = []
        self.sizes: list[int] = []

    def add(self, nums: list[int], den: int) -> None:
        k = len(nums)
        while k and not nums[k - 1]:
            k -= 1
        odd = den >> ((den & -den).bit_length() - 1)  # n/d is dyadic only if odd divides n
        mids, exact = self.mids, self.exact
        for i in range(k):
            num = nums[i]
            try:
                m = num / den
            except OverflowError:
                m = math.inf
            mids.append(m)
            if num % odd or not math.isfinite(m):
                exact.append(False)
            else:
                a, b = m.as_integer_ratio()
                exact.append(a * den == num * b)
        self.sizes.append(k)

    def balls(self) -> tuple[np.ndarray, np.ndarray]:
        sizes = np.array(self.sizes, dtype=np.intp)
        n = max(int(sizes.max(initial=0)), 1)
        col = np.repeat(np.arange(len(sizes)), sizes)
        row = np.arange(len(col)) - np.repeat(np.cumsum(sizes) - sizes, sizes)
        mid = np.zeros((n, len(sizes)))
        exact = np.ones((n, len(sizes)), dtype=bool)
        mid[row, col] = self.mids
        exact[row, col] = self.exact
        bad = ~np.isfinite(mid)
        with quiet():
            rad = np.where(exact, 0.0, round_up(U * np.abs(mid) + ETA))
        return np.where(bad, np.nan, mid), np.where(bad, np.inf, rad)


def _levels(polys: list[fmpq_poly]) -> list[tuple[np.ndarray, np.ndarray]]:
    """Ball coefficients, low to high, of the polynomials ``polys`` (one per piece) and
    of their first LEVELS - 1 derivatives, as (mid, rad) arrays of shape
    (degree + 1, pieces) padded with exact zeros: the polynomials' own coefficients
    rounded (``_poly_balls``), each derivative's from the one before (``_derived``)."""
    return _derived(_poly_balls(polys))


def _derived(balls: tuple[np.ndarray, np.ndarray]) -> list[tuple[np.ndarray, np.ndarray]]:
    """The ball coefficients ``balls`` (of a polynomial per piece) and those of its first
    LEVELS - 1 derivatives, each from the one before times the exact integers k in ball
    arithmetic (a ball that contains k c_k)."""
    b = Ball._of(*balls)
    out = [(b.mid, b.rad)]
    with quiet():
        for _ in range(LEVELS - 1):
            if len(b.mid) > 1:
                k = np.arange(1, len(b.mid), dtype=float)[:, None]
                b = Ball._of(b.mid[1:], b.rad[1:]) * k
            else:
                b = Ball._of(np.zeros_like(b.mid), np.zeros_like(b.rad))
            out.append((b.mid, b.rad))
    return out


def local_form(piece: Piece) -> tuple[fmpq_poly, fmpq_poly]:
    """x and y of ``piece`` as exact polynomials in its local time v = t - start: its
    ``local`` form when it carries one, else shifted exactly (y = path(x) is not formed
    for a piece with a path: zero stands in for it)."""
    if piece.local is not None:
        return piece.local
    shift = fmpq_poly([piece.start, 1])
    x = piece.x(shift) if piece.start != 0 else piece.x
    if piece.path is not None:
        return x, fmpq_poly([])
    return x, piece.y(shift) if piece.start != 0 else piece.y


def _ends(duration: fmpq) -> tuple[float, float]:
    """The largest float <= t_f and the least float >= t_f."""
    f = to_float(duration)  # the nearest float, compared once with t_f
    if not math.isfinite(f):
        lo = last_float(duration)
        return lo, math.nextafter(lo, math.inf)
    g = fmpq(*f.as_integer_ratio())
    if g == duration:
        return f, f
    return (math.nextafter(f, -math.inf), f) if g > duration else (f, math.nextafter(f, math.inf))


def _int_ends(Tn: int, Td: int) -> tuple[float, float] | None:
    """``_ends`` of T = Tn/Td (Td > 0) on its integers; None beyond the double range."""
    try:
        f = Tn / Td
    except OverflowError:
        return None
    a, b = f.as_integer_ratio()
    above, below = a * Td, Tn * b
    if above == below:
        return f, f
    return (math.nextafter(f, -math.inf), f) if above > below else (f, math.nextafter(f, math.inf))


def _half(t: float) -> tuple[int, int]:
    """``dyadic_middle(0.0, t)`` as (M, e): the centre M 2^e."""
    m = 0.5 * (0.0 + t)
    if m == 0 or not math.isfinite(m):
        return 0, 0
    e = math.frexp(m)[1] - 12
    return (round(m / 2.0**e), e) if e >= 0 else (round(m * 2.0**-e), e)


def _shifted(nums: list[int], den: int, M: int, e: int) -> tuple[list[int], int]:
    """The polynomial sum(nums[j] u^j)/den at u + c, c = M 2^e (exact, on integers):
    the Taylor shift by M of the coefficients scaled by 2^(s(n - j)), s = -e, the k-th
    then scaled by 2^(sk), over den 2^(sn)."""
    if M == 0 or not nums:
        return nums, den
    n = len(nums) - 1
    s = max(-e, 0)
    M <<= max(e, 0)
    b = [v << (s * (n - j)) for j, v in enumerate(nums)]
    for i in range(n):
        for j in range(n - 1, i - 1, -1):
            b[j] += M * b[j + 1]
    return [v << (s * k) for k, v in enumerate(b)], den << (s * n)


def _segments(pieces: list[Piece]) -> list[Segment] | None:
    """The pieces' ``waypoints.Segment`` forms when every piece is one, else None."""
    forms = [p.form for p in pieces]
    return forms if all(type(f) is Segment for f in forms) else None  # type: ignore[return-value]


def _of_segments(
    segments: list[Segment],
) -> tuple[tuple[np.ndarray, np.ndarray], np.ndarray, np.ndarray, np.ndarray] | None:
    """What ``Batch`` makes of y in the pieces' exact local forms, made from the
    integers of their ``waypoints.Segment``: the ball coefficients of y recentred on c
    (``_shifted``, ``_Rounded``), the ends (``_ends``) and the centres c (exact
    doubles); the very numbers the exact forms give. None for a piece beyond the double
    range (then the forms)."""
    q = _Rounded()
    last, end, centre = [], [], []
    for seg in segments:
        ends = _int_ends(*seg.T)
        if ends is None:
            return None
        M, e = _half(ends[0])
        if e < -1000:  # the centre's double not exact: the general path says what it is
            return None
        q.add(*_shifted(*seg.integers(1), M, e))
        last.append(ends[0])
        end.append(ends[1])
        centre.append(math.ldexp(M, e))
    return q.balls(), np.array(last), np.array(end), np.array(centre)


def _x_of_segments(segments: list[Segment]) -> tuple[np.ndarray, np.ndarray]:
    """The ball coefficients of x of the pieces' ``waypoints.Segment`` forms."""
    x = _Rounded()
    for seg in segments:
        x.add(*seg.integers(0))
    return x.balls()


class Batch:
    """The direct torque and δ enclosures of many pieces, one pass for all their boxes;
    the pieces share one robot and one form (a path, or y(t)). Each piece is taken in its
    own local time v = t - start (``local_form``: exact, and short when the piece comes
    in that form, as waypoint segments do); the times the batch reports are local to
    their piece's start. ``apart`` says which pieces are proven plain before any exact
    analysis; ``take`` keeps the plain ones. A planner's segments (``waypoints.Segment``)
    are rounded from their integers, their polynomials never made (``_of_segments``),
    and x's coefficients only when a pass reads them (``x``): the same balls."""

    def __init__(self, pieces: list[Piece], robot: Robot) -> None:
        self.robot = robot
        self.pieces = pieces
        self.path = pieces[0].path
        self.direct = self.path is None
        assert all((p.path is None) == self.direct for p in pieces)
        self.cols: np.ndarray | None = None  # a batch taken: its pieces' columns in x, q
        self.stacked = per_robot(robot, stacked_form)
        self._shared: dict[str, Any] = {}  # x, made when first read; shared by ``take``
        segments = _segments(pieces) if self.direct else None
        made = _of_segments(segments) if segments is not None else None
        if segments is not None and made is not None:  # a planner's segments, integers
            q, self.t_last, self.t_end, centre = made
            self.q = _derived(q)
            self.center = Ball._of(centre, np.zeros_like(centre))
            self._shared["segments"] = segments
            return
        forms = [local_form(p) for p in pieces]
        self._shared["x"] = _levels([x for x, _ in forms])
        ends = [_ends(d) for d in self.durations]
        self.t_last = np.array([e[0] for e in ends])
        self.t_end = np.array([e[1] for e in ends])
        if self.path is None:
            centres = [dyadic_middle(0.0, t) for t in self.t_last]
            qs = [y(fmpq_poly([c, 1])) for (_, y), c in zip(forms, centres, strict=True)]
        else:  # y = q(x - c), q the path recentred on the middle of the piece's x range
            centres = self._x_centres()
            qs = [self.path(fmpq_poly([c, 1])) for c in centres]
        self.q = _levels(qs)
        self.center = Ball._of(*_balls(centres))

    @property
    def x(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """The ball coefficients of x and its derivatives (``_levels``), of every piece of
        the batch this one was taken from: made when first read (no pass over y alone
        reads them)."""
        if "x" not in self._shared:
            self._shared["x"] = _derived(_x_of_segments(self._shared["segments"]))
        return self._shared["x"]

    @cached_property
    def durations(self) -> list[fmpq]:
        return [p.end - p.start for p in self.pieces]

    def form(self, j: int) -> tuple[fmpq_poly, fmpq_poly]:
        """The exact local form of piece j (``local_form``)."""
        return local_form(self.pieces[j])

    def _x_centres(self) -> list[fmpq]:
        """A short dyadic number in the middle of each piece's x range, from 17 float
        values of x (conditioning only: any centre keeps the enclosures rigorous)."""
        f = np.linspace(0.0, 1.0, 17)[:, None] * self.t_last[None, :]
        mid = self.x[0][0]
        with quiet():
            xs = np.zeros_like(f)
            for k in range(len(mid) - 1, -1, -1):
                xs = xs * f + mid[k]
            xs = np.where(np.isfinite(xs), xs, np.nan)
            lo, hi = np.nanmin(xs, axis=0), np.nanmax(xs, axis=0)
        return [dyadic_middle(float(a), float(b)) if math.isfinite(a) and math.isfinite(b)
                else fmpq(0) for a, b in zip(lo, hi, strict=True)]  # fmt: skip

    def __len__(self) -> int:
        return len(self.pieces)

    def take(self, ids: list[int]) -> Batch:
        """The batch of the pieces ``ids`` (indices into this one), in that order: the
        ball coefficients shared, not copied (``cols``)."""
        sel = np.array(ids, dtype=int)
        b = object.__new__(Batch)
        b.__dict__.update(self.__dict__)
        for name in ("_start", "_y_span", "durations"):
            b.__dict__.pop(name, None)
        b.pieces = [self.pieces[j] for j in ids]
        b.cols = sel if self.cols is None else self.cols[sel]
        b.center = Ball._of(self.center.mid[sel], self.center.rad[sel])
        b.t_last, b.t_end = self.t_last[sel], self.t_end[sel]
        if "_y_span" in self.__dict__:
            low, up = self._y_span
            b.__dict__["_y_span"] = (low[sel], up[sel])
        return b

    @cached_property
    def _y_span(self) -> tuple[np.ndarray, np.ndarray]:
        """A lower bound of |y| over each whole piece (one box [0, end] each) and an
        upper bound of |y| at its start."""
        n = len(self)
        idx = np.arange(n)
        with quiet():
            y = full(self._y(Ball.hull(np.zeros(n), self.t_end), idx), n, 0)
            y0 = full(self._y(Ball.exact(np.zeros(n)), idx), n, 0)
            low, up = y.lower_abs(), y0.upper_abs()
        return np.where(np.isnan(low), 0.0, low), np.where(np.isnan(up), np.inf, up)

    def apart(self) -> np.ndarray:
        """Which pieces are proven never to meet y = 0 (|y| > 0 over the whole piece, in
        ball arithmetic): such a piece has no singular instant and E is never at A or B
        on it, so its exact singular analysis is the empty one."""
        return self._y_span[0] > 0

    def _min_abs_y(self) -> tuple[int, tuple[float, float]]:
        """min |y| over all the pieces, exactly (``envelope.min_abs_y``), and the piece
        where it is reached (with the local time): only a piece whose certified lower
        bound of |y| does not exceed the least certified |y(start)| can hold it."""
        low, at_start = self._y_span
        bound = float(at_start.min())
        got = []
        for j in (int(k) for k in np.nonzero(low <= bound)[0]):
            x, y = self.form(j)
            if self.path is not None:
                y = self.path(x)
            d = self.durations[j]
            got.append((min_abs_y(Trajectory(x, y, self.path, self.robot.a1, d), d), j))
        best, jy = min(got, key=lambda g: g[0][0])
        return jy, best

    # -- one pass ---------------------------------------------------------------------------
    def _y(self, box: Ball, idx: np.ndarray) -> Ball:
        """y over boxes of many pieces (``jets``' y, alone where it needs no x)."""
        if not self.direct:
            return self.jets(box, idx)[3].v
        col = idx if self.cols is None else self.cols[idx]
        c = Ball._of(self.center.mid[idx], self.center.rad[idx])
        mid, rad = self.q[0][0][:, col], self.q[0][1][:, col]
        return horner([Ball._of(mid[k], rad[k]) for k in range(len(mid))], box - c)

    def jets(self, box: Ball, idx: np.ndarray) -> tuple[Jet, Jet, Jet, Jet, Jet, Jet]:
        """``Polys.jets`` over boxes of many pieces (box j of piece idx[j])."""

        col = idx if self.cols is None else self.cols[idx]

        def at(pm: tuple[np.ndarray, np.ndarray], x: Ball) -> Ball:
            mid, rad = pm[0][:, col], pm[1][:, col]
            return horner([Ball._of(mid[k], rad[k]) for k in range(len(mid))], x)

        xv = [at(c, box) for c in self.x]
        x, xd, xdd = Jet(xv[0], xv[1]), Jet(xv[1], xv[2]), Jet(xv[2], xv[3])
        c = Ball._of(self.center.mid[idx], self.center.rad[idx])
        if self.direct:
            yv = [at(q, box - c) for q in self.q]
            return x, xd, xdd, Jet(yv[0], yv[1]), Jet(yv[1], yv[2]), Jet(yv[2], yv[3])
        w = xv[0] - c
        return x, xd, xdd, *y_chain(xv, [at(q, w) for q in self.q])

    def _pass(self, t: Ball, idx: np.ndarray) -> tuple[Ball, Ball]:
        x, xd, xdd, y, yd, ydd = self.jets(t, idx)
        T = self.stacked.efforts(x, xd, xdd, y, yd, ydd)
        return full(T.v, len(idx)), full(T.d, len(idx))

    def _values(self, t: np.ndarray, idx: np.ndarray) -> Ball:
        x, xd, xdd, y, yd, ydd = (J.v for J in self.jets(Ball.exact(t), idx))
        T = self.stacked.efforts(x, xd, xdd, y, yd, ydd)
        return full(T, len(idx))

    def bounds(
        self, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray | None = None, need: float = 0.0
    ) -> Bounds:
        """``Envelope.bounds`` over boxes of many pieces (box j of piece idx[j]; no
        instant: the direct forms, whatever ``need``)."""
        assert idx is not None
        n = len(lo)
        with quiet():
            box = Ball.hull(lo, hi)
            B, D = self._pass(box, idx)
            P = self._values(np.concatenate([lo, hi]), np.concatenate([idx, idx]))
            pa, pb = P[:, :n], P[:, n:]
            ua, ub = pa.upper_abs(), pb.upper_abs()
            la, lb = pa.lower_abs(), pb.lower_abs()
            last = self.t_last[idx]
            la = np.where(lo <= last, la, 0.0)
            lb = np.where(hi <= last, lb, 0.0)
            width = 2.0 * box.rad
            slope = D.upper_abs()
            mean_value = round_up((ua + ub + slope * width) * 0.5)
            up = np.minimum(B.upper_abs(), mean_value)
            mono = D.lower_abs() > 0
            mono_ok = mono & np.isfinite(ua) & np.isfinite(ub)
            up = np.where(mono_ok, np.minimum(up, np.maximum(ua, ub)), up)
            low = np.maximum(la, lb)
            low_t = np.where(la >= lb, lo, hi)
        up = np.where(np.isnan(up), np.inf, up)
        return Bounds(lo, hi, low, low_t, up, np.zeros_like(up))

    @cached_property
    def _start(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The first partition: START_PER_PIECE boxes per piece, each box's piece."""
        parts = [partition(d, START_PER_PIECE) for d in self.durations]
        lo = np.concatenate([p[0] for p in parts])
        hi = np.concatenate([p[1] for p in parts])
        return lo, hi, np.repeat(np.arange(len(parts)), START_PER_PIECE)

    # -- the peak ---------------------------------------------------------------------------
    def torque_peak(self, rel: float = PEAK_REL) -> tuple[tuple[Peak, int], tuple[Peak, int]]:
        """max |T1| and max |T2| over all the pieces, each with the index of the piece
        where its value is reached (``t``: local time of that piece)."""
        lo, hi, idx = self._start
        b = self.bounds(lo, hi, idx)
        best, best_t = np.zeros(2), np.zeros(2)
        peaks, where = maximise(self, b, idx, best, best_t, rel, MAX_LIVE * len(self))
        return (peaks[0], where[0]), (peaks[1], where[1])

    # -- the limit ---------------------------------------------------------------------------
    def below(self, limit: tuple[float, float]) -> bool:
        """Whether |T_i| <= limit_i is proven over every box of every piece, without the
        peak: the first partition's pass, then only the boxes whose upper bound is above
        a limit cut further (a limit far above the torques is decided by one pass).
        False when a certified value exceeds a limit or the work cap stops the cutting:
        then the pieces are checked one by one (``Envelope.limit_violations``)."""
        lo, hi, idx = self._start
        L = np.array([float(limit[0]), float(limit[1])])[:, None]
        cap = MAX_LIVE * len(self)
        b = self.bounds(lo, hi, idx)
        for _ in range(MAX_ROUNDS):
            if bool((b.low > L).any()):
                return False
            keep = np.asarray((b.up > L).any(axis=0))
            n = int(keep.sum())
            if not n:
                return True
            if n > cap:
                return False
            lo, hi, idx = cut(b.lo, b.hi, idx, keep)
            b = self.bounds(lo, hi, idx)
        return False

    # -- near misses ------------------------------------------------------------------------
    def closest_approach(self, rel: float = PEAK_REL) -> tuple[Approach, int, int]:
        """The closest approach over all the pieces (one piece alone: ``Envelope``'s, from
        its critical points): min |y| exactly, min |δ| by one branch and bound over the
        boxes of every piece, certified to ``rel``. The Approach (``t_y`` local to the
        piece of the first index, ``t_delta`` to that of the second)."""
        jy, ys = self._min_abs_y()
        lo, hi, idx = self._start
        cap = MAX_LIVE * len(self)
        best, best_t, best_j = math.inf, 0.0, 0
        floor = math.inf
        low = np.zeros(0)
        for _ in range(MAX_ROUNDS):
            low, up, ends, where = self._delta_bounds(lo, hi, idx)
            j = int(np.argmin(up))
            if up[j] < best:
                best, best_t, best_j = float(up[j]), float(ends[j]), int(where[j])
            keep = low < best * (1 - rel)
            floor = min(floor, float(low[~keep].min(initial=math.inf)))
            n = int(keep.sum())
            if not n:
                low = np.zeros(0)
                break
            if n > cap:
                break
            lo, hi, idx = cut(lo, hi, idx, keep)
        delta_lo = min(floor, best, float(low.min(initial=best)))
        a = Approach(ys[0], ys[1], delta_lo, best, best_t)
        return a, jy, best_j

    def _delta_bounds(
        self, lo: np.ndarray, hi: np.ndarray, idx: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Lower bounds of |δ| over boxes of many pieces (the mean-value form on jets), and
        certified values of |δ| at their ends, with the piece of each end."""
        n = len(lo)
        pts = np.concatenate([lo, hi])
        both = np.concatenate([idx, idx])
        with quiet():
            box = Ball.hull(lo, hi)
            x, xd, xdd, y, yd, ydd = self.jets(box, idx)
            lg = self.stacked.legs(x, xd, xdd, y, yd, ydd)
            delta = self.stacked.delta(lg, y)
            V, D = full(delta.v, n, 0), full(delta.d, n, 0)
            v = [J.v for J in self.jets(Ball.exact(pts), both)]
            lp = self.stacked.legs(*v)
            P = full(self.stacked.delta(lp, v[3]), 2 * n, 0)
            width = 2.0 * box.rad
            around = P[:n] + D * Ball(0.5 * width, 0.5 * width)
            low = np.maximum(V.lower_abs(), around.lower_abs())
            up = P.upper_abs()
        up = np.where(pts <= self.t_last[both], up, np.inf)
        return low, up, pts, both

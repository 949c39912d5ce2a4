"""Boxes of time and what one pass proves over them: the motion's polynomials enclosed
over boxes (``Polys``), the partition of [0, t_f] and its cuts, stacked balls by
columns, and ``Bounds``, what one pass proves per box."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from flint import fmpq, fmpq_poly

from ...model.dataclass import dataclass
from ...model.numbers import to_float
from ..certified.balls import Ball, centred, flat_coefficients, horner, poly_balls
from ..certified.jets import Jet, y_jets, y_values
from ..certified.kernel import INDEX, KERNEL
from ..certified.motion import CertifiedMotion

START_BOXES = 512  # the initial partition of [0, t_f]
CENTRED_DEGREE = 7  # a longer polynomial is enclosed over boxes by the centred form


class Polys:
    """Ball coefficients of x, x', x'', x''' in t and of q, q', q'', q''' in w = x - c
    (q: the path recentred), or without a path q = y recentred, in w = t - c_t; and the
    fourth derivatives, which the centred form (``balls.centred``) needs where a long
    polynomial is enclosed over boxes."""

    def __init__(self, motion: CertifiedMotion) -> None:
        self.direct = motion.traj.path is None  # then q is y in w = t - c_t
        q3 = motion.y3 if self.direct else motion.q3  # up to the second derivative
        assert q3 is not None
        x, q = motion.traj.x, motion.recentred
        x3 = x.derivative().derivative().derivative()
        q3d = q.derivative().derivative().derivative()
        self.x = [*motion.x3, poly_balls(x3), *_fourth(x3)]
        self.q = [*q3, poly_balls(q3d), *_fourth(q3d)]
        self.x_flat = [flat_coefficients(c) for c in self.x]  # the kernel's Horner inputs
        self.q_flat = [flat_coefficients(c) for c in self.q]
        # the centre subtracted before q is evaluated (w = t - c_t, or x - c), as the ball
        # a Ball operation makes of the exact rational (``Ball.coerce``), made once
        self.shift = Ball.of_rational(motion.t_center if self.direct else motion.center)

    @staticmethod
    def _enclose(
        cs: list[list[Ball]], flat: list[tuple[np.ndarray, ...]], box: Ball, n: int = 4
    ) -> list[Ball]:
        """The polynomial and its first three derivatives over the balls ``box``: by
        Horner's rule, or, where ``cs`` carries the fourth derivative (a degree over
        CENTRED_DEGREE), by the centred form on balls of some width (where cancellation
        makes Horner's enclosure far too wide). By Horner's rule, only the first ``n``
        (each is evaluated on its own, ``flat``: the kernel's coefficient tuples, made
        once); the centred form makes all four."""
        if len(cs) > 4 and bool(np.any(box.rad > 0)):
            return centred(cs, box)[:4]
        return [horner(c, box, f) for c, f in zip(cs[:n], flat, strict=False)]

    def jets(self, motion: CertifiedMotion, box: Ball) -> tuple[Jet, Jet, Jet, Jet, Jet, Jet]:
        """x, x', x'', y, y', y'' as jets over the box: (enclosure, time derivative)."""
        xv = self._enclose(self.x, self.x_flat, box)
        x, xd, xdd = Jet(xv[0], xv[1]), Jet(xv[1], xv[2]), Jet(xv[2], xv[3])
        if self.direct:
            yv = self._enclose(self.q, self.q_flat, box - self.shift)
            return x, xd, xdd, Jet(yv[0], yv[1]), Jet(yv[1], yv[2]), Jet(yv[2], yv[3])
        w = xv[0] - self.shift
        return x, xd, xdd, *y_chain(xv, self._enclose(self.q, self.q_flat, w))

    def values(self, motion: CertifiedMotion, box: Ball) -> tuple[Ball, ...]:
        """x, x', x'', y, y', y'' over the box: the values of ``jets`` (the same ball
        operations in the same order, so the same balls), without the derivatives."""
        xv = self._enclose(self.x, self.x_flat, box, 3)
        if self.direct:
            yv = self._enclose(self.q, self.q_flat, box - self.shift, 3)
            return xv[0], xv[1], xv[2], yv[0], yv[1], yv[2]
        qv = self._enclose(self.q, self.q_flat, xv[0] - self.shift, 3)
        ins = (xv[1], xv[2], *qv[:3])
        got = _compiled(ins, "y_values", 3) or y_values(*ins)
        return xv[0], xv[1], xv[2], qv[0], got[0], got[1]


def y_chain(xv: Sequence[Ball], qv: Sequence[Ball]) -> tuple[Jet, Jet, Jet]:
    """y, y', y'' as jets of y = q(x(t)) over boxes, from the enclosures of x and its first
    three derivatives (``xv``) and of q and its first three derivatives in w (``qv``):
    ``jets.y_jets``, through the compiled kernel where it applies."""
    ins = (xv[1], xv[2], xv[3], *qv[:4])
    got = _compiled(ins, "y_jets", 4) or y_jets(*ins)
    return Jet(qv[0], got[0]), Jet(got[1], got[2]), Jet(got[3], got[4])


def _compiled(ins: tuple[Ball, ...], name: str, qd: int) -> list[Ball] | None:
    """The outputs of the compiled kernel ``name`` (``kernel_gen``) on the balls ``ins``
    (the same doubles as numpy's path, which broadcasts a scalar ball as the kernel
    does), or None where it is not built, or the balls are not all vectors of one length
    or scalars, or x' and q' (``ins[0]``, ``ins[qd]``: every output depends on them) are
    both scalars (numpy's path then runs and makes scalar outputs)."""
    spec = INDEX.get(name)
    if spec is None:
        return None
    x1, q1 = ins[0].mid, ins[qd].mid
    n = x1.shape[0] if x1.ndim == 1 else q1.shape[0] if q1.ndim == 1 else 0
    if not n:
        return None
    for b in ins:
        if type(b) is not Ball or b.mid.shape != b.rad.shape or b.mid.shape not in ((), (n,)):
            return None
    out = np.empty((spec[1], n))
    if not KERNEL.run(spec[0], tuple(a for b in ins for a in (b.mid, b.rad)), out, n):
        return None
    return [Ball._of(out[i], out[i + 1]) for i in range(0, spec[1], 2)]


def _fourth(third: fmpq_poly) -> list[list[Ball]]:
    """The fourth derivative's ball coefficients from the third derivative, where the
    polynomial's degree (the third's plus 3) calls for the centred form; else none."""
    return [poly_balls(third.derivative())] if third.degree() + 3 > CENTRED_DEGREE else []


def full(b: Ball, n: int, rows: int = 2) -> Ball:
    """The ball ``b`` broadcast to ``rows`` rows (0: none) of n columns (a motion that
    does not move, x and y constant, gives balls that do not depend on t)."""
    shape = (rows, n) if rows else (n,)
    if b.mid.shape == shape and b.rad.shape == shape:  # the usual case: a copy
        return Ball._of(np.array(b.mid), np.array(b.rad))
    mid, rad = np.broadcast_to(b.mid, shape), np.broadcast_to(b.rad, shape)
    return Ball._of(np.array(mid), np.array(rad))


def poor_columns(b: Ball) -> np.ndarray:
    """The columns of a stacked ball (rows: torques) whose enclosure is wider than its
    value in some row (unbounded ones included)."""
    return np.asarray(~(b.rad <= np.abs(b.mid)).all(axis=0))


def put_narrower(b: Ball, idx: np.ndarray, new: Ball) -> Ball:
    """b (rows by columns) with its columns ``idx`` replaced by ``new`` where narrower."""
    if not len(idx):
        return b
    mid, rad = b.mid.copy(), b.rad.copy()
    pick = ~(rad[:, idx] <= new.rad)  # NaN radii (unbounded) are replaced
    mid[:, idx] = np.where(pick, new.mid, mid[:, idx])
    rad[:, idx] = np.where(pick, new.rad, rad[:, idx])
    return Ball._of(mid, rad)


def partition(duration: fmpq, n: int) -> tuple[np.ndarray, np.ndarray]:
    """A partition of [0, t_f] into n boxes with float ends (the last one reaches just
    past t_f when t_f is no float)."""
    tf = to_float(duration)
    step = tf / n
    if n & (n - 1) == 0 and math.isfinite(tf) and step * n == tf and step >= 2.0**-1000 \
            and fmpq(*tf.as_integer_ratio()) == duration:  # fmt: skip
        # t_f a float, n a power of 2: t_f/n is exact and i (t_f/n) the double nearest
        # t_f i/n (one correctly rounded product), as the exact line below gives
        ends = np.arange(n + 1) * step
    else:
        ends = np.array([to_float(duration * fmpq(i, n)) for i in range(n + 1)])
    if fmpq(*tf.as_integer_ratio()) < duration:
        ends[-1] = np.nextafter(tf, np.inf)
    return ends[:-1], ends[1:]


def sorted_unique(a: np.ndarray) -> np.ndarray:
    """``np.unique(a)`` of a 1-d array (the same values, the first of each run of equal
    ones kept, as it keeps them), without its test for masked arrays, which imports
    numpy.ma (~10 ms, once a process) at its first call; NaNs left to ``np.unique``."""
    t = np.sort(a)
    if len(t) and np.isnan(t[-1]):  # NaNs sort last
        return np.unique(a)
    keep = np.empty(len(t), dtype=bool)
    keep[:1] = True
    np.not_equal(t[1:], t[:-1], out=keep[1:])
    return t[keep]


def unique_ends(lo: np.ndarray, hi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The boxes' ends, each once and sorted, and where each of lo then hi is among them:
    ``np.unique(np.concatenate([lo, hi]), return_inverse=True)`` (finite floats) at a
    third of its cost."""
    ends = np.concatenate([lo, hi])
    t = np.sort(ends)
    keep = np.empty(len(t), dtype=bool)
    keep[:1] = True
    np.not_equal(t[1:], t[:-1], out=keep[1:])
    t = t[keep]
    return t, np.searchsorted(t, ends)


def split(lo: np.ndarray, hi: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Each box [lo_j, hi_j] cut into k boxes that share their float ends (rounding is
    monotone, so they cover it)."""
    f = np.arange(k + 1) / k
    ends = lo[:, None] + (hi - lo)[:, None] * f[None, :]
    ends[:, 0], ends[:, -1] = lo, hi
    return ends[:, :-1].ravel(), ends[:, 1:].ravel()


def last_float(duration: fmpq) -> float:
    """The largest float <= t_f."""
    tf = to_float(duration)
    if fmpq(*tf.as_integer_ratio()) > duration:
        tf = float(np.nextafter(tf, -np.inf))
    return tf


@dataclass
class Bounds:
    """What one pass proves about boxes [lo_j, hi_j], per torque i (rows):
    ``low``/``low_t``: a certified value of |T_i| at a time of the box (a lower bound of
    its max there; 0 with no such value), ``up``: an upper bound of |T_i| over the box,
    ``floor``: a lower bound of |T_i| over the box."""

    lo: np.ndarray
    hi: np.ndarray
    low: np.ndarray
    low_t: np.ndarray
    up: np.ndarray
    floor: np.ndarray
    ends: tuple[np.ndarray, ...] | None = None  # |T| at the ends: bounds, values (``_crossing``)
    monotone: np.ndarray | None = None  # |T_i| monotone on the box (T' ∌ 0, T ∌ 0)

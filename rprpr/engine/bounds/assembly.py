"""What one pass proves per box (``Envelope.bounds``), from the torques at the boxes'
ends and over the boxes (T and T'): the bounds of ``boxes.Bounds``, and which boxes a
limit check has settled before the forms near singular instants (``settled``).

Both are written here once in numpy (``_assemble``, ``_settled``: the description) and
run in one call of the compiled kernel where it is built (``kernel_c_bounds``: the same
IEEE operations in the same order, so the same doubles; tests/engine/bounds/
test_assembly.py holds the two together), else in numpy.
"""

from __future__ import annotations

import numpy as np

from ..certified.balls import Ball, round_up
from ..certified.kernel import KERNEL
from .boxes import Bounds


def _kernel(
    P: Ball, where: np.ndarray, B: Ball, D: Ball, box: Ball, lo: np.ndarray, hi: np.ndarray,
    t_last: float, limit: tuple[float, float] | None,
) -> np.ndarray | None:  # fmt: skip
    """The kernel's ``bounds`` (``kernel_c_bounds``), or None where it is not built or
    an array is not of the shape and type it takes."""
    if KERNEL is None:
        return None
    n = len(lo)
    arrays = (P.mid, P.rad, where, B.mid, B.rad, D.mid, D.rad, box.rad, lo, hi)
    if P.mid.ndim != 2 or P.mid.shape[0] != 2 or P.rad.shape != P.mid.shape:
        return None
    for a in arrays[3:7]:
        if a.shape != (2, n):
            return None
    if box.rad.shape != (n,) or where.shape != (2 * n,):
        return None
    out = np.empty(n if limit is not None else (11, 2, n))
    if not KERNEL.bounds(*arrays, float(t_last), limit, out, n):
        return None
    return out


def assemble(
    P: Ball, where: np.ndarray, B: Ball, D: Ball, box: Ball, lo: np.ndarray, hi: np.ndarray,
    t_last: float,
) -> Bounds:  # fmt: skip
    """``Bounds`` of the boxes [lo, hi] (``box``: their balls) from T at their ends (P at
    the distinct ends, ``where``: the columns of lo then hi among them), T over them
    (B) and T' (D): ``_assemble``, in one kernel call where it applies."""
    got = _kernel(P, where, B, D, box, lo, hi, t_last, None)
    if got is None:
        return _assemble(P, where, B, D, box, lo, hi, t_last)
    ends = (got[4], got[5], got[6], got[7], got[8], got[9])
    return Bounds(lo, hi, got[0], got[1], got[2], got[3], ends, got[10] != 0)


def settled(
    P: Ball, B: Ball, D: Ball, where: np.ndarray, box: Ball, lo: np.ndarray, hi: np.ndarray,
    limit: np.ndarray,
) -> np.ndarray:  # fmt: skip
    """``_settled``, in one kernel call where it applies."""
    got = _kernel(P, where, B, D, box, lo, hi, 0.0, (float(limit[0]), float(limit[1])))
    if got is None:
        return _settled(P, B, D, where, box, limit)
    return got != 0


def _assemble(
    P: Ball, where: np.ndarray, B: Ball, D: Ball, box: Ball, lo: np.ndarray, hi: np.ndarray,
    t_last: float,
) -> Bounds:  # fmt: skip
    """``assemble`` in numpy (the description the kernel's ``bounds`` follows). Over a
    box [a, b]: |T(t)| <= min(|T(a)| + D (t - a), |T(b)| + D (b - t)) <= the mean of the
    two (the mean-value form), |T| monotone (T' ∌ 0) peaks at an end; T(a) + T' (t - a)
    bounds |T| below."""
    n = len(lo)
    P = Ball._of(P.mid[:, where], P.rad[:, where])
    pa, pb = P[:, :n], P[:, n:]
    ua, ub = pa.upper_abs(), pb.upper_abs()
    la, lb = pa.lower_abs(), pb.lower_abs()
    valid = np.concatenate([lo, hi]) <= t_last
    la = np.where(valid[:n], la, 0.0)
    lb = np.where(valid[n:], lb, 0.0)
    width = 2.0 * box.rad  # >= hi - lo
    slope = D.upper_abs()
    mean_value = round_up((ua + ub + slope * width) * 0.5)
    up = np.minimum(B.upper_abs(), mean_value)
    mono = D.lower_abs() > 0  # T monotone on the box: |T| peaks at an end
    mono_ok = mono & np.isfinite(ua) & np.isfinite(ub)
    up = np.where(mono_ok, np.minimum(up, np.maximum(ua, ub)), up)
    same = mono_ok & (pa.lower() > 0) & (pb.lower() > 0) | (
        mono_ok & (pa.upper() < 0) & (pb.upper() < 0)
    )
    around = pa + D * Ball(0.5 * width, 0.5 * width)
    floor = np.maximum(B.lower_abs(), around.lower_abs())
    floor = np.where(same, np.maximum(floor, np.minimum(la, lb)), floor)
    low = np.maximum(la, lb)
    low_t = np.where(la >= lb, lo, hi)
    up = np.where(np.isnan(up), np.inf, up)
    ends = (np.where(valid[:n], ua, np.inf), np.where(valid[n:], ub, np.inf), la, lb,
            np.abs(pa.mid), np.abs(pb.mid))  # fmt: skip
    return Bounds(lo, hi, low, low_t, up, floor, ends, same)


def _settled(
    P: Ball, B: Ball, D: Ball, where: np.ndarray, box: Ball, limit: np.ndarray
) -> np.ndarray:
    """The boxes on a known side of the limit in both rows before the forms near
    singular instants: |T_i| <= limit_i by the mean-value bound (``_assemble``) or >
    limit_i by the value at the box's start plus T' over the box. The forms only narrow
    P and B, so these boxes keep their side (a box Taylor model decides nothing there)."""
    n = len(box.mid)
    P = Ball._of(P.mid[:, where], P.rad[:, where])
    pa, pb = P[:, :n], P[:, n:]
    width = 2.0 * box.rad
    mean_value = round_up((pa.upper_abs() + pb.upper_abs() + D.upper_abs() * width) * 0.5)
    up = np.minimum(B.upper_abs(), mean_value)
    around = pa + D * Ball(0.5 * width, 0.5 * width)
    floor = np.maximum(B.lower_abs(), around.lower_abs())
    L = limit[:, None]
    return np.asarray(((up <= L) | (floor > L)).all(axis=0))

"""The largest effort over the box in doubles through the compiled kernel, written by hand
after numpy's operations: the windows' guide (``kernel_c.BOX_MAX``,
``robust.windows.box_max``: the largest |T_i| over the links' box and the error's corners
from the regressor's doubles) and the robust peak's proven bounds from the regressor's
balls (``kernel_c.FORM_BOUNDS``, ``robust.regressor.form_bounds``).

- On random regressors (vectors of times, one or four corners, strided views as
  ``regressor_float`` gives them, zeros, a vanishing r² coefficient, vertices inside and
  outside r's interval, infinite and NaN entries), the kernel gives the same doubles as
  numpy's path (a NaN for a NaN; the sign of a zero maximum is not part of the contract:
  numpy's own loops differ on it); a spy counts the kernel's calls, so the equality is
  never numpy's path against itself; what it does not take it declines.
- ``form_worst`` (the robust peak's guide, through ``box_max``) likewise.
- ``form_bounds`` likewise, on random balls (broadcast radii among them), both bounds,
  against its numpy path bit for bit under a spy; its enclosure of the exact maximum is
  ``test_form_bounds.py``'s (which runs whichever path is built).
- Against an exact reference (exact rationals, written apart from the engine: every
  corner, both signs, each link's form at m's and I's ends and at r's ends and the
  parabola's vertex where it lies inside), the doubles are within 1e-12 of the sum of
  the terms' absolute values.
"""

from __future__ import annotations

import itertools
import random
from typing import Any

import numpy as np
import pytest
from flint import fmpq

from rprpr.engine.certified.balls import Ball
from rprpr.engine.certified.kernel import KERNEL
from rprpr.engine.robust import regressor, windows
from rprpr.engine.robust.regressor import BASIS, LINKS, form_bounds
from rprpr.engine.robust.windows import box_max
from tests.engine.certified.test_kernel import Spy, needs_kernel
from tests.reference import Rational as Q  # exact (gmpy2's rationals, else fractions)


def _bounds(rng: np.random.Generator) -> np.ndarray:
    """(6, 4): m_lo, m_hi, r_lo, r_hi, I_lo, I_hi over ``LINKS``."""
    v = rng.uniform([0.5, -0.3, 0.01], [4.0, 0.6, 0.9], (4, 3))
    w = rng.choice([0.0, 0.01, 0.05, 0.1], (4, 3))
    lo, hi = v - np.abs(v) * w, v + np.abs(v) * w
    return np.array([[lo, hi][e][:, q] for q in range(3) for e in (0, 1)])


def _corners(rng: np.random.Generator) -> np.ndarray:
    a = float(rng.choice([0.0, 0.01, 0.5]))
    if a == 0.0:
        return np.array([[0.0, 0.0, 1.0]])
    return np.array([[sx * a, sy * a, 1.0] for sx in (-1, 1) for sy in (-1, 1)])


def _regressor(rng: np.random.Generator, n: int, special: bool) -> np.ndarray:
    """(3, n, 2, 10), as ``regressor_float`` gives it (a transposed view) or contiguous."""
    Y = rng.uniform(-5.0, 5.0, (2, 10, 3, n)) * 10.0 ** rng.integers(-3, 4, (2, 10, 3, n))
    if special:
        hit = rng.random(Y.shape) < 0.05
        Y[hit] = rng.choice([0.0, -0.0, np.inf, -np.inf, np.nan, 1e-300], int(hit.sum()))
        J = [k for k, (_, what) in enumerate(BASIS) if what == "J"]
        Y[:, J, 0, : n // 3] = 0.0  # no r² term
    view = Y.transpose(2, 3, 0, 1)
    return view if rng.integers(0, 2) else np.ascontiguousarray(view)


@needs_kernel
def test_the_box_max_through_the_kernel_is_numpy_bit_for_bit(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    rng = np.random.default_rng(29)
    spy = Spy(KERNEL)
    trials = 200
    for trial in range(trials):
        n = int(rng.choice([1, 2, 17, 112]))
        Ys = _regressor(rng, n, special=trial % 2 == 1)
        corners, bounds = _corners(rng), _bounds(rng)
        with np.errstate(all="ignore"):
            monkeypatch.setattr(windows, "KERNEL", spy)
            got = box_max(Ys, corners, bounds)
            monkeypatch.setattr(windows, "KERNEL", None)
            want = box_max(Ys, corners, bounds)
        assert got.shape == want.shape == (n, 2)
        assert np.array_equal(got, want, equal_nan=True), (trial, got, want)
    assert (spy.took, spy.declined) == (trials, 0)


@needs_kernel
def test_the_kernel_declines_what_it_does_not_take() -> None:
    rng = np.random.default_rng(5)
    Ys, corners, bounds = _regressor(rng, 4, False), _corners(rng), _bounds(rng)
    out = np.empty((4, 2))
    assert KERNEL.box_max(Ys, corners, bounds, out)
    assert not KERNEL.box_max(Ys[:, :, :, :9], corners, bounds, out)  # not the ten columns
    assert not KERNEL.box_max(Ys, corners[:0], bounds, out)  # no corner
    assert not KERNEL.box_max(Ys, corners, bounds[:, :3], out)  # not the four links
    assert not KERNEL.box_max(Ys.astype(np.float32), corners, bounds, out)
    assert not KERNEL.box_max(Ys, np.asfortranarray(np.ones((4, 3))), bounds, out)
    with pytest.raises(ValueError):
        KERNEL.box_max(Ys, corners, bounds, np.empty((3, 2)))  # an output of the wrong size


def _exact(Ys: np.ndarray, corners: np.ndarray, bounds: np.ndarray) -> tuple[list, list]:
    """Per time and joint: the exact largest |T| over the box and the corners, and the sum
    of the terms' absolute values (the scale of the doubles' rounding). (The box is a
    product and each link's form m (A + B r + C r²) + C I a sum of a term in (m, r) and
    one in I: its maximum is the sum of their maxima.)"""
    best, scale = [], []
    b = [[Q(float(v)) for v in row] for row in bounds]
    errors = [(Q(float(ex)), Q(float(ey))) for ex, ey, _ in corners]
    for i, j in itertools.product(range(Ys.shape[1]), range(2)):
        y0, yx, yy = ([Q(float(v)) for v in Ys[e, i, j, :10]] for e in range(3))
        top, size = None, Q(0)
        for (ex, ey), s in itertools.product(errors, (1, -1)):
            x = [s * (y0[k] + ex * yx[k] + ey * yy[k]) for k in range(10)]
            total = Q(0)
            for li, (_, km, kmr, kj) in enumerate(LINKS):
                A, B, C = (x[km] if km is not None else Q(0)), x[kmr], x[kj]
                ml, mh, rl, rh, il, ih = (b[q][li] for q in range(6))
                rs = [rl, rh]
                if C != 0 and rl < -B / (2 * C) < rh:
                    rs.append(-B / (2 * C))
                total += max(m * (A + B * r + C * r * r) for m in (ml, mh) for r in rs)
                total += max(C * il, C * ih)
                R = max(abs(rl), abs(rh))
                size += max(abs(ml), abs(mh)) * (abs(A) + abs(B) * R + abs(C) * R * R)
                size += abs(C) * max(abs(il), abs(ih))
            top = total if top is None else max(top, total)
        best.append(top)
        scale.append(size)
    return best, scale


def test_the_box_max_is_the_exact_maximum_to_the_doubles_rounding() -> None:
    rng = np.random.default_rng(41)
    random.seed(41)
    for _ in range(25):
        n = int(rng.choice([1, 3, 8]))
        Ys = _regressor(rng, n, special=False)
        corners, bounds = _corners(rng), _bounds(rng)
        got = box_max(Ys, corners, bounds).reshape(-1)
        want, scale = _exact(Ys, corners, bounds)
        for g, w, sc in zip(got, want, scale, strict=True):
            assert abs(Q(float(g)) - w) <= Q(1, 10**12) * sc


def _exact_box(rng: np.random.Generator) -> dict[int, tuple[tuple[fmpq, fmpq], ...]]:
    out = {}
    for link in (2, 3, 4, 5):
        ends = []
        for lo, span in ((50, 350), (-30, 90), (1, 89)):
            v = fmpq(int(rng.integers(lo, lo + span)), 100)
            w = fmpq(int(rng.choice([0, 1, 5, 10])), 100)
            ends.append((v - abs(v) * w, v + abs(v) * w))
        out[link] = tuple(ends)
    return out


@needs_kernel
def test_form_bounds_through_the_kernel_is_numpy_bit_for_bit(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    rng = np.random.default_rng(31)
    spy = Spy(KERNEL)
    trials = 150
    for trial in range(trials):
        n = int(rng.choice([1, 2, 17, 64]))
        mid = rng.uniform(-5.0, 5.0, (2, 10, 3, n)) * 10.0 ** rng.integers(-3, 4, (2, 10, 3, n))
        rad: Any = np.abs(mid) * 10.0 ** rng.uniform(-17, -3, mid.shape)
        if trial % 3 == 1:
            hit = rng.random(mid.shape) < 0.03
            mid[hit] = rng.choice([0.0, -0.0, np.inf, -np.inf, np.nan], int(hit.sum()))
        if trial % 3 == 2:
            rad = np.array(float(rng.choice([0.0, 1e-12])))  # one radius, broadcast
        a = fmpq(int(rng.choice([0, 1, 50])), 100)
        corners = ([(fmpq(0), fmpq(0))] if a == 0
                   else [(sx * a, sy * a) for sx in (-1, 1) for sy in (-1, 1)])  # fmt: skip
        Y, box = Ball(mid, rad), _exact_box(rng)
        for upper in (True, False):
            with np.errstate(all="ignore"):
                monkeypatch.setattr(regressor, "KERNEL", spy)
                got = form_bounds(Y, box, corners, upper)
                monkeypatch.setattr(regressor, "KERNEL", None)
                want = form_bounds(Y, box, corners, upper)
            assert got.shape == want.shape == (2, n)
            assert np.array_equal(got, want, equal_nan=True), (trial, upper, got, want)
    assert (spy.took, spy.declined) == (2 * trials, 0)


@needs_kernel
def test_form_bounds_kernel_declines_what_it_does_not_take() -> None:
    rng = np.random.default_rng(7)
    mid = rng.uniform(-1.0, 1.0, (2, 10, 3, 4))
    rad = np.zeros_like(mid)
    es = np.array([[0.01, 0.01], [-0.01, 0.01]])
    ends = np.ones((6, 4))
    out = np.empty((2, 4))
    assert KERNEL.form_bounds(mid, rad, es, ends, 1e-12, True, out)
    assert not KERNEL.form_bounds(mid[:, :9], rad[:, :9], es, ends, 1e-12, True, out)
    assert not KERNEL.form_bounds(mid, rad[..., :3], es, ends, 1e-12, True, out)
    assert not KERNEL.form_bounds(mid, rad, es[:0], ends, 1e-12, True, out)
    assert not KERNEL.form_bounds(mid, rad, es, ends[:5], 1e-12, True, out)
    assert not KERNEL.form_bounds(mid[..., 0], rad[..., 0], es, ends, 1e-12, True, out)
    with pytest.raises(ValueError):
        KERNEL.form_bounds(mid, rad, es, ends, 1e-12, True, np.empty((2, 3)))


@needs_kernel
def test_the_peaks_guide_through_the_kernel_is_numpy_bit_for_bit(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # ``form_worst`` (the robust peak's guide: both signs from one call of ``box_max``)
    rng = np.random.default_rng(37)
    spy = Spy(KERNEL)
    trials = 150
    for trial in range(trials):
        n = int(rng.choice([1, 3, 50]))
        Y = np.ascontiguousarray(_regressor(rng, n, special=trial % 2 == 1).transpose(2, 3, 0, 1))
        bounds = _bounds(rng)
        box = {link: tuple((bounds[2 * q, i], bounds[2 * q + 1, i]) for q in range(3))
               for i, (link, *_) in enumerate(LINKS)}  # fmt: skip
        a = fmpq(int(rng.choice([0, 1, 50])), 100)
        corners = ([(fmpq(0), fmpq(0))] if a == 0
                   else [(sx * a, sy * a) for sx in (-1, 1) for sy in (-1, 1)])  # fmt: skip
        with np.errstate(all="ignore"):
            monkeypatch.setattr(regressor, "KERNEL", spy)
            got = regressor.form_worst(Y, corners, box)
            monkeypatch.setattr(regressor, "KERNEL", None)
            want = regressor.form_worst(Y, corners, box)
        assert got.shape == want.shape == (2, n)
        assert np.array_equal(got, want, equal_nan=True), (trial, got, want)
    assert (spy.took, spy.declined) == (trials, 0)


@needs_kernel
def test_vertices_at_the_margins_and_unequal_corners_are_numpy_bit_for_bit(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # Random regressors almost never put the parabola's vertex -B/2C at the ends of r's
    # interval or within the margin about them, where the upper and the lower bound
    # count it differently; nor use corners with |e_x| != |e_y|. Here B = t, C = -1/2
    # puts the vertex exactly at t: at each end, the end ± its margin (as both paths
    # compute it) and one unit in the last place either side, for every link.
    spy = Spy(KERNEL)
    rng = np.random.default_rng(43)
    box = _exact_box(rng)
    ends = [(float(lo), float(hi)) for _, (lo, hi), _ in (box[link] for link in (2, 3, 4, 5))]
    targets = []
    for rlo, rhi in ends:
        margin = 1e-9 * (max(abs(rlo), abs(rhi)) + (rhi - rlo))
        for t in (rlo, rhi, rlo - margin, rlo + margin, rhi - margin, rhi + margin):
            targets += [np.nextafter(t, -np.inf), t, np.nextafter(t, np.inf)]
    n = len(targets)
    mid = rng.uniform(-1.0, 1.0, (2, 10, 3, n))
    for _, _, kmr, kj in LINKS:
        mid[:, kmr] = 0.0  # B and C the same at every corner of the error
        mid[:, kj] = 0.0
        mid[:, kmr, 0] = targets
        mid[:, kj, 0] = -0.5
    corners = [(fmpq(1, 100), fmpq(-7, 100)), (fmpq(-3, 100), fmpq(1, 20))]
    Y = Ball(mid, np.abs(mid) * 1e-15)
    for upper in (True, False):
        monkeypatch.setattr(regressor, "KERNEL", spy)
        got = form_bounds(Y, box, corners, upper)
        monkeypatch.setattr(regressor, "KERNEL", None)
        want = form_bounds(Y, box, corners, upper)
        assert np.array_equal(got, want, equal_nan=True), upper
    Ys = np.ascontiguousarray(mid.transpose(2, 3, 0, 1))
    plain = np.array([(float(ex), float(ey), 1.0) for ex, ey in corners])
    bounds = np.array([[ends[i][e] if q == 1 else float(box[link][q][e])
                        for i, link in enumerate((2, 3, 4, 5))]
                       for q in range(3) for e in (0, 1)])  # fmt: skip
    monkeypatch.setattr(windows, "KERNEL", spy)
    got = box_max(Ys, plain, bounds)
    monkeypatch.setattr(windows, "KERNEL", None)
    want = box_max(Ys, plain, bounds)
    assert np.array_equal(got, want, equal_nan=True)
    assert (spy.took, spy.declined) == (3, 0)

"""What one pass proves per box (``assembly``): the compiled kernel's ``bounds`` gives the
same arrays as the numpy description (``_assemble``, ``_settled``), bit for bit, on
random balls with NaN, infinities, overflow, zeros and balls holding 0; a call spy
shows the kernel took every call (so equality cannot pass because numpy ran on both
sides), and it declines arrays it does not take; ``Envelope.bounds`` gives the same
``Bounds`` through either path on a task with a pole, where the forms near it narrow P
and B between the two calls."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from rprpr.engine.bounds import assembly
from rprpr.engine.bounds.boxes import Bounds, partition
from rprpr.engine.bounds.envelope import Envelope
from rprpr.engine.certified.balls import Ball, quiet
from rprpr.engine.certified.kernel import KERNEL
from tests.engine.certified.test_kernel import Spy, _mids, needs_kernel
from tests.engine.certified.test_motion import _config, _motion


@pytest.fixture
def spy(monkeypatch: pytest.MonkeyPatch) -> Spy:
    s = Spy(KERNEL)
    monkeypatch.setattr(assembly, "KERNEL", s)
    return s


def _balls(rng: np.random.Generator, shape: tuple[int, ...]) -> Ball:
    mid = _mids(rng, 0, shape)
    with quiet():
        rad = np.abs(mid) * 10.0 ** rng.uniform(-17, 1, shape)
    rad = np.where(rng.random(shape) < 0.05, np.inf, rad)
    rad = np.where(rng.random(shape) < 0.1, 0.0, rad)  # exact values
    rad = np.where(np.isfinite(rad), rad, np.inf)
    return Ball(mid, rad)


def _case(rng: np.random.Generator) -> tuple[Any, ...]:
    n = int(rng.choice([1, 2, 7, 64]))
    lo = np.sort(rng.uniform(0.0, 2.0, n))
    hi = lo + rng.uniform(0.0, 0.1, n) * (rng.random(n) < 0.9)
    times = np.unique(np.concatenate([lo, hi]))
    where = np.searchsorted(times, np.concatenate([lo, hi]))
    P, B, D = _balls(rng, (2, len(times))), _balls(rng, (2, n)), _balls(rng, (2, n))
    with quiet():
        box = Ball.hull(lo, hi)
    t_last = float(rng.choice([2.5, float(np.median(hi)), 0.0]))
    return P, where, B, D, box, lo, hi, t_last


def _same(x: np.ndarray, y: np.ndarray, what: Any) -> None:
    assert x.shape == y.shape and x.dtype == y.dtype, what
    if x.dtype == bool:
        assert (x == y).all(), what
        return
    same = (x.view(np.int64) == y.view(np.int64)) | (np.isnan(x) & np.isnan(y))
    assert same.all(), (what, x[~same], y[~same])


def _same_bounds(a: Bounds, b: Bounds, what: Any) -> None:
    for name in ("lo", "hi", "low", "low_t", "up", "floor", "monotone"):
        _same(np.asarray(getattr(a, name)), np.asarray(getattr(b, name)), (what, name))
    assert a.ends is not None and b.ends is not None
    for k, (x, y) in enumerate(zip(a.ends, b.ends, strict=True)):
        _same(x, y, (what, "ends", k))


@needs_kernel
def test_the_kernels_bounds_are_numpys_bit_for_bit(spy: Spy) -> None:
    rng = np.random.default_rng(23)
    for trial in range(300):
        P, where, B, D, box, lo, hi, t_last = _case(rng)
        L = np.array([rng.choice([0.0, 1.0, 1e3, np.inf]), rng.uniform(0.0, 5.0)])
        with quiet():
            _same_bounds(
                assembly.assemble(P, where, B, D, box, lo, hi, t_last),
                assembly._assemble(P, where, B, D, box, lo, hi, t_last),
                trial,
            )
            _same(
                assembly.settled(P, B, D, where, box, lo, hi, L),
                assembly._settled(P, B, D, where, box, L),
                trial,
            )
    assert (spy.took, spy.declined) == (600, 0)


@needs_kernel
def test_the_kernel_declines_what_it_does_not_take(spy: Spy) -> None:
    rng = np.random.default_rng(5)
    P, where, B, D, box, lo, hi, t_last = _case(rng)
    with quiet():
        want = assembly._assemble(P, where, B, D, box, lo, hi, t_last)
    strided = np.repeat(lo, 2)[::2]  # not contiguous
    bad_where = where.copy()
    bad_where[0] = 10**6  # a column beyond P's
    as_float = where.astype(float)
    with quiet():
        for args in (
            (P, where, B, D, box, strided, hi, t_last),
            (P, bad_where, B, D, box, lo, hi, t_last),
            (P, as_float, B, D, box, lo, hi, t_last),
        ):
            assert assembly._kernel(*args, None) is None
        _same_bounds(assembly.assemble(P, where, B, D, box, lo, hi, t_last), want, "again")
    assert (spy.took, spy.declined) == (1, 3)


@needs_kernel
@pytest.mark.parametrize("name", ["case1_crossing", "paper_path2", "touch"])
def test_envelope_bounds_are_the_same_through_either_path(
    name: str, spy: Spy, monkeypatch: pytest.MonkeyPatch
) -> None:
    def fresh() -> Envelope:  # a new envelope each time: the forms near instants keep state
        return Envelope(_motion(_config(f"{name}.rprpr.yaml")))

    lo, hi = partition(fresh().duration, 64)
    L = np.array([40.0, 40.0])
    got = fresh().bounds(lo, hi, need=40.0, limit=L)
    assert (spy.took, spy.declined) == (2, 0)
    monkeypatch.setattr(assembly, "KERNEL", None)
    _same_bounds(got, fresh().bounds(lo, hi, need=40.0, limit=L), name)

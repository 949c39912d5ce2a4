"""engine.boxes: the partition of [0, t_f] into boxes with float ends."""

from __future__ import annotations

import numpy as np
from flint import fmpq

from rprpr.engine.bounds.boxes import partition, sorted_unique, split, unique_ends


def test_the_first_partition_has_the_nearest_doubles_to_its_exact_ends() -> None:
    """Box ends RN(t_f i/n) (t_f exact), whether t_f is a float or not."""
    for d in (fmpq(5, 2), fmpq(1, 10), fmpq(1000), fmpq(1, 1000), fmpq(123456789, 2**20)):
        lo, hi = partition(d, 512)
        exact = [fmpq(d) * fmpq(i, 512) for i in range(513)]
        nearest = [int(q.p) / int(q.q) for q in exact]
        assert list(lo) == nearest[:-1] and list(hi[:-1]) == nearest[1:-1]
        assert hi[-1] >= nearest[-1] and fmpq(*float(hi[-1]).as_integer_ratio()) >= d


def test_the_ends_of_boxes_are_each_once_sorted_with_where_each_end_is() -> None:
    # ``unique_ends`` against numpy's own np.unique (sorted, each once, the inverse map):
    # boxes sharing ends, zero-width boxes, ends a few ulps apart, bisections of boxes
    rng = np.random.default_rng(7)
    for _ in range(200):
        n = int(rng.integers(1, 40))
        lo = np.sort(rng.choice(rng.random(n) * 10.0, n))
        width = rng.choice([0.0, 1e-3, 5e-16, 1.0], n)
        hi = np.maximum(lo + width, lo)
        a, b = split(lo, hi, int(rng.integers(1, 5)))
        for los, his in ((lo, hi), (a, b)):
            t, where = unique_ends(los, his)
            ref, inv = np.unique(np.concatenate([los, his]), return_inverse=True)
            assert np.array_equal(t, ref) and np.array_equal(where, inv)
            assert np.array_equal(t[where], np.concatenate([los, his]))


def test_sorted_unique_is_numpys_unique_to_the_bit() -> None:
    """``sorted_unique`` against np.unique: the same doubles (bytes: -0.0 and 0.0 kept as
    np.unique keeps the first of them after sorting), with infinities, subnormals, ends
    a few ulps apart, repeats, empty input and NaNs."""
    rng = np.random.default_rng(11)
    pool = np.array([0.0, -0.0, 1.0, np.nextafter(1.0, 2.0), -3.0, 5e-324, 1e-300, np.inf,
                     -np.inf])  # fmt: skip
    for _ in range(500):
        a = np.concatenate([rng.choice(pool, int(rng.integers(0, 12))),
                            rng.normal(size=int(rng.integers(0, 6)))])  # fmt: skip
        ref, got = np.unique(a), sorted_unique(a)
        assert got.dtype == ref.dtype and got.tobytes() == ref.tobytes()
    a = np.array([2.0, np.nan, 0.0, np.nan, 2.0])
    assert np.array_equal(sorted_unique(a), np.unique(a), equal_nan=True)

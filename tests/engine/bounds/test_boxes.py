"""engine.boxes: the partition of [0, t_f] into boxes with float ends."""

from __future__ import annotations

from flint import fmpq

from rprpr.engine.bounds.boxes import partition


def test_the_first_partition_has_the_nearest_doubles_to_its_exact_ends() -> None:
    """Box ends RN(t_f i/n) (t_f exact), whether t_f is a float or not."""
    for d in (fmpq(5, 2), fmpq(1, 10), fmpq(1000), fmpq(1, 1000), fmpq(123456789, 2**20)):
        lo, hi = partition(d, 512)
        exact = [fmpq(d) * fmpq(i, 512) for i in range(513)]
        nearest = [int(q.p) / int(q.q) for q in exact]
        assert list(lo) == nearest[:-1] and list(hi[:-1]) == nearest[1:-1]
        assert hi[-1] >= nearest[-1] and fmpq(*float(hi[-1]).as_integer_ratio()) >= d

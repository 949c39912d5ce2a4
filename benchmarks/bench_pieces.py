"""The audit of a planner's output: 5,000 quintic waypoint segments (a 1 kHz planner over
5 s), the end point on an arc above AB that never meets it.

    .venv/bin/python -m benchmarks.bench_pieces [N]

Measured (2 shared cores, median of 3): N = 1000: 0.15 s, N = 5000: 0.71 s (0.14 ms per
piece; 3.2 s before the batch proved each piece apart from y = 0 ahead of the exact
analysis and built certified motions only when read; ~260 s before ``engine/bounds/batch.py``).
The 5,000-row CSV of ``bench_waypoints`` (17-digit decimals, long rationals) audits in
~1.0 s (12 s before), and ``rprpr check`` of it end to end takes ~2.1 s (11 s before):
loading ~0.45 s, audit ~1.0 s, the rest start-up and the report.
"""

from __future__ import annotations

import sys
import time

from flint import fmpq

from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.model.task import Piece, Task
from rprpr.model.waypoints import Waypoint, interpolate
from tests.conftest import PATH2_FILE


def planner_task(n: int) -> Task:
    """n + 1 waypoints at t = 5 i/n with positions, velocities and accelerations of
    x = 2 + 2 s, y = 1 + s (1 - s) (s = t/5), exact."""
    base = load_task(PATH2_FILE)
    pts = []
    for i in range(n + 1):
        t = fmpq(5 * i, n)
        s = t / 5
        p = (2 + 2 * s, 1 + s * (1 - s))
        v = (fmpq(2, 5), (1 - 2 * s) / 5)
        a = (fmpq(0), fmpq(-2, 25))
        pts.append(Waypoint(t, p, v, a))
    pieces = tuple(Piece(a, b, x, y) for a, b, x, y, _ in interpolate(pts))
    return Task("planner", base.robot, None, None, fmpq(5), base.checks, "waypoints",
                pieces=pieces)  # fmt: skip


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 5000
    task = planner_task(n)
    t0 = time.perf_counter()
    r = audit(task)
    dt = time.perf_counter() - t0
    print(f"{n} pieces: audit {dt:.2f} s ({1e3 * dt / n:.2f} ms per piece), {r.verdict}")


if __name__ == "__main__":
    main()

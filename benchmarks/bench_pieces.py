"""The audit of a planner's output: 5,000 quintic waypoint segments (a 1 kHz planner over
5 s), the end point on an arc above AB that never meets it.

    .venv/bin/python -m benchmarks.bench_pieces [N]

Measured (2 shared cores, median of 3): N = 100: 0.10 s, N = 1000: 0.60 s, N = 5000:
3.2 s (0.63 ms per piece; it was ~47 ms per piece, 5000 pieces ~260 s, before the plain
pieces were enclosed together, ``engine/batch.py``). The aim of 1 s is not met yet: of
the ~3 s, the envelope of all 5,000 pieces (peak, limit, closest approach) takes ~0.7 s;
the rest is the per-piece exact set-up (``pieces.part``: the singular analysis ~0.6 s,
the certified motion's ball coefficients ~1 s and its x-range centre ~0.7 s, profiled).
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

"""The audit of a planner's output: 5,000 quintic waypoint segments (a 1 kHz planner over
5 s), the end point on an arc above AB that never meets it.

    .venv/bin/python -m benchmarks.bench_pieces [N]
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

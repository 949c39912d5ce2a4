"""Benchmark: loading a 5,000-row quintic waypoint CSV (a 1 kHz planner over 5 s).

    python benchmarks/bench_waypoints.py              # 5,000 rows, best of 5
    python benchmarks/bench_waypoints.py -n 20000 --repeat 3

Writes a task file and its CSV (header t,x,y,vx,vy,ax,ay: the paper's Example 2 motion,
path 2 with the quintic law, sampled every millisecond with its velocity and
acceleration, each written as a planner writes a double: up to 17 digits) into a
temporary folder, then times ``load_task`` in this process: reading the CSV (numbers by
their decimal text), the checks (times increasing from 0, the same fields on every row)
and the controller's quintic segments, exact over the rationals. The audit is not timed.

Measured (2 shared cores, median of 3): 5,000 rows 0.44 s (0.99 s before the segment
formulas were shortened), 1,000 rows 0.09 s; the audit of the 5,000 pieces ~1.0 s, and
``rprpr check`` of the task end to end ~2.1 s (1,000 rows: ~1.15 s).
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

from flint import fmpq, fmpq_poly

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from rprpr.io.loader import load_task

TASK = """\
name: 5,000 waypoints
robot:
  a1: 6
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
motion:
  waypoints: planned.csv
"""


def _decimal(v: fmpq) -> str:
    """``v`` as a planner writes a double: its shortest round-trip decimal (17 digits)."""
    return repr(int(v.p) / int(v.q))


def write_csv(path: Path, rows: int, duration: int = 5) -> None:
    t = fmpq_poly([0, fmpq(1, duration)])  # tau = t / t_f
    x = 2 + 2 * (10 * t**3 - 15 * t**4 + 6 * t**5)  # eq. (49)
    y = fmpq_poly([fmpq(-222, 10), fmpq(218, 10), fmpq(-72, 10), fmpq(8, 10)])(x)  # eq. (51)
    polys = [x, y, x.derivative(), y.derivative()]
    polys += [x.derivative().derivative(), y.derivative().derivative()]
    lines = ["t,x,y,vx,vy,ax,ay"]
    for k in range(rows + 1):
        s = fmpq(k * duration, rows)
        lines.append(",".join(_decimal(v) for v in (s, *(p(s) for p in polys))))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=5000, help="segments (rows - 1)")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        write_csv(root / "planned.csv", args.n)
        (root / "task.rprpr.yaml").write_text(TASK, encoding="utf-8")
        size = (root / "planned.csv").stat().st_size
        best = float("inf")
        for _ in range(args.repeat):
            start = time.perf_counter()
            task = load_task(root / "task.rprpr.yaml")
            best = min(best, time.perf_counter() - start)
        assert len(task.pieces) == args.n
        print(
            f"{args.n + 1} rows ({size / 1e6:.2f} MB), {len(task.pieces)} quintic pieces:"
            f" load_task {best * 1000:.0f} ms (best of {args.repeat})"
        )


if __name__ == "__main__":
    main()

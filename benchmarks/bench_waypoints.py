"""Benchmark: a planner's long quintic waypoint CSV, loaded in process and checked end to end.

    python benchmarks/bench_waypoints.py              # 5,000 segments: load_task, best of 5
    python benchmarks/bench_waypoints.py -n 20000 --repeat 3
    python benchmarks/bench_waypoints.py --check      # 99,999 segments over 100 s: rprpr check
    python benchmarks/bench_waypoints.py --check --vs main=/tmp/fast2-main/.venv/bin/python

Writes a task file and its CSV (header t,x,y,vx,vy,ax,ay: the paper's Example 2 motion,
path 2 with the quintic law, sampled at n + 1 evenly spaced times with its velocity and
acceleration, each written as a planner writes a double: up to 17 digits) into a
temporary folder.

Without ``--check``: times ``load_task`` in this process (reading the CSV by its
numbers' decimal text, the checks, and the controller's quintic segments, exact over the
rationals); the audit is not timed.

With ``--check`` (n defaults to 99,999 segments over 100 s, issue 23's case: at most 8
CPU-seconds and 400 MB): ``rprpr check --budget 0 --format json -q TASK`` as a
subprocess for this tree and each ``--vs NAME=PYTHON``, interleaved, ``--repeat`` runs
each (default 5): the median CPU time of the process and its worker (``os.wait4``'s
rusage, user + system) and the median of their maximum resident set size; and the
machine's load before and after. The machine is shared: read CPU times and ratios.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
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


def check_cost(python: str, task: Path) -> tuple[float, float]:
    """CPU seconds (user + system) and maximum resident set size [MB] of one ``rprpr
    check --budget 0 --format json -q`` of ``task`` by ``python``, its worker included."""
    argv = [python, "-m", "rprpr", "check", "--budget", "0", "--format", "json", "-q", str(task)]
    proc = subprocess.Popen(  # run in the task's folder: ``-m`` puts the folder on sys.path
        argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=task.parent
    )
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode not in (0, 1):
        raise SystemExit(f"{python}: rprpr check exited with {proc.returncode}")
    return usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024


def check(args: argparse.Namespace, root: Path) -> None:
    task = root / "task.rprpr.yaml"
    pythons = [("this tree", sys.executable)]
    pythons += [tuple(v.split("=", 1)) for v in args.vs]  # type: ignore[misc]
    got: dict[str, list[tuple[float, float]]] = {name: [] for name, _ in pythons}
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    for _ in range(args.repeat):
        for name, python in pythons:
            got[name].append(check_cost(python, task))
    print(f"load average after:  {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    rows = args.n + 1
    print(f"rprpr check --budget 0 --format json -q, {rows} rows, median of {args.repeat}:")
    base = statistics.median(c for c, _ in got["this tree"])
    for name, _ in pythons:
        cpu = statistics.median(c for c, _ in got[name])
        rss = statistics.median(m for _, m in got[name])
        print(
            f"  {name:>12}: {cpu:6.2f} CPU-s ({cpu / rows * 1000:.3f} ms a row),"
            f" {rss:5.0f} MB max RSS; this tree / it {base / cpu:.2f}"
        )
    print("aim (issue 23): at most 0.08 ms of CPU a row (8 CPU-s at 99,999 segments), 400 MB")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-n", type=int, default=None, help="segments (rows - 1)")
    parser.add_argument("--seconds", type=int, default=None, help="duration (default n/1000)")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--check", action="store_true", help="rprpr check end to end")
    parser.add_argument("--vs", action="append", default=[], metavar="NAME=PYTHON")
    args = parser.parse_args()
    if args.n is None:
        args.n = 99_999 if args.check else 5000
    seconds = args.seconds or max(1, round(args.n / 1000))
    with tempfile.TemporaryDirectory() as folder:
        root = Path(folder)
        write_csv(root / "planned.csv", args.n, seconds)
        (root / "task.rprpr.yaml").write_text(TASK, encoding="utf-8")
        if args.check:
            check(args, root)
            return
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

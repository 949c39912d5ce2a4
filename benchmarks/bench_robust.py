"""Benchmark: what declared uncertainty costs an audit with the peak (issue 24's aim: a
task with ``uncertainty`` at most 3 times the same task without), in CPU time.

    python benchmarks/bench_robust.py                      # this tree (the running Python)
    python benchmarks/bench_robust.py --vs main=/tmp/main/bin/python   # side by side

For each of ``configs/paper_path2.rprpr.yaml`` (revolute) and
``configs/prismatic_crossing.rprpr.yaml`` (linear actuators), in process:
``rprpr.api.audit(task, peak=True)`` and the same with ``uncertainty`` (±5 % on every
link's mass, inertia and r, 0.01 m/s², a 1 ms period), ``time.process_time`` around each,
interleaved, the median of ``--repeat`` runs after one warm-up each; the ratio of the two.
Each interpreter runs this script on this tree's configs (``--inner``). The machine is
shared: read the ratios, not the times.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CONFIGS = ("paper_path2", "prismatic_crossing")


def inner(repeat: int) -> dict[str, tuple[float, float]]:
    """{config: (median CPU without, with uncertainty)} [s] in this interpreter."""
    from flint import fmpq

    from rprpr import api
    from rprpr.io.loader import load_task
    from rprpr.model.task import Uncertainty

    rel = (fmpq(5, 100),) * 3
    u = Uncertainty(dict.fromkeys((2, 3, 4, 5), rel), fmpq(1, 100), fmpq(1, 1000))
    out = {}
    for name in CONFIGS:
        task = load_task(ROOT / "configs" / f"{name}.rprpr.yaml")
        api.audit(task, peak=True)
        api.audit(task, peak=True, uncertainty=u)
        plain, robust = [], []
        for _ in range(repeat):
            start = time.process_time()
            api.audit(task, peak=True)
            plain.append(time.process_time() - start)
            start = time.process_time()
            api.audit(task, peak=True, uncertainty=u)
            robust.append(time.process_time() - start)
        out[name] = (statistics.median(plain), statistics.median(robust))
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=7, help="runs of each; the median (7)")
    ap.add_argument("--vs", action="append", default=[], metavar="NAME=PYTHON",
                    help="another install to measure side by side")  # fmt: skip
    ap.add_argument("--inner", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.inner:
        print(json.dumps(inner(args.repeat)))
        return 0
    pythons = [("this tree", sys.executable)] + [tuple(v.split("=", 1)) for v in args.vs]
    for name, python in pythons:
        done = subprocess.run(
            [python, __file__, "--inner", "--repeat", str(args.repeat)],
            capture_output=True, text=True, check=True, cwd="/",
        )  # fmt: skip
        for config, (plain, robust) in json.loads(done.stdout).items():
            print(
                f"{name:12s} {config:20s} --peak {1000 * plain:6.1f} ms, with uncertainty"
                f" {1000 * robust:6.1f} ms: ×{robust / plain:.1f}"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""Wall time of `rprpr check configs/paper_path2.rprpr.yaml` against the bare imports.

The aim (issue: rprpr check) is at most about 100 ms above
`python -c "import numpy, yaml, click, rich"` on the same machine. Each command is run
``--repeat`` times (default 15) and the median is reported, after one warm-up run.

    python benchmarks/bench_check.py [--repeat N] [--config PATH]
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def wall(cmd: list[str], repeat: int) -> float:
    subprocess.run(cmd, capture_output=True, cwd=ROOT)  # warm-up (file cache)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        subprocess.run(cmd, capture_output=True, cwd=ROOT)
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--repeat", type=int, default=15)
    ap.add_argument("--config", default="configs/paper_path2.rprpr.yaml")
    args = ap.parse_args()
    base = wall([sys.executable, "-c", "import numpy, yaml, click, rich"], args.repeat)
    text = wall([sys.executable, "-m", "rprpr", "check", args.config], args.repeat)
    js = wall(
        [sys.executable, "-m", "rprpr", "check", "--format", "json", args.config], args.repeat
    )
    print(f"python -c 'import numpy, yaml, click, rich'   {base * 1000:7.1f} ms")
    print(f"rprpr check {args.config}  {text * 1000:7.1f} ms  (+{(text - base) * 1000:.1f} ms)")
    print(
        f"rprpr check --format json ...             {js * 1000:7.1f} ms"
        f"  (+{(js - base) * 1000:.1f} ms)"
    )
    print("aim: at most about +100 ms")


if __name__ == "__main__":
    main()

"""Benchmark: what declared uncertainty costs an audit, per kind of crossing (issue 24's
aim: a task with ``uncertainty`` at most 3 times the same task without), in CPU time.

    python benchmarks/bench_robust.py                      # this tree (the running Python)
    python benchmarks/bench_robust.py --vs main=/tmp/main/bin/python   # side by side
    python benchmarks/bench_robust.py --only paper_path2 --only "case 1"   # some kinds

The kinds: each shipped RPRPR config (``configs/*.rprpr.yaml``) on its own, and each kind of
task of ``bench_hard.py``'s mix (``--per-kind`` tasks of it, default 2, from its seed);
every task with ``checks.torque_limit: [300, 300]`` where it has no limit of its own. In
process, for each task: ``rprpr.api.audit(task)`` and the same with ``uncertainty`` (±5 %
on every link's mass, inertia and r, 0.01 m/s², a 1 ms period), by default and with
``peak=True``; ``time.process_time`` around each, interleaved, the median of ``--repeat``
runs after one warm-up each. A kind's ratio is the sum over its tasks of the medians with
uncertainty over the sum without; the last line is the largest ratio. Each interpreter
runs this script on this tree's tasks (``--inner``). The machine is shared: read the
ratios, not the times.
"""

from __future__ import annotations

import argparse
import json
import random
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
LIMIT = "checks:\n  torque_limit: [300, 300]\n"


def tasks(folder: Path, per_kind: int) -> dict[str, list[Path]]:
    """{kind: its task files}: the shipped configs, then the hard mix's kinds (written
    into ``folder``), each with a limit."""
    import bench_hard

    out: dict[str, list[Path]] = {}
    for path in sorted((ROOT / "configs").glob("*.rprpr.yaml")):
        text = path.read_text(encoding="utf-8")
        if re.search(r"^\s*mechanism:\s*5R\b", text, re.M):
            continue  # uncertainty is the RPRPR's analysis (a 5R task refuses it)
        if "torque_limit" not in text:
            text += LIMIT
            path = folder / path.name
            path.write_text(text, encoding="utf-8")
        out[path.name.removesuffix(".rprpr.yaml")] = [path]
    rng = random.Random(23)
    for kind, _, make in bench_hard.KINDS:
        for i in range(per_kind):
            path = folder / f"{kind.replace(' ', '_').replace('/', '_')}_{i}.rprpr.yaml"
            path.write_text(make(rng) + LIMIT, encoding="utf-8")
            out.setdefault(kind, []).append(path)
    return out


def inner(repeat: int, per_kind: int, only: list[str]) -> dict[str, list[float]]:
    """{kind: [CPU without, with uncertainty; the same with the peak]} [s], each the sum
    over the kind's tasks of the medians, in this interpreter."""
    from bench_hard import cold  # nothing kept from the run before
    from flint import fmpq

    from rprpr import api
    from rprpr.io.loader import load_task
    from rprpr.model.task import Uncertainty

    rel = (fmpq(5, 100),) * 3
    u = Uncertainty(dict.fromkeys((2, 3, 4, 5), rel), fmpq(1, 100), fmpq(1, 1000))
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        for kind, paths in tasks(Path(tmp), per_kind).items():
            if only and not any(o in kind for o in only):
                continue
            sums = [0.0] * 4
            for path in paths:
                task = load_task(path)
                for k, peak in enumerate((False, True)):
                    api.audit(task, peak=peak)
                    api.audit(task, peak=peak, uncertainty=u)
                    plain, robust = [], []
                    for _ in range(repeat):
                        cold()
                        start = time.process_time()
                        api.audit(task, peak=peak)
                        plain.append(time.process_time() - start)
                        cold()
                        start = time.process_time()
                        api.audit(task, peak=peak, uncertainty=u)
                        robust.append(time.process_time() - start)
                    sums[2 * k] += statistics.median(plain)
                    sums[2 * k + 1] += statistics.median(robust)
            out[kind] = sums
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=5, help="runs of each; the median (5)")
    ap.add_argument("--per-kind", type=int, default=2, help="tasks of each hard-mix kind (2)")
    ap.add_argument("--only", action="append", default=[], metavar="TEXT",
                    help="only the kinds whose name holds TEXT")  # fmt: skip
    ap.add_argument("--vs", action="append", default=[], metavar="NAME=PYTHON",
                    help="another install to measure side by side")  # fmt: skip
    ap.add_argument("--inner", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.inner:
        print(json.dumps(inner(args.repeat, args.per_kind, args.only)))
        return 0
    pythons = [("this tree", sys.executable)] + [tuple(v.split("=", 1)) for v in args.vs]
    for name, python in pythons:
        argv = [python, __file__, "--inner", "--repeat", str(args.repeat),
                "--per-kind", str(args.per_kind)] + [f"--only={o}" for o in args.only]  # fmt: skip
        done = subprocess.run(argv, capture_output=True, text=True, check=True, cwd="/")
        print(f"{name}: CPU per kind [ms], without -> with uncertainty (ratio)")
        print(f"  {'kind':42s} {'default':>28s} {'--peak':>28s}")
        worst = [0.0, 0.0]
        for kind, (a, b, c, d) in json.loads(done.stdout).items():
            worst = [max(worst[0], b / a), max(worst[1], d / c)]
            print(
                f"  {kind:42s} {1000 * a:8.1f} -> {1000 * b:7.1f} ×{b / a:5.1f}"
                f" {1000 * c:8.1f} -> {1000 * d:7.1f} ×{d / c:5.1f}"
            )
        print(f"  {'largest ratio':42s} {'×' + format(worst[0], '.1f'):>28s}"
              f" {'×' + format(worst[1], '.1f'):>28s}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""In-process cost of certification: the float sampler against the certified one, and the
grid-free torque verdicts (peak, limit check) per task.

For each task: ``sampling.sample`` (today's float pass), the vectorised ball pass alone,
``CertifiedMotion.sample`` (ball pass + zone forms + arb refinement where needed) on the
same grid, and the verdicts of a fresh ``Envelope``: ``torque_peak`` then
``limit_violations`` (the task's ``torque_limit``, else 0.9 of the peak so that the check
has crossings to bracket), median of ``--repeat`` runs each on a new ``Envelope``.

    python benchmarks/bench_certified.py [--samples N] [--repeat R] [CONFIG|FOLDER ...]
    python benchmarks/bench_certified.py --verdicts-only /tmp/envtasks   # a bench_many folder

With ``--verdicts-only`` only the verdicts are timed, and a summary (median, 90th
percentile, worst, worst/median) closes the listing.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from collections.abc import Callable
from pathlib import Path

from rprpr.engine.bounds.envelope import Envelope
from rprpr.engine.certified.balls import quiet
from rprpr.engine.certified.motion import CertifiedMotion
from rprpr.engine.certified.sampling import grid, sample
from rprpr.engine.exact.kept import clear
from rprpr.engine.exact.singular import analyse
from rprpr.engine.exact.trajectory import trajectory
from rprpr.io.loader import parse_task
from rprpr.model.errors import RprprError

ROOT = Path(__file__).resolve().parent.parent


def median_ms(f: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        clear()  # nothing kept between audits from the run before (``exact.kept``)
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def verdicts(motion: CertifiedMotion, limit: tuple[float, float] | None) -> tuple[str, float]:
    """The peak and the limit check on a fresh Envelope: (a summary, the time in ms)."""
    t0 = time.perf_counter()
    env = Envelope(motion)
    peak = env.torque_peak()
    pair = limit
    if pair is None and peak is not None and all(math.isfinite(p.value) for p in peak):
        pair = (0.9 * peak[0].value, 0.9 * peak[1].value)
    checks = env.limit_violations(pair) if pair is not None else None
    ms = 1e3 * (time.perf_counter() - t0)
    text = "peak None"
    if peak is not None:
        text = f"peak ({peak[0].value:.6g}, {peak[1].value:.6g} N m)"
        text += "" if all(p.certified for p in peak) else " NOT CERTIFIED"
    if checks is not None:
        text += f"; limit {[c.passed for c in checks]}"
    return text, ms


def measure(name: str, samples: int, repeat: int, only: bool) -> tuple[str, float]:
    """One line of costs for the task file ``name``, and the verdicts' time in ms."""
    task = parse_task(Path(name).read_text(encoding="utf-8"), name)
    traj = trajectory(task)
    analysis = analyse(traj, task.robot, task.checks)
    motion = CertifiedMotion(traj, task.robot, analysis)
    limit = task.checks.torque_limit
    pair = (float(limit[0]), float(limit[1])) if limit is not None else None
    text, _ = verdicts(motion, pair)
    env_ms = median_ms(lambda: verdicts(motion, pair), repeat)
    line = f"{Path(name).name}: verdicts {env_ms:.2f} ms, {text}"
    if only:
        return line, env_ms
    t = grid(task.duration, samples)

    def ball_pass() -> object:
        with quiet():
            return motion.ball_pass(t)

    flt = median_ms(lambda: sample(traj, task.robot, analysis, t), repeat)
    ball = median_ms(ball_pass, repeat)
    cert = median_ms(lambda: motion.sample(t), repeat)
    line += (
        f"; float {flt:.2f} ms, ball pass {ball:.2f} ms ({ball / flt:.1f}x),"
        f" certified {cert:.2f} ms ({cert / flt:.1f}x)"
    )
    return line, env_ms


def _files(args: list[str]) -> list[str]:
    out = []
    for a in args:
        p = Path(a)
        if p.is_dir():
            out += sorted(str(f) for f in p.rglob("*") if f.suffix in (".yaml", ".yml"))
        else:
            out.append(a)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--samples", type=int, default=1001)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--verdicts-only", action="store_true")
    ap.add_argument("configs", nargs="*")
    args = ap.parse_args()
    configs = _files(args.configs) or sorted(str(p) for p in (ROOT / "configs").glob("*.yaml"))
    times = []
    for name in configs:
        try:
            line, ms = measure(name, args.samples, args.repeat, args.verdicts_only)
        except RprprError:
            continue  # an invalid task file (bench_many writes a few)
        times.append((ms, name))
        print(line)
    if len(times) > 1:
        ms = sorted(t for t, _ in times)
        med = statistics.median(ms)
        worst, where = max(times)
        print(
            f"verdicts over {len(ms)} tasks: median {med:.2f} ms, 90th percentile"
            f" {ms[int(0.9 * (len(ms) - 1))]:.2f} ms, worst {worst:.2f} ms"
            f" ({worst / med:.1f}x the median, {Path(where).name})"
        )


if __name__ == "__main__":
    main()

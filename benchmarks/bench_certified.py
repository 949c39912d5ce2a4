"""In-process cost of certification: the float sampler against the certified one, and the
grid-free torque verdicts (peak, limit check) per task.

For each task: ``sampling.sample`` (today's float pass), the vectorised ball pass alone,
``CertifiedMotion.sample`` (ball pass + zone forms + arb refinement where needed) on the
same grid, and ``Envelope.torque_peak`` / ``limit_violations`` (median of ``--repeat``
runs for the sampling, one run each for the verdicts, which are cached per task).

    python benchmarks/bench_certified.py [--samples N] [--repeat R] [CONFIG ...]
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from pathlib import Path

from rprpr.engine.balls import quiet
from rprpr.engine.certified import CertifiedMotion
from rprpr.engine.envelope import Envelope
from rprpr.engine.sampling import grid, sample
from rprpr.engine.singular import analyse
from rprpr.engine.trajectory import trajectory
from rprpr.io.loader import parse_task

ROOT = Path(__file__).resolve().parent.parent


def median_ms(f: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times)


def once_s(f: Callable[[], object]) -> tuple[float, object]:
    t0 = time.perf_counter()
    out = f()
    return time.perf_counter() - t0, out


def measure(name: str, samples: int, repeat: int) -> str:
    """One line of costs for the task file ``name``."""
    task = parse_task(Path(name).read_text(encoding="utf-8"), name)
    traj = trajectory(task)
    analysis = analyse(traj, task.robot, task.checks)
    t = grid(task.duration, samples)
    motion = CertifiedMotion(traj, task.robot, analysis)

    def ball_pass() -> object:
        with quiet():
            return motion.ball_pass(t)

    flt = median_ms(lambda: sample(traj, task.robot, analysis, t), repeat)
    ball = median_ms(ball_pass, repeat)
    cert = median_ms(lambda: motion.sample(t), repeat)
    env = Envelope(motion)
    t_peak, peak = once_s(env.torque_peak)
    line = (
        f"{Path(name).name}: float {flt:.2f} ms, ball pass {ball:.2f} ms ({ball / flt:.1f}x),"
        f" certified {cert:.2f} ms ({cert / flt:.1f}x); peak {t_peak:.2f} s"
    )
    if peak is not None:
        line += f" ({peak[0].value:.6g}, {peak[1].value:.6g} N m)"  # type: ignore[index]
    limit = task.checks.torque_limit
    if limit is not None:
        pair = (float(limit[0]), float(limit[1]))
        t_lim, checks = once_s(lambda: env.limit_violations(pair))
        line += f"; limit {t_lim:.2f} s {[c.passed for c in checks]}"  # type: ignore[attr-defined]
    return line


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument("--samples", type=int, default=1001)
    ap.add_argument("--repeat", type=int, default=31)
    ap.add_argument("configs", nargs="*")
    args = ap.parse_args()
    configs = args.configs or sorted(str(p) for p in (ROOT / "configs").glob("*.yaml"))
    for name in configs:
        print(measure(name, args.samples, args.repeat))


if __name__ == "__main__":
    main()

"""Float planner output for the robust verdicts' tests (``docs/robust.md``): writes
``plans.json`` beside this file. Not run by the test suite; scipy and ruckig are not
dependencies of rprpr. To regenerate, in a throwaway environment:

    python3 -m venv /tmp/planners
    /tmp/planners/bin/pip install scipy ruckig numpy
    /tmp/planners/bin/python tests/corpora/planners/generate.py

Every plan is for the paper's path 2 robot (``configs/paper_path2.rprpr.yaml``: legs
alike, so a crossing of AB at (3, 0) is consistent exactly when ẍ = 0 there) and runs
from (2, -1) to (4, 1), at rest at both ends:

* ``cubic_spline``: scipy's ``CubicSpline`` through the path 2 motion's positions at
  t = 0, 1.25, 2.5, 3.75, 5 s, clamped (zero velocity at the ends). The data are odd
  about (2.5 s; 3, 0), so the spline is too: it crosses at the knot t = 2.5 s with
  ẍ = 0, consistently — in exact arithmetic.
* ``interp_spline``: scipy's ``make_interp_spline`` (k = 5) through the same positions,
  first and second derivatives zero at both ends, as a ``PPoly``: odd alike.
* ``ruckig_line``: a Ruckig plan with phase synchronisation (a straight line y = x - 3),
  crossing at its middle, where its profile is symmetric: ẍ = 0.
* ``ruckig_flat``: two Ruckig plans joined at (3, 0), the first asked to arrive there
  with velocity (0.75, 0) and zero acceleration (zero vertical velocity: the vertical
  motion is flat there, of order 3 about the junction, a high-order crossing with zero
  slope), the second to go on from that state to (4, 1).

Each plan is written in scipy's PPoly layout (``breaks``, and per axis ``x[j][i]``,
``y[j][i]``: the coefficient of (t - breaks[i])^(k - 1 - j)), every number a double
written by ``repr`` (which reads back to the same double), with the versions of the
planners that made it. A Ruckig profile's phases are cubics in time; the pieces are
the union of both axes' phase boundaries, each axis's cubic re-expanded at a piece's
start in doubles (position, velocity and acceleration from ``Trajectory.at_time`` there,
the phase's jerk from its profile), as a consumer of Ruckig's output would.
"""

from __future__ import annotations

import importlib.metadata
import itertools
import json
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
T_F = 5.0


def path2(t: float) -> tuple[float, float]:
    """The paper's path 2 motion at t, in doubles: the quintic timing law from x = 2 to
    4 over 5 s and y = 0.8 (x - 3)^3 + 0.2 (x - 3)."""
    u = Fraction(t) / 5
    x = 2 + 2 * (10 * u**3 - 15 * u**4 + 6 * u**5)
    y = Fraction(4, 5) * (x - 3) ** 3 + Fraction(1, 5) * (x - 3)
    return float(x), float(y)


def splines() -> dict[str, Any]:
    import numpy as np
    from scipy.interpolate import CubicSpline, PPoly, make_interp_spline

    t = np.array([0.0, 1.25, 2.5, 3.75, T_F])
    xy = np.array([path2(v) for v in t])
    cubic = CubicSpline(t, xy, bc_type="clamped")
    zero = [(1, 0.0), (2, 0.0)]
    axes = [
        PPoly.from_spline(make_interp_spline(t, xy[:, i], k=5, bc_type=(zero, zero)))
        for i in (0, 1)
    ]
    keep = [i for i in range(len(axes[0].x) - 1) if axes[0].x[i + 1] > axes[0].x[i]]
    quintic = {
        "planner": "scipy.interpolate.make_interp_spline(k=5), PPoly.from_spline",
        "breaks": [float(axes[0].x[i]) for i in keep] + [float(axes[0].x[keep[-1] + 1])],
        "x": [[float(row[i]) for i in keep] for row in axes[0].c],
        "y": [[float(row[i]) for i in keep] for row in axes[1].c],
    }
    assert list(axes[0].x) == list(axes[1].x)
    return {
        "cubic_spline": _ppoly(cubic, "scipy.interpolate.CubicSpline(bc_type='clamped')"),
        "interp_spline": quintic,
    }


def _ppoly(p: Any, how: str) -> dict[str, Any]:
    c = p.c  # (k, m, 2)
    return {
        "planner": how,
        "breaks": [float(v) for v in p.x],
        "x": [[float(v) for v in row[:, 0]] for row in c],
        "y": [[float(v) for v in row[:, 1]] for row in c],
    }


def _ruckig(start: Any, target: Any, sync: Any = None) -> Any:
    from ruckig import InputParameter, Result, Ruckig, Trajectory

    otg = Ruckig(2)
    inp = InputParameter(2)
    inp.current_position, inp.current_velocity, inp.current_acceleration = start
    inp.target_position, inp.target_velocity, inp.target_acceleration = target
    inp.max_velocity = [1.0, 1.0]
    inp.max_acceleration = [0.5, 0.5]
    inp.max_jerk = [1.0, 1.0]
    if sync is not None:
        inp.synchronization = sync
    tr = Trajectory(2)
    result = otg.calculate(inp, tr)
    assert result == Result.Working, result
    return tr


def _pieces(trajectories: list[Any], how: str) -> dict[str, Any]:
    """Consecutive Ruckig trajectories as one PPoly (cubic pieces)."""
    breaks: list[float] = [0.0]
    cx: list[list[float]] = [[], [], [], []]
    cy: list[list[float]] = [[], [], [], []]
    offset = 0.0
    for tr in trajectories:
        bounds = {0.0, tr.duration}
        jerks = []
        for dof in range(2):
            (profile,) = [tr.profiles[0][dof]]
            assert not any(profile.brake.t), "a braking pre-profile: not expected here"
            at, ends = 0.0, []
            for dt, j in zip(profile.t, profile.j, strict=True):
                if dt > 0:
                    ends.append((at, at + dt, j))
                    bounds.add(at + dt)
                at += dt
            jerks.append(ends)
        cuts = sorted(b for b in bounds if 0 <= b <= tr.duration)
        for a, b in itertools.pairwise(cuts):
            if b - a <= 0:
                continue
            p, v, acc = tr.at_time(a)
            for dof, out in ((0, cx), (1, cy)):
                j = next((jj for lo, hi, jj in jerks[dof] if lo <= (a + b) / 2 < hi), 0.0)
                out[0].append(j / 6)
                out[1].append(acc[dof] / 2)
                out[2].append(v[dof])
                out[3].append(p[dof])
            breaks.append(offset + b)
        offset += tr.duration
    return {"planner": how, "breaks": breaks, "x": cx, "y": cy}


def ruckig_plans() -> dict[str, Any]:
    from ruckig import Synchronization

    rest = [0.0, 0.0]
    line = _ruckig(([2.0, -1.0], rest, rest), ([4.0, 1.0], rest, rest), Synchronization.Phase)
    first = _ruckig(([2.0, -1.0], rest, rest), ([3.0, 0.0], [0.75, 0.0], rest))
    p, v, a = first.at_time(first.duration)
    second = _ruckig((list(p), list(v), list(a)), ([4.0, 1.0], rest, rest))
    return {
        "ruckig_line": _pieces([line], "ruckig.Ruckig, Synchronization.Phase"),
        "ruckig_flat": _pieces([first, second], "ruckig.Ruckig, two plans joined at (3, 0)"),
    }


def main() -> None:
    versions = {name: importlib.metadata.version(name) for name in ("scipy", "numpy", "ruckig")}
    plans = {**splines(), **ruckig_plans()}
    data = {
        "generated_by": "tests/corpora/planners/generate.py",
        "python": sys.version.split()[0],
        "versions": versions,
        "plans": plans,
    }
    text = json.dumps(data, indent=1) + "\n"
    (HERE / "plans.json").write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()

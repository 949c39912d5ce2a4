"""A 5R motion on a grid of times, every number certified (``rprpr export``, the Python API).

Each value at a time t (the double t, taken exactly) is within a proven bound of the true
value of the 5R's formulas (``exact.five_bar``) at t: mixed error <= TOL (1 + |value|), as
the RPRPR's samples (``certified.pointwise``), or NaN with a reason code (``REASONS``,
the RPRPR's codes where the meaning is the same). It is computed alone in ball arithmetic
at 128 bits, the precision doubled up to 4096 until certified; exactly at a rational
Type II instant, δ is 0 and the torques are their limits there (the Taylor form about
t_s: a_k/δ_m) or undefined (a pole). A value at t depends on t alone.

The angles are the motors' θ1 = angle of C - A and θ2 = angle of D - B, continuous from
their principal values at t = 0 (``five_bar_angles``: the turns decided exactly).
``alpha`` is the distal links' axial force α = ν/δ [N] (the part of the force of leg 2
on leg 1 at E along link 3, the one that blows up at a pole).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from flint import arb, ctx, fmpq

from ...model.dataclass import dataclass
from ..exact import five_bar as fb
from .five_bar import FiveBarMotion
from .five_bar_angles import Crossing, crossings, turns
from .pointwise import BEYOND_DOUBLE, MAX_PREC, OK, POLE, START_PREC, TOL, UNCERTIFIED

TYPE_ONE = 7  # the inverse kinematics fail: a leg stretched or folded, or E out of reach

REASONS = {
    OK: "",
    POLE: "a Type II instant with unbounded torques (a pole of alpha): alpha, T1, T2 undefined",
    UNCERTIFIED: f"not certified to {TOL:g} at {MAX_PREC} bits: no value",
    BEYOND_DOUBLE: "beyond the double range: |value| > 1.8e308 (certified)",
    TYPE_ONE: "a leg stretched or folded, or E out of its reach (Type I), or past the first"
    " Type I instant (the working mode is lost): the joints, δ, alpha and T undefined",
}

# the export columns of a 5R, in order (SI units, angles in radians); the accelerations
# last, as the RPRPR's
COLUMNS = (
    "t", "x", "y", "x_dot", "y_dot", "theta1", "theta2", "theta1_dot", "theta2_dot",
    "delta", "delta_dot", "alpha", "T1", "T2",
    "x_ddot", "y_ddot", "theta1_ddot", "theta2_ddot",
)  # fmt: skip
PATH = ("x", "y", "x_dot", "y_dot", "x_ddot", "y_ddot")
FIELDS = COLUMNS[1:]
LOOSE = ("alpha", "T1", "T2")  # undefined at a pole


@dataclass(frozen=True)
class FiveBarSamples:
    """Sampled 5R motion: one numpy array per column of ``COLUMNS``, all of the length of
    ``t``; ``reason`` holds one code of ``REASONS`` per sample (0: every value certified)."""

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    x_dot: np.ndarray
    y_dot: np.ndarray
    theta1: np.ndarray
    theta2: np.ndarray
    theta1_dot: np.ndarray
    theta2_dot: np.ndarray
    delta: np.ndarray
    delta_dot: np.ndarray
    alpha: np.ndarray
    T1: np.ndarray
    T2: np.ndarray
    x_ddot: np.ndarray
    y_ddot: np.ndarray
    theta1_ddot: np.ndarray
    theta2_ddot: np.ndarray
    reason: np.ndarray

    COLUMNS = COLUMNS
    REASONS = REASONS

    def column(self, name: str) -> np.ndarray:
        return getattr(self, name)

    def rows(self) -> np.ndarray:
        """The export columns as a 2-D array, one row per sample."""
        return np.column_stack([self.column(c) for c in COLUMNS])


def sample(motion: FiveBarMotion, t: np.ndarray) -> FiveBarSamples:
    """The 5R motion at the times ``t`` [s], certified (module docstring)."""
    out = {n: np.full(len(t), math.nan) for n in FIELDS}
    reason = np.zeros(len(t), dtype=int)
    cross = (crossings(motion, 1), crossings(motion, 2)) if len(t) else ([], [])
    for j, tj in enumerate(t.tolist()):
        values, code = at_time(motion, tj, cross)
        for n, v in values.items():
            out[n][j] = v
        reason[j] = code
    return FiveBarSamples(t=np.array(t, dtype=float), reason=reason, **out)


def at_time(
    motion: FiveBarMotion, t: float, cross: tuple[list[Crossing], list[Crossing]] | None = None
) -> tuple[dict[str, float], int]:
    """The certified values at the double ``t`` (absolute: ``motion.start`` taken off
    exactly) and the row's reason code; ``cross``: the
    legs' crossings of the angles' cut (``five_bar_angles.crossings``; none: principal
    angles)."""
    tq = fmpq(*t.as_integer_ratio()) - motion.start  # the motion's own (local) time
    exact = [p(tq) for p in motion.polys]
    path = [exact[i] for i in (0, 3, 1, 4, 2, 5)]  # x, y, x', y', x'', y''
    out = {n: _exact_float(v) for n, v in zip(PATH, path, strict=True)}
    c = fb.conjugates(motion.exact, exact[0], exact[3])
    if not (c.D1 > 0 and c.D2 > 0):
        return out, TYPE_ONE
    at = next((s for s in motion.instants if s.t_exact == tq), None)
    todo = [n for n in FIELDS if n not in PATH]
    on_cut = _on_cut(cross, tq)
    for name, v in on_cut.items():
        out[name] = v
        todo.remove(name)
    bits, beyond = START_PREC, False
    while todo and bits <= MAX_PREC:
        with ctx.workprec(bits):
            got = _balls(motion, tq, at)
        for n in list(todo):
            b = got.get(n)
            if b is None:
                continue
            if b.is_finite() and b.rad() <= TOL * (1 + abs(b.mid())):
                v = float(b.mid())
                if not math.isfinite(v):
                    beyond = True
                out[n] = v
                todo.remove(n)
        bits *= 2
    for i, name in ((0, "theta1"), (1, "theta2")):
        if cross is not None and name not in on_cut and math.isfinite(out[name]):
            out[name] = turns(cross[i], tq, out[name])
    if at is not None and not at.bounded:
        return out, POLE
    if todo:
        return out, UNCERTIFIED
    return out, BEYOND_DOUBLE if beyond else OK


def _on_cut(cross: tuple[list[Crossing], list[Crossing]] | None, t: fmpq) -> dict[str, float]:
    """θ_i at a time at which leg i's elbow is on the angles' cut (the limit from before:
    its principal ball would straddle ±π)."""
    out = {}
    for i, name in ((0, "theta1"), (1, "theta2")):
        if cross is not None and any(c.compare(t) == 0 for c in cross[i]):
            out[name] = turns(cross[i], t, math.nan)
    return out


def _exact_float(v: fmpq) -> float:
    return int(v.p) / int(v.q)


def _balls(motion: FiveBarMotion, tq: fmpq, at: Any) -> dict[str, arb]:
    """The joints, δ, α and the torques at the exact time ``tq`` as balls; at a Type II
    instant ``at``, δ = 0 and α, T their limits (none at a pole)."""
    e = motion.evaluate(arb(tq))
    l1, l2 = e.d.leg1, e.d.leg2
    out = {
        "theta1": arb.atan2(l1.c[1], l1.c[0]), "theta2": arb.atan2(l2.c[1], l2.c[0]),
        "theta1_dot": l1.th_d, "theta2_dot": l2.th_d,
        "theta1_ddot": l1.th_dd, "theta2_ddot": l2.th_dd,
        "delta": e.d.delta, "delta_dot": fb.delta_rate(e.d),
    }  # fmt: skip
    if at is not None:
        out["delta"] = arb(0)
        if at.bounded:
            z = motion.zone(at)
            out["T1"], out["T2"] = motion.limit_at(at)
            out["alpha"] = z.nu[0] / z.q[0]
        return out
    if not e.d.delta.contains(0):
        T = e.torques()
        out.update(alpha=e.d.nu / e.d.delta, T1=T[0], T2=T[1])
    return out

"""A 5R task on the sheet and in the GIF: its audit read for drawing and its samples
(docs/five-bar.md); its curves and links are drawn by ``five_bar_robot``, and what the
panels draw differently for it is said by ``drawing.FiveBarDrawing``.

``motion`` readies a 5R audit (``engine.five_bar_audit.FiveBarAuditResult``) for the
sheet: ``Drawn`` answers what the panels read of an RPRPR's ``AuditResult`` (its
instants as ``Mark``s, each instant's status, the Type I instants with their place), and
``samples`` evaluates the motion, the joints, δ and the torques on a grid, in doubles,
through the engine's 5R formulas (``engine.exact.five_bar``, generic over number types):
what is drawn as curves. Every mark and every number written comes from the audit's
records (``report.five_bar_records``), never from these samples.

The 5R's δ on the sheet is (E − C) × (E − D)/(l3 l4), the sine of the angle between the
distal links (dimensionless, as the RPRPR's sin(θ1 − θ2)); its joints are the motors'
angles θ1, θ2 (links 1 and 2 from the x axis) and the distal links' angles φ1, φ2 (links
3 and 4); C and D are the elbows.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass as std_dataclass
from typing import Any

import numpy as np
from flint import fmpq_poly

from ...engine.certified.sampling import Samples, grid
from ...engine.exact import five_bar as fb
from ...engine.exact.five_bar_instants import FiveBarInstant, TypeOne
from ...engine.exact.singular import Principle
from ...engine.five_bar_audit import FiveBarAuditResult
from ...model.dataclass import dataclass
from ...model.defaults import DEFAULT_SAMPLES
from ...model.numbers import to_float
from ...model.task import Task
from ...report.five_bar_records import value

# -- the audit, read for drawing -----------------------------------------------------------


@dataclass(frozen=True)
class Mark:
    """A 5R Type II instant as the sheet draws it: at (x, y) at t, its order, principles
    and torques, every number from the audit's records (``instant``, the engine's)."""

    instant: FiveBarInstant
    t: float
    x: float
    y: float
    order: int
    torque_bounded: bool
    pole_order: int
    torque_at_singularity: tuple[float, float] | None
    slope_principle: Principle
    velocity_principle: Principle

    @property
    def high_order(self) -> bool:
        return self.order >= 2


def mark_of(s: FiveBarInstant) -> Mark:
    """``s`` as drawn: its record's numbers (``report.five_bar_records.value``)."""
    limit = s.torque_at_singularity
    pair = None
    if limit is not None:
        t1, t2 = value(limit[0]), value(limit[1])
        pair = None if t1 is None or t2 is None else (t1, t2)
    return Mark(
        s, s.t, s.x, s.y, s.order, s.bounded, s.order - s.conditions_met, pair,
        s.slope_principle, s.velocity_principle,
    )  # fmt: skip


@dataclass(frozen=True)
class Kinematic:
    """A Type I instant (a leg stretched or folded) with E's place there."""

    t: float
    x: float
    y: float
    leg: int
    kind: str


def kinematic_of(k: TypeOne, x: fmpq_poly, y: fmpq_poly) -> Kinematic:
    """``k`` with E = (x(t), y(t)) there: exactly at a rational instant, else at its double."""
    if k.t_exact is not None:
        return Kinematic(k.t, to_float(x(k.t_exact)), to_float(y(k.t_exact)), k.leg, k.kind)
    xs, ys = (_polyval(p, np.array([k.t]))[0][0] for p in (x, y))
    return Kinematic(k.t, float(xs), float(ys), k.leg, k.kind)


class Drawn:
    """A 5R audit as the sheet reads an ``AuditResult``: ``singularities`` (``Mark``s),
    ``status_of``, ``kinematic_singularities``, the verdict, findings and knots; what
    the sheet does not draw of a 5R (its torque peak and limit) or a 5R audit does not
    have (a near miss, robust bands) is absent; ``resample`` gives the drawing's samples
    (``samples``)."""

    mechanism = fb.FIVE_BAR.name

    def __init__(self, result: FiveBarAuditResult, grid_size: int = DEFAULT_SAMPLES) -> None:
        self.audit = result
        self.task: Task = result.task
        self.grid_size = grid_size
        self.singularities = tuple(mark_of(s) for s in result.singularities)
        pieces = result.task.motion
        self.kinematic_singularities = tuple(
            kinematic_of(k, pieces[k.piece].x, pieces[k.piece].y) for k in result.type_one
        )
        self.findings = result.findings
        self.strict = result.strict
        self.on_singular_line = result.on_singular_curve
        self.closest_approach = None
        self.torque_peak = None
        self.torque_limit = None
        self.robust: tuple[Any, ...] = ()
        self.knot_jumps: tuple[Any, ...] = result.knot_jumps
        self.parts: tuple[Any, ...] = ()

    @property
    def verdict(self) -> str:
        return self.audit.verdict

    @property
    def samples(self) -> Samples:
        return self.resample(grid(self.task.duration, self.grid_size))

    def resample(self, t: np.ndarray) -> Samples:
        return samples(self, np.asarray(t, dtype=float))

    def status_of(self, s: Mark) -> str:
        """ "fail", "warn" or "ok": the audit's findings at the instant (as ``AuditResult``)."""
        hits = self.audit.findings_at(s.instant)
        if any(f.fails(self.strict) for f in hits):
            return "fail"
        return "warn" if hits else "ok"


# -- the samples ---------------------------------------------------------------------------


@std_dataclass(frozen=True)
class FiveBarSamples(Samples):
    """``Samples`` of a 5R motion (s1, s2 are |AE|, |BE|; λ is not sampled: NaN), with
    the elbows C = (cx, cy), D = (dx, dy) [m] and the distal links' angles φ1, φ2 [rad]."""

    cx: np.ndarray
    cy: np.ndarray
    dx: np.ndarray
    dy: np.ndarray
    phi1: np.ndarray
    phi2: np.ndarray


def _polyval(p: fmpq_poly, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """p, p', p'' at the times ``t`` in doubles."""
    out = []
    for q in (p, p.derivative(), p.derivative().derivative()):
        cs = [to_float(c) for c in q.coeffs()] or [0.0]
        out.append(np.polynomial.polynomial.polyval(t, cs))
    return out[0], out[1], out[2]


def _motion_at(task: Task, t: np.ndarray) -> tuple[np.ndarray, ...]:
    """x, x', x'', y, y', y'' at the times ``t`` in doubles, each time from the piece that
    holds it (the first at a knot; in the piece's local time when the task gives it)."""
    out = [np.full_like(t, np.nan) for _ in range(6)]
    pieces = task.motion
    for k, piece in enumerate(pieces):
        lo, hi = to_float(piece.start), to_float(piece.end)
        at = (t >= lo) & ((t < hi) | (k == len(pieces) - 1) & (t <= hi))
        if k == 0:
            at |= t < lo
        if k == len(pieces) - 1:
            at |= t > hi
        if not np.any(at):
            continue
        local = piece.local
        if local is not None:
            u, (px, py) = t[at] - lo, local
        else:
            u, px, py = t[at], piece.x, piece.y
        for i, v in enumerate(_polyval(px, u) + _polyval(py, u)):
            out[i][at] = v
    return tuple(out)


def samples(d: Drawn, t: np.ndarray) -> FiveBarSamples:
    """The 5R motion at the times ``t`` [s] in doubles (the drawing's curves): E and its
    rates, the joints, δ/(l3 l4) and the torques from ``engine.exact.five_bar``'s formulas
    with numpy arrays for numbers; NaN where a leg cannot reach. At a bounded Type II
    instant the torques are the audit's limits, at an unbounded one ±inf (drawn as a gap).
    This is the one place the sheet's 5R samples come from."""
    task = d.task
    robot = task.robot
    assert robot.five_bar is not None
    p = fb.params(robot.five_bar, robot.gravity, to_float)
    x, xd, xdd, y, yd, ydd = _motion_at(task, t)
    modes = (int(robot.five_bar.modes[0]), int(robot.five_bar.modes[1]))
    with np.errstate(all="ignore"):
        legs = fb.legs(p, modes, x, xd, xdd, y, yd, ydd, lambda D, i: np.sqrt(D))
        dyn = fb.dynamics(legs[0], legs[1], p)
        T1, T2 = fb.torques(dyn)
        T1, T2 = np.array(T1, dtype=float), np.array(T2, dtype=float)
        delta = np.asarray(dyn.delta, dtype=float) / (p.l[2] * p.l[3])
    for s in d.singularities:
        at = t == s.t
        if not np.any(at):
            continue
        delta[at] = 0.0
        if s.torque_at_singularity is not None:
            T1[at], T2[at] = s.torque_at_singularity
        else:
            T1[at], T2[at] = np.nan, np.nan
    l1, l2 = legs
    c1, c2 = l1.c, l2.c
    nan = np.full_like(t, np.nan)

    def angle(v: tuple[Any, Any]) -> np.ndarray:
        a = np.arctan2(np.asarray(v[1], dtype=float), np.asarray(v[0], dtype=float))
        ok = np.isfinite(a)
        a[ok] = np.unwrap(a[ok])
        return a

    reach = np.isfinite(np.asarray(c1[0], dtype=float)) & np.isfinite(np.asarray(c2[0], float))
    return FiveBarSamples(
        t=t, x=x, y=y, x_dot=xd, y_dot=yd, x_ddot=xdd, y_ddot=ydd,
        theta1=angle(c1), s1=np.hypot(x, y), theta2=angle(c2), s2=np.hypot(x - p.a, y),
        theta1_dot=np.asarray(l1.th_d, float), s1_dot=nan, theta2_dot=np.asarray(l2.th_d, float),
        s2_dot=nan, theta1_ddot=np.asarray(l1.th_dd, float), s1_ddot=nan,
        theta2_ddot=np.asarray(l2.th_dd, float), s2_ddot=nan,
        delta=delta, delta_dot=nan, lambda1=nan, lambda2=nan, T1=T1, T2=T2,
        reason=np.where(reach, 0, 1).astype(np.int8),
        cx=np.asarray(c1[0], float), cy=np.asarray(c1[1], float),
        dx=np.asarray(c2[0], float) + p.a, dy=np.asarray(c2[1], float),
        phi1=angle(l1.d), phi2=angle(l2.d),
    )  # fmt: skip


def elbows(m: Any) -> np.ndarray:
    """Every elbow position sampled (rows (x, y)): part of what the workspace shows."""
    s = m.s
    pts = np.concatenate([np.column_stack([s.cx, s.cy]), np.column_stack([s.dx, s.dy])])
    return pts[np.all(np.isfinite(pts), axis=1)]


def motion(result: FiveBarAuditResult, source: str, grid_size: int) -> tuple[Drawn, Samples]:
    """The 5R audit ``result`` ready to draw: ``Drawn`` and its samples on ``grid_size``
    times with every Type II instant added and, about an unbounded one, t_s ± 10^-k t_f
    (k = 3..8), as the RPRPR's (``sheet.motion``)."""
    d = Drawn(result, grid_size)
    t = grid(result.task.duration, grid_size)
    tf = float(t[-1])
    extra = [s.t for s in d.singularities] + [k.t for k in d.kinematic_singularities]
    for s in d.singularities:
        if not s.torque_bounded:
            near = s.t + tf * np.outer([-1, 1], 10.0 ** -np.arange(3, 9)).ravel()
            extra += [float(v) for v in near if 0 < v < tf]
    return d, d.resample(np.union1d(t, extra) if extra else t)


def kinds(motions: Sequence[Any]) -> tuple[bool, bool]:
    """Whether ``motions`` hold an RPRPR's, and whether a 5R's (the headings say which)."""
    five = sum(is_five_bar(m) for m in motions)
    return five < len(motions), five > 0


def is_five_bar(m: Any) -> bool:
    """Whether the motion ``m`` is a 5R's."""
    return isinstance(m.result, Drawn)


__all__ = [
    "Drawn",
    "FiveBarSamples",
    "Mark",
    "elbows",
    "is_five_bar",
    "motion",
    "samples",
]

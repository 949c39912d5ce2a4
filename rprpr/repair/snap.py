"""Failing instants at irrational times moved to short decimal ones, so that the exact
bumps can be centred on them."""

from __future__ import annotations

from flint import fmpq

from ..engine.audit import AuditResult
from ..engine.singular import SingularInstant
from ..model.task import Piece, Task
from .plan import Plan
from .records import Change, NoRepair
from .windows import half_way, short


def snap_plans(
    task: Task,
    before: AuditResult,
    instants: list[SingularInstant],
    keep: str | None,
    window: fmpq | None,
) -> list[Plan]:
    """Failing instants at irrational times (roots of an irreducible factor of y(t) of
    degree >= 2, as a quintic law's crossing of a rational point usually is) moved to a
    short decimal t_r within 10^-4 t_f of t_s, so that the exact bumps can be centred on
    them: with the path given and the crossing point x_s rational, the timing is moved,
    Δx = (x_s - x(t_r)) W (W = (1 - ((t - t_r)/w)²)³: x(t_r) = x_s, x' and the rest of
    the motion kept, a change of order |x'| |t_r - t_s|); otherwise the path, Δy =
    -y(t_r) W. Then the moved instants are repaired as rational ones (``repair``)."""
    plans = []
    for s in instants:
        t_r, piece = _rational_near(task, s.t)
        w = _snap_width(task, before, s, t_r, piece, window)
        x0 = h = fmpq(0)
        x_s = _rational_crossing(task, piece, t_r) if keep != "timing" else None
        if x_s is not None:
            x0 = x_s - piece.x(t_r)
        elif keep != "path":
            h = -piece.y(t_r)
        else:
            raise NoRepair(
                f"the singular instant t ≈ {s.t:.6g} s is irrational and its crossing point"
                " too: no exact change of the timing alone moves it to a rational time;"
                " allow a path change (drop --keep path)"
            )
        x_r = piece.x(t_r)
        change = Change(t_r, x_r, w, ("snap",), (fmpq(0), fmpq(0)), (fmpq(0), fmpq(0)),
                        (fmpq(0), fmpq(0)))  # fmt: skip
        plans.append(Plan(t_r, w, fmpq(0), fmpq(0), fmpq(0), h, change, fmpq(0), x0))
    return plans


def _rational_near(task: Task, t: float) -> tuple[fmpq, Piece]:
    """A short decimal t_r within 10^-4 t_f of ``t`` (the fewest digits, so that the
    repaired task's numbers stay short) and the piece holding it."""
    tol = 1e-4 * float(task.duration)
    den = 10
    while abs(round(t * den) / den - t) > tol:
        den *= 10
    t_r = fmpq(round(t * den), den)
    for p in task.motion:
        if p.start < t_r < p.end:
            return t_r, p
    raise NoRepair(f"the singular instant t ≈ {t:.6g} s is too near a knot to be moved")


def _snap_width(task: Task, before: AuditResult, s: SingularInstant, t_r: fmpq, piece: Piece,
                window: fmpq | None) -> fmpq:  # fmt: skip
    """The snap's half-width: the window the repair will use about t_r (``window``, or
    the largest inside the piece and half-way to the other instants)."""
    gap = half_way(before, t_r, min(t_r - piece.start, piece.end - t_r), skip=s)
    w = window if window is not None else short(min(gap, task.duration / 5))
    if not 0 < w <= gap:
        raise NoRepair(f"no room about t ≈ {s.t:.6g} s to move the instant (at most ±{gap} s)")
    return w


def _rational_crossing(task: Task, piece: Piece, t_r: fmpq) -> fmpq | None:
    """The rational root of the path y = p(x) nearest x(t_r) (within 1e-3 m), or None
    (no path, or the crossing point is irrational)."""
    if task.path is None or piece.path is None:
        return None
    x = piece.x(t_r)
    roots = [-f[0] / f[1] for f, _ in task.path.factor()[1] if f.degree() == 1]
    near = [r for r in roots if abs(r - x) < fmpq(1, 10**3)]  # |ẋ| |t_r - t_s| is far less
    return min(near, key=lambda r: abs(r - x)) if near else None

"""What changed, and by how much: a repair's account against the task as given."""

from __future__ import annotations

from typing import TYPE_CHECKING

from flint import fmpq

from ..engine.audit import AuditResult
from ..engine.roots import max_abs
from ..model.task import Piece, Task
from .records import Repair

if TYPE_CHECKING:
    from .plan import Plan


def account(task: Task, new: Task, before: AuditResult, after: AuditResult,
             plans: list[Plan], path_changed: bool | None = None) -> Repair:  # fmt: skip
    """The change's metrics, exact maxima (``roots.max_abs``, an upper bound within
    about 1e-15): max |Δx(t)| over the motion, and max |Δy| at equal x — the new y(t)
    against the old path at the new x(t) (or, without a path, the old y(t))."""
    dxm: tuple[float, float] | None = None
    dym: tuple[float, float] | None = None
    if path_changed is None:
        path_changed = any(p.b != 0 or p.h != 0 or p.ay != 0 for p in plans)
    for q, o, lo, hi in _overlaps(new.motion, task.motion):
        m, t = max_abs(q.x - o.x, lo, hi)
        if m > 0 and (dxm is None or m > dxm[0]):
            dxm = (m, t)
        if path_changed:
            old_y = task.path(q.x) if task.path is not None else o.y
            m, t = max_abs(q.y - old_y, lo, hi)
            if dym is None or m > dym[0]:
                dym = (m, float(q.x(fmpq(*t.as_integer_ratio()))))
    return Repair(new, before, after, tuple(p.change for p in plans), dym, dxm, not path_changed)


Overlap = tuple[Piece, Piece, fmpq, fmpq]


def _overlaps(new: tuple[Piece, ...], old: tuple[Piece, ...]) -> list[Overlap]:
    """(new piece, old piece, lo, hi) for every interval [lo, hi] of positive length on
    which one new and one old piece both hold."""
    out = []
    i = j = 0
    while i < len(new) and j < len(old):  # both consecutive from t = 0: one merge pass
        q, o = new[i], old[j]
        lo, hi = max(q.start, o.start), min(q.end, o.end)
        if lo < hi:
            out.append((q, o, lo, hi))
        if q.end <= o.end:
            i += 1
        else:
            j += 1
    return out

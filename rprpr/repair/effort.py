"""A repaired crossing's efforts against the original's (pure): a consistency restored by
a violent acceleration drives the actuators far beyond anything the motion asked before,
and the repair says so.

The original's reference is its largest |E_i| on the audit's samples outside the changed
windows (the repair changes nothing there), each less its poles' leading terms
(``regular``: next to a nominal pole the effort is the pole's c/(t - t_s)^m, not what the
motion asks of the actuators); the repaired motion's is its certified peak
(``AuditResult.torque_peak``, which the repair's strict audits compute) or, when it keeps
a nominal pole (under uncertainty, a crossing aimed at the box's middle), its largest
|E_i| on its samples outside the instants' proven saturation windows. More than
``RATIO`` times the reference is a warning.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from ..engine.audit import AuditResult
from ..model.actuation import SCHEMES
from ..model.numbers import number

RATIO = 10  # the repaired peak over the original's largest effort that is warned about


def effort_warning(
    before: AuditResult, after: AuditResult, windows: Sequence[tuple[float, float]]
) -> str | None:
    """The warning when ``after``'s peak exceeds ``RATIO`` times ``before``'s largest
    regular |effort| (``regular``) on its samples outside ``windows`` ((t_s, half-width)
    of each change [s]); None otherwise, or when either cannot be told. ``after``'s peak
    is its certified one or, where it keeps a nominal pole (under uncertainty, a crossing
    aimed at the box's middle), its largest |effort| on its samples outside the proven
    saturation windows (``_top``)."""
    s = before.samples
    keep = np.ones(len(s.t), dtype=bool)
    for t, w in windows:
        keep &= np.abs(s.t - t) > w
    values = np.concatenate([regular(s.t, v, _poles(before))[keep] for v in (s.T1, s.T2)])
    values = values[np.isfinite(values)]
    if not len(values):
        return None
    reference = float(values.max())
    top, t_top, j = _top(after)
    if not math.isfinite(top) or top <= RATIO * reference:
        return None
    e = SCHEMES[after.task.robot.actuation]
    return (
        f"the repaired motion's {e.noun} reach |{e.letter}{j + 1}| = {top:.6g} {e.unit}"
        f" at t = {number(t_top, 6)} s, {number(top / reference, 3)} times the original's"
        f" largest regular |{e.letter}| outside the changed windows ({reference:.6g}"
        f" {e.unit}): the consistency is restored by a large acceleration; a wider --window,"
        " a change of the path's slope there or a slower motion asks less of the actuators"
    )


def _poles(result: AuditResult) -> list[tuple[float, int]]:
    """(t_s, the pole's order) of each instant whose nominal efforts are unbounded."""
    return [(s.t, s.order) for s in result.singularities if not s.torque_bounded]


def _top(after: AuditResult) -> tuple[float, float, int]:
    """(the largest |effort|, its time, the effort 0/1) of the repaired motion: its
    certified peak or, when it keeps a nominal pole, the largest |effort| on its samples
    outside the instants' proven saturation windows (``Robust.span``: inside them the box
    may exceed the limit and RPR205 decides; outside, every effort is one the actuators
    must deliver)."""
    peak = after.torque_peak
    if peak is not None and all(math.isfinite(p.value) for p in peak):
        j = 0 if peak[0].value >= peak[1].value else 1
        return peak[j].value, peak[j].t, j
    s = after.samples
    keep = np.ones(len(s.t), dtype=bool)
    for r in after.robust:
        if r.span is not None:
            keep &= (s.t < r.span[0]) | (s.t > r.span[1])
    best = (-math.inf, math.nan, 0)
    for j, v in enumerate((s.T1, s.T2)):
        a = np.where(keep & np.isfinite(v), np.abs(v), -np.inf)
        k = int(np.argmax(a))
        if a[k] > best[0]:
            best = (float(a[k]), float(s.t[k]), j)
    return best


def regular(t: np.ndarray, v: np.ndarray, poles: Sequence[tuple[float, int]]) -> np.ndarray:
    """|v| less each pole's leading term: next to an instant t_s where the nominal effort
    is unbounded (δ vanishing to order m), v = c±/(t - t_s)^m + the regular part, c± on
    each side taken from the sample nearest t_s there (v (t - t_s)^m); what remains is
    what the motion asks of the actuators, whatever the pole's size (a nominal pole of
    residue 1e-15 changes nothing, the original's pole's long tail goes). Non-finite
    samples stay non-finite."""
    out = np.asarray(v, dtype=float).copy()
    for ts, m in poles:
        h = t - ts
        for side in (h > 0, h < 0):
            idx = np.nonzero(side & np.isfinite(v))[0]
            if not len(idx):
                continue
            near = idx[np.argmin(np.abs(h[idx]))]
            c = v[near] * h[near] ** m
            out[idx] = out[idx] - c / h[idx] ** m
    return np.abs(out)

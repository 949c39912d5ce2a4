"""A repaired crossing's efforts against the original's (pure): a consistency restored by
a violent acceleration drives the actuators far beyond anything the motion asked before,
and the repair says so.

The original's reference is its largest |E_i| on the audit's samples outside the changed
windows (the repair changes nothing there; the failing instants' poles are inside them);
the repaired motion's is its certified peak (``AuditResult.torque_peak``, which the
repair's strict audits compute). More than ``RATIO`` times the reference is a warning.
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
    """The warning when ``after``'s certified peak exceeds ``RATIO`` times ``before``'s
    largest |effort| on its samples outside ``windows`` ((t_s, half-width) of each change
    [s]); None otherwise, or when either cannot be told."""
    peak = after.torque_peak
    if peak is None:
        return None
    s = before.samples
    keep = np.ones(len(s.t), dtype=bool)
    for t, w in windows:
        keep &= np.abs(s.t - t) > w
    values = np.abs(np.concatenate([s.T1[keep], s.T2[keep]]))
    values = values[np.isfinite(values)]
    if not len(values):
        return None
    reference = float(values.max())
    j = 0 if peak[0].value >= peak[1].value else 1
    top = peak[j].value
    if not math.isfinite(top) or top <= RATIO * reference:
        return None
    e = SCHEMES[after.task.robot.actuation]
    return (
        f"the repaired motion's {e.noun} reach |{e.letter}{j + 1}| = {top:.6g} {e.unit}"
        f" at t = {number(peak[j].t, 6)} s, {number(top / reference, 3)} times the original's"
        f" largest |{e.letter}| outside the changed windows ({reference:.6g} {e.unit}):"
        " the consistency is restored by a large acceleration; a wider --window, a change of"
        " the path's slope there or a slower motion asks less of the actuators"
    )

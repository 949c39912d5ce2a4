"""The knots of a piecewise motion as plain data (``knots[]`` of a report), the same for
every mechanism (``records``, ``five_bar_records``)."""

from __future__ import annotations

import math
from typing import Any

from ..engine.exact.knots import Knot


def _f(v: float | None) -> float | None:
    return None if v is None or not math.isfinite(v) else float(v)


def knot_record(k: Knot) -> dict[str, Any]:
    """An interior knot of a piecewise motion: ``t``, ``t_exact`` (text), the jumps of
    velocity [ẋ, ẏ] and acceleration [ẍ, ÿ] (null where continuous) and of the torques
    [T1, T2] (null where the velocity jumps, the acceleration does not, or a side's
    torques are undefined)."""
    jump = k.torque_jump
    return {
        "t": k.t,
        "t_exact": str(k.t_exact),
        "velocity_jump": None if k.velocity_jump is None else list(k.velocity_jump),
        "acceleration_jump": None if k.acceleration_jump is None else list(k.acceleration_jump),
        "torque_jump": None if jump is None else [_f(jump[0]), _f(jump[1])],
    }


_SIDE = (
    "order", "kind", "high_order", "slope", "speed", "slope_principle", "slope_reason",
    "velocity_principle", "velocity_reason", "consistency_residual", "consistent",
    "conditions_required", "conditions_met", "torque_bounded", "pole_order",
    "torque_at_singularity",
)  # fmt: skip


def side_fields(own: str, after: str) -> tuple[str, ...]:
    """The fields of one side of an instant at a knot, the same for every mechanism but
    for its own one (``own``: δ's derivatives of the RPRPR, the residuals of the 5R),
    placed after the field ``after``."""
    i = _SIDE.index(after) + 1
    return (*_SIDE[:i], own, *_SIDE[i:])

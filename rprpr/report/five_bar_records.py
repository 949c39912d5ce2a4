"""A 5R audit as plain data: the report every renderer works from (``records``' shape).

The keys are the RPRPR report's where the meaning is the same, so that every format
renders a 5R task: ``singularities[]`` are its Type II instants, with ``modes`` (the
working modes e1, e2), ``sigma`` (the line-up: -1 E between the elbows, +1 C and D on
one side of E), ``slope`` (tan α, the crossing angle with the Type II curve),
``consistency_residual`` (the reciprocity residual w(t_s) [N]) and ``residuals`` (w^(j)(t_s),
j < order), and at a knot of a piecewise motion ``knot`` and ``sides`` (the one-sided
analyses, as the RPRPR's); ``kinematic_singularities[]`` its first Type I instant (a leg
``stretched`` or ``folded``: the analysis stops there); ``knots[]`` the knots' jumps.
The certified layers (a motion of one piece) are the RPRPR's fields (``records``): the
torque peak, ``torque_limit`` and each unbounded instant's ``saturation``;
``closest_approach`` (the RPRPR's distance to the line AB) is null.
"""

from __future__ import annotations

import math
from typing import Any

from flint import arb, fmpq

from ..engine.exact.five_bar_instants import FiveBarInstant
from ..engine.five_bar_audit import FiveBarAuditResult
from ..model.names import file_name
from ..model.numbers import to_float
from .knot_records import knot_record, side_fields


def value(v: Any) -> float | None:
    """An exact value (rational, ball, float) as a finite double, else None (JSON null)."""
    if v is None:
        return None
    if isinstance(v, fmpq):
        f = to_float(v)
    elif isinstance(v, arb):
        f = float(v.mid())
    else:
        f = float(v)
    return f if math.isfinite(f) else None


def instant_record(
    s: FiveBarInstant, saturation: list[dict[str, Any] | None] | None = None
) -> dict[str, Any]:
    """One Type II instant as JSON-ready data (``singularities[]``), with its
    ``saturation`` record (``records.saturation_record``) at a pole under a limit."""
    limit = s.torque_at_singularity
    return {
        "t": s.t,
        "t_exact": None if s.t_exact is None else str(s.t_exact),
        "x": s.x,
        "y": s.y,
        "modes": list(s.modes),
        "sigma": s.sigma,
        "order": s.order,
        "kind": "crossing" if s.order % 2 else "touch",
        "high_order": s.order >= 2,
        "degenerate": s.degenerate,
        "delta_derivative": value(s.delta_k),
        "slope": value(s.slope),
        "speed": value(math.sqrt(value(s.speed2) or 0.0)),
        "slope_principle": "pass" if s.slope_principle.passed else "fail",
        "slope_reason": s.slope_principle.reason,
        "velocity_principle": "pass" if s.velocity_principle.passed else "fail",
        "velocity_reason": s.velocity_principle.reason,
        "consistency_residual": value(s.consistency_residual),
        "residuals": [value(r) for r in s.residuals],
        "consistent": s.consistent,
        "conditions_required": s.order,
        "conditions_met": s.conditions_met,
        "torque_bounded": s.bounded,
        "pole_order": s.order - s.conditions_met,
        "torque_at_singularity": None if limit is None else [value(limit[0]), value(limit[1])],
        "saturation": saturation,
        "knot": s.knot,
        **({"sides": {n: side_record(side) for n, side in s.sides}} if s.knot else {}),
    }


SIDE_FIELDS = side_fields("residuals", after="consistency_residual")


def side_record(s: FiveBarInstant) -> dict[str, Any]:
    """One side of a Type II instant at a knot: its order, principles, residuals,
    boundedness and limit torques (``SIDE_FIELDS``: the RPRPR's sides' fields, with the
    5R's ``residuals`` in place of δ's derivatives)."""
    fields = instant_record(s)
    return {k: fields[k] for k in SIDE_FIELDS}


def five_bar_report(
    result: FiveBarAuditResult,
    task_path: str,
    findings: list[dict[str, Any]],
    peak: dict[str, Any],
    limit: list[dict[str, Any]] | None = None,
    saturation: dict[int, list[dict[str, Any] | None]] | None = None,
) -> dict[str, Any]:
    """The report of one audited 5R task (a ``reports[]`` entry of ``--format json``):
    ``findings`` its findings as records, ``peak`` the torque peak's fields
    (``records.peak_fields``), ``limit`` the ``torque_limit`` records, ``saturation`` the
    records of the unbounded instants (by ``id``), as the RPRPR's."""
    sat = saturation or {}
    task = result.task
    return {
        "task": file_name(task_path),
        "name": task.name,
        "mechanism": task.robot.mechanism,
        "verdict": result.verdict,
        "strict": result.strict,
        "singularities": [instant_record(s, sat.get(id(s))) for s in result.singularities],
        "kinematic_singularities": [
            {
                "t": k.t,
                "t_exact": None if k.t_exact is None else str(k.t_exact),
                "x": _on(task.motion[k.piece], 0, k),
                "y": _on(task.motion[k.piece], 1, k),
                "leg": k.leg,
                "kind": k.kind,
            }
            for k in result.type_one
        ],
        "on_singular_line": result.on_singular_curve,
        "knots": [knot_record(k) for k in result.knot_jumps],
        **peak,
        "torque_limit": limit,
        "closest_approach": None,
        "findings": findings,
        "beyond_double_range": [],
    }


def _on(piece: Any, i: int, k: Any) -> float | None:
    """x (i = 0) or y (1) of the Type I instant ``k`` on its piece."""
    p = piece.y if i else piece.x
    return value(p(k.t_exact)) if k.t_exact is not None else _at(p, k.t)


def _at(p: Any, t: float) -> float | None:
    """The polynomial ``p`` at the double ``t`` (a Type I instant's irrational time)."""
    return value(sum(float(c) * t**i for i, c in enumerate(p.coeffs())))

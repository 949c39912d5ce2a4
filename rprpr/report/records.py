"""An audit as plain data: the JSON-ready records every renderer (text, JSON, JUnit,
GitHub) works from, so that a worker process can hand them back and all formats agree.

Floats that are not finite become None (JSON null).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

from ..engine.audit import AuditResult
from ..engine.bounds.verdicts import Approach, LimitCheck, Peak, Window
from ..engine.exact.singular import SingularInstant
from ..model.actuation import REVOLUTE, SCHEMES, Scheme
from ..model.errors import TaskFileError
from ..model.names import file_name
from ..model.numbers import labels, number, to_float
from ..model.rules import RULES
from ..model.task import Task
from .knot_records import knot_record as _knot_record
from .knot_records import side_fields

if TYPE_CHECKING:  # the robust machinery loads only for a task that declares uncertainty
    from ..engine.five_bar_audit import FiveBarAuditResult
    from ..engine.robust.windows import Robust

INVALID_TASK = "RPR001"  # the rule of every input error


def _f(v: float | None) -> float | None:
    return None if v is None or not math.isfinite(v) else float(v)


def singularity_record(
    s: SingularInstant, saturation: list[dict[str, Any] | None] | None = None
) -> dict[str, Any]:
    """One singular instant as JSON-ready data (``singularities[]`` of a report): ``t``
    the nearest double, ``t_exact`` the exact time as text ("5/2", "1/10") when it is
    rational, null when it is irrational; ``saturation``: its ``saturation_record``
    (None: bounded, or no torque limit). ``knot``: t_s is a break of a piecewise motion
    (0 and t_f included); then ``sides`` holds the one-sided analyses ``before`` and
    ``after`` (``side_record``; none before t = 0, none after t_f) and the fields above
    are their conservative combination."""
    out = _instant_fields(s)
    out["saturation"] = saturation
    out["knot"] = s.knot
    if s.knot:
        out["sides"] = {name: side_record(side) for name, side in s.sides}
    return out


SIDE_FIELDS = side_fields("delta_derivatives", after="high_order")


def side_record(s: SingularInstant) -> dict[str, Any]:
    """One side of a singular instant at a knot: its order (the multiplicity of the root
    of that side's y(t)), slope, speed, eq. (34) residual, conditions, boundedness and
    limit torque (``SIDE_FIELDS``)."""
    fields = _instant_fields(s)
    return {k: fields[k] for k in SIDE_FIELDS}


def _instant_fields(s: SingularInstant) -> dict[str, Any]:
    return {
        "t": s.t,
        "t_exact": None if s.t_exact is None else str(s.t_exact),
        "x": s.x,
        "y": s.y,
        "case": s.case.number,
        "sigma": s.case.sigma,
        "psi": s.case.psi,
        "order": s.order,
        "kind": s.kind,
        "high_order": s.high_order,
        "delta_derivatives": [_f(v) for v in s.delta_derivatives],
        "slope": _f(s.slope),
        "speed": _f(s.speed),
        "slope_principle": "pass" if s.slope_principle.passed else "fail",
        "slope_reason": s.slope_principle.reason,
        "velocity_principle": "pass" if s.velocity_principle.passed else "fail",
        "velocity_reason": s.velocity_principle.reason,
        "consistency_residual": _f(s.consistency_residual),
        "consistent": s.consistent,
        "conditions_required": s.conditions_required,
        "conditions_met": s.conditions_met,
        "torque_bounded": s.torque_bounded,
        "pole_order": s.pole_order,
        "torque_at_singularity": (
            [_f(s.torque_at_singularity[0]), _f(s.torque_at_singularity[1])]
            if s.torque_at_singularity
            else None
        ),
    }


def _span(w: Window) -> list[float]:
    """A window's extent [start, end], from the earliest its first crossing can be to
    the latest its last can be: outside it |T| is proven within the limit."""
    return [w.start_lo, w.end_hi]


def saturation_record(
    limits: tuple[LimitCheck, LimitCheck], windows: tuple[Window | None, Window | None]
) -> list[dict[str, Any] | None]:
    """Per torque, the window around an unbounded instant in which |T_i| > its limit:
    ``{"limit", "window": [start, end], "width"}`` (None where |T_i| stays within it)."""
    out: list[dict[str, Any] | None] = []
    for c, w in zip(limits, windows, strict=True):
        if w is None:
            out.append(None)
            continue
        start, end = _span(w)
        out.append({"limit": c.limit, "window": [start, end], "width": end - start})
    return out


def limit_record(c: LimitCheck) -> dict[str, Any]:
    """The certified check of one torque against its limit (``torque_limit[i]``):
    ``passed`` true (|T_i(t)| <= limit for every t in [0, t_f]), false, or null
    (undecided: the maximum touches the limit within the certified bounds); ``exceeded``:
    each interval [start, end] in which |T_i| exceeds the limit (outside them it is
    proven within it); ``crossings``: for each, the brackets [[lo, hi], [lo, hi]] of the
    time it rises above the limit and of the time it falls back (within
    ``resolution`` s); ``pole``: for each, whether it holds an unbounded instant."""
    return {
        "limit": c.limit,
        "passed": c.passed,
        "exceeded": [_span(w) for w in c.windows],
        "crossings": [[[w.start_lo, w.start_hi], [w.end_lo, w.end_hi]] for w in c.windows],
        "pole": [w.pole for w in c.windows],
        "resolution": c.resolution,
    }


def approach_record(a: Approach | None) -> dict[str, Any] | None:
    """How close a motion that never meets the line AB comes to it: ``distance`` = min
    |y| (E to AB) [m] at ``t``; ``min_abs_delta`` = a proven lower bound of min |δ|
    (within 1e-6 relative of it), reached at ``t_delta``. None when the motion meets AB;
    a value beyond the double range is null."""
    if a is None:
        return None
    return {
        "distance": _f(a.distance),
        "t": _f(a.t_y),
        "min_abs_delta": _f(a.delta_lo),
        "t_delta": _f(a.t_delta),
    }


PEAK_FIELDS = ("torque_peak", "torque_peak_t", "torque_peak_bound", "torque_peak_certified")


def peak_fields(peak: tuple[Peak, Peak] | None, computed: bool = True) -> dict[str, Any]:
    """``torque_peak`` [max |T1|, max |T2|] over [0, t_f] [N m] (a certified lower bound
    of each, within 1e-6 relative of the true maximum when ``torque_peak_certified``),
    ``torque_peak_t`` where each is reached [s], ``torque_peak_bound`` the proven upper
    bounds [N m]; all null when the torques are unbounded or undefined. When the peak
    was not asked for (not ``computed``: finite torques, no ``--peak``), all null and
    ``torque_peak_computed``: false (the field is there only then: a report with the
    peak reads as it always did)."""
    if not computed:
        return {**dict.fromkeys(PEAK_FIELDS), "torque_peak_computed": False}
    if peak is None or not all(math.isfinite(p.value) for p in peak):
        return dict.fromkeys(PEAK_FIELDS)
    return {
        "torque_peak": [p.value for p in peak],
        "torque_peak_t": [p.t for p in peak],
        "torque_peak_bound": [_f(p.upper) for p in peak],
        "torque_peak_certified": all(p.certified for p in peak),
    }


def _saturations(
    result: AuditResult | FiveBarAuditResult,
) -> dict[int, list[dict[str, Any] | None]]:
    """The saturation record of each unbounded instant, by the instant itself (``id``:
    two instants whose times round to one double are still two)."""
    limits = result.torque_limit
    if limits is None:
        return {}
    sat: list[Any] = result.saturation
    return {id(s): saturation_record(limits, (w1, w2)) for s, w1, w2 in sat}


def task_report(result: AuditResult | FiveBarAuditResult, task_path: str) -> dict[str, Any]:
    """The report of one audited task (the ``reports[]`` entries of ``--format json``);
    a 5R task's is ``five_bar_records.five_bar_report``."""
    saturation = _saturations(result)
    if not isinstance(result, AuditResult):  # a 5R task: its records, the same fields
        from .five_bar_records import five_bar_report

        checked = result.torque_limit
        return five_bar_report(
            result, task_path, _findings(result),
            peak_fields(result.torque_peak, result.peak_computed),
            [limit_record(c) for c in checked] if checked else None, saturation,
        )  # fmt: skip
    task = result.task
    sings = [singularity_record(s, saturation.get(id(s))) for s in result.singularities]
    for rec, r in zip(sings, result.robust, strict=False):
        rec["robust"] = robust_record(r)  # only with declared uncertainty (docs/robust.md)
    findings = _findings(result)
    return {
        "task": file_name(task_path),
        "name": task.name,
        **actuation_fields(task.robot.actuation),
        "verdict": result.verdict,
        "strict": result.strict,
        "singularities": sings,
        "kinematic_singularities": [
            {"t": k.t, "x": k.x, "y": k.y, "leg": k.leg} for k in result.kinematic_singularities
        ],
        "on_singular_line": result.on_singular_line,
        "knots": [_knot_record(k) for k in result.knot_jumps],
        **peak_fields(result.torque_peak, result.peak_computed),
        "torque_limit": (
            [limit_record(c) for c in result.torque_limit] if result.torque_limit else None
        ),
        "closest_approach": approach_record(result.closest_approach),
        "findings": findings,
        "beyond_double_range": beyond_double_range(result),
        **uncertainty_fields(task, result.robust_peak),
    }


def _findings(result: Any) -> list[dict[str, Any]]:
    """The findings of an audit (an ``AuditResult`` or a 5R's) as records."""
    return [
        {
            "rule": f.rule,
            "name": RULES[f.rule].name,
            "severity": "error" if f.fails(result.strict) else "warning",
            "message": f.message,
            "t": _f(f.t),
            "key": f.key,
            "line": f.line or _key_line(result.task.lines, f.key),
        }
        for f in result.findings
    ]


def robust_record(r: Robust) -> dict[str, Any]:
    """An instant's robust analysis (``docs/robust.md``): the residual's bounds over the
    box [N], the proven window [s] (and a lower bound), the effort that reaches furthest
    (1 or 2) and the window's proven ends [s] (both null when the window is 0)."""
    return {
        "residual": [r.residual[0], r.residual[1]],
        "window": r.window,
        "window_lo": r.window_lo,
        "joint": r.joint,
        "span": list(r.span) if r.span is not None else None,
    }


def uncertainty_fields(
    task: Task, peak: tuple[tuple[float, float], tuple[float, float]] | None = None
) -> dict[str, Any]:
    """The declared uncertainty echoed (nothing without it: reports stay as before):
    per link the half-widths of mass, inertia and r as fractions, acceleration [m/s²],
    period [s]; with the peak asked for, ``peak``: the certified [lower, upper] of the
    largest |T1|, |T2| over the box outside the proven windows (``engine.robust.worst_peak``)."""
    u = task.uncertainty
    if u is None:
        return {}
    links = {
        str(i): {"mass": to_float(m), "inertia": to_float(i_), "r": to_float(r)}
        for i, (m, i_, r) in sorted(u.links.items())
    }
    return {
        "uncertainty": {
            "links": links,
            "acceleration": to_float(u.acceleration),
            "period": to_float(u.period),
            **({"peak": [list(peak[0]), list(peak[1])]} if peak is not None else {}),
        }
    }


def actuation_fields(actuation: str) -> dict[str, Any]:
    """``actuation`` and ``effort_unit`` of a prismatic task's report: its efforts (the
    ``torque_*`` fields, ``torque_limit``, ``torque_jump``) are the legs' forces F1, F2
    in N. Nothing for the paper's revolute scheme (torques T1, T2 in N m), whose reports
    stay as they were before the scheme was a choice."""
    if actuation == REVOLUTE:
        return {}
    return {"actuation": actuation, "effort_unit": SCHEMES[actuation].unit}


def scheme(rep: dict[str, Any]) -> Scheme:
    """The actuation scheme of a task report (revolute when it names none)."""
    return SCHEMES[rep.get("actuation", REVOLUTE)]


def beyond_double_range(result: AuditResult) -> list[dict[str, str]]:
    """Each reported quantity whose double is not faithful to its exact value (beyond the
    double range: JSON null where the double is infinite, else the nearest double, 0 or a
    subnormal), with that exact value as text: ``{"quantity": "singularities[0].speed",
    "value": "1.41421e+400"}``."""
    out = []
    for i, k in enumerate(result.kinematic_singularities):
        for name, value in k.beyond_double_range:
            out.append({"quantity": f"kinematic_singularities[{i}].{name}", "value": value})
    for i, s in enumerate(result.singularities):
        for name, value in s.beyond_double_range:
            out.append({"quantity": f"singularities[{i}].{name}", "value": value})
    return out


def instant_times(rep: dict[str, Any]) -> dict[float, str]:
    """The time of each instant of a task report (inverse-kinematic and singular) as text,
    all told apart together as in the findings' messages, so that every renderer names an
    instant the same way and two close instants never alike."""
    kinematic = [k["t"] for k in rep["kinematic_singularities"]]
    return labels(kinematic + [s["t"] for s in rep["singularities"]])


def input_error(e: TaskFileError, task_path: str) -> dict[str, Any]:
    """An input error as data (``input_errors[]`` of ``--format json``).

    ``line``/``column`` are 1-based, None when unknown; ``key`` is the dotted key path,
    None for the whole file. ``text`` is the one-line message of the command line. These
    are the file's first error; ``errors`` lists every error of the file (the first
    among them), each with the same fields but ``errors``.
    """
    return {**_one_error(e, task_path), "errors": [_one_error(x, task_path) for x in e.errors]}


def _one_error(e: TaskFileError, task_path: str) -> dict[str, Any]:
    name = file_name(task_path)
    return {
        "task": name,
        "line": e.line or None,
        "column": e.column or None,
        "key": e.key or None,
        "message": file_name(e.message),
        "rule": INVALID_TASK,
        "text": file_name(f"{e.naming(name)} [{INVALID_TASK}]"),
    }


def internal_error(e: BaseException, task_path: str) -> dict[str, Any]:
    """A bug met while auditing one task, as data (``internal_errors[]``)."""
    return {
        "task": file_name(task_path),
        "message": file_name(f"{type(e).__name__}: {e}"),
        "text": file_name(
            f"{task_path}: internal error ({type(e).__name__}: {e}); please report it to"
            " the rprpr maintainers with this task file"
        ),
        "traceback": file_name("".join(_traceback(e))),
    }


def budget_error(task_path: str, budget: float, stage: str) -> dict[str, Any]:
    """A task whose audit exceeded its work budget of ``budget`` seconds during ``stage``
    (``budget_errors[]``): it was stopped there, and the run went on."""
    message = f"the exact analysis exceeded its budget of {number(budget)} s at {stage}"
    return {
        "task": file_name(task_path),
        "budget": budget,
        "stage": stage,
        "message": message,
        "text": file_name(f"{task_path}: {message} (check --budget SECONDS allows more)"),
    }


# A key the task does not have points at the key that gives the same thing in its form:
# the motion of a path-and-timing task is its timing, the path of a motion is the motion.
_SAME_PLACE = {"motion": "timing", "path": "motion"}


def _key_line(lines: dict[str, int], key: str) -> int:
    """The line of a finding's key, of its top-level section, or of the section that
    gives the same thing in this task's form; 1 when the file has none of them."""
    head = key.split(".")[0]
    for k in (key, head, _SAME_PLACE.get(head, "")):
        if k in lines:
            return lines[k]
    return 1


def _traceback(e: BaseException) -> list[str]:
    """The lines of ``e``'s traceback (traceback is imported only for a bug met)."""
    import traceback

    return traceback.format_exception(e)

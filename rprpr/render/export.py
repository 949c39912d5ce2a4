"""``rprpr export``: the sampled motion of an audit as CSV or JSON text.

One row per sample, t = 0 .. t_f inclusive, the columns of ``samples.COLUMNS`` in that
order, SI units (m, s, rad, N, N m; θ continuous), then a ``reason`` column. The numbers
are the engine's own certified values (``AuditResult.samples``, ``engine.certified``):
every exported value is within a proven bound of the true value of the paper's formulas
at the row's time t (the float t, taken exactly), |err| <= 1e-9 (1 + |value|) — or it is
NaN, and the row's ``reason`` says why. They are written with Python's shortest
round-trip ``repr``, so reading the file back gives the very same floats.

``reason`` is an integer code per row (``engine.certified.REASONS``): 0 = every value of
the row is certified; otherwise the cause of the row's NaN: 1 a singular instant with
unbounded torques (λ2, T1, T2), 2 and 3 the end point at A or at B, 4 the path on the
singular line, 5 a value not certified at the highest precision tried, 6 a value beyond
the double range (|value| > 1.8e308, certified so).

A 5R task's rows have the 5R's columns and codes (``certified.five_bar_samples``: the
motors' angles θ1, θ2, δ, the distal links' axial force ``alpha``, T1, T2; code 7 a leg
stretched or folded), the same certification, the same formats. Every value that is not finite is
``nan`` in CSV and ``null`` in JSON (the JSON is strict: no NaN or Infinity tokens); -0.0
is written as 0.0.

Both formats name the task and the rprpr version: CSV in one leading ``#`` comment line
(read with ``pandas.read_csv(f, comment="#")`` or ``numpy.genfromtxt(f, delimiter=",",
names=True, skip_header=1)``; the task's name and file on one line, control characters
escaped, the reason codes named), JSON in the fields ``rprpr`` and ``task``, with the
codes in ``reasons`` (ASCII text: any other character as a ``\\u`` escape, so the
document is the same bytes on any stream, and a file name that is not UTF-8 still gives
valid JSON).

No click, no matplotlib here: the command line (``cli_plot``) picks the stream and format.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable
from typing import Any, TextIO

import numpy as np

from .._version import __version__
from ..engine.audit import AuditResult
from ..engine.certified.motion import POLE, REASONS, TOL
from ..engine.certified.sampling import COLUMNS
from ..model.actuation import PRISMATIC, REVOLUTE
from ..model.names import file_name
from ..model.numbers import number, round_trip
from ..report.records import actuation_fields, singularity_record
from .escape import inert, inert_json, printable

FORMATS = {".csv": "csv", ".json": "json"}

UNITS = {
    "t": "s", "x": "m", "y": "m", "x_dot": "m/s", "y_dot": "m/s",
    "theta1": "rad", "s1": "m", "theta2": "rad", "s2": "m",
    "theta1_dot": "rad/s", "s1_dot": "m/s", "theta2_dot": "rad/s", "s2_dot": "m/s",
    "delta": "1", "delta_dot": "1/s",
    "lambda1": "N", "lambda2": "N", "T1": "N m", "T2": "N m", "F1": "N", "F2": "N",
    "x_ddot": "m/s^2", "y_ddot": "m/s^2", "theta1_ddot": "rad/s^2", "s1_ddot": "m/s^2",
    "theta2_ddot": "rad/s^2", "s2_ddot": "m/s^2", "reason": "code",
    "T1_worst": "N m", "T2_worst": "N m", "F1_worst": "N", "F2_worst": "N", "alpha": "N",
}  # fmt: skip

FIVE_BAR_UNITS = {"delta": "m^2", "delta_dot": "m^2/s"}  # a 5R's δ = (E - C) × (E - D)

EXPORTED = (*COLUMNS, "reason")  # the columns of a row, in order
FORCES = {"T1": "F1", "T2": "F2"}  # a prismatic robot's efforts: the legs' forces [N]


WORST = ("T1_worst", "T2_worst")  # with uncertainty: max |T_i| over the box, proven


def exported(result: AuditResult) -> tuple[str, ...]:
    """The columns of a row for ``result``'s robot: ``EXPORTED``, with F1, F2 [N] in the
    place of T1, T2 when the legs' prismatic joints are actuated; with declared
    uncertainty, ``WORST`` before ``reason`` (F1_worst, F2_worst for forces); a 5R's
    columns (``FiveBarSamples.COLUMNS``)."""
    if _five_bar(result):
        return (*_any(result).samples.COLUMNS, "reason")
    names = (*COLUMNS, *WORST, "reason") if result.task.uncertainty is not None else EXPORTED
    if result.task.robot.actuation == REVOLUTE:
        return names
    return tuple(FORCES.get(c[:2], c[:2]) + c[2:] if c[:2] in FORCES else c for c in names)


CERTIFIED = f"every value certified to |err| <= {number(TOL)} (1 + |value|)"


# at a pole under linear actuators it is λ1 (not λ2) that diverges, with the forces
_PRISMATIC_POLE = "a singular instant with unbounded forces (a pole of λ1): λ1, F1, F2 undefined"


def _five_bar(result: AuditResult) -> bool:
    """Whether ``result`` is a 5R task's (its samples have their own columns)."""
    return not isinstance(result, AuditResult)


def _any(result: AuditResult) -> Any:
    """A 5R's result as what it is (its samples are ``FiveBarSamples``)."""
    return result


def _reasons(result: AuditResult) -> dict[int, str]:
    """``reasons`` of the task's robot (a 5R's samples carry theirs)."""
    if _five_bar(result):
        return {c: t or "every value certified" for c, t in _any(result).samples.REASONS.items()}
    return reasons(result.task.robot.actuation)


def _units(result: AuditResult) -> dict[str, str]:
    """The units that differ from ``UNITS`` for the task's robot (a 5R's δ is in m²)."""
    return FIVE_BAR_UNITS if _five_bar(result) else {}


def reasons(actuation: str = REVOLUTE) -> dict[int, str]:
    """What each ``reason`` code of a row means (0: every value certified), in the words
    of the task's actuation scheme (the pole's text differs for linear actuators)."""
    out = {code: text or "every value certified" for code, text in REASONS.items()}
    if actuation == PRISMATIC:
        out[POLE] = _PRISMATIC_POLE
    return out


def rows(result: AuditResult) -> np.ndarray:
    """The exported values: one row per sample, the columns of ``COLUMNS`` in order, then
    with declared uncertainty the proven worst case of each effort over the box
    (``engine.robust.worst``: an upper bound of max |E_i| at the row's time; NaN at a pole). The
    ``reason`` codes are ``result.samples.reason``."""
    values = result.samples.rows()
    if result.task.uncertainty is None:
        return values
    from ..engine.robust.worst import worst_efforts

    w1, w2 = worst_efforts(result.task, result.parts, result.samples.t)
    return np.column_stack([values, w1, w2])


def _rows(result: AuditResult) -> Iterable[tuple[list[float], int]]:
    """Each row's values and its reason code."""
    samples = result.samples
    yield from zip(rows(result).tolist(), samples.reason.tolist(), strict=True)


def _csv_number(v: float) -> str:
    if not math.isfinite(v):
        return "nan"  # inf too: the README promises nan for every non-finite value
    if v == 0:
        return "0.0"  # -0.0 too: a spreadsheet would show "-0"
    return round_trip(v)


def _json_number(v: float) -> float | None:
    if not math.isfinite(v):
        return None
    return float(v) + 0.0  # -0.0 -> 0.0


def _one_line(text: str) -> str:
    return printable(" ".join(text.split()))


def comment(result: AuditResult, source: str) -> str:
    """The CSV's header comment (one line, no newline): version, task, file, grid, units."""
    t = result.samples.t
    name = json.dumps(_one_line(result.task.name), ensure_ascii=False)
    where = f" ({_one_line(source)})" if source else ""
    return inert(
        f"# rprpr {__version__} export of task {name}{where}: {len(t)} samples, "
        f"t = 0 .. {number(float(t[-1]))} s; SI units (m, s, rad, N, N m); "
        f"{CERTIFIED}, or nan;{_worst_note(result)} reason codes: "
        + "; ".join(f"{code} = {text}" for code, text in _reasons(result).items())
    )


def _worst_note(result: AuditResult) -> str:
    """The worst-case columns in words ('' without declared uncertainty)."""
    if result.task.uncertainty is None:
        return ""
    w1, w2 = exported(result)[-3:-1]
    return (
        f" {w1}, {w2}: proven upper bounds of the largest |effort| over the declared"
        " uncertainty's box at the row's time (nan at a pole);"
    )


def write_csv(result: AuditResult, out: TextIO, source: str = "") -> None:
    """Write the samples as CSV: the comment line, the column names, one line per sample."""
    out.write(comment(result, source) + "\n")
    out.write(",".join(exported(result)) + "\n")
    for row, reason in _rows(result):
        out.write(",".join(_csv_number(v) for v in row) + f",{reason}\n")


# the fields of each singular instant in the JSON export (a subset of ``rprpr check``'s)
SINGULARITY_FIELDS = (
    "t", "x", "case", "order", "high_order", "torque_bounded", "pole_order",
    "torque_at_singularity",
)  # fmt: skip


# a 5R's: its working modes and line-up in the place of the RPRPR's case
FIVE_BAR_FIELDS = (
    "t", "x", "y", "modes", "sigma", "order", "high_order", "torque_bounded", "pole_order",
    "torque_at_singularity",
)  # fmt: skip


def _singularities(result: AuditResult) -> list[dict[str, Any]]:
    if _five_bar(result):
        from ..report.five_bar_records import instant_record

        return [{k: instant_record(s)[k] for k in FIVE_BAR_FIELDS} for s in result.singularities]  # type: ignore[arg-type]
    records = (singularity_record(s) for s in result.singularities)
    return [{k: r[k] for k in SINGULARITY_FIELDS} for r in records]


def document_head(result: AuditResult, source: str) -> dict[str, Any]:
    """Every field of the JSON document but ``rows``."""
    t = result.samples.t
    return {
        "rprpr": __version__,
        "task": result.task.name,
        "file": file_name(source),
        "samples": len(t),
        "duration": _json_number(float(t[-1])),
        **actuation_fields(result.task.robot.actuation),
        "verdict": result.verdict,
        "columns": list(exported(result)),
        "units": {c: _units(result).get(c, UNITS[c]) for c in exported(result)},
        "reasons": {str(code): text for code, text in _reasons(result).items()},
        "singularities": _singularities(result),
    }


def _json_rows(result: AuditResult) -> Iterable[str]:
    for row, reason in _rows(result):
        yield json.dumps([*(_json_number(v) for v in row), reason], allow_nan=False)


def write_json(result: AuditResult, out: TextIO, source: str = "") -> None:
    """Write the samples as one JSON object: the fields of ``document_head`` and ``rows``
    (a list of rows, each a list in the order of ``columns``; null where a value is
    undefined or not certified, the row's ``reason`` code last).
    One row per line, so that the file stays readable and diffs well."""
    head = inert_json(json.dumps(document_head(result, source), indent=2, allow_nan=False))
    out.write(head[:-2] + ',\n  "rows": [\n')  # head ends in "\n}"
    first = True
    for line in _json_rows(result):
        out.write(("    " if first else ",\n    ") + line)
        first = False
    out.write("\n  ]\n}\n")


def write(result: AuditResult, out: TextIO, fmt: str, source: str = "") -> None:
    """Write ``result``'s samples to ``out`` as ``fmt`` ("csv" or "json")."""
    if fmt == "csv":
        write_csv(result, out, source)
    elif fmt == "json":
        write_json(result, out, source)
    else:
        raise ValueError(f"unknown export format {fmt!r}; expected csv or json")

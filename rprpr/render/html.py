"""A task report as a small HTML table (the rich display of an audit result in a
notebook, ``rprpr.api.AuditResult._repr_html_``), from the report's records only.

Every text is escaped (``html.escape``); numbers go through ``model.numbers``.
"""

from __future__ import annotations

from html import escape
from typing import Any

from ..model.numbers import CELL, number
from ..report.records import instant_times, scheme
from . import phrases

_COLUMNS = ("t [s]", "x [m]", "order", "case σ ψ", "dy/dx", "speed [m/s]", "slope",
            "velocity", "torques")  # fmt: skip


def _cell(v: float | None) -> str:
    return "—" if v is None else number(v, CELL)


def _row(cells: list[str], tag: str = "td") -> str:
    return "<tr>" + "".join(f"<{tag}>{escape(c)}</{tag}>" for c in cells) + "</tr>"


def _instant(s: dict[str, Any], t: str) -> list[str]:
    torque = (
        f"bounded ({s['conditions_met']}/{s['conditions_required']})"
        if s["torque_bounded"]
        else f"unbounded (pole {s['pole_order']})"
    )
    return [
        t,
        _cell(s["x"]),
        f"{s['order']} {s['kind']}",
        f"{s['case']} {s['sigma']:+d} {s['psi']:+d}",
        _cell(s["slope"]),
        _cell(s["speed"]),
        s["slope_principle"],
        s["velocity_principle"],
        torque,
    ]


def report_html(rep: dict[str, Any]) -> str:
    """``rep`` (a ``report.records.task_report``) as HTML: the verdict, a table of the
    singular instants, the findings and the torque peak."""
    times = instant_times(rep)
    parts = [
        f"<p><b>{escape(rep['name'])}</b> ({escape(rep['task'])}): "
        f"<b>{'PASS' if rep['verdict'] == 'pass' else 'FAIL'}</b></p>"
    ]
    if rep["singularities"]:
        rows = [_row([*_COLUMNS[:-1], scheme(rep).noun], "th")]
        rows += [_row(_instant(s, times[s["t"]])) for s in rep["singularities"]]
        parts.append("<table>" + "".join(rows) + "</table>")
    else:
        parts.append("<p>no Type II singular instant in [0, t_f]</p>")
    findings = [
        f"<li>{escape(f['rule'])} {escape(f['name'])} [{escape(f['severity'])}]: "
        f"{escape(f['message'])}</li>"
        for f in rep["findings"]
    ]
    if findings:
        parts.append("<ul>" + "".join(findings) + "</ul>")
    for phrase in (phrases.peak(rep), phrases.approach(rep)):
        if phrase:
            parts.append(f"<p>{escape(phrase)}</p>")
    return "<div>" + "".join(parts) + "</div>"

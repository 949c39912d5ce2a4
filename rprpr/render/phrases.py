"""A task report in words, shared by the text report, JUnit and the HTML report.

Each phrase is made from the report's records (``report.records``), never from the
engine, and every number in it goes through ``model.numbers``:

* ``peak``: ``peak |T1| 66.1221 N m at t = 2.743 s, |T2| 60.5504 N m at t = 0.2024 s``
  (the certified maxima over [0, t_f]; ``≥ ... not certified`` where only a lower bound
  is proven; ``torques unbounded at t = ...`` where a singular instant has a pole;
  ``peak not computed (--peak)`` where it was not asked for);
* ``approach``: ``closest approach to AB: 100 µm at t = 1 s, min |δ| = 6.667e-05 at
  t = 1 s`` for a motion that never meets the singular line;
* ``details``: the task's other lines (scheme, the path on y = 0, E through A or B,
  values beyond the double range, the closest approach).
"""

from __future__ import annotations

from typing import Any

from ..model.actuation import REVOLUTE
from ..model.numbers import CELL, number, outward, with_unit
from ..report.records import instant_times, scheme


def peak(rep: dict[str, Any]) -> str:
    """The torque peak of ``rep`` in words ("" when the torques are undefined: the path
    on y = 0, or E through A or B)."""
    times = instant_times(rep)
    e = scheme(rep)  # |F1| ... N for a prismatic robot
    poles = [f"{times[s['t']]} s" for s in rep["singularities"] if not s["torque_bounded"]]
    if poles:
        return f"{e.noun} unbounded at t = {', '.join(poles)}"
    if rep.get("torque_peak_computed") is False:
        return "peak not computed (--peak)"
    values = rep["torque_peak"]
    if values is None:
        return ""
    certified = rep["torque_peak_certified"]
    parts = [
        f"|{e.letter}{i + 1}| {'' if certified else '≥ '}{number(v)} {e.unit}"
        f" at t = {number(t, CELL)} s"
        for i, (v, t) in enumerate(zip(values, rep["torque_peak_t"], strict=True))
    ]
    return f"peak {', '.join(parts)}{'' if certified else ', not certified'}"


def approach(rep: dict[str, Any]) -> str:
    """How close a motion that never meets the line AB comes to it ("" otherwise)."""
    a = rep["closest_approach"]
    if a is None:
        return ""
    distance = "beyond the double range" if a["distance"] is None else with_unit(a["distance"], "m")
    delta = (
        "beyond the double range"
        if a["min_abs_delta"] is None
        else number(a["min_abs_delta"], CELL)
    )
    return (
        f"closest approach to AB: {distance} at t = {number(a['t'], CELL)}"
        f" s, min |δ| = {delta} at t = {number(a['t_delta'], CELL)} s"
    )


def details(rep: dict[str, Any], times: dict[float, str]) -> list[str]:
    """The task's lines in words (text and HTML reports): the actuation scheme when not
    revolute, the path on y = 0, E through A or B, values beyond the double range and
    the closest approach (the torque peak is in the verdict line)."""
    out = []
    e = scheme(rep)
    if e.name != REVOLUTE:
        out.append(f"actuation: {e.name} (efforts: forces F1, F2 [{e.unit}] in the legs)")
    five_bar = "mechanism" in rep  # a 5R: a Type II curve, legs stretched or folded
    if rep["on_singular_line"]:
        out.append(
            "the path runs along a Type II curve"
            if five_bar
            else "the path lies on the singular line y = 0"
        )
    elif not rep["singularities"] and not (five_bar and rep["kinematic_singularities"]):
        out.append("no Type II singular instant in [0, t_f]")
    for k in rep["kinematic_singularities"]:
        if five_bar:
            out.append(
                f"Type I singularity at t = {times[k['t']]} s: leg {k['leg']} {k['kind']}"
                ": the working modes are lost, the analysis stops here (Type II instants"
                " are sought before it only)"
            )
            continue
        joint = "A" if k["leg"] == 1 else "B"
        out.append(f"inverse-kinematic singularity at t = {times[k['t']]} s: E at {joint}")
    for b in rep["beyond_double_range"]:
        out.append(f"{b['quantity']} = {b['value']}: beyond the double range")
    near = approach(rep)
    if near:
        out.append(near)
    return out


def robust_lines(rep: dict[str, Any]) -> list[str]:
    """One line per singular instant with declared uncertainty: ``  robust t = 2.5 s:
    residual [-0.0211, 0.0211] N, window 5.44 ms (|T1|, t = 2.49728 .. 2.50273 s),
    period 1 ms``."""
    u = rep.get("uncertainty")
    if u is None:
        return []
    e = scheme(rep)
    times = instant_times(rep)
    out = []
    for s in rep["singularities"]:
        r = s.get("robust")
        if r is None:
            continue
        lo, hi = r["residual"]
        residual = "[{}, {}]".format(*outward(lo, hi)) if lo != hi else number(lo)
        where = ""
        if r["joint"] is not None and r["span"] is not None:
            t0, t1 = outward(*r["span"])
            where = f" (|{e.letter}{r['joint']}|, t = {t0} .. {t1} s)"
        out.append(
            f"  robust t = {times[s['t']]} s: residual {residual} N,"
            f" window {with_unit(r['window'], 's', toward=1)}{where},"
            f" period {with_unit(u['period'], 's')}"
        )
    if "peak" in u:
        (_, h1), (_, h2) = u["peak"]
        out.append(
            f"  robust peak outside the windows: |{e.letter}1| <= {number(h1, toward=1)}"
            f" {e.unit}, |{e.letter}2| <= {number(h2, toward=1)} {e.unit} (over the box)"
        )
    return out

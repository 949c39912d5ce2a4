"""``rprpr check --format junit``: JUnit XML, as GitHub, GitLab and Jenkins read it.

One ``testsuite`` per run (inside a ``testsuites`` root), one ``testcase`` per task::

    <testcase classname="configs/paper_path1.rprpr.yaml" name="Example 1 of the paper, path 1"
              file="configs/paper_path1.rprpr.yaml" time="0.004">
      <failure type="RPR101" message="RPR101 slope-principle: t = 2.5 s, ...">...</failure>
      <system-out>...</system-out>
    </testcase>

* a ``failure`` per finding that fails the task (each failing singular instant's broken
  principle or unbounded torques, an inverse-kinematic singularity, ...; in strict mode
  also RPR202 and an accepted RPR201),
  ``type`` = the rule id, ``message`` = rule and reason, the text = file:line and reason;
* an ``error`` (type RPR001) for a task file that could not be read, with the file,
  line, column and key; an ``error`` of type ``internal-error`` for a bug, with the
  traceback; an ``error`` of type ``budget-exceeded`` for a task stopped at its work
  budget;
* ``system-out``: one line per singular instant (and with declared uncertainty its
  robust line, as the text report's), then the strict-mode-only findings that
  do not fail the task (RPR202, and RPR201 accepted with ``checks.unbounded_torque:
  warn`` or ``--warn-unbounded``, when not strict), marked ``warning``, the closest
  approach to AB of a motion that never meets it, and the verdict with the certified
  torque peak. The warnings are not failures, so a CI dashboard stays green, but they
  are shown.

Counts: ``tests`` = testcases, ``failures`` = testcases with a failure, ``errors`` =
testcases with an error, ``skipped`` = 0; ``time`` = seconds to load and audit the task
(a testsuite's: the sum). There is no timestamp or hostname, so the document only
varies from run to run in its times. The elements and attributes are those of the
Jenkins ``junit-10.xsd`` schema, plus ``file`` on a testcase (read by GitLab).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

from ..model.numbers import fixed, number
from ..model.rules import RULES
from ..report.records import instant_times, scheme
from ..report.run import BUDGET, INPUT, INTERNAL, Run
from . import phrases
from .escape import inert_xml, printable

SUITE_NAME = "rprpr check"


def xml_text(s: str) -> str:
    """``s`` fit for XML 1.0: every control character (those XML cannot carry among
    them) escaped by ``escape.printable``, but tab, newline and carriage return, which
    XML carries (in an attribute as ``&#10;``) and a dashboard shows as line breaks."""
    return printable(s, keep="\t\n\r")


def _seconds(t: float) -> str:
    return fixed(t, 3)


def _el(parent: ET.Element, tag: str, text: str | None = None, **attrs: str) -> ET.Element:
    e = ET.SubElement(parent, tag, {k: xml_text(v) for k, v in attrs.items()})
    if text is not None:
        e.text = xml_text(text)
    return e


def _where(file: str, line: int | None, key: str | None) -> str:
    loc = f"{file}:{line}" if line else file
    return f"{loc}: {key}:" if key else f"{loc}:"


def _instant_line(s: dict[str, Any], t: str, effort: str = "torque") -> str:
    """One singular instant of the system-out; ``t`` = its time as text; ``effort``:
    "torque", or "force" for a prismatic robot."""
    bounded = (
        f"{effort} bounded"
        if s["torque_bounded"]
        else f"{effort} unbounded (pole of order {s['pole_order']})"
    )
    where = (
        f"(x, y) = ({number(s['x'])}, {number(s['y'])}), modes"
        f" ({s['modes'][0]:+d}, {s['modes'][1]:+d}), σ = {s['sigma']:+d}"
        if "modes" in s  # a 5R's instant
        else f"(x, y) = ({number(s['x'])}, 0), case {s['case']}"
    )
    return (
        f"t = {t} s: {where}, order {s['order']}"
        f" {s['kind']}; slope principle {s['slope_principle']}, velocity principle"
        f" {s['velocity_principle']}; {bounded}"
    )


def _report_case(case: ET.Element, rep: dict[str, Any]) -> bool:
    """Fill the testcase of an audited task; True when it failed."""
    times = instant_times(rep)
    effort = scheme(rep).noun[:-1]  # torque, force
    out = [_instant_line(s, times[s["t"]], effort) for s in rep["singularities"]]
    out += [line.strip() for line in phrases.robust_lines(rep)]  # with uncertainty only
    for f in rep["findings"]:
        title = RULES[f["rule"]].title
        where = _where(rep["task"], f["line"], f["key"])
        if f["severity"] == "error":
            _el(case, "failure", f"{where} {title}: {f['message']}",
                type=f["rule"], message=f"{title}: {f['message']}")  # fmt: skip
        else:
            out.append(f"warning: {where} {title}: {f['message']} (fails only with --strict)")
    out += [
        f"{b['quantity']} = {b['value']}: beyond the double range"
        for b in rep["beyond_double_range"]
    ]
    near = phrases.approach(rep)
    if near:
        out.append(near)
    n = len(rep["singularities"])
    peak = phrases.peak(rep)
    out.append(
        f"verdict: {rep['verdict']}{' (strict)' if rep['strict'] else ''}, "
        f"{n} singular instant{'s' if n != 1 else ''}{'; ' + peak if peak else ''}"
    )
    _el(case, "system-out", "\n".join(out) + "\n")
    return bool(rep["verdict"] == "fail")


def render(run: Run) -> str:
    """The JUnit XML document of ``run`` (UTF-8 text with its XML declaration)."""
    root = ET.Element("testsuites", {"name": SUITE_NAME})
    suite = ET.SubElement(root, "testsuite", {"name": SUITE_NAME})
    failures = errors = 0
    total = 0.0
    for kind, item, seconds in run.entries():
        total += seconds
        path = item["task"]
        name = item.get("name", path) if kind not in (INPUT, INTERNAL, BUDGET) else path
        case = _el(suite, "testcase", classname=path, name=name, file=path, time=_seconds(seconds))
        if kind == INPUT:
            errors += 1
            rule = RULES[item["rule"]].title
            where = _where(path, item["line"], item["key"])
            more = len(item["errors"]) - 1
            also = f" (and {more} more error{'s' if more != 1 else ''})" if more else ""
            _el(case, "error", "".join(f"{e['text']}\n" for e in item["errors"]),
                type=item["rule"], message=f"{rule}: {where} {item['message']}{also}")  # fmt: skip
        elif kind == INTERNAL:
            errors += 1
            _el(case, "error", item["traceback"], type="internal-error", message=item["text"])
        elif kind == BUDGET:
            errors += 1
            _el(case, "error", f"{item['text']}\n", type="budget-exceeded", message=item["text"])
        elif _report_case(case, item):
            failures += 1
    counts = {
        "tests": str(len(run.order)),
        "failures": str(failures),
        "errors": str(errors),
    }
    root.attrib.update(counts, time=_seconds(total))
    suite.attrib.update(counts, skipped="0", time=_seconds(total))
    ET.indent(root, space="  ")
    text = ET.tostring(root, encoding="unicode")
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + inert_xml(text) + "\n"

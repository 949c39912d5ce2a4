"""HTML from the report's records: ``render``, the page of ``rprpr check --format html``
(a CI artefact), and ``report_html``, one task as a small table (the rich display of an
audit result in a notebook, ``rprpr.api.AuditResult._repr_html_``).

The page is one self-contained file that never reaches the network: inline CSS, each
task's audit sheet as inline SVG (``report.run.Attachment``, drawn by the worker that
audited the task), no script, no font, no image fetched, and a Content-Security-Policy
of ``default-src 'none'`` that would block anything that slipped in. It holds the run's
summary, a contents list, and per task its verdict, its findings (each ``FILE:LINE``
linked to that line of the task file, quoted beside it), its singular instants, its
sheet and its file's lines. Readable on a phone (the tables and the listing scroll
sideways inside the page, the sheet shrinks to the width) and printable (print CSS).

Every text from outside rprpr (a file name, a task's name, a line of the task file, a
quoted value) goes through ``escape.printable`` (controls and bytes that are not UTF-8
made visible) and then ``html.escape``; numbers go through ``model.numbers``. Only the
task file's own lines are quoted, and of a file that could not be read, only the lines
its errors name.
"""

from __future__ import annotations

import re
from html import escape
from typing import Any

from .._version import __version__
from ..model.numbers import CELL, number
from ..model.rules import RULES
from ..report.records import INVALID_TASK, instant_times, scheme
from ..report.run import BUDGET, INPUT, REPORT, Attachment, Run
from . import phrases
from .escape import printable
from .text import columns, instant_cells

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


# ---------------------------------------------------------------- the page (check --format html)

QUOTE_WIDTH = 240  # characters of a quoted line shown; a longer line ends with …
LISTING_LINES = 500  # lines of a task file listed; a longer file lists its first ones
CSP = "default-src 'none'; style-src 'unsafe-inline'; base-uri 'none'; form-action 'none'"

CSS = """
:root{--fg:#1b1f24;--muted:#57606a;--line:#d0d7de;--bg2:#f6f8fa;--pass:#1a7f37;
--fail:#cf222e;--warn:#9a6700;--err:#8250df;--hit:#fff8c5}
*{box-sizing:border-box}
html{-webkit-text-size-adjust:100%;text-size-adjust:100%}
body{margin:0 auto;max-width:1100px;padding:1rem;color:var(--fg);background:#fff;
font:15px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,"Helvetica Neue",Arial,sans-serif}
h1{font-size:1.5rem;margin:.2rem 0 .4rem}
h2{font-size:1.2rem;margin:0 0 .3rem;overflow-wrap:anywhere}
h3{font-size:1rem;margin:1rem 0 .4rem}
a{color:#0969da}
code,pre,.mono{font-family:ui-monospace,SFMono-Regular,Menlo,Consolas,"DejaVu Sans Mono",monospace;
font-size:.86em}
.summary{font-size:1.05rem;margin:.2rem 0}
.note{border-left:4px solid var(--warn);background:#fff8c5;padding:.4rem .7rem;margin:.6rem 0}
.muted{color:var(--muted)}
.badge{display:inline-block;min-width:3.6em;text-align:center;border-radius:.3em;
padding:0 .4em;margin-right:.4em;font-weight:700;color:#fff;font-size:.85em;
vertical-align:.1em}
.badge.pass{background:var(--pass)}.badge.fail{background:var(--fail)}
.badge.error{background:var(--err)}
nav ol{padding-left:1.4rem;margin:.3rem 0}
nav li{margin:.15rem 0;overflow-wrap:anywhere}
section.task{border:1px solid var(--line);border-radius:.5rem;padding:.8rem 1rem;margin:1rem 0}
section.task.fail{border-left:6px solid var(--fail)}
section.task.pass{border-left:6px solid var(--pass)}
section.task.error{border-left:6px solid var(--err)}
.file{margin:0 0 .3rem;overflow-wrap:anywhere}
.verdict{margin:.3rem 0}
ul.details{margin:.3rem 0;padding-left:1.2rem}
ol.findings{list-style:none;padding:0;margin:0}
ol.findings li{border-top:1px solid var(--line);padding:.4rem 0;overflow-wrap:anywhere}
.sev-error{color:var(--fail);font-weight:700}.sev-warning{color:var(--warn);font-weight:700}
.where{font-weight:600}
pre{background:var(--bg2);border:1px solid var(--line);border-radius:.3rem;padding:.4rem .6rem;
margin:.3rem 0;overflow-x:auto;white-space:pre;tab-size:4}
pre.quote{margin:.3rem 0 0}
.fix{margin:.3rem 0 0;color:var(--muted);font-size:.92em}
.ln{display:inline-block;min-width:3ch;text-align:right;color:var(--muted);margin-right:1ch;
user-select:none}
.hit{background:var(--hit)}
.scroll{overflow-x:auto;-webkit-overflow-scrolling:touch;margin:.3rem 0}
table{border-collapse:collapse;font-variant-numeric:tabular-nums;white-space:nowrap;font-size:.9em}
th,td{border:1px solid var(--line);padding:.2rem .5rem;text-align:left}
th{background:var(--bg2)}
td.num{text-align:right}
td.pass{color:var(--pass)}td.fail{color:var(--fail);font-weight:700}
figure.sheet{margin:.5rem 0;overflow-x:auto;-webkit-overflow-scrolling:touch}
figure.sheet svg{display:block;width:100%;min-width:600px;height:auto;max-width:792pt}
details summary{cursor:pointer;font-weight:600;margin:.6rem 0 .2rem}
footer{margin:1.5rem 0 .5rem;color:var(--muted);font-size:.85rem}
@media (max-width:600px){body{padding:.6rem;font-size:14px}section.task{padding:.6rem}}
@media print{
body{max-width:none;padding:0;font-size:10pt}
nav,footer{display:none}
a{color:inherit;text-decoration:none}
section.task{break-inside:auto;border:1px solid #999;border-left-width:6px}
section.task+section.task{break-before:page}
.scroll,pre{overflow:visible}
pre{white-space:pre-wrap;overflow-wrap:anywhere}
table{white-space:normal;font-size:8.5pt}
tr,figure.sheet,ol.findings li{break-inside:avoid}
figure.sheet{overflow:visible}
figure.sheet svg{min-width:0;max-height:24cm}
.badge{print-color-adjust:exact;-webkit-print-color-adjust:exact}
}
"""


def _text(s: str) -> str:
    """A text from outside rprpr, fit for the page: controls made visible, then escaped."""
    return escape(printable(s))


def _plural(n: int, word: str) -> str:
    return f"{n} {word}{'' if n == 1 else 's'}"


def _summary(run: Run) -> str:
    s = run.summary()
    return (
        f"{_plural(s['tasks'], 'task')}: {s['passed']} passed, {s['failed']} failed, "
        f"{_plural(s['errors'], 'error')}"
    )


def render(run: Run, *, quiet: bool = False) -> str:
    """The page of ``run``: the summary, its notes, a contents list, then each task
    (``quiet``: the failing ones and the errors only), in task order."""
    shown = [
        (i, kind, item)
        for i, (kind, item, _) in enumerate(run.entries())
        if not (quiet and kind == REPORT and item["verdict"] == "pass")
    ]
    summary = _summary(run)
    body = [
        "<header>",
        "<h1>rprpr check</h1>",
        f'<p class="summary">{escape(summary)}</p>',
        *(f'<p class="note">{_text(n)}</p>' for n in run.notes),
        "</header>",
    ]
    if shown:
        body.append('<nav aria-label="tasks"><ol>')
        for i, kind, item in shown:
            badge = _badge(kind, item)
            name = f" {_text(item['name'])}" if kind == REPORT else ""
            body.append(
                f'<li>{badge}<a href="#task-{i + 1}" class="mono">{_text(item["task"])}</a>'
                f"{' —' + name if name else ''}</li>"
            )
        body.append("</ol></nav>")
    elif quiet and run.order:
        body.append('<p class="muted">Every task passed (-q lists failures and errors only).</p>')
    body.append("<main>")
    for i, kind, item in shown:
        attachment = run.attachments.get(i, Attachment())
        if kind == REPORT:
            body.append(_task(i + 1, item, attachment))
        else:
            body.append(_error(i + 1, kind, item, attachment))
    body.append("</main>")
    body.append(
        f"<footer>Written by rprpr {escape(__version__)} (rprpr check --format html). "
        "The sheets are drawn from the same audits as the verdicts.</footer>"
    )
    title = f"rprpr check: {summary}"
    return (
        "<!DOCTYPE html>\n"
        '<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
        f'<meta http-equiv="Content-Security-Policy" content="{CSP}">\n'
        f'<meta name="generator" content="rprpr {escape(__version__)}">\n'
        f"<title>{escape(title)}</title>\n<style>{CSS}</style>\n</head>\n<body>\n"
        + "\n".join(body)
        + "\n</body>\n</html>\n"
    )


def _badge(kind: str, item: dict[str, Any]) -> str:
    if kind == REPORT:
        word = "PASS" if item["verdict"] == "pass" else "FAIL"
        return f'<span class="badge {word.lower()}">{word}</span>'
    return '<span class="badge error">ERROR</span>'


def _anchor(n: int, line: int) -> str:
    return f"task-{n}-L{line}"


def _quote(source: tuple[str, ...] | None, line: int | None) -> str:
    """The line ``line`` of the task file, numbered, as a one-line listing ("" when the
    file's lines are not at hand or it has no such line)."""
    if source is None or line is None or not 1 <= line <= len(source):
        return ""
    return f'<pre class="quote"><span class="ln">{line}</span>{_line(source[line - 1])}</pre>'


def _fix(rule: str) -> str:
    """How to fix a finding of ``rule`` (``rprpr rule``'s words), `code` set as code."""
    known = RULES.get(rule)
    if known is None:
        return ""
    words = re.sub(r"`([^`]+)`", r"<code>\1</code>", escape(known.fix))
    return f'<p class="fix"><strong>Fix:</strong> {words}</p>'


def _line(text: str) -> str:
    """One line of a task file, escaped, at most ``QUOTE_WIDTH`` characters."""
    cut = text if len(text) <= QUOTE_WIDTH else text[:QUOTE_WIDTH] + "…"
    return escape(printable(cut, keep="\t"))


def _task(n: int, rep: dict[str, Any], attachment: Attachment) -> str:
    """One audited task: heading, verdict, findings, instants, sheet, file."""
    verdict = "pass" if rep["verdict"] == "pass" else "fail"
    times = instant_times(rep)
    source = attachment.source
    count = len(rep["singularities"])
    high = sum(s["high_order"] for s in rep["singularities"])
    peak = phrases.peak(rep)
    line = (
        f"{_plural(count, 'singular instant')}, {high} high-order"
        + (f"; {peak}" if peak else "")
        + (" (strict)" if rep["strict"] else "")
    )
    out = [
        f'<section class="task {verdict}" id="task-{n}">',
        f"<h2>{_badge(REPORT, rep)}{_text(rep['name'])}</h2>",
        f'<p class="file mono">{_text(rep["task"])}</p>',
        f'<p class="verdict">{escape(line)}</p>',
    ]
    details = phrases.details(rep, times)
    if details:
        out.append('<ul class="details">')
        out += [f"<li>{_text(d)}</li>" for d in details]
        out.append("</ul>")
    if rep["findings"]:
        out.append(f"<h3>Findings ({len(rep['findings'])})</h3>")
        out.append('<ol class="findings">')
        for f in rep["findings"]:
            where = f"{_text(rep['task'])}:{f['line']}"
            linked = source is not None and 1 <= f["line"] <= min(len(source), LISTING_LINES)
            place = (
                f'<a class="where mono" href="#{_anchor(n, f["line"])}">{where}</a>'
                if linked
                else f'<span class="where mono">{where}</span>'
            )
            out.append(
                f'<li class="{escape(f["severity"])}">{place} '
                f'<span class="sev-{escape(f["severity"])}">{escape(f["rule"])}</span> '
                f"[{escape(f['severity'])}] {escape(f['name'])}: {_text(f['message'])}"
                f"{_quote(source, f['line'])}{_fix(f['rule'])}</li>"
            )
        out.append("</ol>")
    out.append("<h3>Singular instants</h3>")
    if rep["singularities"]:
        out.append(_instants(rep, times))
    else:
        out.append('<p class="muted">no Type II singular instant in [0, t_f]</p>')
    if attachment.sheet is not None:
        out.append("<h3>Audit sheet</h3>")
        out.append(f'<figure class="sheet">{inline_svg(attachment.sheet, f"s{n}-")}</figure>')
    elif attachment.note:
        out.append(f'<p class="note">{_text(attachment.note)}</p>')
    if source is not None:
        hits = {f["line"] for f in rep["findings"]}
        out.append(_listing(n, source, hits))
    out.append("</section>")
    return "\n".join(out)


_NUMERIC = {0, 4, 5, 8}  # right-aligned columns


def _instants(rep: dict[str, Any], times: dict[float, str]) -> str:
    """The singular instants as a table (the text report's columns), scrolling sideways
    inside the page where the screen is narrow."""
    head = "".join(f'<th scope="col">{escape(c)}</th>' for c, _ in columns(rep))
    rows = []
    for s in rep["singularities"]:
        principles = {6: s["slope_principle"], 7: s["velocity_principle"]}  # pass/fail
        tds = []
        for k, (word, _) in enumerate(instant_cells(s, times[s["t"]])):
            cls = "num" if k in _NUMERIC else principles.get(k, "")
            tds.append(
                f'<td class="{cls}">{escape(word)}</td>' if cls else f"<td>{escape(word)}</td>"
            )
        rows.append("<tr>" + "".join(tds) + "</tr>")
    return (
        '<div class="scroll"><table><thead><tr>'
        + head
        + "</tr></thead><tbody>"
        + "".join(rows)
        + "</tbody></table></div>"
    )


def _listing(n: int, source: tuple[str, ...], hits: set[int]) -> str:
    """The task file's lines, numbered, each an anchor (``FILE:LINE`` links land there),
    the lines of findings marked; at most ``LISTING_LINES`` of them."""
    shown = source[:LISTING_LINES]
    rows = []
    for k, text in enumerate(shown, start=1):
        cls = ' class="hit"' if k in hits else ""
        rows.append(
            f'<span id="{_anchor(n, k)}"{cls}><span class="ln">{k}</span>{_line(text)}</span>'
        )
    more = (
        f'<p class="muted">… {len(source) - LISTING_LINES} more lines not listed</p>'
        if len(source) > LISTING_LINES
        else ""
    )
    return (
        f"<details open><summary>Task file ({_plural(len(source), 'line')})</summary>"
        f'<pre class="source">' + "\n".join(rows) + "</pre>" + more + "</details>"
    )


def _error(n: int, kind: str, item: dict[str, Any], attachment: Attachment) -> str:
    """A task that was not audited: a bad task file (each error at its line, that line
    quoted), a bug, or a task stopped at its work budget."""
    what = (
        "bad task file"
        if kind == INPUT
        else "stopped at its work budget"
        if kind == BUDGET
        else "internal error"
    )
    out = [
        f'<section class="task error" id="task-{n}">',
        f"<h2>{_badge(kind, item)}{escape(what)}</h2>",
        f'<p class="file mono">{_text(item["task"])}</p>',
        '<ol class="findings">',
    ]
    for e in item.get("errors", [item]):
        line = e.get("line")
        if kind == INPUT:
            where = f"{_text(item['task'])}:{line or 1}:{(e['column'] or 1) if line else 1}"
            message = f"{e['key']}: {e['message']}" if e["key"] else e["message"]
            out.append(
                f'<li class="error"><span class="where mono">{where}</span> '
                f'<span class="sev-error">{escape(e["rule"])}</span> [error] '
                f"{_text(message)}{_quote(attachment.source, line)}</li>"
            )
        else:
            out.append(f'<li class="error">{_text(e["text"])}</li>')
    out.append("</ol>")
    if kind == INPUT:
        out.append(_fix(INVALID_TASK))
    out.append("</section>")
    return "\n".join(out)


# the parts of matplotlib's SVG file that a page does not want inline
_PROLOG = re.compile(r"\A\s*<\?xml[^>]*\?>\s*(<!DOCTYPE[^>]*>\s*)?")
_METADATA = re.compile(r"<metadata>.*?</metadata>\s*", re.S)
_ID = re.compile(r'\bid="([^"]+)"')
_SIZE = re.compile(r'\s(width|height)="[^"]*"')
_TAG = re.compile(r"<[^>]*>")  # text and attribute values hold no < or > (matplotlib escapes)
_UNSAFE = re.compile(r"^</?\s*(script|foreignObject)|\son[a-z]+\s*=|href\s*=\s*\"(?!#)", re.I)


def inline_svg(svg: str, prefix: str) -> str:
    """matplotlib's SVG file ``svg`` fit to sit in the page: no XML prolog or doctype,
    no metadata block, no fixed size (CSS scales it to the width), and every id (and
    each reference to one: ``href="#id"``, ``url(#id)``) prefixed with ``prefix``, so
    that two sheets on one page never share an id (an id the SVG gives twice keeps its
    first, the others numbered: ``-2``); the characters ``escape.printable`` escapes
    (a bidirectional override in a task's name) made visible. An SVG that would script or fetch
    anything is replaced by a line saying so (matplotlib never writes one)."""
    body = _METADATA.sub("", _PROLOG.sub("", svg, count=1), count=1)
    body = printable(body, keep="\n\r\t")  # a bidi override of a task's name, made visible
    if any(_UNSAFE.search(tag) for tag in _TAG.findall(body)):
        return '<p class="note">The audit sheet was left out: it held active content.</p>'
    ids = set(_ID.findall(body))
    if ids:
        names = "|".join(re.escape(i) for i in sorted(ids, key=len, reverse=True))
        body = re.sub(rf'href="#({names})"', lambda m: f'href="#{prefix}{m[1]}"', body)
        body = re.sub(rf"url\(#({names})\)", lambda m: f"url(#{prefix}{m[1]})", body)
        seen: dict[str, int] = {}

        def unique(m: re.Match[str]) -> str:  # an id given twice (two axes of one panel)
            n = seen[m[1]] = seen.get(m[1], 0) + 1  # keeps its first: references find it
            return f'id="{prefix}{m[1]}{"" if n == 1 else f"-{n}"}"'

        body = _ID.sub(unique, body)
    head_end = body.index(">") + 1 if body.startswith("<svg") else 0
    head = _SIZE.sub("", body[:head_end])
    if head:
        head = head[:-1] + ' role="img" focusable="false">'
    return head + body[head_end:]

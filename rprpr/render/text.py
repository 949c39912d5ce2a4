"""The human report of ``rprpr check`` (rich), from the plain reports of ``report``.

For each task, as a linter writes it (ruff's concise style): one line per finding,
``FILE:LINE:COL: RPRnnn [severity] name: message`` (editors and terminals jump to it),
then the task (file and name), its singular instants (the table when it fits the width,
else stacked ``key  value`` rows per instant, so that nothing is cut at any width: 80
columns, 60) and its verdict line with the certified torque peak. A finding's line is
never wrapped, on a terminal or not (a terminal folds it for the eye, but the text keeps
it one line: grep, editors and problem matchers see its ``FILE:LINE`` with all of it);
the other lines wrap at the width, and only a token longer than the width is folded.

Every text that came from outside (a file name, a task's name, a value quoted in a
message) is printed through ``escape.printable``: no control character reaches the
terminal, and no line can be forged (the console's stream makes every line ``inert``
for a CI runner too: ``cli.output.Inert``).

The report is drawn as runs of (text, style) handed to the console as Segments, not
through rich's Table and Text wrapping (milliseconds a row): its cost is proportional to
its characters however many instants a task has, and its bytes are the same."""

from __future__ import annotations

import functools
import itertools
from collections.abc import Iterator
from typing import Any

from rich._wrap import divide_line
from rich.cells import cell_len
from rich.console import Console, ConsoleOptions
from rich.segment import Segment
from rich.style import Style
from rich.text import Text

from ..model.actuation import REVOLUTE
from ..model.numbers import CELL, number
from ..report.records import instant_times, scheme
from ..report.run import Run
from . import phrases
from .escape import printable

# the columns of an instant: (title, justify in the table)
COLUMNS = (
    ("t [s]", "right"), ("(x, y) [m]", "left"), ("case σ ψ", "left"), ("order", "left"),
    ("dy/dx", "right"), ("speed [m/s]", "right"), ("slope", "left"), ("velocity", "left"),
    ("eq.(34) [N]", "right"), ("bounded", "left"), ("T(t_s) [N m]", "left"),
)  # fmt: skip


def _cell(v: float | None) -> str:
    return "—" if v is None else number(v, CELL)


def _pf(v: str) -> tuple[str, str]:
    return ("pass", "green") if v == "pass" else ("FAIL", "bold red")


# a 5R's instant: its working modes and line-up σ, tan α of its crossing angle with the
# Type II curve, the reciprocity residual w(t_s) (report.five_bar_records)
FIVE_BAR_COLUMNS = tuple(
    {"case σ ψ": ("modes σ", "left"), "dy/dx": ("tan α", "right"),
     "eq.(34) [N]": ("w(t_s) [N]", "right")}.get(title, (title, just))
    for title, just in COLUMNS
)  # fmt: skip


def columns(rep: dict[str, Any]) -> tuple[tuple[str, str], ...]:
    """``COLUMNS`` with the titles of the task's actuation scheme (prismatic: the
    moment balance residual and F(t_s) [N]), or of its mechanism (the 5R's)."""
    if "mechanism" in rep:
        return FIVE_BAR_COLUMNS
    e = scheme(rep)
    if e.name == REVOLUTE:
        return COLUMNS
    named = {"eq.(34) [N]": e.column, "T(t_s) [N m]": f"{e.letter}(t_s) [{e.unit}]"}
    return tuple((named.get(title, title), just) for title, just in COLUMNS)


def instant_cells(s: dict[str, Any], t: str) -> list[tuple[str, str]]:
    """The cells of one singular instant, in the order of ``COLUMNS``: (text, style)
    (the text report's table and rows, and the HTML report's table)."""
    order = f"{s['order']} {s['kind']}"
    bounded = f"{s['conditions_met']}/{s['conditions_required']}"
    torque = (
        ", ".join(_cell(v) for v in s["torque_at_singularity"])
        if s["torque_at_singularity"]
        else "sides differ"  # a knot whose two one-sided limits are finite but differ
        if s["torque_bounded"]
        else "unbounded"
    )
    if "modes" in s:  # a 5R's instant (``FIVE_BAR_COLUMNS``)
        e1, e2 = s["modes"]
        where = (f"({_cell(s['x'])}, {_cell(s['y'])})", "")
        case = (f"{e1:+d} {e2:+d}  {s['sigma']:+d}", "")
    else:
        where = (f"({_cell(s['x'])}, 0)", "")
        case = (f"{s['case']}  {s['sigma']:+d} {s['psi']:+d}", "")
    return [
        (t, ""),
        where,
        case,
        (order, "bold red" if s["high_order"] else ""),
        (_cell(s["slope"]), ""),
        (_cell(s["speed"]), ""),
        _pf(s["slope_principle"]),
        _pf(s["velocity_principle"]),
        (_cell(s["consistency_residual"]), ""),
        (
            bounded + (" yes" if s["torque_bounded"] else f" no, pole {s['pole_order']}"),
            "green" if s["torque_bounded"] else "yellow",
        ),
        (torque, ""),
    ]


# -- drawing: styled runs straight to the console ------------------------------------------
# A report can hold thousands of instants and findings (a zig-zag timing crosses y = 0 a
# thousand times); rich's Table and its wrapping cost milliseconds a row. So the text is
# drawn here as runs of (text, style), wrapped where rich wraps (``rich._wrap.divide_line``,
# the same breaks) and handed to the console as Segments: the cost is proportional to the
# characters, and the bytes are those rich's Table and print would write.
Runs = list[tuple[str, str]]  # (text, style) pieces of a line

# the table's rules: rich's HEAVY_HEAD box (a heavy frame about the header)
TOP, HEAD_RULE, BOTTOM = ("┏", "━", "┳", "┓"), ("┡", "━", "╇", "┩"), ("└", "─", "┴", "┘")
HEAD_BAR, ROW_BAR = "┃", "│"
GAP = "  "  # between the key and the value of the stacked rows


class _Segments:
    """Lines of runs as a rich renderable: its Segments, each line ended (runs of one
    style merged; a console without colour gets the plain text, one Segment a line)."""

    def __init__(self, colored: bool) -> None:
        self.colored = colored
        self.segments: list[Segment] = []

    def line(self, runs: Runs) -> None:
        if not self.colored:
            self.segments.append(Segment("".join(text for text, _ in runs) + "\n"))
            return
        for style, group in itertools.groupby(runs, key=lambda run: run[1]):
            text = "".join(t for t, _ in group)
            if text:
                self.segments.append(Segment(text, _style(style)))
        self.segments.append(Segment.line())

    def __rich_console__(self, console: Console, options: ConsoleOptions) -> Iterator[Segment]:
        yield from self.segments


@functools.lru_cache(maxsize=64)
def _style(style: str) -> Style | None:
    return Style.parse(style) if style else None


def _cells_of(text: str) -> int:
    """The terminal cells ``text`` takes (an ASCII text: its length)."""
    return len(text) if text.isascii() else cell_len(text)


def _width(runs: Runs) -> int:
    return sum(_cells_of(text) for text, _ in runs)


def _wrapped(runs: Runs, width: int) -> list[Runs]:
    """``runs`` as lines of at most ``width`` cells, broken as rich's ``Text.wrap``
    breaks them: at spaces (``divide_line``), a word longer than the width folded, and
    a line's trailing blanks dropped as far as it is longer than the width."""
    plain = "".join(text for text, _ in runs)
    if len(plain) <= width and _cells_of(plain) <= width:
        return [runs]
    cuts = [0, *divide_line(plain, width, fold=True), len(plain)]
    lines = []
    for start, end in itertools.pairwise(cuts):
        piece = plain[start:end]
        excess = len(piece) - width
        if excess > 0:
            end -= min(len(piece) - len(piece.rstrip()), excess)
        lines.append(_sliced(runs, start, end))
    return lines


def _sliced(runs: Runs, start: int, end: int) -> Runs:
    """The part of ``runs`` from character ``start`` to ``end``."""
    out: Runs = []
    at = 0
    for text, style in runs:
        lo, hi = max(start - at, 0), min(end - at, len(text))
        if lo < hi:
            out.append((text[lo:hi], style))
        at += len(text)
    return out


def _padded(runs: Runs, width: int, justify: str, pad_style: str) -> Runs:
    room = width - _width(runs)
    left = room if justify == "right" else room // 2 if justify == "center" else 0
    return [(" " * left, pad_style), *runs, (" " * (room - left), pad_style)]


def _instant_cells(rep: dict[str, Any]) -> list[list[tuple[str, str]]]:
    times = instant_times(rep)
    return [instant_cells(s, times[s["t"]]) for s in rep["singularities"]]


def _table_widths(rep: dict[str, Any], rows: list[list[tuple[str, str]]]) -> list[int]:
    """Each column's width: its widest cell, title included."""
    titles = [(title, "") for title, _ in columns(rep)]
    return [max(_cells_of(text) for text, _ in col) for col in zip(titles, *rows, strict=True)]


def singularity_table(rep: dict[str, Any], rows: list[list[tuple[str, str]]]) -> list[Runs]:
    """The singular instants of ``rep`` (their cells ``rows``) as one table, a row per
    instant: every cell on one line, each column as wide as its widest cell (rich's
    Table with the HEAVY_HEAD box, drawn directly)."""
    titles = columns(rep)
    widths = _table_widths(rep, rows)
    justify = [just for _, just in titles]
    header = [[(title, "")] for title, _ in titles]
    lines = [[(_rule(TOP, widths), "")], _row(header, widths, justify, HEAD_BAR, "bold")]
    lines.append([(_rule(HEAD_RULE, widths), "")])
    lines += [_row([[c] for c in row], widths, justify, ROW_BAR) for row in rows]
    lines.append([(_rule(BOTTOM, widths), "")])
    return lines


def _rule(box: tuple[str, str, str, str], widths: list[int]) -> str:
    left, line, cross, right = box
    return left + cross.join(line * (w + 2) for w in widths) + right


def _row(
    cells: list[Runs], widths: list[int], justify: list[str], bar: str, style: str = ""
) -> Runs:
    """One line of the table: each cell padded to its column's width as ``justify``
    says, one space either side, between bars (the header: all of it in ``style``)."""
    out: Runs = [(bar, "")]
    for cell, width, just in zip(cells, widths, justify, strict=True):
        own = style or cell[0][1]  # a cell is one text in one style: its padding too
        runs = [(text, style or s) for text, s in cell]
        out += [(" ", own), *_padded(runs, width, just, own), (" ", own), (bar, "")]
    return out


def stacked(rep: dict[str, Any], rows: list[list[tuple[str, str]]], width: int) -> list[Runs]:
    """The singular instants of ``rep`` (their cells ``rows``) as ``key  value`` rows, one
    block per instant: every cell of the table, in any ``width`` (a value too long for
    it is folded onto the next lines, under its key, as rich's grid folds it)."""
    titles = [title for title, _ in columns(rep)[1:]]
    blocks: list[tuple[str, Runs]] = []
    for i, row in enumerate(rows):
        cells = [[c] for c in row]
        blocks.append((f"instant {i + 1}", [("t = ", ""), *cells[0], (" s", "")]))
        blocks += [(f"  {t}", cell) for t, cell in zip(titles, cells[1:], strict=True)]
    keys = max((_cells_of(k) for k, _ in blocks), default=0)
    values = max((_width(v) for _, v in blocks), default=0)
    room = max(1, min(values, width - keys - len(GAP)))
    lines = []
    for key, value in blocks:
        for n, line in enumerate(_wrapped(value, room)):
            pad = line[-1][1] if len(line) == 1 else ""
            head = (key if n == 0 else "").ljust(keys) + GAP
            lines.append([(head, "bold"), *line, (" " * (room - _width(line)), pad)])
    return lines


def render(
    run: Run, console: Console, err_console: Console, quiet: bool = False,
    errors_inline: bool = False, layout: str = "auto",
) -> None:  # fmt: skip
    """Print each task's report in task order, then a summary line when more than one
    task was checked. A task file that could not be read (or met a bug) is one line per
    error on ``err_console``, or in the report itself when ``errors_inline``. ``quiet``
    leaves out passing tasks, and the summary when every task passed. ``layout``: the
    singular instants as a "table", as key/value "rows", or "auto" (the table where it
    fits the width)."""
    for kind, item, _ in run.entries():
        if kind != "report":
            style = "red" if kind == "input" else "bold red"
            target = console if errors_inline else err_console
            for e in item.get("errors", [item]):  # a bad task file: each of its errors
                target.print(Text(printable(e["text"]), style=style), soft_wrap=True)
            continue
        if quiet and item["verdict"] == "pass":
            continue
        _task(item, console, layout)
    s = run.summary()
    if s["tasks"] > 1 and not (quiet and s["passed"] == s["tasks"]):
        errors = f"{s['errors']} error{'s' if s['errors'] != 1 else ''}"
        console.print(
            f"{s['tasks']} tasks: {s['passed']} passed, {s['failed']} failed, {errors}",
            style="bold",
        )


def finding_line(rep: dict[str, Any], f: dict[str, Any]) -> Runs:
    """``FILE:LINE:1: RPRnnn [severity] name: message`` (the column: the key starts its
    line); a warning is a strict-mode-only finding, which fails only with --strict."""
    style = "red" if f["severity"] == "error" else "yellow"
    return [
        (f"{printable(rep['task'])}:{f['line']}:1:", "bold"),
        (" ", ""),
        (f["rule"], style),
        (f" [{f['severity']}] {f['name']}: {printable(f['message'])}", ""),
    ]


def _task(rep: dict[str, Any], console: Console, layout: str = "auto") -> None:
    """One task's report: its findings (one line each, never wrapped: grep, editors and
    problem matchers see every finding whole), its name, its details, its singular
    instants (the table, or the stacked rows) and its verdict, drawn as runs (one print)."""
    width = console.width
    out = _Segments(console.color_system is not None)
    for f in rep["findings"]:
        out.line(finding_line(rep, f))
    lines = [[(printable(rep["task"]), "bold"), (" — ", ""), (printable(rep["name"]), "")]]
    lines += [[(f"  {line}", "")] for line in phrases.details(rep, instant_times(rep))]
    for line in lines:
        for part in _wrapped(line, width):
            out.line(part)
    if rep["singularities"]:
        rows = _instant_cells(rep)
        natural = sum(w + 3 for w in _table_widths(rep, rows)) + 1
        # the table when asked for (at its natural width, however narrow the terminal)
        # or when it fits; else the stacked rows
        fits = layout == "table" or (layout == "auto" and natural <= width)
        for line in singularity_table(rep, rows) if fits else stacked(rep, rows, width):
            out.line(line)
    for text in phrases.robust_lines(rep):  # with declared uncertainty only (docs/robust.md)
        for part in _wrapped([(text, "")], width):
            out.line(part)
    for part in _wrapped(_verdict(rep), width):
        out.line(part)
    console.print(out, crop=False)


def _verdict(rep: dict[str, Any]) -> Runs:
    """``  verdict: FAIL — 1 singular instant, 1 high-order; <the torque peak>``."""
    n = len(rep["singularities"])
    high = sum(s["high_order"] for s in rep["singularities"])
    peak = phrases.peak(rep)
    verdict = ("PASS", "bold green") if rep["verdict"] == "pass" else ("FAIL", "bold red")
    rest = (
        f" — {n} singular instant{'s' if n != 1 else ''}, {high} high-order"
        + (f"; {peak}" if peak else "")
        + (" (strict)" if rep["strict"] else "")
    )
    return [("  verdict: ", ""), verdict, (rest, "")]

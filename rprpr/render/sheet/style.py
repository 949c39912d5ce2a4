"""The sheet's look, stated once.

One task: colour is the quantity, the same in every panel and in the GIF: leg 1 (A-E;
θ1, s1, T1) blue, leg 2 (B-E; θ2, s2, T2) green, the end point E (path, x_E, y_E) black,
δ purple, the singular line y = 0 red. Two or three tasks overlaid: colour is the task
(``TASK_COLOURS``, Okabe and Ito's colour-blind-safe set) and, within a task, the line
style is the quantity (``QUANTITY_STYLES``: leg 1 solid, leg 2 dashed); a task's single
curves (path, δ) also take the task's line style (``style``), so greyscale still tells
them apart. More tasks are drawn as small multiples, one column each (``OVERLAID``).
A singular instant's status (the audit's, ``AuditResult.status_of``) is red when it fails
the task, amber when it warns, yellow when it passes. Overlaid, every mark of a task
carries the task's colour: a singular mark's edge, a ▲ ▼ or a ring its fill or edge.
"""

from __future__ import annotations

from contextvars import ContextVar
from typing import Any

LEG1 = "#0072B2"  # leg 1, A-E: θ1, s1, T1
LEG2 = "#009E73"  # leg 2, B-E: θ2, s2, T2
POINT = "#000000"  # the end point E: path, x_E, y_E
DELTA = "#6A3D9A"  # δ
LINE = "#D62728"  # the singular line y = 0
LINE_DASH: Any = (0, (7, 2, 1.5, 2))  # ... and its dash pattern
STATUS_COLOUR = {"fail": "#D62728", "warn": "#E69F00", "ok": "#F0E442"}
STATUS_WORD = {"fail": "fails", "warn": "warning", "ok": "passes"}
SEVERITY = {"ok": 0, "warn": 1, "fail": 2}
STYLES: tuple[Any, ...] = ("-", (0, (5, 2)), (0, (1, 1.5)))  # the overlaid tasks' curves
QUANTITY_STYLES: tuple[Any, ...] = ("-", (0, (4, 2)))  # leg 1, leg 2 of one overlaid task
TASK_COLOURS = (  # Okabe and Ito: told apart with each common colour-vision deficiency
    "#0072B2",  # blue
    "#D55E00",  # vermillion
    "#009E73",  # bluish green
    "#CC79A7",  # reddish purple
    "#56B4E9",  # sky blue
    "#E69F00",  # orange
    "#000000",  # black
    "#8C564B",  # brown
)
OVERLAID = 3  # at most this many tasks share axes; beyond, one column per task
# a knot of a piecewise motion (where one piece meets the next), on every time axis: light,
# dotted, under the curves; the same for every task
KNOT: dict[str, Any] = {"color": "#8A8A8A", "lw": 1.0, "ls": (0, (1, 1.6)), "zorder": 0.5}
KNOT_LABEL = "knot: one piece of the motion meets the next"
MARK_EDGE = 1.5  # points: an overlaid task's singular mark edged in the task's colour

NEAR_DELTA = 0.1  # |δ| below this is "near" a Type II singularity (band on δ, cue in the GIF)
WIDTH = 11.0  # sheet width [in] (wider for small multiples)
LABEL_SIZE = 7.5  # points, the text written beside a mark

RC: Any = {  # matplotlib's rcParams for the sheet (Any: its stubs want literal keys)
    "font.size": 9,
    "axes.titlesize": 9.5,
    "axes.labelsize": 9,
    "legend.fontsize": 7.5,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.6,
    "svg.fonttype": "none",  # text stays text: searchable, editable
    "svg.hashsalt": "rprpr",  # reproducible ids
    "pdf.fonttype": 42,  # TrueType, not Type 3: what journals ask for
}


# the scale of every text size while a sheet is drawn (``render``'s ``font_scale``)
FONT_SCALE: ContextVar[float] = ContextVar("rprpr_sheet_font_scale", default=1.0)
_SIZES: tuple[str, ...] = ("font.size", "axes.titlesize", "axes.labelsize", "legend.fontsize")
_SIZES += ("xtick.labelsize", "ytick.labelsize")


def pt(size: float) -> float:
    """A text size [points] as drawn: ``size`` times the sheet's font scale."""
    return size * FONT_SCALE.get()


def rc(scale: float = 1.0) -> Any:
    """``RC`` with every text size times ``scale``."""
    return {**RC, **{k: RC[k] * scale for k in _SIZES}}


def style(i: int) -> Any:
    """The line style of the i-th task's single curves (path, δ) in an overlay."""
    return STYLES[i % len(STYLES)]


def task_colour(i: int) -> str:
    """The colour of the i-th task (distinct for the at most 8 tasks of a sheet)."""
    return TASK_COLOURS[i % len(TASK_COLOURS)]

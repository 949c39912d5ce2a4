"""The sheet's look, stated once: colour is the quantity, line style is the task.

Colours are the same in every panel and in the GIF: leg 1 (A-E; θ1, s1, T1) blue, leg 2
(B-E; θ2, s2, T2) green, the end point E (path, x_E, y_E) black, δ purple, the singular
line y = 0 red. A singular instant's status (the audit's, ``AuditResult.status_of``) is
red when it fails the task, amber when it warns, yellow when it passes.
"""

from __future__ import annotations

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
STYLES: tuple[Any, ...] = (
    "-",
    "--",
    "-.",
    ":",
    (0, (8, 2, 2, 2, 2, 2)),
    (0, (1, 1)),
    (0, (6, 2)),
    (0, (3, 4, 1, 4)),
)

NEAR_DELTA = 0.1  # |δ| below this is "near" a Type II singularity (band on δ, cue in the GIF)
WIDTH = 11.0  # sheet width [in]
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


def style(i: int) -> Any:
    """The line style of the i-th task."""
    return STYLES[i % len(STYLES)]

"""The audit sheet of ``rprpr plot`` (matplotlib: only the plot path imports this package).

``motion`` readies an audited task for drawing (its samples plus every singular instant
at its exact time; no new analysis); ``render`` draws the chosen panels of one motion, or
several overlaid, on a ``matplotlib.figure.Figure`` (headless, no pyplot); ``save``
writes it as PNG, SVG or PDF.

Panels (``PANELS``), each a row of the sheet, in the order asked for, each a module of
``panels``: ``path`` the workspace (the paper's Fig. 3), ``x`` x_E(t) (Fig. 2) and
y_E(t), ``delta`` δ(t) (eq. 29, Fig. 4), ``joints`` θ1, θ2 (Fig. 5) and s1, s2,
``torques`` T1, T2 (eq. 28).

Conventions, stated once:

* colour is the quantity, the same in every panel (``style``); line style is the task,
  in the order given;
* a singular instant is a star when of high order, a diamond when of first order, filled
  with the colour of the audit's status there (``markers``): the same findings as
  ``rprpr check``;
* the robot is drawn by ``robot``, for the sheet and the GIF alike; what differs by
  mechanism (the RPRPR's legs and line AB, a 5R's links and Type II curves: ``five_bar``,
  ``five_bar_robot``) is asked of the motion's ``drawing.Drawing``;
* every number written goes through ``rprpr.model.numbers`` (``words``).

The modules: ``motion`` (what is drawn), ``style``, ``words``, ``markers``, ``labels``
(where text goes), ``axes`` (what panels share), ``robot``, ``panels``, ``layout`` (the
figure and the file).
"""

from __future__ import annotations

from .change import Change
from .labels import MAX_LABELS
from .layout import FORMATS, PANELS, can_show, format_of, metadata, render, save, svg
from .markers import marker_style
from .motion import Motion, finite, motion
from .page import Sheet
from .style import (
    DELTA,
    LEG1,
    LEG2,
    LINE,
    NEAR_DELTA,
    POINT,
    RC,
    STATUS_COLOUR,
    STATUS_WORD,
    TASK_COLOURS,
)
from .words import order_text, short, summary, title

__all__ = [
    "DELTA",
    "FORMATS",
    "LEG1",
    "LEG2",
    "LINE",
    "MAX_LABELS",
    "NEAR_DELTA",
    "PANELS",
    "POINT",
    "RC",
    "STATUS_COLOUR",
    "STATUS_WORD",
    "TASK_COLOURS",
    "Change",
    "Motion",
    "Sheet",
    "can_show",
    "finite",
    "format_of",
    "marker_style",
    "metadata",
    "motion",
    "order_text",
    "render",
    "save",
    "short",
    "summary",
    "svg",
    "title",
]

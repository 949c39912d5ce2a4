"""The sheet as a figure and as a file: the panels drawn in order on a ``page.Sheet``
(laid out in inches), and PNG, SVG or PDF with metadata naming the tasks."""

from __future__ import annotations

import io
import math
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any

import matplotlib
from matplotlib.figure import Figure

from ..._version import __version__
from .change import Change, differences, insets, panel
from .motion import Motion
from .page import DPI, PAPER_MARGIN, Sheet, column_heads
from .panels import BY_NAME
from .style import FONT_SCALE, RC, rc
from .words import description

FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}
PANELS = tuple(BY_NAME)  # the default order


MIN_ROW = 0.6  # in: the least height a row of axes is given to fit a figure's size


def render(
    motions: Sequence[Motion],
    panels: Sequence[str] | str | None = None,
    *,
    figure: Figure | None = None,
    pole_inset: bool = False,
    size: tuple[float, float] | None = None,
    font_scale: float = 1.0,
    change: Change | None = None,
) -> Figure:
    """The audit sheet of ``motions`` with ``panels`` in order (all by default), on a new
    headless ``Figure`` or on ``figure`` (e.g. one of pyplot's, for --show); with
    ``pole_inset``, log|T| against log|t - t_s| beside the torques near an unbounded
    instant. ``panels`` is a list of names or one comma-separated string
    (``"path,delta"``, as ``--panels``).

    For a paper's figure: ``size`` (width, height) [in] makes the figure exactly that
    size, the panels without the sheet's title, their legends and keys under the axes,
    the rows of axes taking the height left (ValueError when it leaves a row less than
    ``MIN_ROW``, or for more than one column of axes); ``font_scale`` multiplies every
    text size (the marks and lines keep theirs).

    For a repair (``rprpr repair --plot``): ``motions`` the old and the new task and
    ``change`` the repair's account (``change.Change``): a last panel of the difference
    new - old [mm] and zoomed insets at the largest change (``change``)."""
    if isinstance(panels, str):  # never its letters, one by one
        panels = [p.strip() for p in panels.split(",") if p.strip()]
    panels = list(BY_NAME) if panels is None else list(panels)
    unknown = [p for p in panels if p not in BY_NAME]
    if unknown or not panels:
        raise ValueError(f"unknown panels {unknown}; choose from {', '.join(BY_NAME)}")
    if not motions:
        raise ValueError("nothing to plot")
    if not 0.25 <= font_scale <= 4:
        raise ValueError(f"font scale {font_scale:g} is outside [0.25, 4]")
    if size is None:
        return _draw(motions, panels, figure, pole_inset, None, font_scale, 1.0, change)[0]
    w, h = size
    if not (0 < w <= 50 and 0 < h <= 50):
        raise ValueError(f"size {w:g} x {h:g} in: each side must be in (0, 50] inches")
    # first on a scratch figure at the default row heights, to learn what the rows can take
    _, first = _draw(motions, panels, Figure(), pole_inset, size, font_scale, 1.0, change)
    fixed = first.y + PAPER_MARGIN - first.rows_total
    scale = (h - fixed) / first.rows_total
    if scale * first.smallest_row < MIN_ROW:
        need = fixed + MIN_ROW / first.smallest_row * first.rows_total
        raise ValueError(
            f"{h:g} in is too short for {', '.join(panels)} at {w:g} in wide:"
            f" at least {math.ceil(need * 10) / 10:g} in"
        )
    return _draw(motions, panels, figure, pole_inset, size, font_scale, scale, change)[0]


def _draw(
    motions: Sequence[Motion],
    panels: Sequence[str],
    figure: Figure | None,
    pole_inset: bool,
    size: tuple[float, float] | None,
    font_scale: float,
    row_scale: float,
    change: Change | None = None,
) -> tuple[Figure, Sheet]:
    token = FONT_SCALE.set(font_scale)
    try:
        with matplotlib.rc_context(rc(font_scale)):
            fig = figure if figure is not None else Figure()
            fig.set_layout_engine("none")
            sheet = Sheet(fig, motions, size=size, row_scale=row_scale)
            sheet.title()
            if len(sheet.columns) > 1:
                column_heads(sheet)
            for n, name in enumerate(panels):
                if n:
                    sheet.gap()
                BY_NAME[name].draw(sheet, pole_inset)
            diff = None
            if change is not None:
                if len(motions) != 2:
                    raise ValueError("a repair's change is drawn for two motions: old, new")
                diff = differences(motions[0].task, motions[1].task, change)
                sheet.gap()
                panel(sheet, diff, change)
            sheet.finish()
            if change is not None and diff is not None:
                insets(fig, motions[0], motions[1], diff, change)
    finally:
        FONT_SCALE.reset(token)
    return fig, sheet


def format_of(path: str) -> str:
    """The sheet format from a file name's extension (raises ValueError if unsupported)."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(f"unsupported sheet format {suffix!r}; use {', '.join(FORMATS)}")
    return FORMATS[suffix]


def metadata(motions: Sequence[Motion], fmt: str) -> dict[str, Any]:
    """File metadata naming the tasks: PNG tEXt chunks, SVG Dublin Core, PDF Info."""
    name = "rprpr audit sheet: " + "; ".join(m.name for m in motions)
    creator = f"rprpr {__version__} (matplotlib {matplotlib.__version__})"
    desc = description(motions)
    if fmt == "png":
        return {"Title": name, "Software": creator, "Description": desc}
    if fmt == "svg":
        return {"Title": name, "Creator": creator, "Description": desc, "Date": None}
    return {"Title": name, "Creator": creator, "Subject": desc, "CreationDate": None}


def save(
    fig: Figure,
    target: str | IO[bytes],
    fmt: str,
    *,
    dpi: int = DPI,
    motions: Sequence[Motion] = (),
) -> None:
    """Write the sheet as ``fmt`` ("png", "svg", "pdf") to a path or binary stream, with
    ``metadata(motions)`` when the motions are given."""
    meta = metadata(motions, fmt) if motions else None
    with matplotlib.rc_context(RC), warnings.catch_warnings():
        fig.savefig(target, format=fmt, dpi=dpi, metadata=meta)


def svg(motions: Sequence[Motion], panels: Sequence[str] | str | None = None) -> str:
    """The sheet of ``motions`` as SVG text, for the HTML report: the same text for the
    same audit (no date; ids from ``RC``'s fixed salt), its words as text (searchable)."""
    fig = render(motions, panels)
    out = io.BytesIO()
    save(fig, out, "svg", motions=motions)
    return out.getvalue().decode("utf-8")


def can_show() -> bool:
    """Whether pyplot has an interactive backend (a window can open)."""
    import matplotlib.pyplot as plt
    from matplotlib.backends.registry import BackendFilter, backend_registry

    interactive = backend_registry.list_builtin(BackendFilter.INTERACTIVE)  # type: ignore[no-untyped-call]
    return plt.get_backend().lower() in interactive

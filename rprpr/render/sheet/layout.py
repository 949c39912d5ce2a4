"""The sheet as a figure and as a file: the panels drawn in order on a ``page.Sheet``
(laid out in inches), and PNG, SVG or PDF with metadata naming the tasks."""

from __future__ import annotations

import io
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any

import matplotlib
from matplotlib.figure import Figure

from ..._version import __version__
from .motion import Motion
from .page import DPI, Sheet, column_heads
from .panels import BY_NAME
from .style import RC
from .words import description

FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}
PANELS = tuple(BY_NAME)  # the default order


def render(
    motions: Sequence[Motion],
    panels: Sequence[str] | str | None = None,
    *,
    figure: Figure | None = None,
    pole_inset: bool = False,
) -> Figure:
    """The audit sheet of ``motions`` with ``panels`` in order (all by default), on a new
    headless ``Figure`` or on ``figure`` (e.g. one of pyplot's, for --show); with
    ``pole_inset``, log|T| against log|t - t_s| beside the torques near an unbounded
    instant. ``panels`` is a list of names or one comma-separated string
    (``"path,delta"``, as ``--panels``)."""
    if isinstance(panels, str):  # never its letters, one by one
        panels = [p.strip() for p in panels.split(",") if p.strip()]
    panels = list(BY_NAME) if panels is None else list(panels)
    unknown = [p for p in panels if p not in BY_NAME]
    if unknown or not panels:
        raise ValueError(f"unknown panels {unknown}; choose from {', '.join(BY_NAME)}")
    if not motions:
        raise ValueError("nothing to plot")
    with matplotlib.rc_context(RC):
        fig = figure if figure is not None else Figure()
        fig.set_layout_engine("none")
        sheet = Sheet(fig, motions)
        sheet.title()
        if len(sheet.columns) > 1:
            column_heads(sheet)
        for n, name in enumerate(panels):
            if n:
                sheet.gap()
            BY_NAME[name].draw(sheet, pole_inset)
        sheet.finish()
    return fig


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

"""The sheet as a figure and as a file: its panels stacked as subfigures, its title, and
PNG, SVG or PDF with metadata naming the tasks."""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any

import matplotlib
from matplotlib.figure import Figure

from ..._version import __version__
from .motion import Motion
from .panels import BY_NAME
from .style import RC, WIDTH
from .words import description, title

PANELS = tuple(BY_NAME)
FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}


def render(
    motions: Sequence[Motion], panels: Sequence[str] = PANELS, *, figure: Figure | None = None
) -> Figure:
    """The audit sheet of ``motions`` (overlaid) with ``panels`` in order, on a new headless
    ``Figure`` or on ``figure`` (e.g. one of pyplot's, for --show). The layout is
    constrained and done when the sheet is saved or drawn (text extents depend on the
    resolution, so it is not fixed in advance)."""
    unknown = [p for p in panels if p not in BY_NAME]
    if unknown or not panels:
        raise ValueError(f"unknown panels {unknown}; choose from {', '.join(PANELS)}")
    if not motions:
        raise ValueError("nothing to plot")
    with matplotlib.rc_context(RC):
        heights = [BY_NAME[p].height(motions) for p in panels]
        fig = _figure(figure, (WIDTH, sum(heights) + 0.5 + 0.2 * len(motions)))
        fig.suptitle(title(motions), fontsize=10, linespacing=1.5)
        subs = fig.subfigures(len(panels), 1, height_ratios=heights, squeeze=False)[:, 0]
        for name, sf in zip(panels, subs, strict=True):
            sf.set_gid(f"panel-{name}")
            BY_NAME[name].draw(sf, motions)
    return fig


def _figure(figure: Figure | None, size: tuple[float, float]) -> Figure:
    """A new headless figure of ``size`` [in], or ``figure`` resized, laid out constrained."""
    if figure is None:
        return Figure(figsize=size, layout="constrained")
    figure.set_size_inches(*size)
    figure.set_layout_engine("constrained")
    return figure


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
    dpi: int = 150,
    motions: Sequence[Motion] = (),
) -> None:
    """Write the sheet as ``fmt`` ("png", "svg", "pdf") to a path or binary stream, with
    ``metadata(motions)`` when the motions are given."""
    meta = metadata(motions, fmt) if motions else None
    with matplotlib.rc_context(RC), warnings.catch_warnings():
        # a crowded sheet (dozens of instants) still draws; matplotlib's layout note
        # about it is no news to the user
        warnings.filterwarnings("ignore", message="constrained_layout not applied")
        fig.savefig(target, format=fmt, dpi=dpi, metadata=meta)


def can_show() -> bool:
    """Whether pyplot has an interactive backend (a window can open)."""
    import matplotlib.pyplot as plt
    from matplotlib.backends.registry import BackendFilter, backend_registry

    interactive = backend_registry.list_builtin(BackendFilter.INTERACTIVE)  # type: ignore[no-untyped-call]
    return plt.get_backend().lower() in interactive

"""The mark of a singular instant, the same in every panel and in the GIF: a star when of
high order, a diamond when of first order, filled with the colour of its status."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from matplotlib.axes import Axes
from matplotlib.lines import Line2D

from ...engine.singular import SingularInstant
from .motion import Motion
from .style import STATUS_COLOUR, STATUS_WORD


def marker_style(s: SingularInstant, status: str) -> dict[str, Any]:
    """Keyword arguments of ``Axes.plot`` for the mark of ``s`` with the audit's
    ``status`` ("fail", "warn" or "ok")."""
    high = s.high_order
    return {
        "marker": "*" if high else "D",
        "markersize": 17 if high else 7.5,
        "markerfacecolor": STATUS_COLOUR[status],
        "markeredgecolor": "black",
        "markeredgewidth": 0.9,
        "linestyle": "none",
        "zorder": 6.5 if high else 6,  # a high-order mark stays on top of a coinciding one
    }


def marker_handles(motions: Sequence[Motion]) -> list[Line2D]:
    """One legend entry per kind of mark on the sheet (high-order first, then by status)."""
    seen: dict[tuple[bool, str], Line2D] = {}
    for m in motions:
        for s in m.result.singularities:
            st = m.result.status_of(s)
            key = (s.high_order, st)
            if key not in seen:
                kind = "high-order" if key[0] else "first-order"
                seen[key] = Line2D(
                    [],
                    [],
                    label=f"{kind} singular instant ({STATUS_WORD[st]})",
                    **marker_style(s, st),
                )
    return [seen[k] for k in sorted(seen, key=lambda k: (not k[0], k[1]))]


def mark(
    ax: Axes,
    panel: str,
    motions: Sequence[Motion],
    value: Callable[[Motion, SingularInstant], float],
) -> None:
    """A mark at each singular instant at (t_s, value); gid panel-singular-task-k."""
    for i, m in enumerate(motions):
        for k, s in enumerate(m.result.singularities):
            ax.plot(
                [s.t],
                [value(m, s)],
                gid=f"{panel}-singular-{i}-{k}",
                **marker_style(s, m.result.status_of(s)),
            )

"""The mark of a singular instant, the same in every panel and in the GIF: a star when of
high order, a diamond when of first order, filled with the colour of its status."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

from matplotlib.axes import Axes
from matplotlib.lines import Line2D

from ...engine.exact.singular import SingularInstant
from ...model.dataclass import dataclass
from .motion import Motion
from .page import Sheet
from .style import MARK_EDGE, STATUS_COLOUR, STATUS_WORD, pt, task_colour


def marker_style(s: SingularInstant, status: str, edge: str | None = None) -> dict[str, Any]:
    """Keyword arguments of ``Axes.plot`` for the mark of ``s`` with the audit's
    ``status`` ("fail", "warn" or "ok"): edged black, or in ``edge`` (an overlaid task's
    colour), thicker."""
    high = s.high_order
    return {
        "marker": "*" if high else "D",
        "markersize": 17 if high else 7.5,
        "markerfacecolor": STATUS_COLOUR[status],
        "markeredgecolor": edge or "black",
        "markeredgewidth": 0.9 if edge is None else MARK_EDGE,
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


def mark_handle(label: str, marker: str, face: str, edge: str, ms: float = 6, **kw: Any) -> Line2D:
    """A legend entry for a mark alone (no line): ``marker`` filled ``face``, edged
    ``edge``."""
    return Line2D([], [], marker=marker, ms=ms, mfc=face, mec=edge, ls="none", label=label, **kw)


SPREAD = 15.0  # points between the key numbers of marks that sit at one point
RING = 3.5  # points of an outer coinciding mark seen around the next one inside it


@dataclass(frozen=True)
class Placed:
    """How one mark of a group of coinciding marks is drawn: at its own data coordinates
    always, nested with the others (concentric): its ``size`` [points], its ``zorder``
    (the inner above the outer), its key number ``dx`` points aside, and ``reach``, half
    the outermost mark's size [points]: the key numbers stand beyond it."""

    size: float
    zorder: float
    dx: float
    reach: float


def nest(
    points: Sequence[tuple[Any, float, float, float]], tol: tuple[float, float]
) -> dict[Any, Placed]:
    """Marks at (x, y) (each with a key and its own size [points]) closer than ``tol`` in
    x and y to the first of a group are one group: never moved, they nest, the largest
    outermost and each next one inside it, at least ``RING`` points smaller all round,
    so that every mark's outline shows; their key numbers stand side by side."""
    groups: list[list[tuple[Any, float, float, float]]] = []
    for p in points:
        g = next(
            (g for g in groups if abs(g[0][1] - p[1]) <= tol[0] and abs(g[0][2] - p[2]) <= tol[1]),
            None,
        )
        if g is None:
            groups.append([p])
        else:
            g.append(p)
    out: dict[Any, Placed] = {}
    for g in groups:
        order = sorted(range(len(g)), key=lambda j: -g[j][3])  # stable: task order on ties
        sizes = [g[j][3] for j in order]
        for j in range(len(sizes) - 2, -1, -1):  # from the innermost outwards
            sizes[j] = max(sizes[j], sizes[j + 1] + 2 * RING)
        for depth, j in enumerate(order):
            out[g[j][0]] = Placed(
                size=sizes[depth],
                zorder=6 + 0.05 * depth,
                dx=(j - (len(g) - 1) / 2) * SPREAD,
                reach=sizes[0] / 2,
            )
    return out


def edge(sheet: Sheet, i: int) -> str | None:
    """The edge of task i's singular marks: its colour in an overlay, else black (None)."""
    return task_colour(i) if sheet.overlay else None


def arrow_mark(
    ax: Axes, x: float, y: float, up: bool, colour: str, gid: str, size: float, **kw: Any
) -> None:
    """▲ (``up``) or ▼ at (x, y) in ``colour``, edged black, over the axis's edge (not
    clipped): where a curve leaves the axis, or a limit lies beyond it."""
    ax.plot(
        [x],
        [y],
        marker="^" if up else "v",
        ms=size,
        color=colour,
        mec="black",
        mew=0.6,
        ls="none",
        clip_on=False,
        zorder=9,
        gid=gid,
        **kw,
    )


def badge(ax: Axes, n: int, xy: tuple[float, float], dx: float, dy: float, gid: str) -> None:
    """The key number ``n`` in a small circle, ``dx``, ``dy`` points from ``xy``: what it
    marks is said in the lane under the legend."""
    ax.annotate(
        str(n),
        xy,
        xytext=(dx, dy),
        textcoords="offset points",
        ha="center",
        va="center",
        fontsize=pt(6.5),
        fontweight="bold",
        bbox={"boxstyle": "circle,pad=0.18", "fc": "white", "ec": "#333333", "lw": 0.6},
        zorder=9,
        annotation_clip=False,
        gid=gid,
    )


def mark(
    ax: Axes,
    panel: str,
    sheet: Sheet,
    column: Sequence[tuple[int, Motion]],
    value: Callable[[Motion, SingularInstant], float],
) -> None:
    """A mark at each singular instant at exactly (t_s, value), nested where several
    coincide (``nest``), with its key number above; gid panel-singular-task-k."""
    keys = sheet.keys
    tf = max(m.duration for _, m in column)
    ax.autoscale_view()
    y0, y1 = ax.get_ylim()
    pts = [
        ((i, k), s.t, value(m, s), marker_style(s, "ok")["markersize"])
        for i, m in column
        for k, s in enumerate(m.result.singularities)
    ]
    ys = [abs(p[2]) for p in pts]
    placed = nest(pts, (0.01 * tf, 0.02 * max(ys, default=1.0) + 1e-9))
    for i, m in column:
        for k, s in enumerate(m.result.singularities):
            p = placed[i, k]
            y = value(m, s)
            style = marker_style(s, m.result.status_of(s), edge(sheet, i))
            style.update(markersize=p.size, zorder=p.zorder)
            ax.plot([s.t], [y], gid=f"{panel}-singular-{i}-{k}", **style)
            if (i, k) in keys:  # above the mark, below it in the axes' upper half
                dy = (p.reach + 6) * (1 if y < (y0 + y1) / 2 else -1)
                badge(ax, keys[i, k], (s.t, y), p.dx, dy, f"{panel}-key-{i}-{k}")

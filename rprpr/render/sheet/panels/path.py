"""The ``path`` panel: the workspace (the paper's Fig. 3).

Base joints A and B, the singular line y = 0 with its three cases' stretches (Table 1),
the end-point paths with their direction, the robot at the start, the end and each
singular instant, and each singular point with its order and verdict."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import SubFigure
from matplotlib.lines import Line2D

from ....engine.singular import SingularInstant
from ....model.numbers import number
from ..axes import OUTSIDE, legend, panel_title
from ..labels import Box, case_label_x, labelled, place
from ..markers import marker_handles, marker_style
from ..motion import Motion, at
from ..robot import (
    View,
    base_joints,
    draw_robot,
    singular_line,
    singular_line_handle,
    view,
    workspace,
)
from ..style import LABEL_SIZE, LEG1, LEG2, LINE, POINT, STATUS_COLOUR, STATUS_WORD, WIDTH, style
from ..words import instant_times, order_text, short, verdict_text

CASES = (  # the singular line's stretches (Table 1): left of A, between A and B, right of B
    "case 2\nθ1 = θ2 = π",
    "case 3\nθ1 = 0, θ2 = π",
    "case 1\nθ1 = θ2 = 0",
)


def height(motions: Sequence[Motion]) -> float:
    """The panel's height [in]: the workspace at equal scales, within 3.2 to 7.5 in."""
    x0, x1, y0, y1 = view(motions)
    axes_width = WIDTH - 3.6  # the legend sits to the right
    return float(np.clip((y1 - y0) / (x1 - x0) * axes_width + 1.2, 3.2, 7.5))


def draw(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    panel_title(sf, "Workspace (paper Fig. 3)", motions)
    ax = sf.subplots()
    ax.set_title("end-point path, robot at start, end and singular instants")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    v, size = workspace(ax, motions)
    singular_line(ax)
    _case_labels(ax, motions, v)
    a1s = base_joints(ax, motions, size)
    # what a singular point's label should not hide: the bases, robots, paths, end labels
    obstacles = [np.array([(a, -size * k) for k in (0, 1, 2, 3)]) for a in (0.0, *a1s)]
    obstacles += _robots(ax, motions, size)
    _paths(ax, motions)
    _singular_points(ax, motions, obstacles, v)
    legend(ax, [("end-point path", POINT)], motions, _legend_extra(motions), **OUTSIDE)
    return [ax]


def _case_labels(ax: Axes, motions: Sequence[Motion], v: View) -> None:
    """Each case's name on its stretch of the singular line, where it hides least."""
    x0, x1, _, _ = v
    a1 = float(motions[0].task.robot.a1)
    span = x1 - x0
    avoid = _near_the_line(motions, v)
    edge = 0.07 * span  # half a label's width, about
    stretches = ((x0 + edge, -0.02 * span), (0.2 * a1, 0.8 * a1), (a1 + 0.02 * span, x1 - edge))
    for (lo, hi), text in zip(stretches, CASES, strict=True):
        if hi <= lo:
            continue
        ax.annotate(
            text,
            (case_label_x(lo, hi, avoid), 0),
            xytext=(0, 3),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=LABEL_SIZE,
            color=LINE,
            gid=f"case-label-{text[5]}",
        )


def _near_the_line(motions: Sequence[Motion], v: View) -> np.ndarray:
    """The points a case label avoids: the paths near y = 0, and the singular points."""
    _, _, y0, y1 = v
    pts = np.concatenate(
        [np.column_stack([m.s.x, m.s.y])[:: max(1, len(m.s.t) // 200)] for m in motions]
    )
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    pts = pts[np.abs(pts[:, 1]) < 0.25 * (y1 - y0)]
    sing = np.array([(s.x, 0.0) for m in motions for s in m.result.singularities]).reshape(-1, 2)
    return np.concatenate([pts, sing])


def _robots(ax: Axes, motions: Sequence[Motion], size: float) -> list[np.ndarray]:
    """The robots (faint at the start and end, solid at the singular instants) and the
    start and end labels; returns the points they cover."""
    covered = []
    written: set[tuple[float, float, str]] = set()  # one label where tasks start alike
    for i, m in enumerate(motions):
        n = len(m.s.t)
        covered.append(draw_robot(ax, m, 0, 0.45, f"robot-{i}-start"))
        covered.append(draw_robot(ax, m, n - 1, 0.45, f"robot-{i}-end"))
        for k, s in enumerate(m.result.singularities):
            covered.append(draw_robot(ax, m, at(m, s.t), 0.9, f"robot-{i}-singular-{k}"))
        covered.append(np.column_stack([m.s.x, m.s.y])[:: max(1, n // 300)])
        covered += _end_labels(ax, m, size, written)
    return covered


def _end_labels(
    ax: Axes, m: Motion, size: float, written: set[tuple[float, float, str]]
) -> list[np.ndarray]:
    """``start, t = …`` and ``end, t = …`` beside the path's ends (not where one is
    ``written`` already); returns the points they cover."""
    covered = []
    for j, word in ((0, "start"), (len(m.s.t) - 1, "end")):
        x, y = m.s.x[j], m.s.y[j]
        key = (round(float(x), 6), round(float(y), 6), word)
        if key in written or not np.isfinite(x):
            continue
        written.add(key)
        down = word == "start"
        covered.append(np.array([(x + size * k, y + (-size if down else size)) for k in (1, 3, 5)]))
        ax.annotate(
            f"{word}, t = {number(m.s.t[j], 3)} s",
            (x, y),
            xytext=(7, -7 if down else 5),
            textcoords="offset points",
            fontsize=LABEL_SIZE,
            color="#444444",
            va="top" if down else "bottom",
        )
    return covered


def _paths(ax: Axes, motions: Sequence[Motion]) -> None:
    """Each end-point path in its task's line style, an arrow giving the direction."""
    for i, m in enumerate(motions):
        ax.plot(m.s.x, m.s.y, color=POINT, ls=style(i), lw=1.8, zorder=4, gid=f"path-{i}")
        x, y = m.s.x, m.s.y
        j = int(0.3 * (len(x) - 1))
        if np.all(np.isfinite([x[j], y[j], x[j + 1], y[j + 1]])):
            ax.annotate(
                "",
                xy=(x[j + 1], y[j + 1]),
                xytext=(x[j], y[j]),
                zorder=4,
                arrowprops={"arrowstyle": "-|>", "color": POINT, "lw": 1.2, "mutation_scale": 14},
            )


def _singular_points(
    ax: Axes, motions: Sequence[Motion], obstacles: list[np.ndarray], v: View
) -> None:
    """Each singular point's mark (ringed when of high order) and its label, placed where
    it hides least; each inverse-kinematic singular point's cross."""
    obs = np.concatenate([o for o in obstacles if o.size])
    obs = obs[np.all(np.isfinite(obs), axis=1)]
    x0, x1, y0, y1 = v
    ppu = 72 * min((WIDTH - 3.9) / (x1 - x0), (height(motions) - 1.3) / (y1 - y0))
    boxes: list[Box] = []
    for i, m in enumerate(motions):
        times = instant_times(m.result)
        for k, s in enumerate(m.result.singularities):
            st = m.result.status_of(s)
            if s.high_order:
                _ring(ax, s, f"path-ring-{i}-{k}")
            ax.plot([s.x], [0], gid=f"path-singular-{i}-{k}", **marker_style(s, st))
            if not labelled(motions):
                continue
            who = f"{short(m.name)}\n" if len(motions) > 1 else ""
            text = (
                f"{who}t = {times[k]} s: {order_text(s)} — {STATUS_WORD[st].upper()}\n"
                f"{verdict_text(s)}"
            )
            offset, box = place(text, (s.x, 0.0), obs, boxes, ppu, v)
            boxes.append(box)
            _point_label(ax, text, s.x, offset, st, f"path-label-{i}-{k}")
        for k, ks in enumerate(m.result.kinematic_singularities):
            ax.plot([ks.x], [ks.y], "X", ms=11, zorder=6, gid=f"path-kinematic-{i}-{k}", **_CROSS)


_CROSS: dict[str, Any] = {"mfc": STATUS_COLOUR["fail"], "mec": "black"}  # E at A or B


def _ring(ax: Axes, s: SingularInstant, gid: str) -> None:
    """A red ring around a high-order singular point: it must stand out."""
    ax.plot(
        [s.x],
        [0],
        "o",
        ms=30,
        mfc="none",
        mec=STATUS_COLOUR["fail"],
        mew=2,
        alpha=0.8,
        zorder=5.5,
        gid=gid,
    )


def _point_label(
    ax: Axes, text: str, x: float, offset: tuple[float, float], status: str, gid: str
) -> None:
    """A singular point's label at ``offset`` (points) from (x, 0), framed in the colour
    of its status, with a leader line to the point."""
    dx, dy = offset
    ax.annotate(
        text,
        (x, 0),
        xytext=(dx, dy),
        textcoords="offset points",
        fontsize=LABEL_SIZE,
        va="top" if dy < 0 else "bottom",
        ha="left" if dx > 0 else "right",
        multialignment="left",
        color="black",
        fontweight="bold" if status != "ok" else "normal",
        bbox={
            "boxstyle": "round,pad=0.25",
            "fc": "white",
            "ec": STATUS_COLOUR[status] if status != "ok" else "#999999",
            "alpha": 0.9,
        },
        arrowprops={"arrowstyle": "-", "color": "#666666", "lw": 0.7, "shrinkA": 0, "shrinkB": 6},
        zorder=8,
        gid=gid,
    )


def _legend_extra(motions: Sequence[Motion]) -> list[Any]:
    """The workspace's legend beyond the paths: the singular line, the legs, the marks."""
    extra: list[Any] = [
        singular_line_handle(),
        Line2D([], [], color=LEG1, lw=2.2, label="leg 1 (A–E): θ1, s1"),
        Line2D([], [], color=LEG2, lw=2.2, label="leg 2 (B–E): θ2, s2"),
        *marker_handles(motions),
    ]
    if any(m.result.kinematic_singularities for m in motions):
        extra.append(
            Line2D([], [], marker="X", ms=9, ls="none", label="E at A or B (s = 0)", **_CROSS)
        )
    return extra

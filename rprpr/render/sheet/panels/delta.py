"""The ``delta`` panel: the Type II determinant δ(t) = sin(θ1 - θ2) (eq. 29, the paper's
Fig. 4), each singular instant marked and labelled with its order and what vanishes."""

from __future__ import annotations

from collections.abc import Sequence

from matplotlib.axes import Axes
from matplotlib.figure import SubFigure
from matplotlib.lines import Line2D

from ....engine.singular import SingularInstant
from ....model.numbers import number
from ..axes import OUTSIDE, legend, panel_title, time_axes
from ..labels import Rows, labelled
from ..markers import mark, marker_handles
from ..motion import Motion, finite
from ..style import DELTA, LABEL_SIZE, NEAR_DELTA, STATUS_COLOUR, style
from ..words import instant_times, order_text, short, vanishing


def height(motions: Sequence[Motion]) -> float:
    return 3.2


def draw(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    panel_title(sf, "Type II determinant (paper Fig. 4)", motions)
    ax = sf.subplots()
    title = r"$\delta(t) = \sin(\theta_1 - \theta_2)$, eq. (29)"
    time_axes(ax, motions, title, r"$\delta$ [–]", "delta")
    ax.axhspan(-NEAR_DELTA, NEAR_DELTA, color="#999999", alpha=0.12, lw=0, zorder=0.2)
    ax.axhline(0, color="#444444", lw=0.8, zorder=0.7)
    for i, m in enumerate(motions):
        ax.plot(m.s.t, finite(m.s.delta), color=DELTA, ls=style(i), lw=1.8, gid=f"delta-{i}")
    mark(ax, "delta", motions, lambda m, s: 0.0)
    if labelled(motions):
        _labels(ax, motions)
    near = f"near singular: |δ| < {number(NEAR_DELTA)}"
    band = Line2D([], [], color="#999999", alpha=0.35, lw=6, label=near)
    legend(ax, [("δ", DELTA)], motions, [*marker_handles(motions), band], **OUTSIDE)
    return [ax]


def _labels(ax: Axes, motions: Sequence[Motion]) -> None:
    """Each singular instant's order beside its mark, stacked clear of one another."""
    rows = Rows(max(m.duration for m in motions), below=True)
    for i, m in enumerate(motions):
        times = instant_times(m.result)
        for k, s in enumerate(m.result.singularities):
            text = _label_text(m, s, times[k], len(motions))
            side, level, right = rows.place(s.t, text)
            ax.annotate(
                text,
                (s.t, 0),
                ha="right" if right else "left",
                va="bottom" if side > 0 else "top",
                xytext=(-10 if right else 10, side * (8 + level)),
                textcoords="offset points",
                fontsize=LABEL_SIZE,
                color=STATUS_COLOUR["fail"] if m.result.status_of(s) == "fail" else "black",
                fontweight="bold" if s.high_order else "normal",
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.6},
                zorder=8,
                gid=f"delta-label-{i}-{k}",
            )


def _label_text(m: Motion, s: SingularInstant, t: str, tasks: int) -> str:
    """The label of ``s`` at time text ``t``: with the task's name when several overlay,
    on one line when more than two do (or the labels outgrow the axes)."""
    said = f"t = {t} s: {order_text(s)} ({vanishing(s.order)})"
    if tasks == 1:
        return said
    if tasks == 2:
        return f"{short(m.name)}\n{said}"
    return f"{short(m.name, 28)}: {order_text(s)}"

"""The sheet's remaining defects (issue 26, item 7), each read back from the drawn figure.

Prismatic words (the actuated joints s1, s2; a force limit in N), the legs' sleeves in
the legend, the case labels clear of the legs, the small multiples' own y-axes per unit
and own time axes for very different durations, the torque jumps of RPR204 at the knots,
the single-panel size and font scale for papers."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from matplotlib.colors import same_color
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from rprpr.render import sheet as P
from rprpr.render.sheet.robot import CYLINDER, CYLINDER_ALPHA
from tests.conftest import CONFIGS
from tests.sheets import PATH1, PATH2, drawn, motions, sheet

PRISMATIC = str(CONFIGS / "prismatic_crossing.rprpr.yaml")


def legend_texts(fig: Figure) -> list[str]:
    return [t.get_text() for leg in fig.legends for t in leg.get_texts()]


def headings(fig: Figure) -> list[str]:
    return [t.get_text() for t in fig.texts]


def gids(fig: Figure, prefix: str) -> list[Any]:
    return [
        a
        for ax in fig.get_axes()
        for a in ax.get_children()
        if (a.get_gid() or "").startswith(prefix)
    ]


def test_a_prismatic_sheet_names_its_actuated_joints_and_a_force_limit() -> None:
    """robot.actuation: prismatic: s1, s2 are actuated (not θ1, θ2), the limit is a
    force limit in N; the paper's revolute sheet keeps its words."""
    (m,) = motions([PRISMATIC])
    assert m.task.robot.actuation == "prismatic" and m.task.checks.torque_limit is not None
    fig = sheet([PRISMATIC])
    heads = headings(fig)
    assert any("actuated joints s1, s2" in h for h in heads), heads
    assert not any("Actuated joints θ1, θ2" in h for h in heads)
    legend = legend_texts(fig)
    assert "force limit ±L [N]" in legend and not any("torque limit" in t for t in legend)
    revolute = sheet([str(CONFIGS / "case1_crossing.rprpr.yaml")])
    assert any("Actuated joints θ1, θ2" in h for h in headings(revolute))
    mixed = P.render(motions([PATH2, PRISMATIC]), ["torques"])
    assert "limit ±L: torque [N m] (revolute), force [N] (prismatic)" in legend_texts(mixed)


@pytest.mark.parametrize("paths", [[PATH1], [PATH1, PATH2]], ids=["single", "overlay"])
def test_the_legs_sleeves_are_in_the_legend_as_drawn(paths: list[str]) -> None:
    """Each leg's sleeve (the cylinder its rod slides in, thick and translucent along AB
    at a singular instant) has a legend entry drawn as the sleeve is."""
    fig = sheet(paths)
    legend = next(leg for leg in fig.legends if "end of the path (t = t_f)" in texts(leg))
    entries = [t for t in texts(legend) if "sleeve" in t]
    assert len(entries) == (2 if len(paths) == 1 else 1), texts(legend)
    drawn_sleeves = [
        a for a in gids(fig, "robot-") if a.get_gid().endswith(("cylinder1", "cylinder2"))
    ]
    assert drawn_sleeves
    handles = [h for h in legend.legend_handles if isinstance(h, Line2D)]
    sleeves = [
        h
        for h in handles
        if h.get_linewidth() == CYLINDER["lw"] and h.get_alpha() == CYLINDER_ALPHA
    ]
    assert sleeves, [(h.get_label(), h.get_linewidth(), h.get_alpha()) for h in handles]
    for a in drawn_sleeves:
        assert a.get_linewidth() == CYLINDER["lw"]
        if len(paths) == 1:  # coloured as its leg, as the legend's sleeve of that leg
            assert any(same_color(a.get_color(), h.get_color()) for h in sleeves)


def texts(legend: Any) -> list[str]:
    return [t.get_text() for t in legend.get_texts()]


def _clear_of_lines(fig: Figure, label_prefix: str, line_prefix: str) -> None:
    """No point of a line whose gid starts ``line_prefix`` lies in a case label's box
    (grown by half the line's width)."""
    renderer = drawn(fig)
    labels = [
        t for ax in fig.get_axes() for t in ax.texts if (t.get_gid() or "").startswith(label_prefix)
    ]
    assert labels
    lines = gids(fig, line_prefix)
    assert lines
    for t in labels:
        box = t.get_window_extent(renderer)
        for line in lines:
            xy = line.get_xydata()
            dense = np.concatenate(
                [xy[0] + f * (xy[-1] - xy[0])[None, :] for f in np.linspace(0, 1, 200)[:, None]]
            )
            px = line.get_transform().transform(dense)
            half = line.get_linewidth() / 2 * fig.dpi / 72
            inside = (
                (px[:, 0] > box.x0 - half)
                & (px[:, 0] < box.x1 + half)
                & (px[:, 1] > box.y0 - half)
                & (px[:, 1] < box.y1 + half)
            )
            assert not np.any(inside), (t.get_text(), line.get_gid())


@pytest.mark.parametrize("path", [PRISMATIC, PATH1, str(CONFIGS / "case2_crossing.rprpr.yaml")])
def test_no_leg_runs_through_a_case_label(path: str) -> None:
    """The case labels on the singular line sit clear of every leg drawn (at the start,
    the end and each singular instant), sleeves included."""
    fig = P.render(motions([path]), ["path"])
    _clear_of_lines(fig, "case-label", "robot-")

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
    assert "limit ±L (T in N m, F in N)" in legend_texts(mixed)


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


@pytest.mark.parametrize(
    "path", [PRISMATIC, PATH1, *(str(CONFIGS / f"case{n}_crossing.rprpr.yaml") for n in (1, 2))]
)
def test_no_leg_runs_through_a_case_label(path: str) -> None:
    """The case labels on the singular line sit clear of every leg drawn (at the start,
    the end and each singular instant), sleeves included."""
    fig = P.render(motions([path]), ["path"])
    _clear_of_lines(fig, "case-label", "robot-")


def test_small_multiples_never_share_a_y_axis_across_units() -> None:
    """Torques [N m] and forces [N] in one row of small multiples: the prismatic
    column's y-limits are its own (its 8 N trace fills its axis, not a sliver of
    ±1,500 N m) and labelled in N; the revolute columns share theirs, in N m."""
    from tests.sheets import CONFIG_FILES

    ms = motions(CONFIG_FILES)
    fig = sheet(CONFIG_FILES)
    drawn(fig)
    row = [ax for ax in fig.get_axes() if ax.get_gid() == "panel-torques"]
    kinds = [m.task.robot.actuation for m in ms]
    assert "prismatic" in kinds and "revolute" in kinds
    (p,) = [c for c, k in enumerate(kinds) if k == "prismatic"]
    revolute = [c for c, k in enumerate(kinds) if k == "revolute"]
    assert len({row[c].get_ylim() for c in revolute}) == 1
    lo, hi = row[p].get_ylim()
    assert row[p].get_ylim() != row[revolute[0]].get_ylim()
    forces = np.concatenate([ms[p].s.T1, ms[p].s.T2])
    forces = forces[np.isfinite(forces)]
    # the forces span at least a third of their own axis
    assert (forces.max() - forces.min()) > (hi - lo) / 3
    assert row[p].get_ylabel() == "$F$ [N]" and row[0].get_ylabel() == "$T$ [N m]"
    # the column after the prismatic one writes its unit again
    if p + 1 < len(row):
        assert row[p + 1].get_ylabel() == "$T$ [N m]"
        assert any(t.get_visible() and t.get_text() for t in row[p + 1].get_yticklabels())


def test_small_multiples_of_very_different_durations_keep_their_own_time_axes() -> None:
    """A 0.5 s task beside 5 s ones: each column's time axes span its own [0, t_f]
    (rows of one column still share it); tasks of like durations share one."""
    from tests.sheets import CONFIG_FILES

    ms = motions(CONFIG_FILES)
    durations = [m.duration for m in ms]
    assert min(durations) < 0.5 * max(durations)
    fig = sheet(CONFIG_FILES)
    for gid in ("panel-delta", "panel-torques", "panel-x", "panel-joints"):
        axes = [ax for ax in fig.get_axes() if ax.get_gid() == gid]
        rows = len(axes) // len(ms)
        for c, m in enumerate(ms):  # rows are added row by row, a column each
            for r in range(rows):
                assert axes[r * len(ms) + c].get_xlim() == (0.0, m.duration), (gid, c)
    alike = [m for m in ms if m.duration >= 0.5 * max(durations)]  # 4 s and 5 s
    assert len(alike) >= 4 and len({m.duration for m in alike}) > 1
    shared = P.render(alike, ["delta"])
    assert {ax.get_xlim() for ax in shared.get_axes() if ax.get_gid() == "panel-delta"} == {
        (0.0, max(durations))
    }


@pytest.mark.parametrize("name", ["trapezoidal", "piecewise_timing"])
def test_torque_jumps_at_knots_are_marked_at_the_knot_times(name: str) -> None:
    """RPR204 (the acceleration jumps at a knot): at each such knot time a bar per
    torque from its value just before the knot to just after, the audit's certified
    values; the lane says by how much."""
    (m,) = motions([str(CONFIGS / f"{name}.rprpr.yaml")])
    rpr204 = [f.t for f in m.result.findings if f.rule == "RPR204"]
    assert len(rpr204) == 2
    fig = P.render([m], ["torques"])
    drawn(fig)
    for n, t in enumerate(rpr204):
        (k,) = [k for k in m.result.knot_jumps if k.t == t]
        before, after = k.torques
        assert before is not None and after is not None
        for j, q in enumerate(("T1", "T2")):
            (bar,) = gids(fig, f"torques-jump-0-{n}-{q}")
            assert bar.get_xydata().tolist() == [[t, before[j]], [t, after[j]]]
            assert bar.get_transform() == bar.axes.transData
    assert "T jump at a knot (RPR204)" in legend_texts(fig)
    lane = "\n".join(t.get_text() for t in fig.texts).replace("\n    ", " ")
    assert lane.count("RPR204") == 2 and "jump by -13.61, -17.45 N m" in lane


def test_an_overlay_of_two_schemes_puts_the_forces_on_their_own_y_axis() -> None:
    """Path 2 (torques, N m) overlaid with the prismatic task (forces, N): the forces
    take a second y axis on the right, labelled in N and scaled to them; nothing
    overlaps."""
    from tests.render.test_sheet_layout import check_texts

    ms = motions([PATH2, PRISMATIC])
    fig = P.render(ms, ["torques"])
    (main,) = [ax for ax in fig.get_axes() if ax.get_gid() == "panel-torques"]
    (twin,) = [ax for ax in fig.get_axes() if ax.get_gid() == "panel-torques-twin"]
    assert main.get_ylabel() == "$T$ [N m]" and twin.get_ylabel() == "$F$ [N]"
    assert {a.get_gid() for a in main.get_lines()} >= {"T1-0", "T2-0"}
    assert {a.get_gid() for a in twin.get_lines()} >= {"T1-1", "T2-1"}
    assert not {"T1-1", "T2-1"} & {a.get_gid() for a in main.get_lines()}
    forces = np.concatenate([ms[1].s.T1, ms[1].s.T2])
    lo, hi = twin.get_ylim()
    assert lo <= forces.min() and forces.max() <= hi
    assert forces.max() - forces.min() > (hi - lo) / 3
    assert twin.get_xlim() == main.get_xlim()
    check_texts(fig)

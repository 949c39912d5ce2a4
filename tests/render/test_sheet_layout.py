"""The audit sheet as a reader sees it: layout facts read from the drawn figure itself.

Every shipped config alone, the paper's two paths overlaid and all six configs as small
multiples are drawn (Agg, at a low resolution: the layout is in inches) and checked: no
text overlaps another or leaves the figure (defects 1, 2, 4), the time axes share their
x-limits and their pixel extents (defect 6), overlaid tasks have distinct colours
(defect 5) and coinciding marks nest at their one point (issue 26). The torque panel's limits,
saturation and pole inset, and a near miss, are checked against the paper and against
``tests.reference`` (defects 4, 7, 9)."""

from __future__ import annotations

import math
import re
from dataclasses import replace
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from flint import fmpq
from matplotlib.colors import same_color
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.model.task import Piece, Task
from rprpr.model.timing import trapezoidal
from rprpr.render import sheet as P
from tests.conftest import task_text
from tests.reference import reference
from tests.sheets import CONFIG_FILES, PATH1, PATH2, PIECEWISE, SETS, drawn, motions, sheet


def texts(fig: Figure) -> list[Text]:
    """Every visible, non-empty text the sheet shows."""
    out: list[Text] = list(fig.texts)
    out += [t for leg in fig.legends for t in leg.get_texts()]
    for ax in fig.get_axes():
        out += [ax.title, ax.xaxis.label, ax.yaxis.label, *ax.texts]
        for axis, (lo, hi) in ((ax.xaxis, ax.get_xlim()), (ax.yaxis, ax.get_ylim())):
            lo, hi = min(lo, hi), max(lo, hi)
            slack = 1e-9 * (hi - lo)
            out += [  # the tick labels drawn: those in the view
                tick.label1
                for tick in axis.get_major_ticks()
                if lo - slack <= tick.get_loc() <= hi + slack and tick.label1.get_visible()
            ]
    return [t for t in out if t.get_visible() and t.get_text().strip()]


def extent(t: Text, renderer: Any) -> Bbox:
    """A text's box as drawn, with its frame (a key's circle) when it has one."""
    box = t.get_window_extent(renderer)
    patch = t.get_bbox_patch()
    return Bbox.union([box, patch.get_window_extent(renderer)]) if patch else box


def overlapping(boxes: list[Bbox], slack: float = 0.5) -> list[tuple[int, int]]:
    """Every pair i < j of ``boxes`` that overlap by more than ``slack`` [px] each way, in
    the order of ``itertools.combinations`` (all pairs at once: a sheet has hundreds of
    texts)."""
    x0, y0, x1, y1 = np.array([b.extents for b in boxes], dtype=float).reshape(-1, 4).T
    hit = (
        (x0[:, None] < x1[None, :] - slack)
        & (x0[None, :] < x1[:, None] - slack)
        & (y0[:, None] < y1[None, :] - slack)
        & (y0[None, :] < y1[:, None] - slack)
    )
    i, j = np.nonzero(np.triu(hit, 1))
    return list(zip(i.tolist(), j.tolist(), strict=True))


def time_axes(fig: Figure) -> list[Any]:
    return [ax for ax in fig.get_axes() if ax.get_gid() not in ("panel-path", "inset")]


def check_texts(fig: Figure) -> Any:
    """No text overlaps another or leaves the figure (defects 1, 2, 4); returns the
    renderer ``drawn`` laid the figure out with (for more measures of it as it is)."""
    renderer = drawn(fig)
    boxes = [(t.get_text(), extent(t, renderer)) for t in texts(fig)]
    page = fig.bbox
    for text, b in boxes:
        assert page.x0 <= b.x0 and b.x1 <= page.x1 and page.y0 <= b.y0 and b.y1 <= page.y1, text
    clashes = [(boxes[i][0], boxes[j][0]) for i, j in overlapping([b for _, b in boxes])]
    assert not clashes, clashes[:5]
    return renderer


@pytest.mark.parametrize("paths", SETS, ids=lambda ps: "+".join(Path(p).stem for p in ps))
def test_no_text_overlaps_or_leaves_the_figure_and_time_axes_align(paths: list[str]) -> None:
    ms = motions(paths)
    fig = sheet(paths)
    check_texts(fig)
    # one t axis: the same limits, and in each column the same pixel extent (defect 6)
    axes = time_axes(fig)
    columns = 1 if len(ms) <= 3 else len(ms)
    durations = [m.duration for m in ms]
    if columns == 1 or min(durations) >= 0.5 * max(durations):
        assert len({ax.get_xlim() for ax in axes}) == 1
        assert axes[0].get_xlim() == (0.0, max(durations))
    else:  # very different durations: each column its own t axis (issue 26)
        for c in range(columns):
            assert {ax.get_xlim() for ax in axes[c::columns]} == {(0.0, durations[c])}
    for c in range(columns):
        spans = {
            (round(ax.bbox.x0, 6), round(ax.bbox.x1, 6)) for ax in axes[c::columns]
        }  # rows are added column by column
        assert len(spans) == 1, spans
    if columns > 1:  # small multiples: the columns are equally wide
        widths = {round(ax.bbox.width, 6) for ax in axes}
        assert len(widths) == 1


def test_overlay_colours_each_task_and_nests_coinciding_marks() -> None:
    """Paths 1 and 2 both cross at (3, 0), t = 2.5 s: the passing diamond sits inside the
    failing star at that very point on every panel (issue 26: never moved off its data;
    tests/render/test_sheet_marks.py checks every mark); the tasks' colours differ
    (defect 5)."""
    fig = sheet([PATH1, PATH2])
    drawn(fig)
    by = {a.get_gid(): a for ax in fig.get_axes() for a in ax.get_children() if a.get_gid()}
    colours = {by[f"path-{i}"].get_color() for i in range(2)}
    assert len(colours) == 2 and colours <= set(P.TASK_COLOURS)
    for panel in ("path", "delta", "x", "y"):
        star, diamond = by[f"{panel}-singular-0-0"], by[f"{panel}-singular-1-0"]
        (x0, y0), (x1, y1) = (
            m.get_transform().transform(m.get_xydata()[0]) for m in (star, diamond)
        )
        assert math.hypot(x1 - x0, y1 - y0) < 1e-6, panel
        assert star.get_markersize() > diamond.get_markersize()
        assert diamond.get_zorder() > star.get_zorder()


def test_more_than_three_tasks_are_small_multiples_sharing_axes() -> None:
    ms = motions(CONFIG_FILES)
    fig = sheet(CONFIG_FILES)
    axes = {
        n: [ax for ax in fig.get_axes() if ax.get_gid() == f"panel-{n}"]
        for n in ("delta", "torques")
    }
    for n, row in axes.items():
        assert len(row) == len(ms)
        # one unit, one y axis: the forces of a prismatic task have their own (issue 26)
        units = [m.task.robot.actuation if n == "torques" else "" for m in ms]
        for u in set(units):
            assert len({ax.get_ylim() for ax, v in zip(row, units, strict=True) if v == u}) == 1
    heads = [t.get_text() for t in fig.texts]
    assert all(P.short(m.name, 20)[:15] in " ".join(heads) for m in ms)


def test_a_long_absolute_path_wraps_the_title_and_abbreviates_the_file(write_task) -> None:  # type: ignore[no-untyped-def]
    """Defect 1: a CI job's absolute path and a long name stay within the sheet."""
    name = "A very long task name that a careful engineer wrote out " * 3
    text = (
        Path(PATH1)
        .read_text(encoding="utf-8")
        .replace("name: Example 1 of the paper, path 1", f"name: {name.strip()}")
    )
    deep = "/".join(["a-rather-deep-directory"] * 8)
    p = write_task(text, "t.yaml")
    m = P.motion(audit(load_task(p), samples=51), f"/{deep}/{p.name}")
    fig = P.render([m], ["delta"])
    renderer = drawn(fig)
    title = fig.texts[1]
    assert title.get_text().count("\n") >= 1  # wrapped
    assert "FAIL" in title.get_text()
    small = fig.texts[2].get_text()
    assert small.startswith("file: …/") and small.endswith("t.yaml") and len(small) < 100
    for t in fig.texts:
        b = t.get_window_extent(renderer)
        assert b.x0 >= 0 and b.x1 <= fig.bbox.x1


def test_torque_limit_lines_saturation_and_the_pole_inset(write_task) -> None:  # type: ignore[no-untyped-def]
    """Path 1 with |T| <= 100 N m: the limit is drawn as lines (it lies near the data);
    |T| > 100 N m is shaded only where the curve lies beyond it, and the reference torques
    there exceed the limit; the inset's slope reads the pole's order, 2 (the paper)."""
    text = Path(PATH1).read_text(encoding="utf-8") + "checks:\n  torque_limit: [100, 100]\n"
    task = load_task(write_task(text))
    m = P.motion(audit(task, samples=101), "p1.yaml")
    fig = P.render([m], ["torques"], pole_inset=True)
    ax = next(a for a in fig.get_axes() if a.get_gid() == "panel-torques")
    by = {a.get_gid(): a for a in ax.get_children() if a.get_gid()}
    assert by["torque-limit-0-0-upper"].get_ydata()[0] == 100
    assert by["torque-limit-0-0-lower"].get_ydata()[0] == -100
    shaded = [g for g in by if g.startswith("torques-saturation-0-")]
    assert shaded
    for g in shaded:
        verts = np.concatenate([p.vertices for p in by[g].get_paths()])
        t = verts[:, 0]
        lo, hi = float(t.min()), float(t.max())
        assert 1.5 < lo < 2.5 < hi < 3.5
        leg = int(g.split("-")[3])
        for tt in (lo + 0.25 * (2.5 - lo), hi - 0.25 * (hi - 2.5)):  # inside the window
            v = reference(task, Fraction(tt).limit_denominator(10**9))[f"T{leg + 1}"]
            assert abs(float(v)) > 100
    inset = next(a for a in fig.get_axes() if a.get_gid() == "inset")
    x, y = next(c for c in inset.get_lines() if c.get_gid() == "inset-T1-before").get_data()
    slope = (y[-1] - y[-4]) / (x[-1] - x[-4])
    assert slope == pytest.approx(-2, abs=0.05)
    keys = "\n".join(t.get_text() for t in fig.texts).replace("\n    ", " ")
    assert "|T1| > 100 N m over" in keys and "pole of order 2" in keys


def test_a_near_miss_is_marked_with_its_value(write_task) -> None:  # type: ignore[no-untyped-def]
    """Defect 9: y = 0.5 (x - 2)(x - 4) + 0.7 over x in [2.5, 3.5] never meets y = 0; it
    comes closest at x = 3 (y = 0.2, t = 1). The path and δ panels mark it, with its value
    (min |δ| as the reference finds it on a fine grid)."""
    y = "0.5*(x - 2)*(x - 4) + 0.7\n  from: [2.5, 0.325]\n  to: [3.5, 0.325]"
    task = load_task(write_task(task_text(y, "timing:\n  duration: 2\n  x: 2.5 + 0.5*t\n")))
    m = P.motion(audit(task, samples=101), "miss.yaml")
    assert not m.result.singularities
    fig = P.render([m], ["path", "delta"])
    keys = "\n".join(t.get_text() for t in fig.texts).replace("\n    ", " ")
    assert "1  near miss: E passes 0.2 m from the line AB at t = 1 s" in keys
    ts = np.linspace(0, 2, 201)
    ref = [abs(float(reference(task, Fraction(t).limit_denominator(10**6))["delta"])) for t in ts]
    assert f"1  near miss: min |δ| = {min(ref):.3g} at t = " in keys
    gids = {a.get_gid() for ax in fig.get_axes() for a in ax.get_children()}
    assert {"path-approach-0", "path-approach-key-0", "delta-approach-0"} <= gids


def marks(fig: Figure) -> list[Line2D]:
    """Every mark the panels draw: a line with a marker and an id."""
    return [
        a
        for ax in fig.get_axes()
        for a in ax.get_lines()
        if a.get_gid() and a.get_marker() not in (None, "None", "none", "", " ")
    ]


def near_miss_task(write_task: Any) -> Task:
    """y = 0.5 (x - 2)(x - 4) + 0.7 over x in [2.5, 3.5]: it never meets y = 0 and comes
    closest at x = 3 (y = 0.2, t = 1)."""
    y = "0.5*(x - 2)*(x - 4) + 0.7\n  from: [2.5, 0.325]\n  to: [3.5, 0.325]"
    return load_task(write_task(task_text(y, "timing:\n  duration: 2\n  x: 2.5 + 0.5*t\n")))


def test_every_mark_of_an_overlaid_task_carries_its_colour(write_task) -> None:  # type: ignore[no-untyped-def]
    """Overlaid, colour is the task (defect 5): each task's singular marks (edged in it,
    filled with the verdict's colour), the torques' ▲ ▼ where they leave the axis, the
    rings at finite limits, a limit's ▲ ▼ beyond the axis, the path's ends, the robot's
    end point and a near miss's rings; only the ring round a high-order point stays red
    (the verdict, as a mark's fill). Alone, a torque's marks take its leg's colour."""
    miss = P.motion(audit(near_miss_task(write_task), samples=51), "miss.yaml")
    ms = [*motions([PATH1, PATH2]), miss]
    fig = P.render(ms, ["path", "x", "delta", "torques"])
    kinds = set()
    for a in marks(fig):
        gid = a.get_gid()
        kind, i = re.fullmatch(r"(\D+)-(\d+)(-.*)?", gid).group(1, 2)  # type: ignore[union-attr]
        if kind == "path-ring":
            assert same_color(a.get_markeredgecolor(), P.STATUS_COLOUR["fail"])
            continue
        colour = P.TASK_COLOURS[int(i)]
        assert same_color(a.get_markeredgecolor(), colour) or same_color(
            a.get_markerfacecolor(), colour
        ), (gid, a.get_markerfacecolor(), a.get_markeredgecolor())
        kinds.add(kind)
        if kind.endswith("-singular"):  # the fill says the verdict, the edge the task
            assert same_color(a.get_markeredgecolor(), colour)
            assert a.get_markerfacecolor() in P.STATUS_COLOUR.values()
    assert {
        "path-singular",
        "x-singular",
        "y-singular",
        "delta-singular",
        "torques-exit",  # path 1's ▲ (task 0)
        "torques-limit",  # path 2's rings at its finite limits (task 1)
        "torque-limit",  # path 2's ±300 N m limit, beyond the axis (task 1)
        "path-start",
        "path-end",
        "robot",
        "path-near",  # the near miss (task 2)
        "delta-approach",
    } <= kinds
    (alone,) = panel(sheet([PATH1]), "torques")
    for q, leg in (("T1", P.LEG1), ("T2", P.LEG2)):
        up = next(a for a in alone.get_lines() if a.get_gid() == f"torques-exit-0-0-{q}-before")
        assert same_color(up.get_markerfacecolor(), leg)
    star = next(a for a in marks(sheet([PATH1])) if a.get_gid() == "delta-singular-0-0")
    assert star.get_markeredgecolor() == "black"


def panel(fig: Figure, name: str) -> list[Any]:
    return [ax for ax in fig.get_axes() if ax.get_gid() == f"panel-{name}"]


def trapezoidal_task() -> Task:
    """Paper path 2 (eq. 51) under a trapezoidal law from x = 2 to 4 in 5 s at a cruise
    speed of 0.5 m/s: blend time t_b = (V t_f - D) / V = 1 s, so the pieces meet at the
    knots t = 1 s and t = 4 s."""
    base = load_task(PATH2)
    assert base.path is not None
    start, pieces = fmpq(0), []
    for end, x in trapezoidal(fmpq(2), fmpq(4), fmpq(5), fmpq(1, 2)):
        pieces.append(Piece(start, end, x, base.path(x), base.path))
        start = end
    return replace(base, pieces=tuple(pieces), x_of_t=None, law="trapezoidal")


def test_knots_are_marked_lightly_on_every_time_axis() -> None:
    """A piecewise motion's knots: one light dotted line each on every time axis (x_E,
    y_E, δ, θ, s, T) at exactly the knot, in one style under the curves, named once in
    the lanes; none on the workspace, and none on a sheet whose tasks have no knots."""
    from rprpr.render import animation as A
    from rprpr.render.sheet.style import KNOT, KNOT_LABEL

    task = trapezoidal_task()
    assert task.knots == (fmpq(1), fmpq(4))
    m = P.motion(audit(task, samples=51), "trapezoidal.yaml")
    fig = P.render([m], pole_inset=True)
    time = time_axes(fig)
    assert [ax.get_gid() for ax in time] == [
        "panel-x",
        "panel-x",
        "panel-delta",
        "panel-joints",
        "panel-joints",
        "panel-torques",
    ]
    for ax in time:
        knots = [a for a in ax.get_lines() if "-knot-" in str(a.get_gid())]
        assert [tuple(a.get_xdata()) for a in knots] == [(1.0, 1.0), (4.0, 4.0)]
        curves = [a for a in ax.get_lines() if re.fullmatch(r"\w+-0", str(a.get_gid()))]
        assert curves
        for a in knots:
            assert same_color(a.get_color(), KNOT["color"]) and a.get_linewidth() == KNOT["lw"]
            assert a.get_zorder() < min(c.get_zorder() for c in curves)
    assert not [a for a in panel(fig, "path")[0].get_lines() if "knot" in str(a.get_gid())]
    entries = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert entries.count(KNOT_LABEL) == 1
    # the knots' entry fits the lane (the workspace is left out: beyond its first piece the
    # engine does not follow this motion yet, and the path drawn runs far up)
    check_texts(P.render([m], ["x", "delta", "joints", "torques"]))
    # the GIF's δ and torque strips mark them too
    gif = Figure()
    A._Column(gif.subfigures(1, 1), m, A.clock([m], 5), m.duration)
    knots = sorted(
        (a.get_gid(), a.get_xdata()[0])
        for ax in gif.get_axes()
        for a in ax.get_lines()
        if "knot" in str(a.get_gid())
    )
    assert [x for _, x in knots] == [1.0, 4.0, 1.0, 4.0]
    # a motion of one polynomial: nothing
    for paths in SETS:
        if set(paths) & set(PIECEWISE):
            continue
        f = sheet(paths)
        assert not any("knot" in str(a.get_gid()) for ax in f.get_axes() for a in ax.get_lines())
        assert KNOT_LABEL not in [t.get_text() for leg in f.legends for t in leg.get_texts()]
    # each shipped piecewise task: a line at each of its knots, on the six time axes
    for path in PIECEWISE:
        knots = sorted(float(k) for k in load_task(path).knots)
        assert knots
        f = sheet([path])  # shared: the knots are the task's, whatever the samples
        xs = [a.get_xdata()[0] for ax in f.get_axes() for a in ax.get_lines()
              if "knot" in str(a.get_gid())]  # fmt: skip
        assert sorted(xs) == sorted(knots * 6)

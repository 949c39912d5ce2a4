"""The audit sheet as a reader sees it: layout facts read from the drawn figure itself.

Every shipped config alone, the paper's two paths overlaid and all six configs as small
multiples are drawn (Agg, at a low resolution: the layout is in inches) and checked: no
text overlaps another or leaves the figure (defects 1, 2, 4), the time axes share their
x-limits and their pixel extents (defect 6), overlaid tasks have distinct colours
(defect 5) and coinciding marks sit side by side (defect 3). The torque panel's limits,
saturation and pole inset, and a near miss, are checked against the paper and against
``tests.reference`` (defects 4, 7, 9)."""

from __future__ import annotations

import itertools
import math
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.render import sheet as P

from .conftest import task_text
from .reference import reference
from .sheets import CONFIG_FILES, DPI, PATH1, PATH2, SETS, drawn, motions, sheet


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


def overlap(a: Bbox, b: Bbox, slack: float = 0.5) -> bool:
    return (
        a.x0 < b.x1 - slack and b.x0 < a.x1 - slack and a.y0 < b.y1 - slack and b.y0 < a.y1 - slack
    )


def time_axes(fig: Figure) -> list[Any]:
    return [ax for ax in fig.get_axes() if ax.get_gid() not in ("panel-path", "inset")]


@pytest.mark.parametrize("paths", SETS, ids=lambda ps: "+".join(Path(p).stem for p in ps))
def test_no_text_overlaps_or_leaves_the_figure_and_time_axes_align(paths: list[str]) -> None:
    ms = motions(paths)
    fig = sheet(paths)
    renderer = drawn(fig)
    boxes = [(t.get_text(), extent(t, renderer)) for t in texts(fig)]
    page = fig.bbox
    for text, b in boxes:
        assert page.x0 <= b.x0 and b.x1 <= page.x1 and page.y0 <= b.y0 and b.y1 <= page.y1, text
    clashes = [(s, t) for (s, a), (t, b) in itertools.combinations(boxes, 2) if overlap(a, b)]
    assert not clashes, clashes[:5]
    # one t axis: the same limits, and in each column the same pixel extent (defect 6)
    axes = time_axes(fig)
    assert len({ax.get_xlim() for ax in axes}) == 1
    assert axes[0].get_xlim() == (0.0, max(m.duration for m in ms))
    columns = 1 if len(ms) <= 3 else len(ms)
    for c in range(columns):
        spans = {
            (round(ax.bbox.x0, 6), round(ax.bbox.x1, 6)) for ax in axes[c::columns]
        }  # rows are added column by column
        assert len(spans) == 1, spans
    if columns > 1:  # small multiples: the columns are equally wide
        widths = {round(ax.bbox.width, 6) for ax in axes}
        assert len(widths) == 1


def test_overlay_colours_each_task_and_sets_coinciding_marks_side_by_side() -> None:
    """Paths 1 and 2 both cross at (3, 0), t = 2.5 s: the passing diamond sits beside the
    failing star on every panel (defect 3); the tasks' colours differ (defect 5)."""
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
        apart = math.hypot(x1 - x0, y1 - y0) * 72 / DPI  # points
        half = (star.get_markersize() + diamond.get_markersize()) / 2 / 1.4
        assert apart >= half, (panel, apart)


def test_more_than_three_tasks_are_small_multiples_sharing_axes() -> None:
    ms = motions(CONFIG_FILES)
    fig = sheet(CONFIG_FILES)
    axes = {
        n: [ax for ax in fig.get_axes() if ax.get_gid() == f"panel-{n}"]
        for n in ("delta", "torques")
    }
    for row in axes.values():
        assert len(row) == len(ms)
        assert len({ax.get_ylim() for ax in row}) == 1
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

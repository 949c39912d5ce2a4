"""``rprpr repair --plot`` shows the change (issue 26, item 5): a 0.77 mm timing change
or a 36 mm path change is read off the sheet, not only the overlay of two curves that
coincide at the sheet's scale.

The sheet's legends say "before" and "after"; a last panel draws new - old in mm, its
largest value the repair's account (``Repair.timing_change`` / ``path_deviation``); an
inset on the x panel (timing) or the workspace (path) is zoomed at that point, both
motions drawn in it. Each is read back from the figure the command draws."""

from __future__ import annotations

import re

import numpy as np
import pytest
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from rprpr.io.loader import load_task
from rprpr.render import sheet as P
from rprpr.repair import repair
from tests.conftest import CONFIGS
from tests.render.test_sheet_layout import check_texts
from tests.sheets import drawn, repaired

TRAPEZOIDAL = str(CONFIGS / "trapezoidal.rprpr.yaml")  # timing: 0.768 mm at t = 3.51 s
PATH1 = str(CONFIGS / "paper_path1.rprpr.yaml")  # path: 35.7 mm at x = 3.28 m


def repair_sheet(task: str) -> tuple[Figure, list[P.Motion], str]:
    """The figure ``rprpr repair TASK --plot`` draws, its motions, and its account (drawn
    once per test process: ``tests.sheets.repaired``)."""
    done = repaired(task)
    assert done.code == 0 and done.sheet_written, done.err
    return done.fig, done.motions, done.out


def axes(fig: Figure, gid: str) -> Axes:
    (ax,) = [a for a in fig.get_axes() if a.get_gid() == gid][:1]
    return ax


def inset(fig: Figure, gid: str) -> Axes:
    (small,) = [c for a in fig.get_axes() for c in a.child_axes if c.get_gid() == gid]
    return small


def test_the_legends_tell_before_from_after() -> None:
    fig, ms, _ = repair_sheet(TRAPEZOIDAL)
    assert [m.label for m in ms] == ["before", "after"]
    labels = [t.get_text() for leg in fig.legends for t in leg.get_texts()]
    assert labels.count("before") >= 4 and labels.count("after") >= 4, labels
    assert not any("trapezoidal timing" in t for t in labels)  # no cut names
    notes = " ".join(t.get_text() for t in fig.texts)
    assert "before: t = 2.5 s" in notes and "after: t = 2.5 s" in notes
    check_texts(fig)  # the change panel and its lane overlap nothing


def test_a_small_timing_change_is_drawn_in_mm_and_zoomed_at_its_largest() -> None:
    fig, ms, out = repair_sheet(TRAPEZOIDAL)
    found = re.search(r"timing: max \|Δx\(t\)\| ([\d.e-]+) m at t = ([\d.]+) s", out)
    assert found is not None, out
    size, t0 = float(found.group(1)), float(found.group(2))
    r = repair(load_task(TRAPEZOIDAL))
    assert r.timing_change is not None and r.path_deviation is None
    assert (size, t0) == pytest.approx(r.timing_change, rel=1e-5)
    # the difference panel: Δx(t) in mm, its largest |value| the account's
    change = axes(fig, "panel-change")
    (dx,) = [ln for ln in change.get_lines() if ln.get_gid() == "change-x"]
    assert not any(ln.get_gid() == "change-y" for ln in change.get_lines())  # path kept
    values = np.asarray(dx.get_ydata(), dtype=float)
    assert np.nanmax(np.abs(values)) == pytest.approx(1e3 * r.timing_change[0], rel=1e-6)
    (mark,) = [ln for ln in change.get_lines() if ln.get_gid() == "change-max-x"]
    assert float(mark.get_xdata()[0]) == pytest.approx(r.timing_change[1], abs=1e-9)
    assert abs(float(mark.get_ydata()[0])) == pytest.approx(1e3 * r.timing_change[0], rel=1e-6)
    assert "max |Δx| 0.7677 mm at t = 3.512 s" in " ".join(t.get_text() for t in fig.texts)
    # the inset on the x panel: about (t0, x(t0)), both motions in it and told apart there
    small = inset(fig, "inset-change-x")
    (t_lo, t_hi), (x_lo, x_hi) = small.get_xlim(), small.get_ylim()
    before, after = (m.result.resample(np.array([r.timing_change[1]])).x[0] for m in ms)
    assert t_lo < r.timing_change[1] < t_hi
    assert x_lo < min(before, after) and max(before, after) < x_hi
    assert abs(after - before) == pytest.approx(r.timing_change[0], rel=1e-6)
    assert abs(after - before) > 0.1 * (x_hi - x_lo)  # visibly apart, not one line
    assert len([ln for ln in small.get_lines() if ln.get_gid()]) == 2
    # the inset stands inside its panel
    renderer = drawn(fig)
    parent = axes(fig, "panel-x").get_window_extent(renderer)
    box = small.get_tightbbox(renderer)
    assert box is not None
    assert parent.x0 <= box.x0 and box.x1 <= parent.x1 and parent.y0 <= box.y0 <= parent.y1


def test_a_path_change_is_zoomed_on_the_workspace() -> None:
    fig, ms, _ = repair_sheet(PATH1)
    r = repair(load_task(PATH1))
    assert r.path_deviation is not None and r.timing_change is None
    size, x0 = r.path_deviation
    change = axes(fig, "panel-change")
    (dy,) = [ln for ln in change.get_lines() if ln.get_gid() == "change-y"]
    values = np.asarray(dy.get_ydata(), dtype=float)
    assert np.nanmax(np.abs(values)) == pytest.approx(1e3 * size, rel=1e-4)  # 4 digits
    small = inset(fig, "inset-change-path")
    (lo, hi), (y_lo, y_hi) = small.get_xlim(), small.get_ylim()
    assert lo < x0 < hi
    y_after = float(np.interp(x0, ms[1].s.x, ms[1].s.y))
    y_before = float(np.interp(x0, ms[0].s.x, ms[0].s.y))
    assert y_lo < min(y_before, y_after) and max(y_before, y_after) < y_hi
    assert abs(y_after - y_before) == pytest.approx(size, rel=1e-3)

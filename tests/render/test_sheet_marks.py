"""Every singular mark at its data coordinates (issue 26, item 1), on every sheet kind.

A mark's position is read back from the figure: the artist's data (``Line2D.get_xydata``)
and its transform, which must be its axes' data transform (no offset in points: the
mark is drawn where the audit's numbers put it), checked against the audit's numbers
(``result.singularities[k].t, .x``; y = 0 and δ = 0 at a Type II instant). Coinciding
marks (the paper's two paths, both at (3, 0) at t = 2.5 s) stay where they belong and
nest: told apart by shape, size, outline and z-order."""

from __future__ import annotations

import re
from collections.abc import Sequence

import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from rprpr.render import animation as A
from rprpr.render import sheet as P
from tests.conftest import CONFIGS
from tests.sheets import CONFIG_FILES, PATH1, PATH2, drawn, gif, motions, repaired, sheet

MARK = re.compile(r"^(path|x|y|delta|gif-path|gif-delta)-singular-(\d+)-(\d+)$")


def marks(fig: Figure) -> dict[str, Line2D]:
    """Every singular mark of ``fig`` by its gid."""
    out = {}
    for ax in fig.get_axes():
        for a in ax.get_children():
            gid = a.get_gid()
            if isinstance(a, Line2D) and gid and MARK.match(gid):
                out[gid] = a
    return out


def expected(panel: str, m: P.Motion, k: int) -> tuple[float, float]:
    """Where the audit puts task m's k-th singular instant on ``panel``."""
    s = m.result.singularities[k]
    y = getattr(s, "y", 0.0)  # a 5R's instant sits on its Type II curve, an RPRPR's at y = 0
    return {
        "path": (s.x, y),
        "gif-path": (s.x, y),
        "x": (s.t, s.x),
        "y": (s.t, y),
        "delta": (s.t, 0.0),
        "gif-delta": (s.t, 0.0),
    }[panel]


def check_at_data(fig: Figure, ms: Sequence[P.Motion], panels: Sequence[str]) -> int:
    """Each mark's data are the audit's numbers and it is drawn through its axes' data
    transform alone; every instant has its mark on each panel. Returns the marks seen."""
    found = marks(fig)
    for gid, line in found.items():
        match = MARK.match(gid)
        assert match is not None
        panel, i, k = match.group(1), int(match.group(2)), int(match.group(3))
        want = expected(panel, ms[i], k)
        assert line.get_xydata().tolist() == [list(want)], gid  # type: ignore[union-attr]
        ax = line.axes
        assert ax is not None
        assert line.get_transform() == ax.transData, gid  # no shift in points
        assert np.allclose(
            line.get_transform().transform(line.get_xydata()), ax.transData.transform([want])
        ), gid
    for panel in panels:
        for i, m in enumerate(ms):
            for k in range(len(m.result.singularities)):
                assert f"{panel}-singular-{i}-{k}" in found, (panel, i, k)
    return len(found)


SHEET_PANELS = ("path", "x", "y", "delta")


@pytest.mark.parametrize(
    "paths",
    [[PATH1], [str(CONFIGS / "zero_speed_crossing.rprpr.yaml")], [PATH1, PATH2], CONFIG_FILES],
    ids=["single", "single-zero-speed", "overlay", "small-multiples"],
)
def test_every_mark_sits_at_the_audits_numbers(paths: list[str]) -> None:
    ms = motions(paths)
    fig = sheet(paths)
    drawn(fig)
    assert check_at_data(fig, ms, SHEET_PANELS) >= len(SHEET_PANELS)


def test_coinciding_marks_nest_at_the_one_point_and_read_apart() -> None:
    """Paths 1 and 2 both cross at (3, 0) at t = 2.5 s: both marks at exactly that point
    on every panel, the high-order star outside, the first-order diamond inside it and
    above it, each edged in its task's colour; the t_s line runs through both."""
    ms = motions([PATH1, PATH2])
    (s1,), (s2,) = (m.result.singularities for m in ms)
    assert (s1.t, s1.x, s2.t, s2.x) == (2.5, 3.0, 2.5, 3.0)
    fig = sheet([PATH1, PATH2])
    drawn(fig)
    found = marks(fig)
    for panel in ("path", "x", "y", "delta"):
        star, diamond = found[f"{panel}-singular-0-0"], found[f"{panel}-singular-1-0"]
        assert star.get_xydata().tolist() == diamond.get_xydata().tolist()  # type: ignore[union-attr]
        assert (star.get_marker(), diamond.get_marker()) == ("*", "D")
        assert star.get_markeredgecolor() != diamond.get_markeredgecolor()
        assert diamond.get_zorder() > star.get_zorder()
        # the diamond inside leaves the star's outline clear all round
        assert star.get_markersize() >= diamond.get_markersize() + 2 * 3.5
        if panel != "path":
            ax = star.axes
            assert ax is not None
            (tline,) = [a for a in ax.get_lines() if a.get_gid() == f"{panel}-tsline-0-0"]
            assert tline.get_xdata()[0] == s1.t  # type: ignore[index]
    # on the path the ring is the star's outline: it encloses both
    ring = next(
        a for ax in fig.get_axes() for a in ax.get_lines() if a.get_gid() == "path-ring-0-0"
    )
    assert ring.get_xydata().tolist() == [[3.0, 0.0]]  # type: ignore[union-attr]
    assert ring.get_markersize() > found["path-singular-0-0"].get_markersize()


def test_same_shaped_marks_at_one_point_nest_by_size() -> None:
    """Two first-order diamonds at one point (a task beside itself, as a repair sheet's
    before and after can be): the first outside, the second inside, both at the point."""
    (m,) = motions([PATH2])
    fig = P.render([m, m], ["delta"])
    drawn(fig)
    found = marks(fig)
    outer, inner = found["delta-singular-0-0"], found["delta-singular-1-0"]
    assert outer.get_xydata().tolist() == inner.get_xydata().tolist() == [[2.5, 0.0]]  # type: ignore[union-attr]
    assert outer.get_markersize() >= inner.get_markersize() + 7
    assert inner.get_zorder() > outer.get_zorder()
    keys = [
        a for ax in fig.get_axes() for a in ax.texts if (a.get_gid() or "").startswith("delta-key")
    ]
    assert len({k.get_position() for k in keys}) == 2  # the key numbers stand apart


def test_the_repair_sheet_marks_before_and_after_at_their_data() -> None:
    """``rprpr repair --plot``: the old and the new motion, each mark at its instant."""
    done = repaired(PATH1)  # the command's figure, drawn once per test process
    code, err, fig, ms = done.code, done.err, done.fig, done.motions
    assert code == 0 and done.sheet_written, err
    assert len(ms) == 2
    drawn(fig)
    assert check_at_data(fig, ms, SHEET_PANELS) >= 8


def test_the_gifs_static_marks_at_their_data() -> None:
    """The GIF of both paths side by side (tests/render/test_animation.py reads its file):
    the marks are static, drawn once whatever the frames."""
    ms = motions([PATH1, PATH2])
    a = gif((PATH1, PATH2), 2, 30).animation
    check_at_data(a.fig, ms, ("gif-path", "gif-delta"))


def test_the_gifs_singular_line_shows_over_the_legs_at_t_s() -> None:
    """Path 2 at t_s = 2.5 s: E is at (3, 0), both legs lie along AB; the singular line
    (red) is drawn over them, as on the sheet: red pixels along y = 0 between A and E."""
    (m,) = ms = motions([PATH2])
    a = A.Animation(ms, frames=5, dpi=60)
    k = next(j for j, v in enumerate(a.t) if v == m.result.singularities[0].t)
    rgba = a.rgba(k)
    c = a.columns[0]
    height = rgba.shape[0]
    xs = np.linspace(0.3, 2.7, 200)
    px = c.ax.transData.transform(np.column_stack([xs, np.zeros_like(xs)]))
    rows = np.round(height - px[:, 1]).astype(int)
    cols = np.round(px[:, 0]).astype(int)
    red = 0
    for r, col in zip(rows, cols, strict=True):
        patch = rgba[r - 1 : r + 2, col, :3].astype(int)
        red += int(np.any((patch[:, 0] > 170) & (patch[:, 1] < 110) & (patch[:, 2] < 110)))
    assert red > 60, red  # the dash-dot line's dashes, not hidden by leg 1's rod
    zs = {x.get_gid(): x.get_zorder() for x in c.moving if x.get_gid()}
    assert zs["gif-singular-line-0"] > max(r.get_zorder() for r in c.robot.artists[:-1])

"""A figure for a paper: ``rprpr plot --size W,H --font-scale F`` (issue 26, item 7).

The figure is exactly W x H inches (the page of a PDF too), holds the panels without the
sheet's title, their legends and keys under the axes, nothing overlapping or outside;
every text size is F times the sheet's; a size too small is one usage line."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from matplotlib.figure import Figure

from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.render import sheet as P
from tests.conftest import run_cli
from tests.render.test_sheet_layout import check_texts, extent, texts
from tests.sheets import CONFIG_FILES, PATH1, PATH2, drawn, motions, small_pictures


def sizes(fig: Figure) -> dict[str, float]:
    """The size of a few kinds of text: tick labels, legend entries, key numbers."""
    drawn(fig)
    ax = next(a for a in fig.get_axes() if a.get_gid() == "panel-delta")
    badge = next(t for t in ax.texts if (t.get_gid() or "").startswith("delta-key"))
    return {
        "tick": ax.yaxis.get_ticklabels()[0].get_fontsize(),
        "label": ax.yaxis.label.get_fontsize(),
        "legend": fig.legends[0].get_texts()[0].get_fontsize(),
        "key": badge.get_fontsize(),
    }


@pytest.mark.parametrize("panel", ["delta", "path", "torques"])
def test_a_sized_figure_is_exactly_that_size_and_nothing_overlaps(panel: str) -> None:
    fig = P.render(motions([PATH1, PATH2]), [panel], size=(5.0, 4.6))
    assert tuple(fig.get_size_inches()) == (5.0, 4.6)
    renderer = check_texts(fig)  # every text inside the figure, none over another
    texts = " ".join(t.get_text() for t in fig.texts)
    assert "audit sheet" not in texts and "file:" not in texts  # no sheet title
    (ax,) = [a for a in fig.get_axes() if a.get_gid() == f"panel-{panel}"]
    legend = fig.legends[0].get_window_extent(renderer)  # as laid out (unchanged since)
    assert legend.y1 <= ax.get_tightbbox().y0 + 1  # the legend under the axes


def test_font_scale_multiplies_every_text_size() -> None:
    ms = motions([PATH1, PATH2])
    base = sizes(P.render(ms, ["delta"], size=(4.5, 5.5)))
    big = sizes(P.render(ms, ["delta"], size=(4.5, 5.5), font_scale=1.5))
    assert base == {"tick": 8.0, "label": 9.0, "legend": 7.5, "key": 6.5}
    assert big == {k: 1.5 * v for k, v in base.items()}
    # the sheet itself scales alike
    assert sizes(P.render(ms, ["delta"], font_scale=1.25))["tick"] == 10.0


def test_the_command_writes_a_pdf_page_of_the_size_asked(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    small_pictures(monkeypatch)  # the page's size is read here, not its fonts
    out = tmp_path / "fig4.pdf"
    code, _, err = run_cli(
        "plot", PATH2, "--panels", "delta", "--size", "3.5,3", "--font-scale", "1.2",
        "-o", str(out), "--samples", "101",
    )  # fmt: skip
    assert code == 0, err
    box = re.search(rb"/MediaBox \[\s*0 0 ([\d.]+) ([\d.]+)\s*\]", out.read_bytes())
    assert box is not None
    assert (float(box.group(1)), float(box.group(2))) == (3.5 * 72, 3 * 72)


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--size", "3.5,0.8"], "0.8 in is too short for delta at 3.5 in wide: at least"),
        (["--size", "3.5"], "expected W,H in inches such as 3.5,2.4"),
        (["--size", "0,3"], "each side must be in (0, 50] inches"),
        (["--font-scale", "9"], "--font-scale"),
    ],
)
def test_a_size_that_cannot_be_is_one_usage_line(
    tmp_path: Path, args: list[str], words: str
) -> None:
    out = tmp_path / "x.png"
    code, _, err = run_cli(
        "plot", PATH2, "--panels", "delta", *args, "-o", str(out), "--samples", "51"
    )
    assert code == 2 and words in err and len(err.strip().splitlines()) == 1, err
    assert not out.exists()


def test_a_sized_figure_holds_one_column_of_axes() -> None:
    with pytest.raises(ValueError, match="at most 3 tasks"):
        P.render(motions(CONFIG_FILES), ["delta"], size=(7.0, 4.0))


@pytest.mark.parametrize(("panel", "scale"), [("torques", 1.2), ("delta", 1.0), ("delta", 1.2)])
def test_a_single_panel_paper_figure_gives_its_axes_the_height_text_leaves(
    panel: str, scale: float
) -> None:
    """3.5 x 3.2 in, one panel (issue 26): the axes take at least 45 % of the height, the
    heading is one line (a shorter form or a smaller size, never broken inside a formula),
    no text overlaps, and the lane ends at the figure's foot (no empty band)."""
    m = P.motion(audit(load_task(PATH2), samples=101, peak=True), PATH2)
    fig = P.render([m], [panel], size=(3.5, 3.2), font_scale=scale)
    renderer = check_texts(fig)  # laid out once: the figure is only read from here on
    (ax,) = [a for a in fig.get_axes() if a.get_gid() == f"panel-{panel}"]
    assert ax.get_position().height >= 0.45, ax.get_position().height
    heading = next(t for t in fig.texts if t.get_fontweight() == "bold")
    assert "\n" not in heading.get_text(), heading.get_text()
    if panel == "delta":
        assert "sin(θ1 − θ2)" in heading.get_text()
    boxes = [extent(t, renderer) for t in texts(fig)]
    dpi = fig.dpi
    foot = min(b.y0 for b in boxes) / dpi  # in, from the figure's bottom edge
    assert foot <= 0.12, foot
    top = fig.bbox.y1 - max(b.y1 for b in boxes)
    assert top / dpi <= 0.12
    # the axes' tick labels and label stand clear of the legend under them
    legend = fig.legends[0].get_window_extent(renderer)
    assert ax.get_tightbbox(renderer).y0 >= legend.y1 - 1

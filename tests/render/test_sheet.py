"""rprpr plot: the audit sheet's content — panels, titles, labels with units, the markers at
the singular instants, the overlay's legend — in PNG, SVG and PDF, and the paper's
Figs. 3-5 in the drawn data."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from PIL import Image

from rprpr.cli.main import main
from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.render import sheet as P
from tests.cli.forked import fresh_probe
from tests.conftest import task_text
from tests.sheets import CONFIG_FILES, PATH1, PATH2, SAMPLES, SETS, drawn, motions, sheet

NAME1 = "Example 1 of the paper, path 1"
NAME2 = "Example 2 of the paper, path 2"
AXES_PER_ROW = {"path": 1, "x": 2, "delta": 1, "joints": 2, "torques": 1}
HEAVY5 = """\
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 3.0, inertia: 0.05, r: 0.5}
"""
PATH2_Y = "0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2\n  from: [2, -1]\n  to: [4, 1]"
QUINTIC = "timing:\n  duration: 5\n  law: quintic\n"


def panel_axes(fig: Figure) -> dict[str, list[Any]]:
    out: dict[str, list[Any]] = {}
    for ax in fig.get_axes():
        if (ax.get_gid() or "").startswith("panel-"):
            out.setdefault(ax.get_gid().removeprefix("panel-"), []).append(ax)
    return out


def by_gid(ax: Any, gid: str) -> Any:
    hits = [a for a in ax.get_children() if a.get_gid() == gid]
    assert len(hits) == 1, f"{gid}: {len(hits)} artists"
    return hits[0]


def legend_texts(fig: Figure) -> list[str]:
    """Every legend entry of the sheet (the legends sit in the lane, on the figure)."""
    return [t.get_text() for leg in fig.legends for t in leg.get_texts()]


def lane_texts(fig: Figure) -> str:
    """The sheet's own texts: its title, the panels' headings and the lane's keys (each
    key on one line, unwrapped)."""
    return "\n".join(t.get_text() for t in fig.texts).replace("\n    ", " ")


def run(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    with pytest.raises(SystemExit) as e:
        main(args)
    out, err = capsys.readouterr()
    return int(e.value.code or 0), out, err


def svg_texts(path: Path) -> tuple[str, set[str]]:
    """All text of an SVG's <text> elements, and every id."""
    root = ET.parse(path).getroot()
    texts = " ".join("".join(t.itertext()) for t in root.iter("{http://www.w3.org/2000/svg}text"))
    ids = {e.get("id") for e in root.iter() if e.get("id")}
    return texts, ids  # type: ignore[return-value]


# ---------------------------------------------------------------------------------------
# every panel of every config and of the overlay, on the figure; each format saved once

PANEL_WORDS = (
    "Workspace (paper Fig. 3)",
    "x_E(t) (paper Fig. 2)",
    "eq. (29) (paper Fig. 4)",
    "θ1, θ2 (paper Fig. 5)",
    "Motor torques T1, T2, eq. (28)",
    "t [s]",
    "x [m]",
    "y [m]",
)


FIVE_BAR_WORDS = (
    "Workspace",
    "Type II curve S₊ = 0",
    "Type II curve S₋ = 0",
    "x_E(t) and y_E(t)",
    "δ(t) = (E − C) × (E − D)/(l3 l4)",
    "Motor angles θ1, θ2",
    "Motor torques T1, T2",
)


def figure_texts(fig: Figure) -> str:
    """Every text the sheet shows: titles, axis labels, annotations and legends."""
    texts = [lane_texts(fig), *legend_texts(fig)]
    for ax in fig.get_axes():
        texts += [ax.get_title(), ax.get_xlabel(), ax.get_ylabel()]
        texts += [t.get_text() for t in ax.texts]
    return " ".join(texts)


def figure_gids(fig: Figure) -> set[str]:
    return {a.get_gid() for ax in fig.get_axes() for a in ax.get_children() if a.get_gid()}


def check_content(fig: Figure, ms: Sequence[P.Motion]) -> None:
    axes = panel_axes(fig)
    assert list(axes) == list(P.PANELS)
    columns = 1 if len(ms) <= 3 else len(ms)
    title = lane_texts(fig)
    for m in ms:
        assert m.name in title  # the sheet's title names the task(s)
    for name, axs in axes.items():
        assert len(axs) == AXES_PER_ROW[name] * columns
        assert re.search(r"\[.+\]", axs[0].get_ylabel()), axs[0].get_ylabel()  # units
        assert axs[-1].get_xlabel() == ("x [m]" if name == "path" else "t [s]")
    if 1 < len(ms) <= 3:
        assert {m.name for m in ms} <= set(legend_texts(fig))
    assert axes["path"][0].get_ylabel() == "y [m]"
    assert [ax.get_ylabel() for ax in axes["joints"][::columns]] == [
        r"$\theta$ [deg]",
        r"$\varphi$ [deg]" if ms[0].task.robot.mechanism == "5R" else "$s$ [m]",
    ]
    kinds = {m.task.robot.actuation for m in ms}  # forces in N for linear actuators
    if columns > 1:  # small multiples: the first column's axis is in its own unit (issue 26)
        kinds = {ms[0].task.robot.actuation}
    unit = {frozenset({"revolute"}): "$T$ [N m]", frozenset({"prismatic"}): "$F$ [N]"}
    assert axes["torques"][0].get_ylabel() == unit.get(frozenset(kinds), "$T$ [N m], $F$ [N]")
    for i, m in enumerate(ms):
        for k, s in enumerate(m.result.singularities):
            shape = "*" if s.high_order else "D"
            for panel, gid, xy in (
                ("path", f"path-singular-{i}-{k}", (s.x, getattr(s, "y", 0.0))),
                ("delta", f"delta-singular-{i}-{k}", (s.t, 0.0)),
                ("x", f"x-singular-{i}-{k}", (s.t, s.x)),
            ):
                ax = next(
                    a for a in axes[panel] if any(c.get_gid() == gid for c in a.get_children())
                )
                mark = by_gid(ax, gid)
                assert mark.get_marker() == shape
                assert tuple(mark.get_xydata()[0]) == pytest.approx(xy)
                assert mark.get_markerfacecolor() == P.STATUS_COLOUR[m.result.status_of(s)]
                key = by_gid(ax, f"{panel}-key-{i}-{k}").get_text()
                assert re.search(rf"^{key}  .*order {s.order}", title, re.M)


def check_words_and_ids(texts: str, ids: set[str], ms: Sequence[P.Motion]) -> None:
    """The panels' titles, the axes and the tasks' names are written; every curve and
    singular instant has its id."""
    kinds = {m.task.robot.actuation for m in ms}  # the effort panel names its scheme
    efforts = {
        frozenset({"revolute"}): PANEL_WORDS[4],
        frozenset({"prismatic"}): "Leg forces F1, F2 (prismatic actuation)",
    }.get(frozenset(kinds), "Actuator efforts: torques T [N m] (revolute), forces F [N]")
    panel_words = [w if w != PANEL_WORDS[4] else efforts for w in PANEL_WORDS]
    if all(m.task.robot.mechanism == "5R" for m in ms):  # the paper's figures are the RPRPR's
        panel_words = [*FIVE_BAR_WORDS, *PANEL_WORDS[5:]]
    for words in (*panel_words, *(m.name for m in ms)):
        assert words in texts, words
    for i, m in enumerate(ms):
        assert {f"path-{i}", f"delta-{i}", f"theta1-{i}", f"T1-{i}", f"T2-{i}"} <= ids
        for k in range(len(m.result.singularities)):
            assert {
                f"path-singular-{i}-{k}",
                f"delta-singular-{i}-{k}",
                f"delta-key-{i}-{k}",
            } <= ids


@pytest.mark.parametrize("paths", SETS, ids=lambda ps: "+".join(Path(p).stem for p in ps))
def test_every_panel_shows_its_content(paths: list[str]) -> None:
    ms = motions(paths)
    fig = sheet(paths)
    check_content(fig, ms)
    check_words_and_ids(figure_texts(fig), figure_gids(fig), ms)


@pytest.fixture(scope="module")
def saved(tmp_path_factory: pytest.TempPathFactory) -> tuple[list[P.Motion], Path]:
    """The sheet of every shipped config, saved once as SVG and PDF: every config drawn
    in the formats that keep its text as text and as embedded fonts."""
    ms = motions(CONFIG_FILES)
    fig = sheet(CONFIG_FILES)
    out = tmp_path_factory.mktemp("sheet")
    P.save(fig, str(out / "sheet.svg"), "svg", motions=ms)
    P.save(fig, str(out / "sheet.pdf"), "pdf", motions=ms)
    return ms, out


def test_png_has_the_sheets_size_and_names_the_tasks(tmp_path: Path) -> None:
    """The paper's overlay as PNG at 20 dpi (Agg lays out every config's sheet in
    tests/render/test_sheet_layout.py; a raster of the six, or a finer one, would add only
    time: no pixel is read here)."""
    ms = motions([PATH1, PATH2])
    fig = sheet([PATH1, PATH2])
    P.save(fig, str(tmp_path / "sheet.png"), "png", dpi=20, motions=ms)
    with Image.open(tmp_path / "sheet.png") as im:
        im.verify()
    with Image.open(tmp_path / "sheet.png") as im:
        w, h = fig.get_size_inches()
        assert im.size == (int(w * 20), int(h * 20))  # whole pixels, as Agg cuts them
        assert all(m.name in im.text["Title"] for m in ms)
        assert im.text["Software"].startswith("rprpr ")


def test_svg_keeps_the_text_and_an_id_per_curve_and_instant(
    saved: tuple[list[P.Motion], Path],
) -> None:
    ms, out = saved
    check_words_and_ids(*svg_texts(out / "sheet.svg"), ms)


def test_pdf_is_one_page_naming_the_tasks_in_truetype(
    saved: tuple[list[P.Motion], Path],
) -> None:
    ms, out = saved
    data = (out / "sheet.pdf").read_bytes()
    assert data.startswith(b"%PDF-") and data.rstrip().endswith(b"%%EOF")
    title = re.search(rb"/Title \((.*?)\)", data)
    assert title and all(m.name.encode() in title.group(1) for m in ms)
    assert b"/Count 1" in data  # one page
    assert b"DejaVuSans" in data  # the text is there, as embedded TrueType (fonttype 42):
    assert b"/FontFile2" in data and b"/Type3" not in data  # a TrueType font file, no Type 3


# ---------------------------------------------------------------------------------------
# the paper's figures in the drawn data


def quintic_x(t: np.ndarray) -> np.ndarray:
    return 2 + 4 / 25 * t**3 - 6 / 125 * t**4 + 12 / 3125 * t**5  # eq. (49)


def test_fig4_path1_flattens_at_2_5_while_path2_crosses_with_slope() -> None:
    ms = motions([PATH1, PATH2], samples=1001)
    fig = P.render(ms, ["delta"])
    ax = panel_axes(fig)["delta"][0]
    for i, (path, slope) in enumerate(
        ((lambda x: (x - 3) ** 3, 0.0), (lambda x: 0.8 * x**3 - 7.2 * x**2 + 21.8 * x - 22.2, -0.1))
    ):
        t, d = by_gid(ax, f"delta-{i}").get_data()
        t, d = np.asarray(t), np.asarray(d)
        # independently: δ = -a1 y / (s1 s2), eq. (29) in product form, from eqs. (49)-(51)
        x = quintic_x(t)
        y = path(x)
        assert np.allclose(d, -6 * y / (np.hypot(x, y) * np.hypot(x - 6, y)), atol=1e-12)
        j = int(np.argmin(np.abs(t - 2.5)))
        assert t[j] == 2.5 and d[j] == 0.0
        h = t[j + 1] - t[j]
        d1 = (d[j + 1] - d[j - 1]) / (2 * h)
        d2 = (d[j + 1] - 2 * d[j] + d[j - 1]) / h**2
        assert d1 == pytest.approx(slope, abs=1e-4)
        if i == 0:  # δ = δ' = δ'' = 0: the curve is flat at t_s (third order)
            assert abs(d2) < 1e-2
    assert by_gid(ax, "delta-singular-0-0").get_marker() == "*"  # high order stands out
    assert by_gid(ax, "delta-singular-1-0").get_marker() == "D"
    assert (
        "1  Example 1 of the paper, path 1: t = 2.5 s, order 3, high-order (δ = δ' = δ'' = 0)"
        in (lane_texts(fig))
    )
    assert by_gid(ax, "delta-key-0-0").get_text() == "1"
    assert legend_texts(fig)[:2] == [NAME1, NAME2]


def test_fig5_joint_angles_in_degrees_are_continuous() -> None:
    (m,) = motions([PATH2], samples=1001)
    fig = P.render([m], ["joints"])
    ax_theta, ax_s = panel_axes(fig)["joints"]
    _, th1 = by_gid(ax_theta, "theta1-0").get_data()
    _, th2 = by_gid(ax_theta, "theta2-0").get_data()
    assert th1[0] == pytest.approx(-26.5651, abs=5e-5)
    assert th2[0] == pytest.approx(-165.9638, abs=5e-5)
    assert th1[-1] == pytest.approx(math.degrees(math.atan2(1, 4)), abs=1e-9)
    assert th2[-1] == pytest.approx(math.degrees(math.atan2(1, -2)) - 360, abs=1e-9)  # no 2π jump
    assert np.max(np.abs(np.diff(th1))) < 0.5 and np.max(np.abs(np.diff(th2))) < 0.5
    _, s1 = by_gid(ax_s, "s1-0").get_data()
    assert s1[0] == pytest.approx(math.sqrt(5)) and s1[-1] == pytest.approx(math.sqrt(17))


def test_fig3_workspace_shows_bases_singular_line_and_robots() -> None:
    fig = sheet([PATH1, PATH2])
    ax = panel_axes(fig)["path"][0]
    assert ax.get_aspect() == 1.0
    texts = {t.get_text() for t in ax.texts}
    assert {"A", "B"} <= texts
    assert {"case 1\nθ1 = θ2 = 0", "case 2\nθ1 = θ2 = π", "case 3\nθ1 = 0, θ2 = π"} <= texts
    x, y = by_gid(ax, "path-0").get_data()
    assert (x[0], y[0], x[-1], y[-1]) == pytest.approx((2, -1, 4, 1))
    # the robot at t_s: both legs on the singular line, meeting at E = (3, 0); dashed and
    # under the line AB, which stays visible (defect 8)
    line = by_gid(ax, "singular-line")
    for n, base in ((1, 0.0), (2, 6.0)):
        leg = by_gid(ax, f"robot-0-singular-0-leg{n}")
        lx, ly = leg.get_data()
        assert (lx[0], ly[0]) == pytest.approx((base, 0.0))
        assert (lx[1], ly[1]) == pytest.approx((3.0, 0.0), abs=1e-12)
        assert leg.get_linestyle() == "--" and leg.get_zorder() < line.get_zorder()
        # an overlay draws each task's robot at its singular instants only (defect 5)
        assert not [a for a in ax.get_children() if a.get_gid() == f"robot-0-start-leg{n}"]
    by_gid(ax, "path-ring-0-0")  # the high-order point of path 1 is ringed
    assert not [a for a in ax.get_children() if a.get_gid() == "path-ring-1-0"]
    keys = lane_texts(fig)
    assert "1  Example 1 of the paper, path 1: t = 2.5 s, order 3, high-order — FAILS" in keys
    assert "slope principle fails" in keys
    assert (
        "2  Example 2 of the paper, path 2: t = 2.5 s, order 1 — PASSES: T → (63.23, -5.445) N m"
        in keys
    )
    entries = legend_texts(fig)
    assert {
        NAME1,
        NAME2,
        "high-order singular instant (fails)",
        "first-order singular instant (passes)",
        "singular line y = 0 (δ = 0)",
    } <= set(entries)


def test_torques_clip_to_the_bounded_part_and_mark_the_divergence() -> None:
    (m,) = motions([PATH1])
    assert np.nanmax(np.abs(m.s.T1)) > 1e6  # the samples beside t_s are huge ...
    fig = sheet([PATH1])
    ax = panel_axes(fig)["torques"][0]
    lo, hi = ax.get_ylim()
    assert -200 < lo < -60 and 60 < hi < 200  # ... the axis keeps the bounded part
    assert by_gid(ax, "torques-unbounded-0-0").get_xdata()[0] == 2.5
    for q in ("T1", "T2"):
        for side in ("before", "after"):
            mark = by_gid(ax, f"torques-exit-0-0-{q}-{side}")
            tx, ty = mark.get_xydata()[0]
            assert ty == hi and mark.get_marker() == "^"  # pole of order 2: +∞ on both sides
            assert 0 < abs(tx - 2.5) < 0.5
    assert "1  T → ∞ at t = 2.5 s: pole of order 2" in lane_texts(fig)
    assert "leaves the axis: diverges" in legend_texts(fig)


def test_torques_bounded_limit_far_outside_is_marked_at_the_edge() -> None:
    """Path 2 peaks at 66 N m under a ±300 N m limit: the axis keeps to the data (defect
    7) and the limit is marked at its right edge, not as a band over it (defect 4)."""
    fig = sheet([PATH2])
    ax = panel_axes(fig)["torques"][0]
    assert tuple(by_gid(ax, "torques-limit-0-0-T1").get_xydata()[0]) == pytest.approx((2.5, 63.225))
    assert tuple(by_gid(ax, "torques-limit-0-0-T2").get_xydata()[0]) == pytest.approx((2.5, -5.445))
    lo, hi = ax.get_ylim()
    assert -100 < lo < -60 and 66 < hi < 100
    for end, shape in (("upper", "^"), ("lower", "v")):  # marked at the edge
        edge = by_gid(ax, f"torque-limit-0-0-edge-{end}")
        assert edge.get_clip_on() is False and edge.get_marker() == shape
    assert not [p for p in ax.patches if p.get_width() >= 1 and p.get_height() > 0]  # no band
    assert "limits |T1|, |T2| ≤ 300 N m: beyond the axis" in lane_texts(fig)
    assert not [a for a in ax.get_children() if str(a.get_gid()).startswith("torques-unbounded")]


def test_inconsistent_crossing_diverges_with_opposite_signs(write_task) -> None:  # type: ignore[no-untyped-def]
    """Path 2 with link 5 heavier: eq. (34) fails at t_s, a pole of order 1: T changes
    sign through infinity, and the instant fails (red): unbounded torque (RPR201)."""
    task = write_task(
        task_text(PATH2_Y, QUINTIC, links=HEAVY5).replace("name: test", "name: heavy link 5")
    )
    m = P.motion(audit(load_task(task), samples=SAMPLES), str(task))
    (s,) = m.result.singularities
    assert not s.consistent and s.pole_order == 1
    fig = P.render([m], ["delta", "torques"])
    axes = panel_axes(fig)
    mark = by_gid(axes["delta"][0], "delta-singular-0-0")
    assert mark.get_markerfacecolor() == P.STATUS_COLOUR["fail"]
    ax = axes["torques"][0]
    shapes = {
        by_gid(ax, f"torques-exit-0-0-T2-{side}").get_marker() for side in ("before", "after")
    }
    assert shapes == {"^", "v"}


def test_close_instants_read_apart_on_the_sheet(write_task) -> None:  # type: ignore[no-untyped-def]
    """Crossings at t = 1 and t = 1.000001: 4 digits would write both as t = 1 s; the
    labels, the notes and the file's description take the digits that tell them apart."""
    task = write_task(task_text("(x-3)*(x-3.000001)", "timing:\n  duration: 2\n  x: 2 + t\n"))
    m = P.motion(audit(load_task(task), samples=11), str(task))
    assert [s.t for s in m.result.singularities] == [1.0, 1.000001]
    fig = P.render([m], ["path", "delta", "torques"])
    keys = lane_texts(fig)
    assert "1  t = 1 s, order 1" in keys and "2  t = 1.000001 s, order 1" in keys
    assert "T → ∞ at t = 1.000001 s" in keys
    assert P.summary(m).endswith("torques unbounded at t = 1.000001 s")
    assert (
        "(t = 1 s order 1 ok; t = 1.000001 s order 1 fail)" in P.metadata([m], "png")["Description"]
    )


@pytest.mark.parametrize(
    ("y", "timing", "expect"),
    [
        ("0\n  from: [2, 0]\n  to: [4, 0]", QUINTIC, "no bounded torque sample"),  # δ ≡ 0
        ("x - 10\n  from: [2, -8]\n  to: [4, -6]", QUINTIC, None),  # never singular
        (
            "x\n  from: [-1, -1]\n  to: [1, 1]",
            "timing:\n  duration: 2\n  law: quintic\n",
            "E at A or B (s = 0)",
        ),
        ("(x - 2.5)*(x - 3.5)\n  from: [2, 0.75]\n  to: [4, 0.75]", QUINTIC, "t = 3.203 s"),
    ],
    ids=["on-the-singular-line", "no-singularity", "through-A", "two-crossings"],
)
def test_unusual_motions_render_without_warnings(
    write_task, y: str, timing: str, expect: str | None
) -> None:  # type: ignore[no-untyped-def]
    task = write_task(task_text(y, timing))
    m = P.motion(audit(load_task(task), samples=SAMPLES), str(task))
    fig = P.render([m])
    drawn(fig)  # a draw, unpainted: warnings are errors here (pytest's filterwarnings)
    if expect is not None:
        assert expect in figure_texts(fig), expect


# ---------------------------------------------------------------------------------------
# the command line


def test_the_issues_overlay_command_writes_figs_3_and_4(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "fig.png"
    code, stdout, err = run(
        [
            "plot",
            PATH1,
            PATH2,
            "--panels",
            "path,delta",
            "-o",
            str(out),
            "--samples",
            "21",
            "--dpi",
            "50",
        ],
        capsys,
    )
    assert code == 0 and stdout == "" and f"wrote {out}" in err
    with Image.open(out) as im:
        assert im.format == "PNG"
        assert NAME1 in im.text["Title"] and NAME2 in im.text["Title"]
        assert "t = 2.5 s order 3 fail" in im.text["Description"]
        assert "t = 2.5 s order 1 ok" in im.text["Description"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fig.png"]


def test_panels_pick_and_order(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    fig = P.render(motions([PATH2]), ["torques", "path"])
    assert list(panel_axes(fig)) == ["torques", "path"]
    out = tmp_path / "two.svg"
    code, _, _ = run(
        ["plot", PATH2, "--panels", " torques , PATH", "-o", str(out), "--samples", "21"],
        capsys,
    )
    assert code == 0
    text = out.read_text(encoding="utf-8")
    assert text.index('id="T1-0"') < text.index('id="path-0"')
    assert 'id="delta-0"' not in text and 'id="theta1-0"' not in text


def test_default_output_is_the_first_tasks_stem_in_the_cwd(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    code, _, err = run(
        ["plot", PATH2, PATH1, "--panels", "delta", "--samples", "21", "--dpi", "50"], capsys
    )
    assert code == 0 and "wrote paper_path2.png" in err
    assert [p.name for p in tmp_path.iterdir()] == ["paper_path2.png"]


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["-o", "sheet.jpg"], "'.jpg'"),
        (["-o", "sheet"], "(none)"),
        (["--panels", "path,torque"], "unknown panel 'torque'"),
        (["--panels", "delta,delta"], "given twice"),
        (["--panels", ","], "no panel"),
        (["--animate", "robot.mp4"], "'.mp4'"),
        (["--samples", "5"], "--samples"),
    ],
)
def test_bad_invocation_exits_2_with_one_line(
    args: list[str],
    says: str,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    code, out, err = run(["plot", PATH2, *args], capsys)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and says in err, err
    assert list(tmp_path.iterdir()) == []


def test_bad_task_file_exits_2_with_one_line(
    write_task, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:  # type: ignore[no-untyped-def]
    bad = write_task(task_text("x - 3\n  from: [2, 5]\n  to: [4, 1]", QUINTIC))
    code, out, err = run(["plot", PATH2, str(bad), "-o", str(tmp_path / "s.png")], capsys)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and f"{bad}:" in err and "path.from" in err
    assert not (tmp_path / "s.png").exists()


def test_at_most_eight_tasks_overlay(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    for i in range(9):
        (tmp_path / f"t{i}.rprpr.yaml").write_text(Path(PATH2).read_text())
    code, _, err = run(["plot", str(tmp_path), "-o", str(tmp_path / "s.png")], capsys)
    assert code == 2 and "at most 8" in err


def test_show_without_a_display_writes_the_default_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(P, "can_show", lambda: False)
    code, _, err = run(
        ["plot", PATH2, "--show", "--panels", "delta", "--samples", "21", "--dpi", "50"], capsys
    )
    assert code == 0 and "no display for --show" in err
    assert (tmp_path / "paper_path2.png").exists()


def test_show_opens_a_pyplot_window_and_writes_o(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    import matplotlib.pyplot as plt

    shown: list[Figure] = []
    monkeypatch.setattr(P, "can_show", lambda: True)
    monkeypatch.setattr(plt, "show", lambda: shown.extend(plt.get_fignums()))
    try:
        out = tmp_path / "s.png"
        args = ["--show", "-o", str(out), "--panels", "x", "--samples", "21", "--dpi", "50"]
        code, _, _ = run(["plot", PATH2, *args], capsys)
        assert code == 0 and out.read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
        assert len(shown) == 1
        fig = plt.figure(shown[0])
        assert list(panel_axes(fig)) == ["x"]
    finally:
        plt.close("all")


fresh_probe(  # a start-up probe (``tests.cli.forked.fresh_probe``): a fresh process
    "test_sheet plot modules",
    "numpy, flint, yaml, click, rich.console",
    "import sys\n"
    "import rprpr.cli.main, rprpr.cli.plot, rprpr.cli.export\n"
    "print(any(m.split('.')[0] == 'matplotlib' for m in sys.modules))\n",
)


def test_plot_loads_matplotlib_only_when_plotting(fresh: dict[str, tuple[int, str, str]]) -> None:
    _, stdout, stderr = fresh["test_sheet plot modules"]
    assert stdout.strip() == "False", stderr


fresh_probe(
    "test_sheet plot without pyplot",
    "numpy, flint, yaml, click, rich.console",
    "import sys\n"
    "from rprpr.cli.main import main\n"
    "for n, extra in enumerate(([], ['--size', '3.5,2.4'])):\n"
    "    try:\n"
    f"        main(['plot', {PATH2!r}, '--panels', 'delta', '-o', f'sheet{{n}}.svg', *extra])\n"
    "    except SystemExit as e:\n"
    "        assert not e.code, e.code\n"
    "print(sorted(m for m in sys.modules if m.startswith('matplotlib.pyplot')))\n",
)


def test_plot_draws_every_sheet_without_pyplot(fresh: dict[str, tuple[int, str, str]]) -> None:
    """A sheet, and a paper figure of a given size, are drawn on figures of their own (no
    pyplot: no backend chosen, no window toolkit probed)."""
    code, stdout, stderr = fresh["test_sheet plot without pyplot"]
    assert (code, stdout.strip()) == (0, "[]"), stderr


def test_line_styles_tell_the_tasks_apart_and_colours_the_quantities() -> None:
    fig = sheet([PATH1, PATH2])
    axes = panel_axes(fig)
    th = axes["joints"][0]
    # overlaid, colour is the task (defect 5) and line style the leg
    assert by_gid(th, "theta1-0").get_color() == by_gid(th, "theta2-0").get_color()
    assert by_gid(th, "theta1-0").get_color() != by_gid(th, "theta1-1").get_color()
    assert by_gid(th, "theta1-0").get_linestyle() == "-"
    assert by_gid(th, "theta2-1").get_linestyle() == "--"
    tq = axes["torques"][0]
    assert by_gid(tq, "T1-0").get_color() == P.TASK_COLOURS[0]
    assert by_gid(tq, "T2-1").get_color() == P.TASK_COLOURS[1]
    assert isinstance(by_gid(tq, "T1-1"), Line2D)
    # one task alone: colour is the quantity, as on the robot's legs
    (one,) = panel_axes(sheet([PATH1]))["joints"][:1]
    assert by_gid(one, "theta1-0").get_color() == P.LEG1
    assert by_gid(one, "theta2-0").get_color() == P.LEG2


def test_the_python_api_as_readme_documents_it(tmp_path: Path) -> None:
    """``motion(audit(task))`` and ``motion(task)`` alike; ``render`` takes the panels as
    a list or as one comma-separated string (never letter by letter)."""
    task = load_task(PATH2)
    by_result, by_task = P.motion(audit(task, samples=101)), P.motion(task)
    assert by_result.name == by_task.name == task.name
    assert by_task.result.verdict == "pass"
    listed = P.render([by_result], ["path", "delta"])
    comma = P.render([by_result], "path, delta")
    assert len(comma.axes) == len(listed.axes) < len(P.render([by_result]).axes)
    with pytest.raises(ValueError, match="unknown panels \\['paths'\\]"):
        P.render([by_result], "paths,delta")
    out = tmp_path / "s.svg"
    P.save(comma, str(out), "svg")
    assert out.read_text(encoding="utf-8").startswith("<?xml")

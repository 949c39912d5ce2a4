"""``rprpr plot`` on a 5R task: what the sheet and the GIF draw, read back from the figure
and checked against references written here or in tests/fivebar, never the engine.

The shipped DexTAR-like robot (configs/five_bar_*.rprpr.yaml): A = (0, 0), B = (0.14, 0),
four links of 0.13 m, modes (+1, -1), no gravity; its end point crosses S₋ at the
rational singular pose E = (0.126, 0.098), C = (0, 0.13), D = (0.252, 0.066) at t = 0.1 s
(docs/five-bar.md §3, scaled by 0.13). The references: the elbows as circle-circle
intersections in mpmath, the working mode by the side of AE (BE) the elbow is on; the
Type II curves in sympy (tests/fivebar/locus.py); the torques by Newton-Euler in mpmath
(tests/fivebar/reference.py) on the task file's motion, expanded here in sympy.
"""

from __future__ import annotations

from fractions import Fraction as Q
from functools import cache
from pathlib import Path
from typing import Any

import mpmath
import numpy as np
import pytest
import sympy as sp
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from PIL import Image

from rprpr.render import animation as A
from tests.conftest import CONFIGS, run_cli
from tests.fivebar import locus
from tests.fivebar.reference import FiveBar, Motion, torques
from tests.render.test_sheet_marks import check_at_data
from tests.sheets import drawn, few_frames, motions, sheet, small_pictures

CROSSING = str(CONFIGS / "five_bar_consistent_crossing.rprpr.yaml")
STOP = str(CONFIGS / "five_bar_stop_on_curve.rprpr.yaml")
DEXTAR = Path(__file__).resolve().parents[1] / "io" / "data" / "five_bar_dextar.rprpr.yaml"
BASE, LINK = Q(14, 100), Q(13, 100)
MODES = (1, -1)
TS = Q(1, 10)
E_S, C_S, D_S = (0.126, 0.098), (0.0, 0.13), (0.252, 0.066)  # the rational singular pose
START, END = (0.076, 0.073), (0.176, 0.123)  # path.from, path.to of both tasks
ACC = Q(8802796400, 46526113179)  # x''(t_s) of the crossing: its timing's (t - 0.1)^2 is ACC/2


def elbows(E: tuple[float, float]) -> tuple[tuple[Any, Any], tuple[Any, Any]]:
    """C and D at E, in mpmath at 40 digits: the intersections of the circle of radius l1
    about A with that of radius l3 about E (l2 about B, l4 about E), C the one to the left
    of AE (e1 = +1), D the one to the right of BE (e2 = -1)."""

    def meet(P: Any, r: Any, E: Any, s: Any, side: int) -> tuple[Any, Any]:
        dx, dy = E[0] - P[0], E[1] - P[1]
        d = mpmath.sqrt(dx * dx + dy * dy)
        along = (r * r - s * s + d * d) / (2 * d)
        h = mpmath.sqrt(r * r - along * along)
        mx, my = P[0] + along * dx / d, P[1] + along * dy / d
        for sign in (1, -1):
            X = (mx - sign * h * dy / d, my + sign * h * dx / d)
            if (dx * (X[1] - P[1]) - dy * (X[0] - P[0])) * side > 0:  # (E - P) × (X - P)
                return X
        raise AssertionError("no elbow on that side")

    with mpmath.workdps(40):
        e = (mpmath.mpf(E[0]), mpmath.mpf(E[1]))
        l = mpmath.mpf(LINK.numerator) / LINK.denominator  # noqa: E741
        b = (mpmath.mpf(BASE.numerator) / BASE.denominator, mpmath.mpf(0))
        return meet((0, 0), l, e, l, MODES[0]), meet(b, l, e, l, MODES[1])


def artist(fig: Figure, gid: str) -> Any:
    (hit,) = [a for ax in fig.get_axes() for a in ax.get_children() if a.get_gid() == gid]
    return hit


def segment(fig: Figure, gid: str) -> np.ndarray:
    return np.asarray(artist(fig, gid).get_xydata(), dtype=float)


def test_the_robot_is_drawn_with_its_elbows_where_the_lengths_put_them() -> None:
    """At the start, the end and the singular instant: links A–C, B–D, C–E, D–E and the
    elbows at the independent C, D of the task's E; at t_s, §3's rational pose."""
    fig = sheet([CROSSING])
    C, D = elbows(E_S)
    assert [float(v) for v in (*C, *D)] == pytest.approx([*C_S, *D_S], abs=1e-15)
    for gid, E in (("start", START), ("end", END), ("singular-0", E_S)):
        C, D = elbows(E)
        c, d = (tuple(float(v) for v in p) for p in (C, D))
        want = {1: ((0, 0), c), 2: ((0.14, 0), d), 3: (c, E), 4: (d, E)}
        for n, (p, q) in want.items():
            got = segment(fig, f"robot-0-{gid}-link{n}")
            assert got == pytest.approx(np.array([p, q], dtype=float), abs=1e-12)
        for name, p in (("elbow-C", c), ("elbow-D", d), ("end-point", E)):
            got = segment(fig, f"robot-0-{gid}-{name}")
            assert got == pytest.approx(np.array([p], dtype=float), abs=1e-12)


@cache
def _curves() -> dict[int, tuple[Any, Any, Any]]:
    """S_σ and its gradient for the shipped robot, from tests/fivebar/locus.py (sympy)."""
    out = {}
    for sigma in (1, -1):
        S = locus.curve(sigma, BASE, LINK, LINK, LINK, LINK)
        f = sp.lambdify((locus.x, locus.y), S, "mpmath")
        gx = sp.lambdify((locus.x, locus.y), sp.diff(S, locus.x), "mpmath")
        gy = sp.lambdify((locus.x, locus.y), sp.diff(S, locus.y), "mpmath")
        out[sigma] = (f, gx, gy)
    return out


def test_the_type_ii_curves_drawn_lie_on_s_plus_and_s_minus_and_no_line_ab() -> None:
    """Every vertex drawn of S₊ (S₋) is within a grid cell of the zero set of the sympy
    S₊ (S₋): |S|/|∇S| (the distance to first order) under the cell's diagonal; S₋ passes
    within a cell of the singular point; the RPRPR's line y = 0 is not drawn."""
    fig = sheet([CROSSING])
    ax = artist(fig, "path-0").axes
    assert not [a for a in ax.get_children() if a.get_gid() == "singular-line"]
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    cell = float(np.hypot(x1 - x0, y1 - y0)) / 100  # the curves' grid is finer than this
    refs = _curves()
    for sigma, name in ((1, "plus"), (-1, "minus")):
        lc = artist(fig, f"path-curve-0-{name}")
        assert isinstance(lc, LineCollection)
        pts = np.concatenate([np.asarray(p.vertices) for p in lc.get_paths()])
        assert len(pts) > 50
        f, gx, gy = refs[sigma]
        with mpmath.workdps(30):
            for px, py in pts[:: max(1, len(pts) // 300)]:
                X, Y = mpmath.mpf(float(px)), mpmath.mpf(float(py))
                dist = abs(f(X, Y)) / mpmath.sqrt(gx(X, Y) ** 2 + gy(X, Y) ** 2)
                assert dist < cell, (name, px, py, dist)
        if sigma == -1:
            assert np.min(np.hypot(pts[:, 0] - E_S[0], pts[:, 1] - E_S[1])) < cell


@pytest.mark.parametrize("path", [CROSSING, STOP], ids=["crossing", "stop"])
def test_each_mark_sits_at_the_instants_t_x_and_y(path: str) -> None:
    """The marks on the workspace, x_E, y_E and δ at the audit's numbers, which are the
    task file's singular pose at t = 0.1 s."""
    ms = motions([path])
    fig = sheet([path])
    drawn(fig)
    (s,) = ms[0].result.singularities
    assert (s.t, s.x, s.y) == (0.1, *E_S)
    assert check_at_data(fig, ms, ("path", "x", "y", "delta")) == 4


@cache
def reference_motion() -> Motion:
    """The crossing's motion as polynomials in t (Fractions), from its task file's numbers:
    x = 0.126 + (t - 0.1)/2 + ACC/2 (t - 0.1)^2 - 50 ACC (t - 0.1)^4, y = x/2 + 0.035."""
    t = sp.Symbol("t")
    tau = t - sp.Rational(1, 10)
    acc = sp.Rational(ACC.numerator, ACC.denominator)
    x = sp.Rational(126, 1000) + tau / 2 + acc / 2 * tau**2 - 50 * acc * tau**4
    y = x / 2 + sp.Rational(35, 1000)
    cs = [sp.Poly(p, t).all_coeffs()[::-1] for p in (x, y)]
    return Motion(*(tuple(Q(int(c.p), int(c.q)) for c in c_) for c_ in cs))


ROBOT = FiveBar(
    BASE, (LINK,) * 4, (Q(2, 10), Q(2, 10), Q(1, 10), Q(1, 10)),
    (Q(3, 10000), Q(3, 10000), Q(15, 100000), Q(15, 100000)), (Q(65, 1000),) * 4, Q(0),
)  # fmt: skip  # the task file's robot


def test_the_torques_drawn_are_newton_eulers_and_the_audits_limit_at_t_s() -> None:
    """T1, T2 drawn against the Newton-Euler reference away from t_s (to 1e-9 mixed); at
    t_s the drawn value and its ring are the audit's limit, which the reference reaches
    at t_s ± 1e-7."""
    (m,) = motions([CROSSING])
    fig = sheet([CROSSING])
    t = np.asarray(artist(fig, "T1-0").get_xdata(), dtype=float)
    drawn_T = [np.asarray(artist(fig, f"T{j}-0").get_ydata(), dtype=float) for j in (1, 2)]
    motion = reference_motion()
    for k in range(0, len(t), 10):
        if abs(t[k] - 0.1) < 1e-6:
            continue
        want = torques(ROBOT, motion, Q(float(t[k])), MODES)
        for j in (0, 1):
            got, ref = drawn_T[j][k], float(want[j])
            assert abs(got - ref) <= 1e-9 * (1 + abs(ref)), (t[k], j, got, ref)
    (k,) = np.flatnonzero(t == 0.1)
    (s,) = m.result.singularities
    assert s.torque_at_singularity is not None
    near = [torques(ROBOT, motion, TS + side * Q(1, 10**7), MODES) for side in (-1, 1)]
    for j in (0, 1):
        assert drawn_T[j][k] == s.torque_at_singularity[j]
        for ref in near:
            assert abs(float(ref[j]) - drawn_T[j][k]) < 1e-5
    ring = artist(fig, "torques-limit-0-0-T1")
    assert ring.get_xydata().tolist() == [[0.1, s.torque_at_singularity[0]]]


def test_the_stop_s_unbounded_torques_leave_a_gap_and_a_line_at_t_s() -> None:
    """At the stop's unbounded instant the curve has a gap (NaN at t_s), the dashed line
    marks t_s, and the curve grows without bound towards it."""
    fig = sheet([STOP])
    t = np.asarray(artist(fig, "T1-0").get_xdata(), dtype=float)
    T1 = np.asarray(artist(fig, "T1-0").get_ydata(), dtype=float)
    (k,) = np.flatnonzero(t == 0.1)
    assert np.isnan(T1[k])
    assert artist(fig, "torques-unbounded-0-0").get_xdata()[0] == 0.1
    close = np.abs(t - 0.1)
    finite = np.isfinite(T1) & (close > 0)
    assert np.max(np.abs(T1[finite & (close < 1e-6)])) > 100 * np.max(
        np.abs(T1[finite & (close > 0.05)])
    )


def test_delta_and_the_joint_angles_are_the_links_independent_angles() -> None:
    """δ = (E − C) × (E − D)/(l3 l4), θ1, θ2 the directions of A→C, B→D and φ1, φ2 of
    C→E, D→E (degrees, continuous), from the independent elbows at E's drawn samples."""
    fig = sheet([CROSSING])
    t = np.asarray(artist(fig, "delta-0").get_xdata(), dtype=float)
    xs = np.asarray(artist(fig, "x-0").get_ydata(), dtype=float)
    ys = np.asarray(artist(fig, "y-0").get_ydata(), dtype=float)
    curves = {
        n: np.asarray(artist(fig, f"{n}-0").get_ydata(), dtype=float)
        for n in ("delta", "theta1", "theta2", "phi1", "phi2")
    }
    l = float(LINK)  # noqa: E741
    for k in range(0, len(t), 7):
        E = (float(xs[k]), float(ys[k]))
        C, D = ((float(p[0]), float(p[1])) for p in elbows(E))
        u, v = (E[0] - C[0], E[1] - C[1]), (E[0] - D[0], E[1] - D[1])
        assert curves["delta"][k] == pytest.approx((u[0] * v[1] - u[1] * v[0]) / l**2, abs=1e-9)
        for name, vec in (
            ("theta1", C),
            ("theta2", (D[0] - 0.14, D[1])),
            ("phi1", u),
            ("phi2", v),
        ):
            ang = np.degrees(np.arctan2(vec[1], vec[0]))
            assert (curves[name][k] - ang) % 360 == pytest.approx(0, abs=1e-7) or (
                curves[name][k] - ang
            ) % 360 == pytest.approx(360, abs=1e-7)
    for name in ("theta1", "theta2", "phi1", "phi2"):
        assert np.max(np.abs(np.diff(curves[name]))) < 10  # continuous [deg]


def test_the_gif_moves_the_links_through_the_singular_pose() -> None:
    """The GIF's frame at t_s: the links at the independent pose, the marks at the
    instant's (x, y) and the Type II curves over the links."""
    (m,) = motions([STOP])
    an = A.Animation([m], frames=9, dpi=20)  # its artists' data are read, not its pixels
    col = an.columns[0]
    (k,) = [j for j, s in enumerate(col.at) if s is not None]
    an.draw(k)
    robot = col.robot.robot  # the 5R's moving links (``five_bar_robot.MovingFiveBar``)
    C, D = (tuple(float(v) for v in p) for p in elbows(E_S))
    got = {n: np.asarray(line.get_xydata(), dtype=float) for n, line in robot.links.items()}
    want = {1: [(0, 0), C], 2: [(0.14, 0), D], 3: [C, E_S], 4: [D, E_S]}
    for n in want:
        assert got[n] == pytest.approx(np.array(want[n], dtype=float), abs=1e-12)
    assert {a.get_gid() for a in col.over} >= {"gif-curve-0-plus", "gif-curve-0-minus"}
    assert check_at_data(an.fig, [m], ("gif-path", "gif-delta")) == 2


@pytest.mark.parametrize("suffix", [".png", ".svg", ".pdf"])
def test_plot_writes_a_5r_sheet_in_every_format_and_its_gif(
    suffix: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    small_pictures(monkeypatch)
    few_frames(monkeypatch)
    out, gif = tmp_path / f"s{suffix}", tmp_path / "r.gif"
    extra = ["--animate", str(gif)] if suffix == ".png" else []
    code, stdout, err = run_cli("plot", STOP, CROSSING, "-o", str(out), "--pole-inset", *extra)
    assert (code, stdout) == (0, "")
    assert out.stat().st_size > 1000
    if extra:
        with Image.open(gif) as im:
            assert im.n_frames > 10
        assert err.splitlines() == [f"rprpr: wrote {out}", f"rprpr: wrote {gif}"]


def test_an_rprpr_and_a_5r_on_one_set_of_axes_are_refused_in_one_line(tmp_path: Path) -> None:
    rprpr = str(CONFIGS / "case1_crossing.rprpr.yaml")
    code, out, err = run_cli("plot", CROSSING, rprpr, "-o", str(tmp_path / "x.png"))
    assert code == 2 and out == ""
    line = next(i for i, ln in enumerate(Path(rprpr).read_text().splitlines(), 1) if ln == "robot:")
    assert err == (
        f"rprpr: {rprpr}:{line}: robot.mechanism: an RPRPR task cannot be overlaid with a 5R"
        " task on one sheet's axes (plot them apart, or with more than 3 tasks, one column"
        " each)\n"
    )
    assert list(tmp_path.iterdir()) == []


def test_a_5r_plot_checks_the_torque_limit_on_one_piece_or_several(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A torque limit is checked on a motion of one piece and of several: the sheet is drawn
    (at SMALL_DPI: that it is written is read here, not its pixels)."""
    small_pictures(monkeypatch)
    code, _, err = run_cli("plot", str(DEXTAR), "-o", str(tmp_path / "one.png"))
    assert code == 0 and (tmp_path / "one.png").exists(), err
    text = DEXTAR.read_text()
    start, end = text.index("path:"), text.index("checks:")
    pieces = (
        "motion:\n  pieces:\n"
        "    - until: 0.25\n      x: -0.05 + 0.6*t\n      y: 0.3\n"
        "    - until: 0.5\n      x: -0.05 + 0.6*t\n      y: 0.3\n"
    )
    task = tmp_path / "pieces.rprpr.yaml"
    task.write_text(text[:start] + pieces + text[end:])
    code, _, err = run_cli("plot", str(task), "-o", str(tmp_path / "x.png"))
    assert code == 0 and (tmp_path / "x.png").exists(), err


def test_the_html_report_draws_a_5r_s_sheet(tmp_path: Path) -> None:
    """``check --format html``: the task's sheet, with its Type II curves and its links."""
    out = tmp_path / "r.html"
    # no budget: its wall time never leaves the sheet out on a busy machine
    code, _, _ = run_cli("check", "--format", "html", "--budget", "0", "-o", str(out), CROSSING)
    assert code == 0
    html = out.read_text(encoding="utf-8")
    assert html.count("<svg") == 1
    for gid in ("path-curve-0-minus", "robot-0-singular-0-elbow-C", "path-singular-0-0"):
        assert f'id="s1-{gid}"' in html, gid  # the page prefixes each sheet's ids


def test_a_5r_motion_of_two_pieces_is_drawn_piece_by_piece(tmp_path: Path) -> None:
    """tests/fivebar/test_pieces.py's bend (E along +x at 1 m/s, then from t = 1/2 also
    y = 9 + (t - 1/2)²): the drawn path follows each piece's own polynomials (written
    here in Fractions), the torques drawn on each side of the knot are Newton-Euler's on
    that piece, and the RPR204 jump bar spans Newton-Euler's T(1/2-) to T(1/2+)."""
    from tests.fivebar import test_pieces as P
    from tests.fivebar.reference import torques as ne_torques

    p1 = Motion((Q(58, 5), Q(1)), (Q(9),))
    p2 = Motion((Q(58, 5), Q(1)), (Q(9) + Q(1, 4), Q(-1), Q(1)))
    path = str(P.pieces_file(tmp_path, "bend", [(Q(1, 2), p1), (Q(1), p2)]))
    fig = sheet([path])
    xy = segment(fig, "path-0")

    def at(m: Motion, t: float) -> tuple[float, float]:
        return tuple(float(sum(c * Q(t) ** k for k, c in enumerate(p))) for p in (m.x, m.y))

    t = np.asarray(artist(fig, "T1-0").get_xdata(), dtype=float)
    assert len(t) == len(xy) and t[0] == 0 and t[-1] == 1
    drawn_T = [np.asarray(artist(fig, f"T{j}-0").get_ydata(), dtype=float) for j in (1, 2)]
    for k in range(0, len(t), 7):
        m = p1 if t[k] < 0.5 else p2
        want = at(m, float(t[k]))
        assert np.allclose(xy[k], want, rtol=0, atol=1e-12), (t[k], xy[k], want)
        ref = ne_torques(P.ROBOT, m, Q(float(t[k])), P.MODES)
        for j in (0, 1):
            assert abs(drawn_T[j][k] - float(ref[j])) <= 1e-9 * (1 + abs(float(ref[j])))
    before, after = (ne_torques(P.ROBOT, m, Q(1, 2), P.MODES) for m in (p1, p2))
    for j, q in enumerate(("T1", "T2")):
        bar = artist(fig, f"torques-jump-0-0-{q}").get_xydata().tolist()
        assert [p[0] for p in bar] == [0.5, 0.5]
        for got, ref in zip([p[1] for p in bar], (before[j], after[j]), strict=True):
            assert abs(got - float(ref)) <= 1e-9 * (1 + abs(float(ref)))

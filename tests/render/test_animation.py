"""rprpr plot --animate: the GIF decodes, has the expected frames, bounded size, and shows
the singular instant and its neighbourhood."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image, ImageSequence

from rprpr.cli.main import main
from rprpr.render import animation as A
from rprpr.render import sheet as P
from tests.sheets import PATH1, PATH2, ZERO, gif, motions, sheet

MAX_BYTES = 3 * 1024 * 1024


def frames_of(path: Path) -> list[tuple[np.ndarray, int]]:
    """Every frame as an RGB array, with its duration [ms]."""
    with Image.open(path) as im:
        assert im.format == "GIF"
        return [
            (np.asarray(f.convert("RGB")), int(f.info["duration"]))
            for f in ImageSequence.Iterator(im)
        ]


def share(rgb: np.ndarray, colour: str, tol: float = 40) -> float:
    """Fraction of the frame's pixels of ``colour`` (#RRGGBB)."""
    c = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)], dtype=float)
    return float(np.mean(np.all(np.abs(rgb.astype(float) - c) <= tol, axis=2)))


def test_one_clock_spans_the_longest_motion_and_hits_each_singular_instant() -> None:
    """Defect 10: path 2 (t_f = 5 s, t_s = 2.5 s) beside the zero-speed crossing (t_f =
    2 s, t_s = 1 s) run on one clock; the shorter holds its last pose once ended."""
    p2, zero = motions([PATH2, ZERO])
    t = A.clock([p2, zero], 100)
    assert len(t) == 100 and t[0] == 0.0 and t[-1] == 5.0 and np.all(np.diff(t) > 0)
    assert {1.0, 2.5} <= set(t.tolist())
    own, at = A.frame_times(p2, t)
    assert np.array_equal(own, t)
    k = int(np.nonzero(t == 2.5)[0][0])
    assert at[k] is p2.result.singularities[0] and sum(s is not None for s in at) == 1
    own, at = A.frame_times(zero, t)
    assert np.array_equal(own, np.minimum(t, 2.0)) and own[-1] == 2.0
    assert at[int(np.nonzero(t == 1.0)[0][0])] is zero.result.singularities[0]


@pytest.fixture(scope="module")
def p2_gif(tmp_path_factory: pytest.TempPathFactory) -> tuple[int, Path]:
    """Path 2's GIF in 21 frames at 40 dpi, written once: the frame count returned, and
    the file."""
    out = tmp_path_factory.mktemp("gif") / "p2.gif"
    return A.write_gif(motions([PATH2]), str(out), frames=21, dpi=40), out


def test_gif_decodes_with_the_expected_frames_size_and_hold(p2_gif: tuple[int, Path]) -> None:
    n, out = p2_gif
    assert n == 21
    frames = frames_of(out)
    assert len(frames) == 21
    w, h = A.COLUMN_SIZE
    assert frames[0][0].shape == (round(h * 40), round(w * 40), 3)
    durations = [d for _, d in frames]
    # t = 2.5 s is frame 10 of 21 (0.25 s apart): held, the others at FPS
    assert durations[10] == int(1000 * A.HOLD)
    assert set(durations[:10] + durations[11:]) == {int(1000 / A.FPS)}
    assert out.stat().st_size < MAX_BYTES


def test_gif_cues_at_and_near_the_singular_configuration(p2_gif: tuple[int, Path]) -> None:
    frames = [f for f, _ in frames_of(p2_gif[1])]
    t = np.linspace(0, 5, 21)
    delta = motions([PATH2])[0].result.resample(t).delta
    at, near, far = 10, int(np.argmin(np.where(np.abs(delta) > 0, np.abs(delta), 9))), 0
    assert 0 < abs(delta[near]) < P.NEAR_DELTA
    # the workspace is framed in red at t_s, in amber while |δ| < 0.1, not otherwise
    assert share(frames[at], A.AT_EDGE) > share(frames[far], A.AT_EDGE) + 0.01
    assert share(frames[near], A.NEAR_EDGE) > share(frames[far], A.NEAR_EDGE) + 0.01
    # ... and never washed over: the workspace stays white around A and B (defect 10)
    for f in (frames[at], frames[near]):
        assert share(f, "#FFFFFF", tol=2) > share(frames[far], "#FFFFFF", tol=2) - 0.05
    assert not np.array_equal(frames[1], frames[2])  # the robot moves
    # a torque trace under the robot and the δ strip: T1's blue low in the frame
    h = frames[far].shape[0]
    strip = frames[far][int(0.75 * h) : int(0.93 * h)].astype(int)
    r, g, b = strip[..., 0], strip[..., 1], strip[..., 2]
    assert np.mean((b > r + 80) & (b > g + 25)) > 0.005  # thin, antialiased: bluish


def test_the_gif_draws_the_robot_as_the_sheet_does() -> None:
    """One drawing of the robot: at path 1's singular instant the GIF's legs are the
    sheet's (both on the singular line, meeting at E = (3, 0))."""
    from matplotlib.figure import Figure

    from rprpr.render.sheet.robot import MovingRobot

    (m,) = motions([PATH1])
    path = sheet([PATH1]).axes[0]
    robot = MovingRobot(Figure().subplots(), m)
    (s,) = m.result.singularities
    j = int(np.nonzero(m.s.t == s.t)[0][0])
    robot.move(np.array([m.s.x[j], m.s.y[j]]))
    for n, (cylinder, rod) in robot.legs.items():
        for moving, part in ((cylinder, "cylinder"), (rod, "leg")):
            [drawn] = [a for a in path.lines if a.get_gid() == f"robot-0-singular-0-{part}{n}"]
            assert np.array_equal(moving.get_xydata(), drawn.get_xydata())
            assert moving.get_linewidth() == drawn.get_linewidth()
            assert moving.get_color() == drawn.get_color()
        assert tuple(rod.get_xydata()[1]) == pytest.approx((3.0, 0.0), abs=1e-12)
    assert tuple(robot.end.get_xydata()[0]) == pytest.approx((3.0, 0.0), abs=1e-12)


def test_tasks_play_side_by_side() -> None:
    out = gif((PATH1, PATH2), 2, 30).path  # written once (the marks' test reads its figure)
    (first, _), *_ = frames_of(out)
    w, h = A.COLUMN_SIZE
    assert first.shape == (round(h * 30), round(2 * w * 30), 3)


LIMIT = 3  # frames: the upper clamp at a stand-in for MAX_FRAMES, written in a moment


@pytest.mark.parametrize(("asked", "written"), [(1, 2), (10**6, LIMIT)])
def test_frame_count_is_clamped(
    asked: int, written: int, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Asked for too few frames, 2; for too many, MAX_FRAMES: ``write_gif`` reads the
    limit when called, so the clamp is shown at a limit of LIMIT frames (a real GIF of
    MAX_FRAMES frames would test the same line and cost a hundred frames more)."""
    assert 2 < LIMIT < A.MAX_FRAMES <= 120  # the shipped limit keeps a GIF small
    monkeypatch.setattr(A, "MAX_FRAMES", LIMIT)
    out = tmp_path / "c.gif"
    assert A.write_gif(motions([PATH2]), str(out), frames=asked, dpi=20) == written
    with Image.open(out) as im:
        assert im.n_frames == written <= 120


@pytest.mark.slow  # the real thing: A.FRAMES frames at A.DPI, as `rprpr plot --animate` writes
def test_the_command_line_writes_a_bounded_gif(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    gif = tmp_path / "robot.gif"
    with pytest.raises(SystemExit) as e:
        main(
            [
                "plot",
                PATH1,
                "--panels",
                "delta",
                "--samples",
                "21",
                "--dpi",
                "50",
                "-o",
                str(tmp_path / "sheet.png"),
                "--animate",
                str(gif),
            ]
        )
    assert e.value.code == 0
    assert f"wrote {gif}" in capsys.readouterr().err
    with Image.open(gif) as im:
        assert im.n_frames == A.FRAMES <= 120
        assert im.size == (round(A.COLUMN_SIZE[0] * A.DPI), round(A.COLUMN_SIZE[1] * A.DPI))
        assert im.info["loop"] == 0
        for frame in ImageSequence.Iterator(im):
            frame.load()  # every frame decodes
    assert gif.stat().st_size < MAX_BYTES
    assert sorted(p.name for p in tmp_path.iterdir()) == ["robot.gif", "sheet.png"]


def test_the_gif_names_each_tasks_efforts_in_its_units() -> None:
    """The strip under each robot plots that task's efforts: T [N m] for motors at A and
    B, F [N] for linear actuators (a column of each in one GIF)."""
    from matplotlib.figure import Figure

    from tests.conftest import CONFIGS

    prismatic = str(CONFIGS / "prismatic_crossing.rprpr.yaml")
    ms = motions([PATH2, prismatic])
    fig = Figure()
    subs = fig.subfigures(1, 2).ravel()
    t = A.clock(ms, 4)
    tf = max(m.duration for m in ms)
    for sf, m in zip(subs, ms, strict=True):
        A._Column(sf, m, t, tf)
    assert [sf.axes[2].get_ylabel() for sf in subs] == ["T [N m]", "F [N]"]

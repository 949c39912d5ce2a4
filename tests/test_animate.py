"""rprpr plot --animate: the GIF decodes, has the expected frames, bounded size, and shows
the singular instant and its neighbourhood."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pytest
from PIL import Image, ImageSequence

from rprpr.cli.main import main
from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.render import animation as A
from rprpr.render import sheet as P

from .conftest import CONFIGS

PATH1 = str(CONFIGS / "paper_path1.rprpr.yaml")
PATH2 = str(CONFIGS / "paper_path2.rprpr.yaml")
MAX_BYTES = 3 * 1024 * 1024

_cache: dict[str, P.Motion] = {}


def motions(paths: Sequence[str]) -> list[P.Motion]:
    for p in paths:
        if p not in _cache:
            _cache[p] = P.motion(audit(load_task(p), samples=101), p)
    return [_cache[p] for p in paths]


def frames_of(path: Path) -> list[tuple[np.ndarray, int]]:
    """Every frame as an RGB array, with its duration [ms]."""
    with Image.open(path) as im:
        assert im.format == "GIF"
        return [
            (np.asarray(f.convert("RGB")), int(f.info["duration"]))
            for f in ImageSequence.Iterator(im)
        ]


def tinted(rgb: np.ndarray, face: str) -> float:
    """Fraction of the frame washed with ``face`` at the cue's alpha over white."""
    c = np.array([int(face[i : i + 2], 16) for i in (1, 3, 5)], dtype=float)
    washed = 255 + 0.55 * (c - 255)
    return float(np.mean(np.all(np.abs(rgb.astype(float) - washed) <= 3, axis=2)))


def test_frame_times_span_the_motion_and_hit_each_singular_instant() -> None:
    (m,) = motions([PATH2])
    t, at = A.frame_times(m, 100)
    assert len(t) == len(at) == 100
    assert t[0] == 0.0 and t[-1] == 5.0 and np.all(np.diff(t) > 0)
    k = int(np.nonzero(t == 2.5)[0][0])
    assert at[k] is m.result.singularities[0]
    assert sum(s is not None for s in at) == 1


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
    assert tinted(frames[at], A.AT_FACE) > 0.2  # the workspace turns red at t_s
    assert tinted(frames[near], A.NEAR_FACE) > 0.2  # amber while |δ| < 0.1
    assert tinted(frames[far], A.AT_FACE) < 0.01 and tinted(frames[far], A.NEAR_FACE) < 0.01
    assert not np.array_equal(frames[1], frames[2])  # the robot moves


def test_the_gif_draws_the_robot_as_the_sheet_does() -> None:
    """One drawing of the robot: at path 1's singular instant the GIF's legs are the
    sheet's (both on the singular line, meeting at E = (3, 0))."""
    from matplotlib.figure import Figure

    from rprpr.render.sheet.robot import MovingRobot

    (m,) = motions([PATH1])
    sheet = P.render([m], ["path"]).axes[0]
    robot = MovingRobot(Figure().subplots(), m)
    (s,) = m.result.singularities
    j = int(np.nonzero(m.s.t == s.t)[0][0])
    robot.move(np.array([m.s.x[j], m.s.y[j]]))
    for n, (cylinder, rod) in robot.legs.items():
        for moving, part in ((cylinder, "cylinder"), (rod, "leg")):
            [drawn] = [a for a in sheet.lines if a.get_gid() == f"robot-0-singular-0-{part}{n}"]
            assert np.array_equal(moving.get_xydata(), drawn.get_xydata())
            assert moving.get_linewidth() == drawn.get_linewidth()
            assert moving.get_color() == drawn.get_color()
        assert tuple(rod.get_xydata()[1]) == pytest.approx((3.0, 0.0), abs=1e-12)
    assert tuple(robot.end.get_xydata()[0]) == pytest.approx((3.0, 0.0), abs=1e-12)


def test_tasks_play_side_by_side(tmp_path: Path) -> None:
    out = tmp_path / "both.gif"
    A.write_gif(motions([PATH1, PATH2]), str(out), frames=6, dpi=30)
    (first, _), *_ = frames_of(out)
    w, h = A.COLUMN_SIZE
    assert first.shape == (round(h * 30), round(2 * w * 30), 3)


@pytest.mark.parametrize(("asked", "written"), [(1, 2), (10**6, A.MAX_FRAMES)])
def test_frame_count_is_clamped(asked: int, written: int, tmp_path: Path) -> None:
    out = tmp_path / "c.gif"
    assert A.write_gif(motions([PATH2]), str(out), frames=asked, dpi=20) == written
    with Image.open(out) as im:
        assert im.n_frames == written <= 120


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
                "101",
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

"""``rprpr plot --animate``: the robot moving along its planned motion, as an animated GIF.

Each task gets a column: the workspace on top (base joints A and B, the singular line,
the planned path, the legs drawn from A and B to E, the trace of E so far, the current t
and δ), then δ(t) and the torques T1(t), T2(t) (scaled to their bounded part) with a
moving cursor. While the robot is near a Type II singular configuration
(|δ| < ``sheet.NEAR_DELTA``) the workspace is framed in amber and says so; at a singular
instant itself (always one of the frames) the frame turns red, names the order and the
verdict, and the frame is held for ``HOLD`` seconds. The cue frames the workspace and
never covers it: A, B and the robot stay legible.

Frames are drawn with ``matplotlib.animation.FuncAnimation`` and written by a Pillow
movie writer (``GifWriter``) that gives each frame its own duration. The size is bounded:
``FRAMES`` frames (at most ``MAX_FRAMES``) at ``FPS``, a few seconds, each
``COLUMN_SIZE`` inches at ``DPI``. Several tasks play side by side on one clock
(``clock``): frame k shows t = k T/(frames - 1) in every column, T the longest t_f, each
task's singular instants replacing the nearest frames; a task that has ended holds its
last pose.

The workspace and the robot are drawn by the sheet's ``robot`` module, the singular
instants' marks by its ``markers``: the GIF and the sheet look alike.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import matplotlib
import numpy as np
from matplotlib.animation import AbstractMovieWriter
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle
from PIL import Image

from ..engine.certified.sampling import Samples
from ..engine.exact.singular import SingularInstant
from ..model.actuation import SCHEMES
from ..model.numbers import number
from . import sheet as P
from .sheet import robot
from .sheet.axes import knot_lines
from .sheet.drawing import drawing

FRAMES = 100  # default frame count: 5 s at FPS
MAX_FRAMES = 120
FPS = 20
HOLD = 0.6  # s, a singular instant's frame stays this long
DPI = 90
COLUMN_SIZE = (5.0, 5.6)  # in, per task
MAX_COLUMNS = 3

RC = {**P.RC, "font.size": 8}  # matplotlib's rcParams for the GIF: the sheet's, smaller text

NEAR_EDGE = "#E69F00"  # the workspace's frame near a singular configuration
AT_EDGE = "#D62728"  # ... at a singular instant


class GifWriter(AbstractMovieWriter):
    """matplotlib movie writer for a GIF through Pillow, with a duration per frame
    (``durations``, ms) and endless looping.

    ``grab_frame`` takes the canvas as last drawn (the caller blits each frame onto an Agg
    canvas, ``write_gif``): no full redraw per frame."""

    def __init__(self, durations: Sequence[int], fps: int = FPS) -> None:
        super().__init__(fps=fps)
        self.durations = [int(d) for d in durations]
        self._frames: list[Image.Image] = []

    def setup(self, fig: Figure, outfile: Any, dpi: float | None = None) -> None:
        super().setup(fig, outfile, dpi=dpi)
        self._frames = []

    def grab_frame(self, **savefig_kwargs: Any) -> None:
        canvas = self.fig.canvas
        assert isinstance(canvas, FigureCanvasAgg), "draw the frame on an Agg canvas first"
        w, h = canvas.get_width_height(physical=True)
        rgba = canvas.buffer_rgba()  # type: ignore[no-untyped-call]
        im = Image.frombuffer("RGBA", (w, h), rgba, "raw", "RGBA", 0, 1)
        # a fast octree palette per frame: a median cut costs most of the GIF's time
        self._frames.append(im.convert("RGB").quantize(255, Image.Quantize.FASTOCTREE))

    def finish(self) -> None:
        if not self._frames:
            return
        durations = self.durations[: len(self._frames)]
        durations += [int(1000 / self.fps)] * (len(self._frames) - len(durations))
        self._frames[0].save(
            self.outfile,
            format="GIF",
            save_all=True,
            append_images=self._frames[1:],
            duration=durations,
            loop=0,
        )


def clock(motions: Sequence[P.Motion], frames: int) -> np.ndarray:
    """The times of the frames, one clock for every column: ``frames`` times evenly over
    [0, the longest t_f], each task's singular instants replacing the nearest frame time
    (the next free one where two instants fall to one frame)."""
    tf = max(m.duration for m in motions)
    t = np.linspace(0.0, tf, frames)
    taken = np.zeros(frames, dtype=bool)
    for ts in sorted({s.t for m in motions for s in m.result.singularities}):
        k = int(np.argmin(np.abs(t - ts)))
        if taken[k]:
            free = [j for j in (k - 1, k + 1) if 0 <= j < frames and not taken[j]]
            if not free:
                continue
            k = free[0]
        t[k], taken[k] = ts, True
    return np.sort(t)


def frame_times(m: P.Motion, t: np.ndarray) -> tuple[np.ndarray, list[SingularInstant | None]]:
    """Task ``m``'s time at each frame of the clock ``t`` (held at t_f once it has
    ended) and, per frame, its singular instant shown (or None)."""
    own = np.minimum(t, m.duration)
    at = [next((s for s in m.result.singularities if s.t == v), None) for v in t]
    return own, at


def _time_format(tf: float, frames: int) -> str:
    """Enough decimals that consecutive frame times differ."""
    step = tf / max(frames - 1, 1)
    return f".{max(0, 1 - math.floor(math.log10(step)))}f" if step > 0 else ".3g"


class _Column:
    """One task's workspace and δ strip, and the artists each frame moves."""

    def __init__(self, sf: Any, m: P.Motion, t: np.ndarray, tf: float, i: int = 0) -> None:
        self.i = i
        self.m = m
        self.clock_t = t
        self.t, self.at = frame_times(m, t)
        self.f: Samples = m.result.resample(self.t)
        self.fmt = _time_format(tf, len(t))
        ax, strip, torques = sf.subplots(3, 1, height_ratios=[3.2, 1, 1])
        self.ax: Axes = ax
        self.strip: Axes = strip
        sf.suptitle(P.short(m.name, 48), fontsize=9, fontweight="bold")
        self._workspace(ax)
        self._strip(strip, tf)
        self._torques(torques, tf)
        strip.sharex(torques)
        strip.tick_params(labelbottom=False)
        strip.set_xlabel("")
        self.moving += [self.tcursor]

    def _workspace(self, ax: Axes) -> None:
        m = self.m
        _, size = robot.workspace(ax, [m])
        ax.set_xlabel("x [m]", labelpad=1)
        ax.set_ylabel("y [m]", labelpad=1)
        ax.tick_params(labelsize=7)
        # the singular locus (the line AB, a 5R's curves) and the marks move with the
        # robot: redrawn over its legs every frame
        d = drawing(m)
        x0, x1, y0, y1 = robot.view([m])
        w, h = x1 - x0, y1 - y0  # the view grows to the axes' shape: the locus beyond it
        box = (x0 - w, x1 + w, y0 - h, y1 + h)
        self.over: list[Any] = d.locus(ax, m, box, d.locus_gid("gif", self.i))
        robot.base_joints(ax, [m], size)
        ax.plot(m.s.x, m.s.y, color="#AAAAAA", lw=1.0, ls="--", zorder=2)
        for k, s in enumerate(m.result.singularities):
            style = {**P.marker_style(s, m.result.status_of(s)), "alpha": 0.9}
            px, py = d.point(s)
            self.over += ax.plot([px], [py], gid=f"gif-path-singular-{self.i}-{k}", **style)
        self.trace = ax.plot([], [], color=P.POINT, lw=1.8, zorder=4)[0]
        self.robot = d.moving(ax, m)
        self.clock = ax.text(
            0.02,
            0.97,
            "",
            transform=ax.transAxes,
            va="top",
            fontsize=8,
            family="monospace",
            zorder=9,
            bbox={"fc": "white", "ec": "none", "alpha": 0.8, "pad": 1.5},
        )
        self.cue = ax.text(
            0.98,
            0.03,
            "",
            transform=ax.transAxes,
            ha="right",
            va="bottom",
            fontsize=8,
            fontweight="bold",
            zorder=9,
            bbox={"fc": "white", "ec": "none", "alpha": 0.85, "pad": 1.5},
        )
        # the cue: a frame around the workspace, never over it
        self.tint = Rectangle(
            (0, 0), 1, 1, transform=ax.transAxes, fill=False, lw=6, alpha=0.0, clip_on=False
        )
        ax.add_patch(self.tint)

    def _torques(self, ax: Axes, tf: float) -> None:
        """T1, T2 (or F1, F2) over the task's motion, scaled to their bounded part, and a
        cursor."""
        from .sheet.panels.torques import torque_range

        m = self.m
        for v, c in ((m.s.T1, P.LEG1), (m.s.T2, P.LEG2)):
            ax.plot(m.s.t, P.finite(v), color=c, lw=1.2)
        rng = torque_range([m])
        if rng is not None:
            ax.set_ylim(*rng)
        for s in m.result.singularities:
            if not s.torque_bounded:
                ax.axvline(s.t, color=P.STATUS_COLOUR["fail"], lw=1.0, ls="--")
        knot_lines(ax, m, "gif-torques-knot")
        ax.set_xlim(0, tf)
        ax.set_xlabel("t [s]", labelpad=1, fontsize=8)
        e = SCHEMES[m.task.robot.actuation]  # T [N m], or F [N] for linear actuators
        ax.set_ylabel(f"{e.letter} [{e.unit}]", fontsize=8)
        ax.tick_params(labelsize=7)
        self.tcursor = ax.axvline(0, color="black", lw=1.0)

    def _strip(self, ax: Axes, tf: float) -> None:
        m = self.m
        ax.plot(m.s.t, P.finite(m.s.delta), color=P.DELTA, lw=1.4)
        ax.axhspan(-P.NEAR_DELTA, P.NEAR_DELTA, color="#999999", alpha=0.15, lw=0)
        ax.axhline(0, color="#444444", lw=0.7)
        knot_lines(ax, m, "gif-delta-knot")
        for k, s in enumerate(m.result.singularities):
            small = {"markersize": 11 if s.high_order else 6}  # the strip is narrow
            style = {**P.marker_style(s, m.result.status_of(s)), **small}
            ax.plot([s.t], [0], gid=f"gif-delta-singular-{self.i}-{k}", **style)
        ax.set_xlim(0, tf)
        ax.set_ylabel("δ", fontsize=8)
        ax.tick_params(labelsize=7)
        self.cursor = ax.axvline(0, color="black", lw=1.0)
        self.dot = ax.plot([], [], "o", ms=4, color="black")[0]
        self.moving = [
            self.tint,
            self.trace,
            *self.robot.artists,
            *self.over,
            self.clock,
            self.cue,
            self.cursor,
            self.dot,
        ]

    def update(self, k: int) -> list[Any]:
        f, m = self.f, self.m
        upto = m.s.t <= self.t[k]
        self.trace.set_data(m.s.x[upto], m.s.y[upto])
        self.robot.pose(f, k)
        delta = float(f.delta[k]) + 0.0  # no "-0.0000"
        ended = " (ended)" if self.clock_t[k] > m.duration else ""
        self.clock.set_text(f"t = {self.clock_t[k]:{self.fmt}} s{ended}\nδ = {delta:+.4f}")
        self.cursor.set_xdata([self.t[k], self.t[k]])
        self.tcursor.set_xdata([self.t[k], self.t[k]])
        self.dot.set_data([self.t[k]], [delta])
        s = self.at[k]
        if s is not None:
            st = m.result.status_of(s)
            self.tint.set_edgecolor(AT_EDGE)
            self.tint.set_alpha(1.0)
            self.cue.set_text(f"TYPE II SINGULARITY: {P.order_text(s)} — {P.STATUS_WORD[st]}")
            self.cue.set_color(P.STATUS_COLOUR["fail"])
        elif np.isfinite(delta) and abs(delta) < P.NEAR_DELTA:
            self.tint.set_edgecolor(NEAR_EDGE)
            self.tint.set_alpha(1.0)
            self.cue.set_text(f"near a singular configuration: |δ| < {number(P.NEAR_DELTA)}")
            self.cue.set_color("#9A6200")
        else:
            self.tint.set_alpha(0.0)
            self.cue.set_text("")
        return self.moving


def _inches(inches: float, dpi: int) -> float:
    """``inches``, raised by a few units in the last place at most so that ``inches * dpi``
    is not below the whole number of pixels it stands for (5.6 in at 90 dpi is
    503.99999999999994 in doubles): matplotlib releases that truncate the canvas's size
    and those that round it then draw frames of one size."""
    pixels = round(inches * dpi)
    while inches * dpi < pixels:
        inches = math.nextafter(inches, math.inf)
    return inches


class Animation:
    """The GIF's figure: the static parts drawn once on an Agg canvas, and each frame
    drawn over them (``draw``): only the moving artists, in their z-order, so that the
    singular line and the marks stay above the legs as on the sheet."""

    def __init__(self, motions: Sequence[P.Motion], frames: int = FRAMES, dpi: int = DPI) -> None:
        self.frames = frames = int(min(max(frames, 2), MAX_FRAMES))
        ncols = min(len(motions), MAX_COLUMNS)
        nrows = math.ceil(len(motions) / ncols)
        if nrows > 1:  # keep the frame within one row's pixels: the file size stays bounded
            dpi = max(40, int(dpi / math.sqrt(nrows)))
        self.dpi = dpi
        with matplotlib.rc_context(RC):
            size = (_inches(COLUMN_SIZE[0] * ncols, dpi), _inches(COLUMN_SIZE[1] * nrows, dpi))
            fig = Figure(figsize=size, dpi=dpi, layout="constrained")
            self.fig = fig
            self.canvas = FigureCanvasAgg(fig)
            subs = fig.subfigures(nrows, ncols, squeeze=False).ravel()
            self.t = t = clock(motions, frames)
            tf = max(m.duration for m in motions)
            self.columns = [
                _Column(sf, m, t, tf, i)
                for i, (sf, m) in enumerate(zip(subs, motions, strict=False))
            ]
            for sf in subs[len(motions) :]:
                sf.set_visible(False)
            for c in self.columns:
                for a in c.moving:
                    a.set_animated(True)
            self.canvas.draw()  # type: ignore[no-untyped-call]  # lays out (once), draws what stays
            fig.set_layout_engine("none")
            self.background = self.canvas.copy_from_bbox(fig.bbox)  # type: ignore[no-untyped-call]
        self.hold = [any(c.at[k] is not None for c in self.columns) for k in range(frames)]

    def draw(self, k: int) -> None:
        """Frame k on the canvas: the static parts, then what moves, lowest z-order first."""
        with matplotlib.rc_context(RC):
            self._paint(k)

    def _paint(self, k: int) -> None:
        """``draw`` within the GIF's ``RC`` already set (``write_gif`` sets it once for
        every frame: entering it costs a copy and a validation of every rcParam)."""
        self.canvas.restore_region(self.background)  # type: ignore[no-untyped-call]
        for c in self.columns:
            for a in sorted(c.update(k), key=lambda a: a.get_zorder()):
                self.fig.draw_artist(a)

    def rgba(self, k: int) -> np.ndarray:
        """Frame k as pixels (rows from the top, RGBA)."""
        self.draw(k)
        return np.asarray(self.canvas.buffer_rgba()).copy()  # type: ignore[no-untyped-call]


def write_gif(
    motions: Sequence[P.Motion],
    path: str,
    *,
    frames: int = FRAMES,
    fps: int = FPS,
    dpi: int = DPI,
) -> int:
    """Write the animation of ``motions`` (side by side) to the file ``path`` as a GIF;
    returns the number of frames (``frames``, clamped to 2..MAX_FRAMES).

    The static parts are drawn once on an Agg canvas; each frame restores them and draws
    only the moving artists (blitting), which keeps a 100-frame GIF to a second or two."""
    a = Animation(motions, frames, dpi)
    durations = [int(1000 * HOLD) if h else int(1000 / fps) for h in a.hold]
    writer = GifWriter(durations, fps=fps)
    with writer.saving(a.fig, path, a.dpi), matplotlib.rc_context(RC):
        for k in range(a.frames):
            a._paint(k)
            writer.grab_frame()
    return a.frames

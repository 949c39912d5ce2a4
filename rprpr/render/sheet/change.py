"""What ``rprpr repair --plot`` adds to the sheet of the old and the new motion: the
change itself, which on the overlaid panels is often far smaller than a line's width (a
0.77 mm timing change on a 2 m path).

``differences`` evaluates the new motion minus the old one exactly as the repair's
account measures it (``rprpr.repair``): Δx(t) = x_new(t) - x_old(t), and Δy at equal x,
the new y(t) against the old path at the new x(t) (without a path, the old y(t)); the
differences are exact polynomials, evaluated in floating point only at the end.
``panel`` draws them in mm over t, the account's maximum marked; ``insets`` zooms the x
panel (a timing change) and the workspace (a path change) about the account's point of
largest change, both motions drawn.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from flint import fmpq_poly
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from ...model.dataclass import dataclass
from ...model.numbers import number
from ...model.task import Task
from .motion import Motion
from .page import Sheet, measuring_renderer
from .style import LABEL_SIZE, POINT, pt, style, task_colour

ROW = 1.5  # in
SAMPLES = 4001  # per task's duration, with the account's instants added
INSET_HALF = 4.0  # the inset spans this many largest changes either side of the point


@dataclass(frozen=True)
class Change:
    """The repair's account (``rprpr.repair.Repair``): (max |Δx(t)| [m], the t where) or
    None when the timing is kept; (max |Δy| at equal x [m], the x where) or None when the
    path is kept."""

    timing: tuple[float, float] | None = None
    path: tuple[float, float] | None = None


@dataclass(frozen=True)
class Differences:
    """New minus old, sampled: times [s], Δx and Δy [m] (Δy None when the path is kept)."""

    t: np.ndarray
    dx: np.ndarray
    dy: np.ndarray | None


def _value(p: fmpq_poly, t: np.ndarray) -> np.ndarray:
    coeffs = [float(c) for c in reversed(p.coeffs())] or [0.0]
    return np.asarray(np.polyval(coeffs, t), dtype=float)


def differences(old: Task, new: Task, change: Change, n: int = SAMPLES) -> Differences:
    """``new`` minus ``old`` on ``n`` times over [0, t_f] plus the account's instant,
    each piece's difference an exact polynomial (as the account's maxima are taken)."""
    tf = float(new.duration)
    extra = [change.timing[1]] if change.timing is not None else []
    t = np.union1d(np.linspace(0.0, tf, n), extra)
    dx = np.full(t.shape, np.nan)
    dy = np.full(t.shape, np.nan)
    for q in new.motion:
        for o in old.motion:
            lo, hi = max(q.start, o.start), min(q.end, o.end)
            if not lo < hi:
                continue
            inside = (t >= float(lo)) & (t <= float(hi))
            dx[inside] = _value(q.x - o.x, t[inside])
            old_y = old.path(q.x) if old.path is not None else o.y
            dy[inside] = _value(q.y - old_y, t[inside])
    return Differences(t, dx, dy if change.path is not None else None)


def spot(d: Differences, after: Motion, name: str, where: float) -> int:
    """The sample of ``d`` at the account's largest change: at its t (Δx), or where the
    new x(t) is nearest its x (Δy; the largest |Δy| there when x is passed twice)."""
    if name == "x":
        return int(np.argmin(np.abs(d.t - where)))
    assert d.dy is not None
    x = np.interp(d.t, after.s.t, after.s.x)
    near = np.abs(x - where) <= np.min(np.abs(x - where)) + 1e-9
    return int(np.flatnonzero(near)[np.argmax(np.abs(d.dy[near]))])


def panel(sheet: Sheet, d: Differences, change: Change) -> Axes:
    """The change as a panel of its own: Δx(t) and Δy at equal x [mm] over t, the
    account's largest change of each marked (gid ``change-max-x`` / ``-y``) and keyed in
    the lane."""
    sheet.heading("The repair's change: after − before [mm]", "Change: after − before")
    (row,) = sheet.rows("change", (ROW,))
    ax = row[0]
    ax.axhline(0, color="#444444", lw=0.8, zorder=0.7)
    entries: list[object] = []
    notes = []
    for name, v, dash, account in (
        ("x", d.dx, "-", change.timing),
        ("y", d.dy, "--", change.path),
    ):
        if v is None or account is None:
            continue
        label = "Δx(t)" if name == "x" else "Δy at equal x"
        (line,) = ax.plot(
            d.t, 1e3 * v, color=POINT, ls=dash, lw=1.5, gid=f"change-{name}", label=label
        )
        entries.append(line)
        size, where = account
        k = spot(d, sheet.motions[1], name, where)
        ax.plot(
            [d.t[k]],
            [1e3 * v[k]],
            "o",
            ms=6,
            mfc="white",
            mec=POINT,
            mew=1.4,
            zorder=6,
            gid=f"change-max-{name}",
        )
        at = f"t = {number(where, 4)} s" if name == "x" else f"x = {number(where, 4)} m"
        notes.append(f"max |Δ{name}| {number(1e3 * size, 4)} mm at {at} (the repair's account)")
    if not entries:  # a change the account does not measure (neither x(t) nor y moved)
        notes.append("x(t) and the path unchanged (the repair's account)")
    ax.set_ylabel("Δ [mm]")
    sheet.lane(ax, entries, notes)
    return ax


def insets(fig: Figure, before: Motion, after: Motion, d: Differences, change: Change) -> None:
    """Zoomed insets at the largest change, both motions drawn (gid ``inset-change-x`` on
    the x panel for a timing change, ``inset-change-path`` on the workspace for a path
    change), each tied to its spot by ``indicate_inset_zoom``."""
    axes = {a.get_gid(): a for a in reversed(fig.get_axes())}  # each panel's first row
    if change.timing is not None and "panel-x" in axes:
        size, t0 = change.timing
        k = spot(d, after, "x", t0)
        x_old = float(np.interp(t0, before.s.t, before.s.x))
        x_new = x_old + float(d.dx[k])
        speed = max(abs(float(np.interp(t0, after.s.t, after.s.x_dot))), 1e-9)
        half = INSET_HALF * size
        span = min(half / speed, float(after.duration) / 20)
        _inset(
            axes["panel-x"],
            "inset-change-x",
            (t0, (x_old + x_new) / 2),
            (span, half),
            [(m, m.s.t, m.s.x) for m in (before, after)],
            lambda m, ts: m.result.resample(ts).x,
        )
    if change.path is not None and d.dy is not None and "panel-path" in axes:
        size, x0 = change.path
        k = spot(d, after, "y", x0)
        y_new = float(np.interp(d.t[k], after.s.t, after.s.y))
        half = INSET_HALF * size
        _inset(
            axes["panel-path"],
            "inset-change-path",
            (x0, y_new - float(d.dy[k]) / 2),
            (half, half),
            [(m, m.s.x, m.s.y) for m in (before, after)],
            None,
            (0.24, 0.38),
        )


def _inset(
    ax: Axes,
    gid: str,
    centre: tuple[float, float],
    half: tuple[float, float],
    curves: list[tuple[Motion, np.ndarray, np.ndarray]],
    fine: Callable[[Motion, np.ndarray], np.ndarray] | None,
    size: tuple[float, float] = (0.36, 0.56),
) -> Axes:
    """An inset of ``ax`` about ``centre`` ± ``half``, in the corner of ``ax`` farthest
    from the spot, the curves redrawn there (densely about the spot for a time axis)."""
    w, h = size
    u, v = _drawn_points(ax)
    spot = ax.transAxes.inverted().transform(ax.transData.transform(centre))
    # its tick labels stand left of and under it (0.4 in, 0.25 in): inside the panel
    box = ax.get_window_extent()  # in pixels, at the figure's dpi
    dpi = float(ax.figure.dpi)
    mx, my = 0.4 * dpi / box.width, 0.25 * dpi / box.height
    lefts, bottoms = np.linspace(mx, 0.98 - w, 9), np.linspace(my, 0.96 - h, 7)
    places = [(a, b) for b in bottoms for a in lefts]

    def covered(place: tuple[float, float]) -> float:  # what the inset would hide
        a, b = place
        inside = (u >= a - mx) & (u <= a + w + 0.02) & (v >= b - my) & (v <= b + h + 0.04)
        near = a - 0.05 <= spot[0] <= a + w + 0.05 and b - 0.08 <= spot[1] <= b + h + 0.08
        return float(np.count_nonzero(inside)) + (1e9 if near else 0.0)

    left, bottom = min(places, key=covered)
    small = ax.inset_axes((left, bottom, w, h))
    small.set_zorder(20)  # over every mark of the panel
    small.set_gid(gid)
    lo, hi = centre[0] - half[0], centre[0] + half[0]
    for i, (m, xs, ys) in enumerate(curves):
        if fine is not None:  # the curve resampled about the spot: the grid is too coarse
            xs = np.linspace(lo, hi, 201)
            ys = fine(m, xs)
        small.plot(xs, ys, lw=1.3, color=task_colour(i), ls=style(i), gid=f"{gid}-{i}")
    small.set_xlim(lo, hi)
    small.set_ylim(centre[1] - half[1], centre[1] + half[1])
    small.tick_params(labelsize=pt(LABEL_SIZE) - 1, length=2, pad=1)
    small.xaxis.set_major_locator(MaxNLocator(3))
    small.yaxis.set_major_locator(MaxNLocator(3))
    small.set_facecolor("white")
    ax.indicate_inset_zoom(small, edgecolor="#555555")
    return small


def _drawn_points(ax: Axes) -> tuple[np.ndarray, np.ndarray]:
    """Points along every line and mark of ``ax`` in axes coordinates (each segment
    filled in), where an inset should not go."""
    to_axes = ax.transAxes.inverted()
    us, vs = [], []
    for line in ax.get_lines():
        xy = line.get_transform().transform(np.asarray(line.get_xydata(), dtype=float))
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if len(xy) == 0:
            continue
        if len(xy) <= 2 or line.get_marker() not in (None, "None", "", " "):
            xy = np.repeat(xy, 200, axis=0)  # a mark, a straight line: weigh as a curve
        elif len(xy) > 1:
            steps = np.linspace(0.0, 1.0, 20, endpoint=False)
            seg = xy[:-1, None, :] + (xy[1:, None, :] - xy[:-1, None, :]) * steps[None, :, None]
            xy = np.concatenate([seg.reshape(-1, 2), xy[-1:]])
        a = to_axes.transform(xy)
        us.append(a[:, 0])
        vs.append(a[:, 1])
    renderer = measuring_renderer(ax.figure.dpi)  # as drawn at the figure's resolution
    for text in ax.texts:
        box = text.get_window_extent(renderer)  # a grid over it, weighing as a long line
        gx, gy = np.meshgrid(np.linspace(box.x0, box.x1, 6), np.linspace(box.y0, box.y1, 4))
        a = to_axes.transform(np.column_stack([gx.ravel(), gy.ravel()]))
        us.append(np.repeat(a[:, 0], 1000))
        vs.append(np.repeat(a[:, 1], 1000))
    if not us:
        return np.zeros(0), np.zeros(0)
    return np.concatenate(us), np.concatenate(vs)

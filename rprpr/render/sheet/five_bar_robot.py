"""A 5R's Type II curves and links, drawn the same on the sheet and in the GIF (as the
sheet's ``robot`` module draws the RPRPR's legs).

``curves`` draws the Type II curves S₊ = 0 and S₋ = 0 (``engine.exact.five_bar.curve``)
where both legs reach, by contouring the polynomial in doubles on a grid (contourpy,
matplotlib's own); ``draw_robot`` draws one pose for good (the sheet) and
``MovingFiveBar`` holds the links' artists and moves them per frame (the GIF)."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.lines import Line2D

from ...engine.exact import five_bar as fb
from ...model.numbers import to_float
from ...model.task import Task
from .robot import END_POINT, SINGULAR_LEGS

CURVES = {1: "#6A3D9A", -1: "#B15928"}  # S₊, S₋: purple, brown (none of the quantities')
CURVE_DASH: Any = (0, (5, 2))
CURVE_NAMES = {
    1: "Type II curve S₊ = 0 (C, D on one side of E)",
    -1: "Type II curve S₋ = 0 (E between the elbows)",
}
CURVE_Z = 3.8  # above the links, as the RPRPR's singular line
GRID = 361  # points a side of the grid the curves are contoured on
PROXIMAL: dict[str, Any] = {"lw": 4.2, "solid_capstyle": "round", "zorder": 3.5}
DISTAL: dict[str, Any] = {"lw": 2.2, "solid_capstyle": "round", "zorder": 3.6}
ELBOW: dict[str, Any] = {"ms": 4.5, "mfc": "white", "mew": 1.1, "zorder": 3.7}


def curve_lines(task: Task, box: tuple[float, float, float, float]) -> dict[int, list[Any]]:
    """The zero sets of S₊ and S₋ (σ = 1, -1) of ``task``'s robot within ``box``
    (x0, x1, y0, y1) where both legs reach: polylines (arrays of (x, y) rows), contoured
    on a GRID x GRID grid in doubles."""
    import contourpy

    robot = task.robot
    assert robot.five_bar is not None
    p = fb.params(robot.five_bar, robot.gravity, to_float)
    x0, x1, y0, y1 = box
    X, Y = np.meshgrid(np.linspace(x0, x1, GRID), np.linspace(y0, y1, GRID))
    c = fb.conjugates(p, X, Y)
    out_of_reach = (c.D1 < 0) | (c.D2 < 0)
    lines = {}
    for sigma in (1, -1):
        Z = np.ma.array(fb.curve(p, sigma, X, Y), mask=out_of_reach)
        gen = contourpy.contour_generator(X, Y, Z)
        lines[sigma] = [seg for seg in gen.lines(0.0) if len(seg) > 1]
    return lines


def curves(
    ax: Axes, m: Any, box: tuple[float, float, float, float], gid: str
) -> list[LineCollection]:
    """The Type II curves of ``m``'s robot on ``ax`` (gids ``<gid>-plus``,
    ``<gid>-minus``), not counted in the axes' data limits (the view stays the motion's)."""
    out = []
    for sigma, segs in curve_lines(m.task, box).items():
        lc = LineCollection(
            segs, colors=CURVES[sigma], linewidths=1.1, linestyles=CURVE_DASH, zorder=CURVE_Z
        )
        lc.set_gid(f"{gid}-{'plus' if sigma > 0 else 'minus'}")
        ax.add_collection(lc, autolim=False)
        out.append(lc)
    return out


def curve_handles() -> list[Line2D]:
    """The curves' legend entries."""
    return [
        Line2D([], [], color=CURVES[s], lw=1.1, ls=CURVE_DASH, label=CURVE_NAMES[s])
        for s in (1, -1)
    ]


def base(m: Any) -> float:
    """|AB| [m]: B's x."""
    return float(m.task.robot.a1)


def links(m: Any, i: int) -> dict[int, tuple[np.ndarray, np.ndarray]] | None:
    """Links 1..4 at sample i as (from, to) points: A–C, B–D, C–E, D–E (None where a leg
    cannot reach)."""
    s = m.s
    E = np.array([s.x[i], s.y[i]])
    C = np.array([s.cx[i], s.cy[i]])
    D = np.array([s.dx[i], s.dy[i]])
    if not (np.all(np.isfinite(E)) and np.all(np.isfinite(C)) and np.all(np.isfinite(D))):
        return None
    A, B = np.array([0.0, 0.0]), np.array([base(m), 0.0])
    return {1: (A, C), 2: (B, D), 3: (C, E), 4: (D, E)}


def draw_robot(
    ax: Axes,
    m: Any,
    i: int,
    alpha: float,
    gid: str,
    *,
    singular: bool = False,
    colour: str | None = None,
    legs: tuple[str, str] = ("", ""),
) -> np.ndarray:
    """The 5R at sample i of ``m`` (gids ``<gid>-link<n>``, ``<gid>-elbow-C``,
    ``<gid>-elbow-D``, ``<gid>-end-point``): links 1, 3 in ``legs[0]``'s colour, 2, 4
    in ``legs[1]``'s, or all in ``colour``; at a ``singular`` instant the distal links
    dashed, so that the Type II curve through E shows. Returns points along the links."""
    drawn = links(m, i)
    if drawn is None:
        return np.empty((0, 2))
    along = np.linspace(0, 1, 24)[:, None]
    pts = []
    for n, (P, Q) in drawn.items():
        c = colour or legs[(n - 1) % 2]
        kw = dict(PROXIMAL if n <= 2 else DISTAL)
        if n <= 2:
            kw["alpha"] = 0.6 * alpha
        else:
            kw["alpha"] = alpha
            if singular:
                kw["ls"] = SINGULAR_LEGS
        ax.plot([P[0], Q[0]], [P[1], Q[1]], color=c, gid=f"{gid}-link{n}", **kw)
        pts.append(P + along * (Q - P))
    for name, n in (("C", 1), ("D", 2)):
        P = drawn[n][1]
        c = colour or legs[n - 1]
        ax.plot([P[0]], [P[1]], "o", mec=c, alpha=alpha, gid=f"{gid}-elbow-{name}", **ELBOW)
    E = drawn[3][1]
    end = {**END_POINT, "mec": colour or END_POINT["mec"]}
    ax.plot([E[0]], [E[1]], "o", alpha=alpha, gid=f"{gid}-end-point", **end)
    return np.concatenate(pts)


class MovingFiveBar:
    """The artists of one 5R on ``ax``, moved to sample k of ``f`` (the frames' samples) by
    ``move``."""

    def __init__(self, ax: Axes, m: Any, legs: tuple[str, str]) -> None:
        self.a = base(m)
        self.links = {
            n: ax.plot([], [], color=legs[(n - 1) % 2], **(PROXIMAL if n <= 2 else DISTAL))[0]
            for n in (1, 2, 3, 4)
        }
        for n in (1, 2):
            self.links[n].set_alpha(0.6)
        self.elbows = [ax.plot([], [], "o", mec=c, **ELBOW)[0] for c in legs]
        self.end = ax.plot([], [], "o", **END_POINT)[0]
        self.artists: list[Line2D] = [*self.links.values(), *self.elbows, self.end]

    def move(self, E: np.ndarray, C: np.ndarray, D: np.ndarray) -> None:
        """E, and the elbows C, D (a leg that cannot reach, or E not finite: hidden)."""
        ok = bool(np.all(np.isfinite(E)) and np.all(np.isfinite(C)) and np.all(np.isfinite(D)))
        A, B = np.array([0.0, 0.0]), np.array([self.a, 0.0])
        for n, (P, Q) in {1: (A, C), 2: (B, D), 3: (C, E), 4: (D, E)}.items():
            self.links[n].set_data([P[0], Q[0]] if ok else [], [P[1], Q[1]] if ok else [])
        for e, P in zip(self.elbows, (C, D), strict=True):
            e.set_data([P[0]] if ok else [], [P[1]] if ok else [])
        self.end.set_data([E[0]], [E[1]])

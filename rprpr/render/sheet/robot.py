"""The robot in its workspace, drawn the same on the sheet and in the GIF.

The workspace (the paper's Fig. 3) is the plane of the end point E at equal scales, with
the singular line y = 0 and the base joints A = (0, 0) and B = (a1, 0), each a grounded
revolute joint. The robot is its two legs: leg n is a cylinder pivoting at its base and a
rod sliding in it to E (the prismatic joint s_n), in the leg's colour.

``draw_robot`` draws one pose for good (the sheet); ``MovingRobot`` holds the artists of
one robot and moves them to a new pose per frame (the GIF)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.lines import Line2D
from matplotlib.patches import Polygon

from ...engine.certified.sampling import Samples
from .five_bar import elbows, is_five_bar
from .motion import Motion
from .style import LEG1, LEG2, LINE, LINE_DASH, POINT, pt

View = tuple[float, float, float, float]  # x0, x1, y0, y1 [m]

CYLINDER: dict[str, Any] = {"lw": 7, "solid_capstyle": "butt", "zorder": 3.5}
ROD: dict[str, Any] = {"lw": 2.2, "solid_capstyle": "round", "zorder": 3.6}
END_POINT: dict[str, Any] = {"ms": 6, "mfc": "white", "mec": POINT, "mew": 1.3, "zorder": 5}
CYLINDER_SHARE = 0.45  # of the shortest leg length over the motion: the cylinder's length
CYLINDER_ALPHA = 0.45  # the cylinder's opacity, relative to its rod's
GROUND = "#333333"
SINGULAR_LINE_Z = 3.8  # above the legs: at a singular instant they lie on AB
SINGULAR_LEGS = (0, (3, 1.5))  # the legs' rods at a singular instant: AB shows through


def view(motions: Sequence[Motion]) -> View:
    """The workspace shown: every path, A and B and the singular line (a 5R's elbows
    too), with room around."""
    links = [elbows(m) for m in motions if is_five_bar(m)]
    xs = np.concatenate(
        [m.s.x for m in motions]
        + [np.array([0.0, float(m.task.robot.a1)]) for m in motions]
        + [p[:, 0] for p in links]
    )
    ys = np.concatenate([m.s.y for m in motions] + [np.zeros(1)] + [p[:, 1] for p in links])
    xs, ys = xs[np.isfinite(xs)], ys[np.isfinite(ys)]
    x0, x1 = float(xs.min()), float(xs.max())
    y0, y1 = float(ys.min()), float(ys.max())
    padx = 0.18 * (x1 - x0)  # room for the case 1 and case 2 stretches beyond A and B
    pady = max(0.12 * (y1 - y0), 0.08 * (x1 - x0))
    return min(x0, 0.0) - padx, x1 + padx, y0 - pady, y1 + pady


def workspace(ax: Axes, motions: Sequence[Motion]) -> tuple[View, float]:
    """Set ``ax`` up as the workspace of ``motions``: equal scales over ``view``. Returns
    the view and the size of a base joint's symbol [m]."""
    x0, x1, y0, y1 = v = view(motions)
    # equal scales; the view grows to fill the axes (fixed limits would fight the aspect)
    ax.set_aspect("equal", adjustable="datalim")
    ax.margins(0)
    ax.update_datalim([(x0, y0), (x1, y1)])
    return v, 0.028 * (x1 - x0)


def singular_line(ax: Axes, gid: str = "singular-line") -> Line2D:
    """The singular line y = 0 (δ = 0), above the legs (``SINGULAR_LINE_Z``)."""
    return ax.axhline(0, color=LINE, lw=1.1, ls=LINE_DASH, zorder=SINGULAR_LINE_Z, gid=gid)


def singular_line_handle() -> Line2D:
    """The singular line's legend entry."""
    return Line2D([], [], color=LINE, lw=1.1, ls=LINE_DASH, label="singular line y = 0 (δ = 0)")


def base_joints(ax: Axes, motions: Sequence[Motion], size: float) -> list[float]:
    """A at the origin and B at each distinct a1 (B1, B2, … by increasing a1 when there
    are several); returns the distinct a1 [m]."""
    ground(ax, 0.0, size, "A")
    a1s = sorted({float(m.task.robot.a1) for m in motions})
    for j, a in enumerate(a1s):
        ground(ax, a, size, "B" if len(a1s) == 1 else f"B{j + 1}")
    return a1s


def ground(ax: Axes, x: float, size: float, label: str) -> None:
    """A base joint: a grounded triangle under a revolute joint at (x, 0)."""
    h = size
    triangle = [(x, 0), (x - 0.6 * h, -h), (x + 0.6 * h, -h)]
    ax.add_patch(
        Polygon(triangle, closed=True, facecolor="#BBBBBB", edgecolor=GROUND, lw=0.8, zorder=3)
    )
    ax.plot([x - 0.9 * h, x + 0.9 * h], [-h, -h], color=GROUND, lw=1.2, zorder=3)
    for k in range(5):
        xx = x - 0.9 * h + k * 0.45 * h
        ax.plot([xx, xx - 0.35 * h], [-h, -1.4 * h], color=GROUND, lw=0.7, zorder=3)
    ax.plot([x], [0], "o", ms=6, mfc="white", mec=GROUND, mew=1.2, zorder=7)
    ax.annotate(
        label,
        (x, -1.4 * h),
        xytext=(0, -3),
        textcoords="offset points",
        ha="center",
        va="top",
        fontsize=pt(10),
        fontweight="bold",
    )


def cylinders(s: Samples) -> tuple[float | None, float | None]:
    """Each leg's cylinder length [m]: a share of its shortest length over the samples
    (None without a finite sample)."""
    out = []
    for lengths in (s.s1, s.s2):
        finite = lengths[np.isfinite(lengths)]
        out.append(CYLINDER_SHARE * float(finite.min()) if finite.size else None)
    return out[0], out[1]


def legs(
    a1: float, E: np.ndarray, cyl: tuple[float | None, float | None]
) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """Leg n's base and the end of its cylinder, for each leg of nonzero length when E is
    at ``E``; a cylinder is at most 0.8 of its leg (0.3 without a length of its own)."""
    out: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    if not np.all(np.isfinite(E)):
        return out
    for n, base, c in ((1, (0.0, 0.0), cyl[0]), (2, (a1, 0.0), cyl[1])):
        P = np.array(base)
        length = float(np.hypot(*(E - P)))
        if length == 0:
            continue
        u = (E - P) / length
        out[n] = (P, P + min(0.3 * length if c is None else c, 0.8 * length) * u)
    return out


def draw_robot(
    ax: Axes,
    m: Motion,
    i: int,
    alpha: float,
    gid: str,
    *,
    singular: bool = False,
    colour: str | None = None,
) -> np.ndarray:
    """The robot at sample i of ``m`` (gids ``<gid>-cylinder<n>``, ``<gid>-leg<n>``,
    ``<gid>-end-point``), in the legs' colours or all in ``colour``; at a ``singular``
    instant its rods dashed, so that the line AB they lie on shows through. Returns points
    along the legs."""
    E = np.array([m.s.x[i], m.s.y[i]])
    if not np.all(np.isfinite(E)):
        return np.empty((0, 2))
    pts = []
    along = np.linspace(0, 1, 24)[:, None]
    for n, (P, C) in legs(float(m.task.robot.a1), E, cylinders(m.s)).items():
        c = colour or (LEG1 if n == 1 else LEG2)
        kw = {"color": c, "alpha": CYLINDER_ALPHA * alpha, **CYLINDER}
        ax.plot([P[0], C[0]], [P[1], C[1]], gid=f"{gid}-cylinder{n}", **kw)
        rod = {**ROD, "ls": SINGULAR_LEGS} if singular else ROD
        ax.plot([P[0], E[0]], [P[1], E[1]], color=c, alpha=alpha, gid=f"{gid}-leg{n}", **rod)
        pts.append(P + along * (E - P))
    end = {**END_POINT, "mec": colour or POINT}
    ax.plot([E[0]], [E[1]], "o", alpha=alpha, gid=f"{gid}-end-point", **end)
    return np.concatenate(pts) if pts else np.empty((0, 2))


class MovingRobot:
    """The artists of one robot on ``ax``, moved to a pose per frame by ``move``."""

    def __init__(self, ax: Axes, m: Motion) -> None:
        self.a1 = float(m.task.robot.a1)
        self.cylinders = cylinders(m.s)
        self.legs = {
            n: (
                ax.plot([], [], color=c, alpha=CYLINDER_ALPHA, **CYLINDER)[0],
                ax.plot([], [], color=c, **ROD)[0],
            )
            for n, c in ((1, LEG1), (2, LEG2))
        }
        self.end = ax.plot([], [], "o", **END_POINT)[0]
        self.artists: list[Line2D] = [*(a for leg in self.legs.values() for a in leg), self.end]

    def move(self, E: np.ndarray) -> None:
        """Put the end point at ``E`` (a leg of zero length, or every leg when E is not
        finite, is hidden)."""
        drawn = legs(self.a1, E, self.cylinders)
        for n, (cyl, rod) in self.legs.items():
            if n not in drawn:
                cyl.set_data([], [])
                rod.set_data([], [])
                continue
            P, C = drawn[n]
            cyl.set_data([P[0], C[0]], [P[1], C[1]])
            rod.set_data([P[0], E[0]], [P[1], E[1]])
        self.end.set_data([E[0]], [E[1]])

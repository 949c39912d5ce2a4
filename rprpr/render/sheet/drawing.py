"""What the sheet and the GIF draw differently for each mechanism, behind one interface.

``drawing(m)`` is the motion's ``Drawing``: the RPRPR's (its legs, the singular line
y = 0, its leg lengths s1, s2) or the 5R's (its links and elbows, its Type II curves,
its distal links' angles φ1, φ2). The panels and the GIF ask it where an instant sits,
how the robot and the singular locus are drawn and what the joints panel's second row
shows, never the mechanism itself; what a sheet says of its tasks as a whole (a
heading naming the paper's figure, or both mechanisms) reads ``kinds``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes

from . import five_bar as FB
from . import five_bar_robot as FBR
from . import robot as R
from .motion import Motion
from .style import LEG1, LEG2

Box = tuple[float, float, float, float]  # x0, x1, y0, y1 [m]


class Drawing:
    """The RPRPR's drawing (the paper's robot): a leg is a sleeve and a rod from its base
    joint to E; the singular locus is the line AB (y = 0), one for every task of a set of
    axes (``shared_locus``); an instant sits on it at (x, 0)."""

    name = "rprpr"
    shared_locus = True  # one line y = 0 serves every RPRPR task on a set of axes
    y_line = True  # the y_E(t) axes show the singular line y = 0
    second_label = "$s$ [m]"
    second_names = (("$s_1 = |AE|$", LEG1), ("$s_2 = |BE|$", LEG2))

    def point(self, s: Any) -> tuple[float, float]:
        """Where the instant ``s`` sits in the workspace."""
        return s.x, 0

    def y_mark(self, s: Any) -> float:
        """The instant's mark on the y_E(t) axes."""
        return 0.0

    def locus_gid(self, where: str, i: int) -> str:
        """The gid of task i's singular locus on the sheet (``where`` = "path") or in
        the GIF ("gif")."""
        return "singular-line" if where == "path" else f"gif-singular-line-{i}"

    def locus(self, ax: Axes, m: Motion, box: Box, gid: str) -> list[Any]:
        """The singular locus on ``ax`` over ``box`` (the view as drawn): the line AB."""
        return [R.singular_line(ax, gid)]

    def robot(self, ax: Axes, m: Motion, i: int, alpha: float, gid: str, **kw: Any) -> np.ndarray:
        """The robot at sample i of ``m`` (``robot.draw_robot``)."""
        return R.draw_robot(ax, m, i, alpha, gid, **kw)

    def moving(self, ax: Axes, m: Motion) -> Any:
        """The robot's artists for the GIF, moved by ``pose(f, k)`` to frame k of the
        samples ``f``."""
        return _MovingLegs(ax, m)

    def second_row(self, m: Motion) -> tuple[tuple[np.ndarray, str], tuple[np.ndarray, str]]:
        """The joints panel's second row: the curves with their gids (s1, s2 [m])."""
        return (m.s.s1, "s1"), (m.s.s2, "s2")


class FiveBarDrawing(Drawing):
    """A 5R's drawing (``five_bar``, ``five_bar_robot``): its proximal and distal links
    and the elbows; its Type II curves S₊ = 0, S₋ = 0, each robot's own; an instant sits
    on them at its (x, y); the second joints row is the distal links' angles φ1, φ2."""

    name = "5R"
    shared_locus = False
    y_line = False
    second_label = r"$\varphi$ [deg]"
    second_names = ((r"$\varphi_1$ (link C–E)", LEG1), (r"$\varphi_2$ (link D–E)", LEG2))

    def point(self, s: Any) -> tuple[float, float]:
        return s.x, s.y

    def y_mark(self, s: Any) -> float:
        return float(s.y)

    def locus_gid(self, where: str, i: int) -> str:
        return f"{where}-curve-{i}"

    def locus(self, ax: Axes, m: Motion, box: Box, gid: str) -> list[Any]:
        return list(FBR.curves(ax, m, box, gid))

    def robot(self, ax: Axes, m: Motion, i: int, alpha: float, gid: str, **kw: Any) -> np.ndarray:
        return FBR.draw_robot(ax, m, i, alpha, gid, legs=(LEG1, LEG2), **kw)

    def moving(self, ax: Axes, m: Motion) -> Any:
        return _MovingLinks(ax, m)

    def second_row(self, m: Motion) -> tuple[tuple[np.ndarray, str], tuple[np.ndarray, str]]:
        s: Any = m.s  # a 5R's samples (``five_bar.FiveBarSamples``)
        return (np.degrees(s.phi1), "phi1"), (np.degrees(s.phi2), "phi2")


class _MovingLegs:
    def __init__(self, ax: Axes, m: Motion) -> None:
        self.robot = R.MovingRobot(ax, m)
        self.artists = self.robot.artists

    def pose(self, f: Any, k: int) -> None:
        self.robot.move(np.array([f.x[k], f.y[k]]))


class _MovingLinks:
    def __init__(self, ax: Axes, m: Motion) -> None:
        self.robot = FBR.MovingFiveBar(ax, m, (LEG1, LEG2))
        self.artists = self.robot.artists

    def pose(self, f: Any, k: int) -> None:
        E, C, D = (np.array([f.x[k], f.y[k]]), np.array([f.cx[k], f.cy[k]]),
                   np.array([f.dx[k], f.dy[k]]))  # fmt: skip
        self.robot.move(E, C, D)


RPRPR_DRAWING = Drawing()
FIVE_BAR_DRAWING = FiveBarDrawing()


def drawing(m: Motion) -> Drawing:
    """The drawing of the motion ``m``'s mechanism."""
    return FIVE_BAR_DRAWING if FB.is_five_bar(m) else RPRPR_DRAWING


def kinds(motions: Sequence[Motion]) -> tuple[bool, bool]:
    """Whether ``motions`` hold an RPRPR's, and whether a 5R's (the headings say which)."""
    return FB.kinds(motions)

"""The sheet's panels, each a row of the sheet, each a module with ``draw(sf, motions)``
(the panel on a subfigure; returns its axes) and ``height(motions)`` (its height [in])."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

from matplotlib.axes import Axes
from matplotlib.figure import SubFigure

from ..motion import Motion
from . import delta, joints, path, torques, x


@dataclass(frozen=True)
class Panel:
    """A panel's two functions: draw it on a subfigure, and its height [in]."""

    draw: Callable[[SubFigure, Sequence[Motion]], list[Axes]]
    height: Callable[[Sequence[Motion]], float]


BY_NAME = {  # in the sheet's default order
    "path": Panel(path.draw, path.height),
    "x": Panel(x.draw, x.height),
    "delta": Panel(delta.draw, delta.height),
    "joints": Panel(joints.draw, joints.height),
    "torques": Panel(torques.draw, torques.height),
}

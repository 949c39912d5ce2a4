"""The sheet's panels, each a module with ``draw(sheet, pole_inset)``: its heading, its
rows of axes (``Sheet.rows``) and its lane (``Sheet.lane``); returns its axes."""

from __future__ import annotations

from collections.abc import Callable

from matplotlib.axes import Axes

from ..page import Sheet
from . import delta, joints, path, torques, x

Draw = Callable[[Sheet, bool], list[Axes]]


class Panel:
    """A panel: how it is drawn."""

    def __init__(self, draw: Draw) -> None:
        self.draw = draw


BY_NAME = {  # in the sheet's default order (= layout.PANELS)
    "path": Panel(path.draw),
    "x": Panel(x.draw),
    "delta": Panel(delta.draw),
    "joints": Panel(joints.draw),
    "torques": Panel(torques.draw),
}

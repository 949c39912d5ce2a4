"""What the tasks of one robot share: its constants as balls (``per_robot``), made once
for every motion of a robot with the same exact parameters.

A planner's batch is one robot, and each task file states it again: converting its
constants to balls (``Ball.of_rational`` of each rational, the stacked pairs of
``stacked.Stacked``) once per robot rather than once per task or per piece is the same
work done once. The key is exact (``exact.kept.robot_key``): the mechanism that drives the robot
and every field of the robot by type and exact value, so no two robots that differ in
anything share a form. The forms are read-only (their arrays are frozen: a write
raises rather than leaking into another task), the cache holds at most ``CACHED``
robots (the oldest made is dropped first), and a forked worker's copy is keyed the same
way as its parent's, so it is right in either."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

from ...model.task import Robot
from ..exact.kept import Kept, also, robot_key
from .balls import Ball

Shared = TypeVar("Shared")

CACHED = 16  # robots whose forms are kept, per kind of form

_LAST: dict[Callable[[Robot], Any], tuple[Robot, Any]] = also({})  # by identity: the pieces
_BY_KEY: Kept[Any] = Kept(CACHED)  # by exact parameters (``exact.kept``)


def per_robot(robot: Robot, make: Callable[[Robot], Shared]) -> Shared:
    """make(robot), made once for every robot with the same exact parameters
    (``robot_key``): the robot last given (by identity, the pieces of one motion), else
    the forms kept for the robot's key (``CACHED`` at most), else made now, frozen."""
    hit = _LAST.get(make)
    if hit is not None and hit[0] is robot:
        return hit[1]

    def frozen() -> Shared:
        made = make(robot)
        freeze(made)
        return made

    made: Shared = _BY_KEY.get((make, robot_key(robot)), frozen)
    _LAST[make] = (robot, made)
    return made


def freeze(x: Any, depth: int = 0) -> None:
    """Every numpy array held by x (its attributes, tuples, lists, dicts, a few levels
    down: balls, pairs of balls, a form's constants) made read-only."""
    if type(x) is Ball:
        x.mid.flags.writeable = x.rad.flags.writeable = False
        return
    if isinstance(x, np.ndarray):
        x.flags.writeable = False
        return
    if depth > 4 or isinstance(x, (str, bytes, int, float, type)):
        return
    if isinstance(x, (tuple, list)):
        items: Any = x
    elif isinstance(x, dict):
        items = x.values()
    else:  # an object's attributes, in its __dict__ or its slots
        slots = (n for c in type(x).__mro__ for n in getattr(c, "__slots__", ()))
        items = [*getattr(x, "__dict__", {}).values(), *(getattr(x, n, None) for n in slots)]
    for v in items:
        freeze(v, depth + 1)

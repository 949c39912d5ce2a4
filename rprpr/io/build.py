"""The ``Task``, from the values a walk over the task file read (defaults applied).

The paper's form (a rest-to-rest law, or an explicit x(t)) or a piecewise motion (the
trapezoidal law, timing.x given as pieces, motion.pieces, waypoints); the rule levels of
checks.warn and checks.ignore; the file's stem as the name when the file gives none.
"""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any

from flint import fmpq, fmpq_poly

from ..model.defaults import LINK_QUANTITIES, MOVING_LINKS
from ..model.five_bar import FIVE_BAR, FIVE_BAR_LINKS, FiveBar
from ..model.rules import rule_id
from ..model.task import Checks, Link, Piece, Robot, Task, Uncertainty
from ..model.timing import timing_law, trapezoidal
from .schema import TASK, TRAPEZOIDAL

if TYPE_CHECKING:
    from ..model.waypoints import Waypoint
    from .walk import Walk

_LINKS = TASK.children["robot"].children["links"]  # the paper's moving links 2..5


def stem(file: str) -> str:
    """``pathlib.PurePath(file).stem``, the task's name when its file gives none (pathlib
    itself is not imported for it: start-up)."""
    path = os.path.splitdrive(file)[1]
    if os.altsep:
        path = path.replace(os.altsep, os.sep)
    parts = [p for p in path.split(os.sep) if p and p != "."]
    name = parts[-1] if parts else ""
    i = name.rfind(".")
    return name[:i] if 0 < i < len(name) - 1 else name


def task(w: Walk, file: str) -> Task:
    """The ``Task`` of a walk over the whole file (defaults applied); the file's stem
    names it when the file does not."""
    v = w.values
    law, x_of_t, pieces = _motion(w)
    return Task(
        name=v["name"] if "name" in v else stem(file),
        robot=_robot(v),
        path=v.get("path.y"),
        x_of_t=x_of_t,
        duration=pieces[-1].end if pieces else v["timing.duration"],
        checks=Checks(
            min_slope=v["checks.min_slope"],
            min_speed=v["checks.min_speed"],
            torque_limit=v.get("checks.torque_limit"),
            strict=v["checks.strict"],
            unbounded_torque=v["checks.unbounded_torque"],
            rules=_levels(w),
            peak=v["checks.peak"],
        ),
        law=law,
        lines=dict(w.lines),
        source=file,
        pieces=tuple(pieces),
        uncertainty=_uncertainty(w) if "uncertainty" in w.nodes else None,
    )


def _uncertainty(w: Walk) -> Uncertainty:
    """The task's ``uncertainty``: a link or quantity not named is exact, and so is an
    acceleration or period not given (the schema states no default: "not given: 0").
    It needs a torque limit, the task's or the configuration's: checked once the
    configuration is applied (``cli.uncertainty.needs_limit``)."""
    v = w.values
    mark = w.nodes["uncertainty"].start_mark
    zero = fmpq(0)
    links: dict[int, tuple[fmpq, fmpq, fmpq]] = {}
    every = v.get("uncertainty.links", zero)
    for i in MOVING_LINKS:
        if every == "per link":
            m, j, r = (v.get(f"uncertainty.links.{i}.{n}", zero) for n in LINK_QUANTITIES)
            links[i] = (m, j, r)
        else:
            links[i] = (every, every, every)
    return Uncertainty(
        links,
        v.get("uncertainty.acceleration", zero),
        v.get("uncertainty.period", zero),
        where=(mark.line + 1, mark.column + 1),
    )


def _levels(w: Walk) -> dict[str, str]:
    """Rule id -> "warn" or "ignore", from checks.warn and checks.ignore (both: ignore),
    whose keys are rule ids or names."""
    if "checks.warn" not in w.nodes and "checks.ignore" not in w.nodes:
        return {}  # neither given: no key below them has a value
    out = {}
    for level in ("warn", "ignore"):  # both: ignore wins
        for k in w.values:
            if k.startswith(f"checks.{level}."):
                name = k[len(f"checks.{level}.") :]
                out[rule_id(name) or name] = level
    return out


def _robot(v: dict[str, Any]) -> Robot:
    if v["robot.mechanism"] == FIVE_BAR:
        return _five_bar(v)
    links = {int(i): _link(v, f"robot.links.{i}") for i in _LINKS.children}
    return Robot(
        a1=v["robot.a1"],
        links=links,
        gravity=v["robot.gravity"],
        actuation=v["robot.actuation"],
        mechanism=v["robot.mechanism"],
    )


def _five_bar(v: dict[str, Any]) -> Robot:
    """A 5R's ``Robot``: its ``FiveBar``, whose |AB| and links are also the robot's."""
    links = {i: _link(v, f"robot.links.{i}") for i in FIVE_BAR_LINKS}
    l1, l2, l3, l4 = v["robot.lengths"]
    e1, e2 = v["robot.modes"]
    five_bar = FiveBar(a=v["robot.base"], lengths=(l1, l2, l3, l4), modes=(e1, e2), links=links)
    return Robot(
        a1=five_bar.a,
        links=links,
        gravity=v["robot.gravity"],
        mechanism=FIVE_BAR,
        five_bar=five_bar,
    )


def _link(v: dict[str, Any], key: str) -> Link:
    return Link(mass=v[f"{key}.mass"], inertia=v[f"{key}.inertia"], r=v[f"{key}.r"])


def _motion(w: Walk) -> tuple[str, fmpq_poly | None, list[Piece]]:
    """(law, x_E(t), pieces): the paper's form (a rest-to-rest law from path.from to
    path.to, or "explicit" timing.x) with no pieces, or a piecewise motion ("trapezoidal",
    "pieces", "motion", "waypoints") with x_E(t) None."""
    v = w.values
    if "motion.pieces" in v:
        return "motion", None, _motion_pieces(v["motion.pieces"])
    if "motion.waypoints" in v:
        return "waypoints", None, _waypoint_pieces(v["motion.waypoints"], w.csv_file)
    p = v["path.y"]
    if v.get("timing.law") == TRAPEZOIDAL:
        line = w.lines.get("timing.law", 0)
        return TRAPEZOIDAL, None, [Piece(s, e, x, p(x), p, line) for s, e, x in timing(w)]
    if "timing.law" in v:
        return v["timing.law"], timing(w)[0][2], []
    if isinstance(v["timing.x"], list):
        return "pieces", None, [Piece(s, e, x, p(x), p, ln) for s, e, x, ln in _timed(v)]
    return "explicit", v["timing.x"], []


def _x_pieces(v: dict[str, Any]) -> list[tuple[fmpq, fmpq, fmpq_poly]]:
    """(start, end, x(t)) of the timing: the trapezoidal law's pieces, timing.x's pieces,
    or the one polynomial of a rest-to-rest law or of an explicit x(t)."""
    t_f = v["timing.duration"]
    if v.get("timing.law") == TRAPEZOIDAL:
        law = trapezoidal(v["path.from"][0], v["path.to"][0], t_f, v["timing.cruise_speed"])
        ends = [fmpq(0), *(end for end, _ in law)]
        return [(s, e, x) for s, (e, x) in zip(ends, law, strict=False)]
    if "timing.law" in v:
        return [
            (fmpq(0), t_f, timing_law(v["timing.law"], v["path.from"][0], v["path.to"][0], t_f))
        ]
    if isinstance(v["timing.x"], list):
        return [(s, e, x) for s, e, x, _ in _timed(v)]
    return [(fmpq(0), t_f, v["timing.x"])]


def timing(w: Walk) -> list[tuple[fmpq, fmpq, fmpq_poly]]:
    """``_x_pieces`` of the walk's values, worked out once (the caps check needs them
    before the ``Task`` does)."""
    if w.x_pieces is None:
        w.x_pieces = _x_pieces(w.values)
    return w.x_pieces


def _timed(v: dict[str, Any]) -> list[tuple[fmpq, fmpq, fmpq_poly, int]]:
    """(start, end, x(t), line) of each piece of timing.x given as pieces."""
    items = v["timing.x"]
    starts = [fmpq(0), *(it["until"] for it in items[:-1])]
    return [(s, it["until"], it["x"], it["line"]) for s, it in zip(starts, items, strict=True)]


def _motion_pieces(items: list[dict[str, Any]]) -> list[Piece]:
    """The pieces of motion.pieces, from t = 0 (polynomials in absolute time)."""
    starts = [fmpq(0), *(it["until"] for it in items[:-1])]
    return [
        Piece(s, it["until"], it["x"], it["y"], None, it["line"])
        for s, it in zip(starts, items, strict=True)
    ]


def _waypoint_pieces(points: list[Waypoint], file: str) -> list[Piece]:
    """The joint_trajectory_controller's pieces through the waypoints; ``file`` is the
    CSV file they were read from ('' when inline: their lines are the task file's)."""
    from ..model.waypoints import pieces as waypoint_pieces  # a task of waypoints only

    return waypoint_pieces(points, file)

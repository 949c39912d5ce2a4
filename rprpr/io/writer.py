"""A task as task-file text (YAML), exactly: every number an exact rational.

``task_text`` writes the robot, the checks and the motion of a ``Task`` in the form the
loader reads back to the same task: the paper's form (``path`` and ``timing.x``), the
piecewise timing (``timing.x`` as ``{until, x}`` pieces, the path kept) or the end
point's pieces (``motion.pieces``). Used by ``rprpr repair`` for its output.
"""

from __future__ import annotations

from typing import Any

import yaml
from flint import fmpq

from ..model.actuation import REVOLUTE
from ..model.defaults import SCHEMA_MODELINE
from ..model.numbers import polynomial
from ..model.numbers import rational_text as number
from ..model.task import Robot, Task


def task_mapping(task: Task, comment: str = "") -> dict[str, Any]:
    """The task file's mapping of ``task`` (its name, robot, motion and checks)."""
    out: dict[str, Any] = {"name": task.name, "robot": _robot(task.robot)}
    pieces = task.motion
    if task.path is not None:
        x0, xf = pieces[0].x(fmpq(0)), pieces[-1].x(task.duration)
        out["path"] = {
            "y": polynomial(task.path, "x"),
            "from": [_Q(x0), _Q(task.path(x0))],
            "to": [_Q(xf), _Q(task.path(xf))],
        }
        timing: dict[str, Any] = {"duration": _D(task.duration)}
        if len(pieces) == 1:
            timing["x"] = polynomial(pieces[0].x, "t")
        else:
            timing["x"] = [{"until": _Q(p.end), "x": polynomial(p.x, "t")} for p in pieces]
        out["timing"] = timing
    else:
        out["motion"] = {
            "pieces": [
                {"until": _Q(p.end), "x": polynomial(p.x, "t"), "y": polynomial(p.y, "t")}
                for p in pieces
            ]
        }
    c = task.checks
    checks: dict[str, Any] = {}
    if c.min_slope:
        checks["min_slope"] = _D(c.min_slope)
    if c.min_speed:
        checks["min_speed"] = _D(c.min_speed)
    if c.torque_limit is not None:
        checks["torque_limit"] = [_D(c.torque_limit[0]), _D(c.torque_limit[1])]
    if c.strict:
        checks["strict"] = True
    if c.unbounded_torque != "fail":
        checks["unbounded_torque"] = c.unbounded_torque
    if checks:
        out["checks"] = checks
    return out


def _robot(r: Robot) -> dict[str, Any]:
    """The task file's ``robot``: the RPRPR's (its actuation when not the default), or a
    5R's (``mechanism: 5R``, base, lengths, modes)."""
    links = {
        i: {"mass": _D(k.mass), "inertia": _D(k.inertia), "r": _D(k.r)}
        for i, k in sorted(r.links.items())
    }
    if r.five_bar is not None:
        fb = r.five_bar
        return {
            "mechanism": r.mechanism,
            "base": _D(fb.a),
            "lengths": [_D(length) for length in fb.lengths],
            "modes": list(fb.modes),
            "gravity": _D(r.gravity),
            "links": links,
        }
    out: dict[str, Any] = {"a1": _D(r.a1), "gravity": _D(r.gravity), "links": links}
    if r.actuation != REVOLUTE:  # the default is not written (as the user's file had it)
        out = {"actuation": r.actuation, **out}
    return out


def decimal(q: fmpq) -> str:
    """An exact rational as a terminating decimal (0.05), for the keys that take no
    fraction; ValueError when its denominator has a prime factor other than 2 and 5."""
    d, k2, k5 = int(q.q), 0, 0
    while d % 2 == 0:
        d, k2 = d // 2, k2 + 1
    while d % 5 == 0:
        d, k5 = d // 5, k5 + 1
    if d != 1:
        raise ValueError(f"{number(q)} has no exact decimal form")
    k = max(k2, k5)
    if k == 0:
        return str(q.p)
    scaled = abs(int(q.p)) * 10**k // int(q.q)
    digits = str(scaled).rjust(k + 1, "0")
    return ("-" if q < 0 else "") + digits[:-k] + "." + digits[-k:]


class _Q(str):
    """An exact number, written plain (3) or as a fraction (1/20)."""

    def __new__(cls, q: fmpq) -> _Q:
        return super().__new__(cls, number(q))


class _D(str):
    """An exact number written as a decimal (0.05)."""

    def __new__(cls, q: fmpq) -> _D:
        return super().__new__(cls, decimal(q))


class Dumper(yaml.SafeDumper):  # type: ignore[misc]
    """YAML's safe dumper, writing exact numbers plain (3, 0.05) or as fractions (1/20)."""


def _represent_q(dumper: yaml.SafeDumper, value: str) -> yaml.Node:
    tag = "tag:yaml.org,2002:" + ("str" if "/" in value else "float" if "." in value else "int")
    return dumper.represent_scalar(tag, str(value))


Dumper.add_representer(_Q, _represent_q)
Dumper.add_representer(_D, _represent_q)


def task_text(task: Task, comment: str = "", modeline: str = SCHEMA_MODELINE) -> str:
    """``task`` as task-file text: the schema ``modeline`` (by default ``rprpr init``'s),
    then ``comment`` (lines) at its top."""
    head = f"{modeline}\n"
    head += "".join(f"# {line}\n" if line else "#\n" for line in comment.splitlines())
    body = yaml.dump(
        task_mapping(task), Dumper=Dumper, sort_keys=False, allow_unicode=True, width=10_000
    )
    return head + body

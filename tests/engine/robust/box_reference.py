"""The consistency residual at a Type II instant over a box, from the independent
reference (``tests/reference.py``: mpmath, the paper's equations, nothing from
``rprpr.engine``), shared by the robust tests and the repair's.

The joint values at t_s depend on the motion and the acceleration error only, so they
are evaluated once per error (``joints``); the residual is then formed from them with
each corner's link parameters (``residual_of``): σ(M22 s1'' + N2) + M44 s2'' + N4 under
the paper's scheme (eq. 34), U1/s1 + σ U2/s2 under the prismatic one (docs/prismatic.md).
"""

from __future__ import annotations

import dataclasses
import itertools
from fractions import Fraction
from typing import Any

import mpmath
from flint import fmpq

from rprpr.model.task import Link, Task, Uncertainty
from tests import reference as ref

DPS = 50
Q = Fraction
Motion = tuple[Q, Q, Q, Q, Q, Q]  # x, x', x'', y, y', y'' at one time


def link_corners(task: Task, u: Uncertainty) -> list[dict[int, Link]]:
    """Every corner of the links' box: each link's (mass, inertia, r) at its ends (one
    value where the half-width is 0)."""
    axes = []
    for i in (2, 3, 4, 5):
        link = task.robot.links[i]
        ends = []
        for v, w in zip((link.mass, link.inertia, link.r), u.links[i], strict=True):
            q, w = Q(int(v.p), int(v.q)), Q(str(w))
            ends.append(sorted({q - abs(q) * w, q + abs(q) * w}))
        axes.append([(i, m, j, r) for m in ends[0] for j in ends[1] for r in ends[2]])
    return [
        {i: Link(_q(m), _q(j), _q(r)) for i, m, j, r in combo} for combo in itertools.product(*axes)
    ]


def errors(u: Uncertainty) -> list[tuple[Q, Q]]:
    """The corners of the acceleration error's square (one point when it is 0)."""
    a = Q(str(u.acceleration))
    return sorted({(sx * a, sy * a) for sx in (-1, 1) for sy in (-1, 1)})


def joints(task: Task, motion: Motion, e: tuple[Q, Q]) -> dict[str, Any]:
    """The reference's joint values for ``motion`` with the error ``e`` added."""
    x, xd, xdd, y, yd, ydd = motion
    with mpmath.workdps(DPS):
        return ref._evaluate(task, (x, xd, xdd + e[0], y, yd, ydd + e[1]), upto_delta=True)


def residual_of(task: Task, links: dict[int, Link], v: dict[str, Any]) -> Any:
    """The consistency residual from the joint values ``v`` (eqs. 7-14) with ``links``."""
    with mpmath.workdps(DPS):
        g = ref._mpf(task.robot.gravity)
        m = {i: ref._mpf(links[i].mass) for i in links}
        inertia = {i: ref._mpf(links[i].inertia) for i in links}
        r = {i: ref._mpf(links[i].r) for i in links}
        s1, s2 = v["s1"], v["s2"]
        c1, c2 = mpmath.cos(v["theta1"]), mpmath.cos(v["theta2"])
        sigma = 1 if c1 * c2 > 0 else -1
        if task.robot.actuation == "prismatic":
            M11 = m[2] * r[2] ** 2 + inertia[2] + m[3] * (s1 - r[3]) ** 2 + inertia[3]
            M33 = m[4] * r[4] ** 2 + inertia[4] + m[5] * (s2 - r[5]) ** 2 + inertia[5]
            N1 = (
                2 * m[3] * v["s1_dot"] * v["theta1_dot"] * (s1 - r[3])
                + (m[2] * r[2] + m[3] * (s1 - r[3])) * g * c1
            )
            N3 = (
                2 * m[5] * v["s2_dot"] * v["theta2_dot"] * (s2 - r[5])
                + (m[4] * r[4] + m[5] * (s2 - r[5])) * g * c2
            )
            U1 = M11 * v["theta1_ddot"] + N1
            U2 = M33 * v["theta2_ddot"] + N3
            return U1 / s1 + sigma * U2 / s2
        N2 = -m[3] * (s1 - r[3]) * v["theta1_dot"] ** 2  # sin θ1 = 0 at t_s
        N4 = -m[5] * (s2 - r[5]) * v["theta2_dot"] ** 2
        return sigma * (m[3] * v["s1_ddot"] + N2) + m[5] * v["s2_ddot"] + N4


def vertex_residuals(task: Task, u: Uncertainty, motion: Motion) -> list[Any]:
    """The residual at every vertex of the box (links and error) for ``motion`` at t_s."""
    corners = link_corners(task, u)
    out = []
    for e in errors(u):
        v = joints(task, motion, e)
        out += [residual_of(task, links, v) for links in corners]
    return out


def task_with(task: Task, links: dict[int, Link]) -> Task:
    return dataclasses.replace(task, robot=dataclasses.replace(task.robot, links=links))


def _q(v: Q) -> fmpq:
    return fmpq(v.numerator, v.denominator)

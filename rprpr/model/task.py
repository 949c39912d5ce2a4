"""The task: a robot, a path and a timing law, as frozen dataclasses of exact numbers.

A ``Task`` is what the loader hands to the core; it is already validated (positive
a1, non-negative masses, a path that meets ``from``/``to``, ...), so the core never
sees a bad task. Numbers are ``flint.fmpq`` (exact rationals), polynomials
``flint.fmpq_poly``. Lengths in m, masses in kg, inertias in kg m^2, times in s.

No field holds a default value of the task file (gravity 9.81, zero margins, ...): their
one home is ``io.schema.TASK`` (``Spec.default``), which the loader applies.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from flint import fmpq, fmpq_poly


@dataclass(frozen=True)
class Link:
    """One moving link i = 2..5: mass m_i, centroidal inertia I_i, and r_i (Section 2)."""

    mass: fmpq
    inertia: fmpq
    r: fmpq


@dataclass(frozen=True)
class Robot:
    """Fixed link length a1 = |AB| (A at the origin, B at (a1, 0)), gravity g along -y,
    and the moving links 2 (leg A, revolute side), 3 (leg A, at E), 4 and 5 (leg B)."""

    a1: fmpq
    links: dict[int, Link]
    gravity: fmpq


@dataclass(frozen=True)
class Checks:
    """The user's margins: |dy/dx| > min_slope and speed > min_speed at a singular
    instant; torque_limit = (|T1| max, |T2| max) in N m or None; strict gates also on
    the torque limit (and on every finding); unbounded_torque "fail" (unbounded torques
    at a singular instant fail the task) or "warn" (accepted: a warning, failing only in
    strict mode); ``rules``: the level chosen for a rule (rule id -> "error", "warn" or
    "ignore", ``rules.with_levels``), from the task's ``checks.ignore`` and
    ``checks.warn`` (each with the reason the file gives) and the repository's
    configuration."""

    min_slope: fmpq
    min_speed: fmpq
    torque_limit: tuple[fmpq, fmpq] | None
    strict: bool
    unbounded_torque: str
    rules: dict[str, str]


@dataclass(frozen=True)
class Task:
    """An audited motion: the end point follows y = path(x) with x = x_of_t(t), 0 <= t <= duration.

    ``law`` records how x(t) was given ("quintic", "cubic" or "explicit"); ``lines`` maps
    dotted key paths (``path.y``, ``timing``) to their 1-based line in the task file, so
    that findings can point back at the file.
    """

    name: str
    robot: Robot
    path: fmpq_poly
    x_of_t: fmpq_poly
    duration: fmpq
    checks: Checks
    law: str = "explicit"
    lines: dict[str, int] = field(default_factory=dict)
    source: str = ""

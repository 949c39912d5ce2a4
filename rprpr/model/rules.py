"""The audit's rules: stable ids, names, what each means and how to fix it (one home).

A rule is *gating* when a finding of it fails the task in every mode, and *strict* when it
fails the task only in strict mode (``--strict`` or ``checks.strict: true``) and is a
warning otherwise. ``key`` is the task-file key a finding points back to. A gating finding
the user chose to accept (RPR201 under ``checks.unbounded_torque: warn`` or
``--warn-unbounded``) is ``downgraded``: it then fails only in strict mode, like a strict
rule's.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Rule:
    id: str
    name: str
    strict_only: bool
    key: str
    meaning: str
    fix: str

    @property
    def title(self) -> str:
        return f"{self.id} {self.name}"


RULES: dict[str, Rule] = {
    r.id: r
    for r in (
        Rule(
            "RPR001", "invalid-task", False, "",
            "The task file could not be read or validated.",
            "Correct the key the message names; `rprpr schema` prints what is allowed.",
        ),
        Rule(
            "RPR101", "slope-principle", False, "path.y",
            "At a Type II singular point the path is horizontal (dy/dx = 0, eq. 48) or its "
            "slope does not exceed checks.min_slope: the singularity is of high order.",
            "Reshape path.y so that it crosses y = 0 with a nonzero slope (paper, Section 3).",
        ),
        Rule(
            "RPR102", "velocity-principle", False, "timing",
            "At a Type II singular instant the end point is at rest (eq. 47) or slower than "
            "checks.min_speed: the singularity is of high order.",
            "Change the timing law so that the end point moves through the singular point.",
        ),
        Rule(
            "RPR103", "kinematic-singularity", False, "path.y",
            "The end point reaches A or B (s1 = 0 or s2 = 0): the inverse kinematics fail.",
            "Keep the path away from the base joints A = (0, 0) and B = (a1, 0).",
        ),
        Rule(
            "RPR104", "path-on-singular-line", False, "path.y",
            "The path lies on the line AB (y = 0): the robot is singular all along the motion.",
            "Move the path off the x-axis; cross it only at isolated points.",
        ),
        Rule(
            "RPR201", "unbounded-torque", False, "robot.links",
            "At a Type II singular instant the torques are unbounded (infinite torque cannot "
            "be executed): the equations of motion are inconsistent (eq. 34 residual ≠ 0) or "
            "fewer than all boundedness conditions hold (k of m).",
            "Change the mass distribution or the timing so that eq. (34) and the conditions "
            "on the derivatives of μ1, μ2 hold at t_s, or avoid the singularity; to accept "
            "it, checks.unbounded_torque: warn or --warn-unbounded.",
        ),
        Rule(
            "RPR202", "torque-limit", True, "checks.torque_limit",
            "A required actuator torque exceeds checks.torque_limit.",
            "Slow the motion down (timing.duration) or raise the limit if the drives allow.",
        ),
    )
}  # fmt: skip


@dataclass(frozen=True)
class Finding:
    """One thing the audit found wrong: the rule, a message, and when (None: the whole task).

    The task-file key it points back to is the rule's (``Rule.key``), never passed by hand.
    """

    rule: str
    message: str
    t: float | None = None
    downgraded: bool = False  # accepted by the user: fails only in strict mode

    @property
    def key(self) -> str:
        return RULES[self.rule].key

    @property
    def strict_only(self) -> bool:
        """The finding fails its task only in strict mode (its rule's, or downgraded)."""
        return RULES[self.rule].strict_only or self.downgraded

    def fails(self, strict: bool) -> bool:
        return strict or not self.strict_only

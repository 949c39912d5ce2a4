"""The audit's rules: stable ids, names, what each means and how to fix it (one home).

A rule is *gating* when a finding of it fails the task in every mode, and *strict* when it
fails the task only in strict mode (``--strict`` or ``checks.strict: true``) and is a
warning otherwise. ``key`` is the task-file key a finding points back to. A gating finding
the user chose to accept (RPR201 under ``checks.unbounded_torque: warn`` or
``--warn-unbounded``) is ``downgraded``: it then fails only in strict mode, like a strict
rule's.

Each rule's *level* can be set per repository (``[tool.rprpr]``: ``select``, ``ignore``,
``warn``, ``error``) and per task (``checks.ignore``, ``checks.warn``): ``ignore`` drops
its findings, ``warn`` downgrades them, ``error`` promotes them (they fail in every mode).
``levels`` resolves rule selectors (``RPR2`` names RPR201 and RPR202) into one level per
rule, ``with_levels`` applies them to findings.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import field, replace

from .dataclass import dataclass

INVALID_TASK = "RPR001"  # a task file that cannot be read: never audited, never silenced
LEVELS = ("error", "warn", "ignore")
ALL = "ALL"  # the selector of every rule


@dataclass(frozen=True)
class Rule:
    """A rule: its id and name, whether it gates only in strict mode, the task-file key a
    finding points at; what it checks (``meaning``), the paper's equation it rests on,
    why it matters and how to fix it (``rprpr rule ID`` prints them all)."""

    id: str
    name: str
    strict_only: bool
    key: str
    meaning: str
    fix: str
    equation: str = ""
    why: str = ""

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
            "",
            "A task that cannot be read is never audited: no verdict can be trusted.",
        ),
        Rule(
            "RPR101", "slope-principle", False, "path.y",
            "At a Type II singular point the path is horizontal (dy/dx = 0, eq. 48) or its "
            "slope does not exceed checks.min_slope: the singularity is of high order.",
            "Reshape path.y so that it crosses y = 0 with a nonzero slope (paper, Section 3).",
            "eq. (48): dy_E/dx_E = 0 at δ = 0 (eq. 29) makes the singularity of high order "
            "(eq. 46)",
            "A high-order singularity needs more conditions than the consistency of eq. (34) "
            "to be passed with bounded torques; with a nonzero slope, consistency alone "
            "suffices (the paper's path design principle).",
        ),
        Rule(
            "RPR102", "velocity-principle", False, "timing",
            "At a Type II singular instant the end point is at rest (eq. 47) or slower than "
            "checks.min_speed: the singularity is of high order.",
            "Change the timing law so that the end point moves through the singular point.",
            "eq. (47): the end-point velocity is zero at δ = 0 (eq. 29), which makes the "
            "singularity of high order (eq. 46)",
            "An end point at rest on the singular line turns a first-order singularity into "
            "a high-order one; keeping it moving is the paper's trajectory design principle.",
        ),
        Rule(
            "RPR103", "kinematic-singularity", False, "path.y",
            "The end point reaches A or B (s1 = 0 or s2 = 0): the inverse kinematics fail.",
            "Keep the path away from the base joints A = (0, 0) and B = (a1, 0).",
            "s1 = |AE| = 0 or s2 = |BE| = 0: the joint angles θ1, θ2 are undefined",
            "The inverse kinematics have no solution there: no joint motion follows the "
            "path, whatever the torques.",
        ),
        Rule(
            "RPR104", "path-on-singular-line", False, "path.y",
            "The path lies on the line AB (y = 0): the robot is singular all along the motion.",
            "Move the path off the x-axis; cross it only at isolated points.",
            "eq. (29): δ = sin(θ1 - θ2) ≡ 0 when y_E ≡ 0",
            "The robot stays in a Type II singular configuration (Table 1): the actuated "
            "joints cannot control the end point anywhere along the motion.",
        ),
        Rule(
            "RPR201", "unbounded-torque", False, "robot.links",
            "At a Type II singular instant the torques are unbounded (infinite torque cannot "
            "be executed): the equations of motion are inconsistent (eq. 34 residual ≠ 0) or "
            "fewer than all boundedness conditions hold (k of m).",
            "Change the mass distribution or the timing so that eq. (34) and the conditions "
            "on the derivatives of μ1, μ2 hold at t_s, or avoid the singularity; to accept "
            "it, checks.unbounded_torque: warn or --warn-unbounded.",
            "eqs. (30)-(36): λ = μ/δ stays finite at δ = 0 only if μ1 = μ2 = 0 there "
            "(eq. 35), i.e. the consistency condition eq. (34) holds, plus the higher "
            "conditions of a high-order singularity",
            "Unbounded torques saturate the actuators: the robot becomes uncontrollable at "
            "the singular instant (the paper's Introduction).",
        ),
        Rule(
            "RPR202", "torque-limit", True, "checks.torque_limit",
            "A required actuator torque exceeds checks.torque_limit.",
            "Slow the motion down (timing.duration) or raise the limit if the drives allow.",
            "eq. (28): the torques T1, T2 of the inverse dynamics, certified over [0, t_f]",
            "A drive asked for more than it can give saturates: the motion is not followed.",
        ),
        Rule(
            "RPR203", "velocity-jump", False, "motion",
            "At a knot t_k of a piecewise motion the end-point velocity jumps (a C0 knot, "
            "e.g. waypoints with positions only): the torques would be impulsive there.",
            "Give the waypoints velocities (cubic or quintic segments), or pieces whose "
            "first derivatives agree at every knot.",
            "eq. (28): the torques depend on the accelerations s'', θ'', which are a Dirac "
            "impulse where the velocity jumps",
            "No actuator delivers an impulse: the motion is not followed at the knot.",
        ),
        Rule(
            "RPR204", "torque-jump", True, "motion",
            "At a knot t_k of a piecewise motion the end-point acceleration jumps (a C1 "
            "knot): the torques T1, T2 jump by the amounts the message gives.",
            "Give the waypoints accelerations (quintic segments) or pieces whose second "
            "derivatives agree at every knot, if the drives cannot follow a torque step.",
            "eq. (28): the torques depend on the accelerations, which jump at a C1 knot",
            "A torque step excites the structure and the current loops; it is executable, "
            "so it is a warning (it fails only in strict mode).",
        ),
        Rule(
            "RPR205", "saturation-window", False, "uncertainty",
            "With uncertainty declared: around a Type II singular instant, for some link "
            "parameters within the declared box and some acceleration tracking error within "
            "its bound, an effort may exceed checks.torque_limit for longer than the "
            "controller's period (docs/robust.md).",
            "Make the crossing consistent for the nominal model (rprpr repair), cross faster "
            "(|dy/dt| larger) or with a steeper path, track the acceleration more closely, or "
            "identify the masses better; a window no longer than uncertainty.period passes.",
            "eqs. (30)-(34): near t_s, λ = μ/δ with μ(t_s) the residual of eq. (34) over "
            "the box and δ ≈ -a1 ẏ (t - t_s)/(s1 s2)",
            "No real crossing is exact: masses are known to a few per cent and a controller "
            "tracks with error, so the residual is never exactly zero; what decides is how "
            "long the actuators saturate, against the controller's sample period.",
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
    promoted: bool = False  # made an error by the user: fails in every mode
    line: int | None = None  # the task file's line it points at, when not its key's (a knot)
    # the index of the singular instant it was made at (``AuditResult.findings_at``)
    instant: int | None = field(default=None, repr=False)
    # the mode of the audit that made it (``audit`` sets it): what ``severity`` reads
    strict: bool = field(default=False, compare=False, repr=False)

    @property
    def key(self) -> str:
        return RULES[self.rule].key

    @property
    def strict_only(self) -> bool:
        """The finding fails its task only in strict mode (its rule's, or downgraded),
        unless promoted."""
        return not self.promoted and (RULES[self.rule].strict_only or self.downgraded)

    def fails(self, strict: bool) -> bool:
        return strict or not self.strict_only

    @property
    def severity(self) -> str:
        """ "error" when the finding fails its task in the mode of the audit that made it
        (``strict``), else "warning": the ``[severity]`` of every report."""
        return "error" if self.fails(self.strict) else "warning"


class Judged:
    """The verdict of an audit's result from its ``findings`` and ``strict`` (what every
    mechanism's result shares): "fail" if a finding fails under ``strict``, else "pass"."""

    findings: Sequence[Finding]
    strict: bool

    @property
    def verdict(self) -> str:
        return "fail" if any(f.fails(self.strict) for f in self.findings) else "pass"

    @property
    def passed(self) -> bool:
        return self.verdict == "pass"


def with_levels(findings: Iterable[Finding], levels: Mapping[str, str]) -> list[Finding]:
    """``findings`` at the levels chosen for their rules (``levels``: rule id -> "error",
    "warn" or "ignore"; a rule not named keeps its own level): an ignored rule's findings
    are dropped, a warned one's downgraded, an error's promoted."""
    out = []
    for f in findings:
        level = levels.get(f.rule)
        if level == "ignore":
            continue
        if level is not None:
            f = replace(f, downgraded=level == "warn", promoted=level == "error")
        out.append(f)
    return out


class SelectorError(ValueError):
    """A rule selector that names no rule, or a rule given two levels at once."""


def rule_id(name_or_id: str) -> str | None:
    """The id of the rule named by its id (any case: ``rpr201``) or its name
    (``unbounded-torque``); None when no rule is so named."""
    wanted = name_or_id.strip()
    for r in RULES.values():
        if wanted.upper() == r.id or wanted.lower() == r.name:
            return r.id
    return None


def selected(selector: str) -> list[str]:
    """The audit rules a selector names: ``ALL``, a rule id (``RPR201``) or its name
    (``unbounded-torque``), or the start of ids (``RPR2``: RPR201 and RPR202); RPR001 is
    never among them. A selector that names no rule is a ``SelectorError`` (with the
    closest id or name, when one is close)."""
    audit_rules = [r for r in RULES if r != INVALID_TASK]
    if selector == ALL:
        return audit_rules
    named = rule_id(selector) if not selector.startswith("RPR") else None
    if named is not None and named != INVALID_TASK:
        return [named]
    if selector == INVALID_TASK or named == INVALID_TASK:
        raise SelectorError(
            f"{INVALID_TASK} ({RULES[INVALID_TASK].name}) cannot be selected, ignored or"
            " demoted: a task file that cannot be read is never audited"
        )
    found = [r for r in audit_rules if r.startswith(selector)]
    if not found or not selector.startswith("RPR"):
        import difflib

        names = [RULES[r].name for r in audit_rules]
        near = difflib.get_close_matches(selector.upper(), audit_rules, n=1, cutoff=0.6)
        near = near or difflib.get_close_matches(selector.lower(), names, n=1, cutoff=0.6)
        hint = f" (did you mean {near[0]}?)" if near else ""
        raise SelectorError(f"unknown rule {selector!r}{hint}; `rprpr rule` lists the rules")
    return found


def levels(
    select: Sequence[str] = (ALL,),
    ignore: Sequence[str] = (),
    warn: Sequence[str] = (),
    error: Sequence[str] = (),
) -> dict[str, str]:
    """The level of each rule that the selectors change (rule id -> "error", "warn" or
    "ignore"), as ruff resolves them: a rule not selected is ignored; between selectors
    naming the same rule the most specific (longest) wins; ``ignore`` wins a tie with
    ``select``; ``warn`` and ``error`` naming a rule equally specifically is a
    ``SelectorError``."""
    spec: dict[str, dict[str, int]] = {}
    for kind, selectors in (("select", select), ("ignore", ignore), ("warn", warn),
                            ("error", error)):  # fmt: skip
        for sel in selectors:
            # as specific as its characters of an id; a name is as specific as its rule's id
            named = rule_id(sel) if not sel.startswith("RPR") else None
            weight = 0 if sel == ALL else len(named or sel)
            for r in selected(sel):
                best = spec.setdefault(r, {})
                best[kind] = max(best.get(kind, -1), weight)
    out: dict[str, str] = {}
    for r in RULES:
        if r == INVALID_TASK:
            continue
        s = spec.get(r, {})
        if s.get("select", -1) < 0 or s.get("ignore", -1) >= s["select"]:
            out[r] = "ignore"
            continue
        w, e = s.get("warn", -1), s.get("error", -1)
        if w == e >= 0:
            raise SelectorError(f"{r} is both in warn and in error: name it in one")
        if max(w, e) >= 0:
            out[r] = "warn" if w > e else "error"
    return out

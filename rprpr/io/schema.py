"""The task-file schema, as data: the one home of what a task file may contain.

The loader walks it generically (``loader``: kinds, bounds, choices, required and
unknown keys, defaults) and ``rprpr schema`` prints it as a JSON Schema (draft 2020-12)
for editors (``json_schema``). What spans several keys (from/to on the path, law or x,
the degree of y(x(t))) is the loader's, as small named rules.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..model.rules import INVALID_TASK, RULES
from ..model.timing import LAWS

UNBOUNDED_TORQUE = ("fail", "warn")  # checks.unbounded_torque


@dataclass(frozen=True)
class Spec:
    """One key of the task file.

    kind: "mapping", "number", "polynomial", "string", "bool", "enum", "pair" (a list
    of two numbers, ``items`` naming each) or "point" (a point of the path: its x alone,
    ``[x, y]`` or ``{x: ..., y: ...}``, each coordinate a decimal or a fraction such as
    ``-2/3``; y, when given, must be p(x) exactly, and is p(x) when left out). For
    numbers and pairs, ``minimum`` with ``exclusive`` bounds the value. ``default`` is
    the value of an omitted key (a number as its decimal text, so that it is exact); the
    loader applies it, ``rprpr schema`` prints it.
    """

    kind: str
    description: str
    required: bool = False
    default: Any = None
    minimum: float | None = None
    exclusive: bool = False
    variable: str = ""  # of a polynomial
    choices: tuple[str, ...] = ()
    children: dict[str, Spec] = field(default_factory=dict)
    items: tuple[str, ...] = ()  # of a pair: what each number is, for messages


def _num(
    description: str,
    *,
    required: bool = False,
    minimum: float | None = None,
    exclusive: bool = False,
    default: Any = None,
) -> Spec:
    return Spec("number", description, required, default, minimum, exclusive)


def _reasons(description: str) -> Spec:
    """``checks.ignore`` / ``checks.warn``: rule id -> the reason, as text (required)."""
    return Spec(
        "mapping",
        description,
        children={
            r.id: Spec("string", f"Why {r.id} ({r.name}) is accepted here.")
            for r in RULES.values()
            if r.id != INVALID_TASK
        },
    )


def _link(i: int, r_means: str) -> Spec:
    return Spec(
        "mapping",
        f"Link {i}: mass, centroidal moment of inertia and r{i} = {r_means}.",
        required=True,
        children={
            "mass": _num(f"m{i} [kg]", required=True, minimum=0),
            "inertia": _num(f"I{i}, centroidal [kg m^2]", required=True, minimum=0),
            "r": _num(f"r{i} = {r_means} [m]", required=True, minimum=0),
        },
    )


_POINT = ("x [m]", "y [m]")
_POINT_MEANS = (
    "{} point on the path [m]: x alone (1, -2/3), [x, y] or {{x: ..., y: ...}}; numbers"
    " or fractions such as -2/3; y, when given, must equal p(x) exactly (left out: p(x))."
)
# a coordinate of a point written as a fraction of two decimals: -2/3, 1.5/4
_DECIMAL = r"([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?"
FRACTION_PATTERN = rf"^\s*[-+]?\s*{_DECIMAL}\s*(/\s*{_DECIMAL}\s*)?$"

TASK = Spec(
    "mapping",
    "An rprpr task: an RPRPR planar parallel robot and a planned end-point motion.",
    children={
        "name": Spec("string", "A name for reports (default: the file's stem)."),
        "robot": Spec(
            "mapping",
            "The robot: A at the origin, B at (a1, 0); actuated revolute joints at A and B.",
            required=True,
            children={
                "a1": _num("|AB| [m]", required=True, minimum=0, exclusive=True),
                "gravity": _num("g [m/s^2], along -y", minimum=0, default="9.81"),
                "links": Spec(
                    "mapping",
                    "The paper's moving links 2..5.",
                    required=True,
                    children={
                        "2": _link(2, "|AG2|"),
                        "3": _link(3, "|EG3|"),
                        "4": _link(4, "|BG4|"),
                        "5": _link(5, "|EG5|"),
                    },
                ),
            },
        ),
        "path": Spec(
            "mapping",
            "The end-point path y = p(x).",
            required=True,
            children={
                "y": Spec(
                    "polynomial",
                    "p(x) [m]: numbers, x, + - * / ^ ** and parentheses.",
                    required=True,
                    variable="x",
                ),
                "from": Spec("point", _POINT_MEANS.format("Start"), items=_POINT),
                "to": Spec("point", _POINT_MEANS.format("End"), items=_POINT),
            },
        ),
        "timing": Spec(
            "mapping",
            "How x_E moves in time: a rest-to-rest law between path.from and path.to, or x.",
            required=True,
            children={
                "duration": _num("t_f [s]", required=True, minimum=0, exclusive=True),
                "law": Spec(
                    "enum",
                    "Rest-to-rest law in x (eq. 49 is the quintic).",
                    choices=LAWS,
                ),
                "x": Spec("polynomial", "x_E(t) [m], explicitly, instead of law.", variable="t"),
            },
        ),
        "checks": Spec(
            "mapping",
            "Margins and limits.",
            children={
                "min_slope": _num(
                    "|dy/dx| at a singular point must exceed this", minimum=0, default=0
                ),
                "min_speed": _num(
                    "End-point speed [m/s] at a singular instant must exceed this",
                    minimum=0,
                    default=0,
                ),
                "torque_limit": Spec(
                    "pair",
                    "|T1|, |T2| limits [N m], each > 0; gated in strict mode.",
                    minimum=0,
                    exclusive=True,
                    items=("|T1| limit [N m]", "|T2| limit [N m]"),
                ),
                "strict": Spec(
                    "bool",
                    "Also fail on torque limits and on accepted unbounded torques.",
                    default=False,
                ),
                "unbounded_torque": Spec(
                    "enum",
                    "A singular instant with unbounded torques (RPR201): fail the task, or "
                    "warn (accepted; fails only in strict mode).",
                    default="fail",
                    choices=UNBOUNDED_TORQUE,
                ),
                "ignore": _reasons("Rules silenced for this task (no finding), each with why."),
                "warn": _reasons("Rules downgraded to warnings for this task, each with why."),
            },
        ),
    },
)


def json_schema() -> dict[str, Any]:
    """The task schema as a JSON Schema (draft 2020-12) document.

    Shipped as ``rprpr/io/task.schema.json`` (a test keeps the two equal). JSON Schema
    cannot say everything the loader checks: the exact polynomial grammar (the pattern
    below only admits the right characters), the degree caps, ``from``/``to`` lying on
    the path and agreeing with an explicit x(t), finite numbers, duplicate keys and
    YAML tags are the loader's alone.
    """
    doc = _json(TASK)
    doc["$schema"] = "https://json-schema.org/draft/2020-12/schema"
    doc["$id"] = "https://rprpr.dev/schema/task.json"
    doc["title"] = "rprpr task file"
    timing = doc["properties"]["timing"]
    timing["oneOf"] = [{"required": ["law"]}, {"required": ["x"]}]
    # A rest-to-rest law moves between path.from and path.to, so it needs both.
    doc["if"] = {"required": ["timing"], "properties": {"timing": {"required": ["law"]}}}
    doc["then"] = {"properties": {"path": {"required": ["from", "to"]}}}
    return doc


def _json(s: Spec) -> dict[str, Any]:
    out: dict[str, Any] = {"description": s.description}
    if s.kind == "mapping":
        out["type"] = "object"
        out["properties"] = {k: _json(v) for k, v in s.children.items()}
        out["required"] = [k for k, v in s.children.items() if v.required]
        out["additionalProperties"] = False
    elif s.kind == "number":
        out["type"] = "number"
        if s.minimum is not None:
            out["exclusiveMinimum" if s.exclusive else "minimum"] = s.minimum
    elif s.kind == "polynomial":
        out["type"] = ["string", "number"]
        # the grammar's characters only, with at least one digit or the variable
        chars = rf"[0-9{s.variable}+\-*/^(). \t\r\neE]*"
        out["pattern"] = rf"^{chars}[0-9{s.variable}]{chars}$"
    elif s.kind == "string":
        out["type"] = ["string", "number"]  # a name such as 2024 is taken as written
    elif s.kind == "bool":
        out["type"] = "boolean"
    elif s.kind == "enum":
        out["enum"] = list(s.choices)
    elif s.kind == "point":
        fraction = {"type": "string", "pattern": FRACTION_PATTERN}
        coordinate = {"oneOf": [{"type": "number"}, fraction]}
        out["oneOf"] = [
            coordinate,
            {"type": "array", "items": coordinate, "minItems": 2, "maxItems": 2},
            {
                "type": "object",
                "properties": {"x": coordinate, "y": coordinate},
                "required": ["x"],
                "additionalProperties": False,
            },
        ]
    elif s.kind == "pair":
        item: dict[str, Any] = {"type": "number"}
        if s.minimum is not None:
            item["exclusiveMinimum" if s.exclusive else "minimum"] = s.minimum
        out.update(type="array", items=item, minItems=2, maxItems=2)
    if s.default is not None:
        number = s.kind == "number" and isinstance(s.default, str)  # a decimal's text
        out["default"] = float(s.default) if number else s.default
    return out

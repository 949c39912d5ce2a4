"""The task-file schema, as data: the one home of what a task file may contain.

The loader walks it generically (``loader``: kinds, bounds, choices, required and
unknown keys, defaults) and ``rprpr schema`` prints it as a JSON Schema (draft 2020-12)
for editors (``json_schema``). What spans several keys (from/to on the path, law or x,
the degree of y(x(t))) is the loader's, as small named rules.
"""

from __future__ import annotations

from dataclasses import field, replace
from typing import Any

from ..model.actuation import ACTUATIONS, REVOLUTE
from ..model.dataclass import dataclass
from ..model.defaults import LINK_QUANTITIES, MOVING_LINKS, PERCENT, SCHEMA_URL
from ..model.five_bar import FIVE_BAR, MECHANISMS, RPRPR
from ..model.rules import INVALID_TASK, RULES
from ..model.timing import LAWS

TRAPEZOIDAL = "trapezoidal"  # timing.law: the piecewise LSPB law (model.timing.trapezoidal)

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

    The piecewise motions add: "time" (an instant [s], >= 0: a decimal or a fraction
    such as ``5/3``), "vector" (a list of two numbers or fractions, ``items`` naming
    each), "list" (a list of mappings, each read with ``item``) and "waypoints" (such a
    list, or the name of a CSV file). A "polynomial" with ``item`` may also be given as a
    list of pieces, each read with ``item``. A key ``required`` ``unless`` its sibling
    key ``unless`` is given (``path`` and ``timing``, unless ``motion``) is only required
    without it.

    The 5R adds: "numbers" (a list of ``len(items)`` numbers, each bounded as "pair"'s)
    and "signs" (a list of ``len(items)`` signs, each +1 or -1). A mapping whose keys
    depend on the value of one of them (``robot``, by ``mechanism``) names that key
    ``select`` and its other forms ``variants`` (the value -> the mapping read instead;
    the key's default reads the mapping itself); ``elsewhere`` maps a key of another
    form to (what to say when it is given here, the key of this form it stands for).
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
    item: Spec | None = None  # of a list: the mapping each element is
    unless: str = ""  # a required key is not required when this sibling key is given
    select: str = ""  # of a mapping: the key whose value chooses among ``variants``
    variants: dict[str, Spec] = field(default_factory=dict)
    elsewhere: dict[str, tuple[str, str]] = field(default_factory=dict)


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
    """``checks.ignore`` / ``checks.warn``: rule id or name -> the reason, as text
    (required)."""
    rules = [r for r in RULES.values() if r.id != INVALID_TASK]
    return Spec(
        "mapping",
        description,
        children={
            **{r.id: Spec("string", f"Why {r.id} ({r.name}) is accepted here.") for r in rules},
            **{r.name: Spec("string", f"Why {r.name} ({r.id}) is accepted here.") for r in rules},
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

_TIME = "a decimal or a fraction such as 5/3"
_VECTOR = ("x", "y")


def _time(description: str) -> Spec:
    return Spec("time", f"{description} [s]: {_TIME}.", required=True, minimum=0)


def _vector(what: str, unit: str, *, required: bool = False) -> Spec:
    return Spec(
        "vector",
        f"{what} [{unit}]: [x, y], numbers or fractions such as -2/3.",
        required=required,
        items=tuple(f"{what} {c} [{unit}]" for c in _VECTOR),
    )


def _piece(what: str, coordinates: str) -> Spec:
    """A piece of ``what`` with the polynomials ``coordinates`` (of x_E, y_E) in
    absolute time t, ending at ``until``."""
    children = {"until": _time("End of the piece")}
    for c in coordinates:
        children[c] = Spec(
            "polynomial", f"{c}_E(t) [m] on the piece, in absolute time t.", True, variable="t"
        )
    text = f"A piece of {what}: from the previous piece's until (0 for the first) to until."
    return Spec("mapping", text, children=children)


_X_PIECE = _piece("x_E(t)", "x")
_MOTION_PIECE = _piece("the motion", "xy")
_WAYPOINT = Spec(
    "mapping",
    "A waypoint: time, position, and optionally velocity and acceleration (every point"
    " gives the same fields).",
    children={
        "t": _time("Time from the start"),
        "p": _vector("position", "m", required=True),
        "v": _vector("velocity", "m/s"),
        "a": _vector("acceleration", "m/s^2"),
    },
)
WAYPOINT_COLUMNS = ("t", "x", "y", "vx", "vy", "ax", "ay")  # a waypoint CSV's header

_FRACTION_SCHEMA = {"type": "string", "pattern": FRACTION_PATTERN}
_COORDINATE = {"oneOf": [{"type": "number"}, _FRACTION_SCHEMA]}
# a waypoint CSV: a relative path without "..", ending in .csv
CSV_PATTERN = r"^(?!/)(?!.*(^|/)\.\.(/|$))[^\\\x00-\x1f]*\.[cC][sS][vV]$"

RELATIVE_LINKS = Spec(
    "mapping",
    "Per link 2..5: the relative half-width of each quantity (a quantity not named: 0%).",
    children={
        str(i): Spec(
            "mapping",
            f"Link {i}'s relative half-widths.",
            children={q: Spec("percent", f"{q} of link {i}") for q in LINK_QUANTITIES},
        )
        for i in MOVING_LINKS
    },
)
UNCERTAINTY = Spec(
    "mapping",
    "What the real robot may differ by from the model (docs/robust.md): a window around"
    " each singular instant in which some effort may exceed checks.torque_limit (required"
    " with it), failing (RPR205) when longer than period. Absent: the exact verdicts.",
    children={
        "links": Spec(
            "relative",
            "every link's mass, inertia and r; or per link and quantity: {3: {mass: 2%}};"
            " not given: 0%",
        ),
        "acceleration": _num(
            "Bound on the end point's acceleration tracking error, each axis [m/s^2]; not given: 0",
            minimum=0,
        ),
        "period": _num(
            "The controller's sample period [s]: a saturation window no longer is tolerated;"
            " required: every window is judged against it (period: 0 fails every window)",
            required=True,
            minimum=0,
        ),
    },
)

_MECHANISM = Spec(
    "enum",
    "The robot's mechanism: rprpr (the paper's RPRPR, the default) or 5R (the all-revolute"
    " five-bar, docs/five-bar.md); the robot's other keys depend on it.",
    default=RPRPR,
    choices=MECHANISMS,
)
_GRAVITY = _num("g [m/s^2], along -y", minimum=0, default="9.81")
_FIVE_BAR_KEY = "is for mechanism: 5R (the all-revolute five-bar)"
FIVE_BAR_ROBOT = Spec(
    "mapping",
    "The 5R five-bar (docs/five-bar.md): motors at A = (0, 0) and B = (base, 0) drive the"
    " proximal links 1 (A to the elbow C) and 2 (B to the elbow D), torques T1, T2 [N m];"
    " the distal links 3 (C to E) and 4 (D to E) meet at the end point E.",
    required=True,
    children={
        "mechanism": _MECHANISM,
        "base": _num(
            "|AB| [m], between the motors' axes", required=True, minimum=0, exclusive=True
        ),
        "lengths": Spec(
            "numbers",
            "[l1, l2, l3, l4] [m], each > 0: the proximal links |AC| and |BD|, then the"
            " distal links |CE| and |DE|.",
            required=True,
            minimum=0,
            exclusive=True,
            items=("l1 = |AC| [m]", "l2 = |BD| [m]", "l3 = |CE| [m]", "l4 = |DE| [m]"),
        ),
        "modes": Spec(
            "signs",
            "[e1, e2], each +1 or -1: the working modes at t = 0 (e1 = +1: the elbow C to the"
            " left of AE, seen from A towards E; e2 = +1: D to the left of BE).",
            required=True,
            items=("e1 (the elbow C)", "e2 (the elbow D)"),
        ),
        "gravity": _GRAVITY,
        "links": Spec(
            "mapping",
            "The moving links 1..4: 1 and 2 proximal (at A and B), 3 and 4 distal (at E).",
            required=True,
            children={
                "1": _link(1, "|AG1|"),
                "2": _link(2, "|BG2|"),
                "3": _link(3, "|CG3|"),
                "4": _link(4, "|DG4|"),
            },
        ),
    },
    elsewhere={
        "a1": ("a1 is for mechanism: rprpr; a 5R takes base (|AB| [m]) instead", "base"),
        "actuation": (
            "actuation is for mechanism: rprpr; a 5R is driven by its motors at A and B"
            " (revolute), with nothing to choose",
            "",
        ),
    },
)
ROBOT = Spec(
    "mapping",
    "The robot: A at the origin, B at (a1, 0); actuated revolute joints at A and B"
    " (torques T1, T2 [N m]) or actuated prismatic joints in the legs (forces"
    " F1, F2 [N]).",
    required=True,
    children={
        "mechanism": _MECHANISM,
        "a1": _num("|AB| [m]", required=True, minimum=0, exclusive=True),
        "gravity": _GRAVITY,
        "actuation": Spec(
            "enum",
            "The actuated joints: revolute (at A and B, torques T1, T2 [N m], the"
            " paper) or prismatic (the legs' s1, s2, forces F1, F2 [N]).",
            default=REVOLUTE,
            choices=ACTUATIONS,
        ),
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
    select="mechanism",
    variants={FIVE_BAR: FIVE_BAR_ROBOT},
    elsewhere={
        "base": (f"base {_FIVE_BAR_KEY}; the rprpr takes a1 (|AB| [m]) instead", "a1"),
        "lengths": (f"lengths {_FIVE_BAR_KEY}; the rprpr's legs have no fixed length", ""),
        "modes": (f"modes {_FIVE_BAR_KEY}: the working modes of its elbows", ""),
    },
)

TASK = Spec(
    "mapping",
    "An rprpr task: an RPRPR planar parallel robot and a planned end-point motion.",
    children={
        "name": Spec("string", "A name for reports (default: the file's stem)."),
        "robot": ROBOT,
        "path": Spec(
            "mapping",
            "The end-point path y = p(x).",
            required=True,
            unless="motion",
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
            unless="motion",
            children={
                "duration": _num("t_f [s]", required=True, minimum=0, exclusive=True),
                "law": Spec(
                    "enum",
                    "Rest-to-rest law in x (eq. 49 is the quintic; trapezoidal: constant"
                    " acceleration, cruise at cruise_speed, constant deceleration).",
                    choices=(*LAWS, TRAPEZOIDAL),
                ),
                "cruise_speed": _num(
                    "|dx/dt| while cruising [m/s], law trapezoidal only; in (D/t_f, 2D/t_f],"
                    " D = |x1 - x0|",
                    minimum=0,
                    exclusive=True,
                ),
                "x": Spec(
                    "polynomial",
                    "x_E(t) [m], explicitly, instead of law: one polynomial in t, or a list"
                    " of consecutive pieces {until, x}, each a polynomial in absolute time t.",
                    variable="t",
                    item=_X_PIECE,
                ),
            },
        ),
        "motion": Spec(
            "mapping",
            "The end point's motion directly, instead of path and timing: pieces {until, x,"
            " y} (polynomials in absolute time t), or waypoints interpolated as"
            " joint_trajectory_controller does (linear, cubic or quintic by the fields"
            " given), inline or as a CSV file (header t,x,y[,vx,vy[,ax,ay]]) relative to"
            " the task file.",
            children={
                "pieces": Spec(
                    "list", "Consecutive pieces from t = 0: {until, x, y}.", item=_MOTION_PIECE
                ),
                "waypoints": Spec(
                    "waypoints",
                    "Waypoints {t, p, v, a} from t = 0 (at least two), or a CSV file's name.",
                    item=_WAYPOINT,
                ),
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
                    "|T1|, |T2| limits [N m], each > 0 (with robot.actuation prismatic:"
                    " |F1|, |F2| limits [N]); gated in strict mode.",
                    minimum=0,
                    exclusive=True,
                    items=("|T1| limit [N m]", "|T2| limit [N m]"),
                ),
                "strict": Spec(
                    "bool",
                    "Also fail on torque limits and on accepted unbounded torques.",
                    default=False,
                ),
                "peak": Spec(
                    "bool",
                    "Compute the certified torque peak (max |T1|, max |T2| over [0, t_f]) for"
                    " the report (= --peak); no verdict needs it.",
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
        "uncertainty": UNCERTAINTY,
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
    doc["$id"] = SCHEMA_URL
    doc["title"] = "rprpr task file"
    timing = doc["properties"]["timing"]
    # cruise_speed with law trapezoidal, and only with it
    timing["if"] = {"required": ["law"], "properties": {"law": {"const": TRAPEZOIDAL}}}
    timing["then"] = {"required": ["cruise_speed"]}
    timing["else"] = {"not": {"required": ["cruise_speed"]}}
    motion = doc["properties"]["motion"]
    motion["oneOf"] = [{"required": ["pieces"]}, {"required": ["waypoints"]}]
    doc["allOf"] = [
        # A rest-to-rest law moves between path.from and path.to, so it needs both.
        {
            "if": {"required": ["timing"], "properties": {"timing": {"required": ["law"]}}},
            "then": {"properties": {"path": {"required": ["from", "to"]}}},
        },
        # path and timing (law or x), or motion (then timing gives its duration alone)
        {
            "if": {"not": {"required": ["motion"]}},
            "then": {
                "required": ["path", "timing"],
                "properties": {"timing": {"oneOf": [{"required": ["law"]}, {"required": ["x"]}]}},
            },
            "else": {
                "not": {"required": ["path"]},
                "properties": {"timing": {"propertyNames": {"const": "duration"}}},
            },
        },
    ]
    return doc


_POINT_FORMS = [  # a point: one coordinate (x), [x, y] or {x:, y:}
    _COORDINATE,
    {"type": "array", "items": _COORDINATE, "minItems": 2, "maxItems": 2},
    {
        "type": "object",
        "properties": {"x": _COORDINATE, "y": _COORDINATE},
        "required": ["x"],
        "additionalProperties": False,
    },
]


def _json(s: Spec) -> dict[str, Any]:
    if s.variants:
        return _variants(s)
    out: dict[str, Any] = {"description": s.description}
    if s.kind == "mapping":
        out["type"] = "object"
        out["properties"] = {k: _json(v) for k, v in s.children.items()}
        out["required"] = [k for k, v in s.children.items() if v.required and not v.unless]
        out["additionalProperties"] = False
    elif s.kind == "number":
        out["type"] = "number"
        if s.minimum is not None:
            out["exclusiveMinimum" if s.exclusive else "minimum"] = s.minimum
    elif s.kind == "polynomial":
        # the grammar's characters only, with at least one digit or the variable
        chars = rf"[0-9{s.variable}+\-*/^(). \t\r\neE]*"
        text = {"type": ["string", "number"], "pattern": rf"^{chars}[0-9{s.variable}]{chars}$"}
        if s.item is None:
            out.update(text)
        else:  # or a list of pieces
            pieces = {"type": "array", "items": _json(s.item), "minItems": 1}
            out["oneOf"] = [text, pieces]
    elif s.kind == "time":
        out["oneOf"] = [{"type": "number", "minimum": 0}, _FRACTION_SCHEMA]
    elif s.kind == "vector":
        out.update(type="array", items=_COORDINATE, minItems=2, maxItems=2)
    elif s.kind == "list":
        assert s.item is not None
        out.update(type="array", items=_json(s.item), minItems=1)
    elif s.kind == "waypoints":
        assert s.item is not None
        inline = {"type": "array", "items": _json(s.item), "minItems": 2}
        out["oneOf"] = [inline, {"type": "string", "pattern": CSV_PATTERN}]
    elif s.kind == "string":
        out["type"] = ["string", "number"]  # a name such as 2024 is taken as written
    elif s.kind == "bool":
        out["type"] = "boolean"
    elif s.kind == "enum":
        out["enum"] = list(s.choices)
    elif s.kind == "point":
        out["oneOf"] = _POINT_FORMS
    elif s.kind == "percent":
        out.update(type="string", pattern=PERCENT)
    elif s.kind == "relative":
        out["oneOf"] = [{"type": "string", "pattern": PERCENT}, _json(RELATIVE_LINKS)]
    elif s.kind in ("pair", "numbers"):
        item: dict[str, Any] = {"type": "number"}
        if s.minimum is not None:
            item["exclusiveMinimum" if s.exclusive else "minimum"] = s.minimum
        n = 2 if s.kind == "pair" else len(s.items)
        out.update(type="array", items=item, minItems=n, maxItems=n)
    elif s.kind == "signs":
        n = len(s.items)
        out.update(type="array", items={"enum": [1, -1]}, minItems=n, maxItems=n)
    if s.default is not None:
        number = s.kind == "number" and isinstance(s.default, str)  # a decimal's text
        out["default"] = float(s.default) if number else s.default
    return out


def _variants(s: Spec) -> dict[str, Any]:
    """A mapping with variants: each variant's schema when its ``select`` key names it,
    else the mapping's own (the key's default, or the key left out)."""
    chosen: dict[str, Any] = _json(replace(s, select="", variants={}))
    for name, variant in reversed(s.variants.items()):
        chosen = {
            "if": {"properties": {s.select: {"const": name}}, "required": [s.select]},
            "then": _json(variant),
            "else": chosen,
        }
    return {"description": s.children[s.select].description, "type": "object", **chosen}

"""Cross-field rules: what no single key's ``Spec`` can say, one function each.

Each rule is filed in ``RULES`` under a key, and runs as soon as that key has been read
(a mapping: with all its keys), so the error reported is the first problem in reading
order; it runs only when the values it needs were all read, so that a bad value is
reported once, by its own reader.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from typing import TYPE_CHECKING

from flint import fmpq, fmpq_poly

from ..model.errors import TaskFileError
from ..model.five_bar import RPRPR
from ..model.numbers import number, to_float
from ..model.numbers import rational as _q
from ..model.task import Task
from ..model.timing import LAWS
from .build import timing
from .expression import MAX_DEGREE, height
from .schema import TRAPEZOIDAL
from .walk import Rules, Walk

if TYPE_CHECKING:
    from ..model.waypoints import Waypoint

MAX_COMPOSED_BITS = 1 << 16  # bound on the coefficients of y(x(t)), see _composition_within_caps


def _on_path(w: Walk, key: str) -> None:
    """path.from or path.to lies on y = p(x); a point given by its x alone gets y = p(x)."""
    p = w.values["path.y"]
    x0, y0 = w.values[key]
    if y0 is None:
        w.values[key] = (x0, p(x0))
        return
    if p(x0) != y0:
        raise w.error(
            f"point ({_q(x0)}, {_q(y0)}) is not on the path: y({_q(x0)}) = {_q(p(x0))},"
            f" found y = {_q(y0)}",
            w.nodes[key],
            key,
        )


def _law_or_x(w: Walk, key: str) -> None:
    """timing gives exactly one of law and x (checked once its duration is read); with
    motion, neither (nor cruise_speed): its duration alone."""
    if "motion" in w.nodes:
        given = [k for k in ("law", "cruise_speed", "x") if f"timing.{k}" in w.nodes]
        if given:
            raise w.error(
                f"with motion, timing gives only duration (the motion's own times say how"
                f" it moves), found {', '.join(given)}",
                w.nodes[f"timing.{given[0]}"],
                f"timing.{given[0]}",
            )
        return
    law, x = "timing.law" in w.nodes, "timing.x" in w.nodes
    if not (law or x) and {"timing.law", "timing.x"} & w.misspelt:
        return  # the misspelt key is reported as such
    if law and x:
        raise w.error(
            "give either law or x, not both (law moves x between path.from and path.to;"
            " x gives x(t) explicitly)",
            w.nodes["timing"],
            "timing",
        )
    if not law and not x:
        raise w.error(
            f"missing timing law: give law ({', '.join(LAWS)}, or {TRAPEZOIDAL} with"
            " cruise_speed) or x (a polynomial in t, or pieces {until, x})",
            w.nodes["timing"],
            "timing",
        )


def _law_needs(w: Walk, key: str) -> None:
    """A rest-to-rest law moves between path.from and path.to: both must be given; the
    trapezoidal law needs its cruise_speed too."""
    if "motion" in w.nodes:
        return  # timing.law with motion: _law_or_x said so
    cruise = "timing.cruise_speed"
    if w.values[key] == TRAPEZOIDAL and cruise not in w.nodes and cruise not in w.misspelt:
        w.errors.append(
            w.error(
                "law trapezoidal needs cruise_speed (|dx/dt| while cruising [m/s], in"
                " (D/t_f, 2D/t_f], D = |x1 - x0|)",
                w.nodes[key],
                key,
            )
        )
    if "path" not in w.nodes:
        return  # the path is missing (or misspelt): reported as such
    ends = [f"path.{end}" for end in ("from", "to")]
    missing = [end[5:] for end in ends if end not in w.nodes and end not in w.misspelt]
    if missing:
        raise w.error(
            f"law {w.values[key]} needs path.{' and path.'.join(missing)} (the points it"
            " moves between)",
            w.nodes[key],
            key,
        )


def _cruise(w: Walk, key: str) -> None:
    """cruise_speed goes with law trapezoidal, and lies in (D/t_f, 2D/t_f]: slower, the
    motion cannot cover D in t_f; faster, it cannot reach the speed and stop again."""
    if "motion" in w.nodes or ("timing.law" in w.nodes and "timing.law" not in w.values):
        return  # said so by _law_or_x, or the law is bad: reported as such
    if w.values.get("timing.law") != TRAPEZOIDAL:
        raise w.error("cruise_speed is only for law: trapezoidal", w.nodes[key], key)
    if "path.from" not in w.values or "path.to" not in w.values:
        return  # missing or bad: reported as such
    V, t_f = w.values[key], w.values["timing.duration"]
    D = abs(w.values["path.to"][0] - w.values["path.from"][0])
    if D == 0:
        raise w.error(
            "law trapezoidal needs path.from and path.to at different x (it moves x"
            f" from one to the other), both have x = {_q(w.values['path.to'][0])}",
            w.nodes["timing.law"],
            "timing.law",
        )
    lo, hi = D / t_f, 2 * D / t_f
    if not lo < V <= hi:
        why = (
            "too slow to cover D in t_f"
            if lo >= V
            else "too fast to reach and leave again in t_f (at 2D/t_f the profile is a triangle)"
        )
        raise w.error(
            f"cruise_speed {_q(V)} is outside (D/t_f, 2D/t_f] = ({_q(lo)}, {_q(hi)}] for"
            f" D = |x1 - x0| = {_q(D)} m and t_f = {_q(t_f)} s: {why}",
            w.nodes[key],
            key,
        )


def _pieces_meet(w: Walk, key: str, coords: tuple[str, ...], t_f: fmpq | None) -> bool:
    """The pieces at ``key`` are consecutive from t = 0, in increasing time, end at
    ``t_f`` (when given) and are continuous in position (``coords``) at every knot;
    errors are recorded, True when there were none."""
    items = w.values[key]
    before = len(w.errors)
    prev = fmpq(0)
    for i, it in enumerate(items):
        if not it["until"] > prev:
            after = "t = 0" if i == 0 else f"the previous piece's until ({_q(prev)})"
            w.errors.append(
                w.error(
                    f"until {_q(it['until'])} must come after {after}: pieces are consecutive"
                    " from t = 0, in increasing time",
                    w.nodes[f"{it['key']}.until"],
                    f"{it['key']}.until",
                )
            )
        prev = max(prev, it["until"])
    if len(w.errors) > before:
        return False
    from ..model.motion import position_jump  # a task of pieces only

    for a, b in itertools.pairwise(items):
        t = a["until"]
        jump = position_jump([a[c] for c in coords], [b[c] for c in coords], t)
        if jump is not None:
            names = coords[0] if len(coords) == 1 else f"({', '.join(coords)})"
            left, right = (
                _q(v[0]) if len(v) == 1 else f"({', '.join(_q(c) for c in v)})" for v in jump
            )
            w.errors.append(
                w.error(
                    f"the position jumps at the knot t = {_q(t)}: {names} = {left} before,"
                    f" {right} after (line {b['line']}); position must be continuous",
                    w.nodes[f"{a['key']}.until"],
                    f"{a['key']}.until",
                )
            )
    last = items[-1]
    if t_f is not None and last["until"] != t_f:
        w.errors.append(
            w.error(
                f"the last piece ends at until = {_q(last['until'])}, but timing.duration is"
                f" {_q(t_f)}: they must be equal",
                w.nodes[f"{last['key']}.until"],
                f"{last['key']}.until",
            )
        )
    return len(w.errors) == before


def _x_meets_ends(w: Walk, key: str) -> None:
    """An explicit x(t) starts at path.from's x and ends at path.to's, where given; given
    as pieces, they are consecutive and continuous, and end at the duration."""
    x, t_f = w.values[key], w.values["timing.duration"]
    if isinstance(x, list):
        if not _pieces_meet(w, key, ("x",), t_f):
            return
        first, last = x[0]["x"], x[-1]["x"]
    else:
        first = last = x
    for end, poly, at, when in (
        ("path.from", first, fmpq(0), "0"),
        ("path.to", last, t_f, f"t_f = {_q(t_f)}"),
    ):
        if end in w.values and poly(at) != w.values[end][0]:
            raise w.error(
                f"{end} has x = {_q(w.values[end][0])} but timing.x gives"
                f" x({when}) = {_q(poly(at))}: they must agree",
                w.nodes[end],
                end,
            )


def _composition_within_caps(w: Walk, key: str) -> None:
    """Cap the degree of y(x(t)) and bound the size of its coefficients.

    With p = P/dp and x = X/dx (integer polynomials over their common denominators),
    p(x) = sum P_k X^k dx^(d-k) / (dp dx^d), so every integer in it has at most
    h(p) + d (h(x) + log2 len(X)) + log2 (d + 1) bits, h = ``expression.height``.
    """
    v = w.values
    if "motion" in w.nodes:
        return
    if not ("timing.x" in v or all(k in v for k in ("timing.law", "path.from", "path.to"))):
        return  # x(t) could not be read: its own error is reported
    try:
        pieces = timing(w)
    except (KeyError, ValueError):
        return  # no cruise_speed, or a bad one: reported as such
    for _, _, x in pieces:
        _composed_within_caps(w, v["path.y"], x)


def _composed_within_caps(w: Walk, p: fmpq_poly, x: fmpq_poly) -> None:
    dp, dx = max(p.degree(), 0), max(x.degree(), 0)
    if dp * dx > MAX_DEGREE:
        raise w.error(
            f"the composition y(x(t)) has degree {dp * dx} (path degree {dp} × timing degree"
            f" {dx}), beyond the cap of {MAX_DEGREE}",
            w.nodes["path.y"],
            "path.y",
        )
    bits = height(p) + dp * (height(x) + len(x.coeffs()).bit_length()) + (dp + 1).bit_length()
    if bits > MAX_COMPOSED_BITS:
        raise w.error(
            f"numbers too large: the coefficients of y(x(t)) may reach {bits} bits, beyond the"
            f" cap of {MAX_COMPOSED_BITS}",
            w.nodes["path.y"],
            "path.y",
        )


def _given_duration(w: Walk) -> fmpq | None:
    """timing.duration when the task gives it with motion (then the motion must end
    there), else None."""
    return w.values.get("timing.duration") if "timing.duration" in w.nodes else None


def _motion_pieces_meet(w: Walk, key: str) -> None:
    """motion.pieces: consecutive from t = 0, continuous in (x, y), ending at
    timing.duration when given."""
    _pieces_meet(w, key, ("x", "y"), _given_duration(w))


def _waypoints_in_order(w: Walk, key: str) -> None:
    """At least two waypoints, from t = 0, in increasing time, all giving the same
    fields; the last at timing.duration when given. A CSV row's error names the file
    and the row (at the line of ``waypoints:``)."""
    points: list[Waypoint] = w.values[key]

    def error(i: int, message: str) -> TaskFileError:
        if w.csv_name:
            return w.error(f"{w.csv_name}:{points[i].line}: {message}", w.nodes[key], key)
        return w.error(message, w.nodes[f"{key}[{i}].t"], f"{key}[{i}].t")

    if len(points) < 2:
        raise w.error(f"expected at least two waypoints, found {len(points)}", w.nodes[key], key)
    if points[0].t != 0:
        w.errors.append(
            error(0, f"the first waypoint is at t = {_q(points[0].t)}; waypoints start at t = 0")
        )
    first = _fields(points[0])
    for i in range(1, len(points)):
        if not points[i].t > points[i - 1].t:
            w.errors.append(
                error(
                    i,
                    f"t = {_q(points[i].t)} does not come after the previous waypoint's"
                    f" t = {_q(points[i - 1].t)}: times must increase",
                )
            )
        if _fields(points[i]) != first:
            w.errors.append(
                error(
                    i,
                    f"this waypoint gives {_fields(points[i])} but the first gives {first}:"
                    " every waypoint must give the same fields (p; p, v; or p, v, a)",
                )
            )
    t_f = _given_duration(w)
    if t_f is not None and points[-1].t != t_f:
        w.errors.append(
            error(
                len(points) - 1,
                f"the last waypoint is at t = {_q(points[-1].t)}, but timing.duration is"
                f" {_q(t_f)}: they must be equal",
            )
        )


def _fields(point: Waypoint) -> str:
    return point.given


def _motion_alone(w: Walk, key: str) -> None:
    """motion gives exactly one of pieces and waypoints, and replaces path."""
    given = [k for k in ("pieces", "waypoints") if f"motion.{k}" in w.nodes]
    if "path" in w.nodes:
        w.errors.append(
            w.error(
                "give either path (with timing) or motion, not both (motion gives the end"
                " point's x(t) and y(t) directly)",
                w.nodes[key],
                key,
            )
        )
    if len(given) == 2:
        raise w.error("give either pieces or waypoints, not both", w.nodes[key], key)
    if not given and not {"motion.pieces", "motion.waypoints"} & w.misspelt:
        raise w.error(
            "missing motion: give pieces (a list of {until, x, y}) or waypoints (a list of"
            " {t, p, v, a}, or a CSV file's name)",
            w.nodes[key],
            key,
        )


def _five_bar_lengths(w: Walk, key: str) -> None:
    """A 5R's lengths make a five-bar: some point is reached by both legs. Leg i reaches
    the annulus m_i <= |E - base_i| <= M_i (m = |l_p - l_d|, M = l_p + l_d) about its
    base, and two annuli whose centres are a apart meet iff radii r1, r2 in them have
    |r1 - r2| <= a <= r1 + r2: iff M1 + M2 >= a, m1 <= M2 + a and m2 <= M1 + a."""
    a = w.values["robot.base"]
    l1, l2, l3, l4 = w.values[key]
    (m1, big1), (m2, big2) = (abs(l1 - l3), l1 + l3), (abs(l2 - l4), l2 + l4)
    if big1 + big2 < a:
        why = (
            f"the legs cannot meet: l1 + l3 + l2 + l4 = {_q(big1 + big2)} m is shorter than"
            f" base = {_q(a)} m"
        )
    elif m1 > big2 + a or m2 > big1 + a:
        i, j, hole, out = (1, 2, m1, big2 + a) if m1 > big2 + a else (2, 1, m2, big1 + a)
        p, d = (1, 3) if i == 1 else (2, 4)
        why = (
            f"leg {j} cannot reach out of leg {i}'s hole: leg {i} reaches no point nearer its"
            f" base than |l{p} - l{d}| = {_q(hole)} m, leg {j} none farther from it than"
            f" {_q(out)} m"
        )
    else:
        return
    raise w.error(
        f"these lengths make no five-bar: {why} (expected lengths for which some point is"
        " within reach of both legs)",
        w.nodes[key],
        key,
    )


def _rprpr_uncertainty(w: Walk, key: str) -> None:
    """uncertainty names the RPRPR's links 2..5: it is for mechanism rprpr only."""
    mechanism = w.values["robot.mechanism"]
    if mechanism != RPRPR:
        raise w.error(
            f"uncertainty is for mechanism: rprpr (its links 2..5); the robust audit of a"
            f" {mechanism} is not available in this build",
            w.nodes[key],
            key,
        )


def _start(w: Walk, task: Task) -> tuple[fmpq, fmpq, str]:
    """The motion's start point E(0), and the key of the file that gives it."""
    first = task.motion[0]
    given = ("path.from", "timing.x", "timing.law", "motion.pieces[0].x")
    waypoints = ("motion.waypoints[0].p", "motion.waypoints")  # inline, or a CSV file's name
    key = next((k for k in (*given, *waypoints) if k in w.nodes), "motion")
    return first.x(first.start), first.y(first.start), key


def _five_bar_start(w: Walk, task: Task) -> None:
    """A 5R's start point is within reach of both legs (D1, D2 >= 0, docs/five-bar.md §2),
    and neither leg is stretched or folded there (D_i = 0), where its working modes
    coincide and robot.modes cannot choose one. Exact (rational D_i)."""
    fb = task.robot.five_bar
    if fb is None:
        return
    x, y, key = _start(w, task)
    at = f"the start point E(0) = ({_q(x)}, {_q(y)})"
    for i, name in ((1, "A"), (2, "B")):
        d = fb.discriminant(i, x, y)
        if d > 0:
            continue
        base = fb.leg(i)[0]
        p, q = (1, 3) if i == 1 else (2, 4)
        lo, hi = fb.annulus(i)
        r2 = (x - base) ** 2 + y**2
        reach = f"[|l{p} - l{q}|, l{p} + l{q}] = [{_q(lo)}, {_q(hi)}] m"
        if d < 0:
            found = f"|E - {name}| = {number(math.sqrt(to_float(r2)), 6)} m"
            w.errors.append(
                w.error(
                    f"{at} is out of reach of leg {i} (at {name}): expected |E - {name}| in"
                    f" {reach}, found {found}",
                    w.nodes[key],
                    key,
                )
            )
            continue
        how = "stretched" if r2 == hi**2 else "folded"
        side = f"l{p} + l{q}" if how == "stretched" else f"|l{p} - l{q}|"
        modes = w.nodes["robot.modes"]  # a list of two: its reader said so
        w.errors.append(
            w.error(
                f"working mode e{i} = {fb.modes[i - 1]:+d} does not exist at {at}: leg {i} is"
                f" {how} there (|E - {name}| = {side} = {_q(hi if how == 'stretched' else lo)}"
                f" m), where its two working modes coincide; expected a start point where"
                f" leg {i} is neither stretched nor folded",
                modes.value[i - 1],
                f"robot.modes[{i - 1}]",
            )
        )


# the rules on the whole task, once it is built (every key read without error)
TASK_RULES: tuple[Callable[[Walk, Task], None], ...] = (_five_bar_start,)


# key -> (its rule, the values the rule needs besides the key's own): a rule runs only
# when they were all read, so that a bad value is reported once, by its own reader
RULES: Rules = {
    "path.from": (_on_path, ("path.y",)),
    "path.to": (_on_path, ("path.y",)),
    "timing.duration": (_law_or_x, ()),  # before law or x is read
    "timing.law": (_law_needs, ()),
    "timing.cruise_speed": (_cruise, ("timing.duration",)),
    "timing.x": (_x_meets_ends, ("timing.duration",)),
    "timing": (_composition_within_caps, ("path.y", "timing.duration")),
    "motion.pieces": (_motion_pieces_meet, ()),
    "motion.waypoints": (_waypoints_in_order, ()),
    "motion": (_motion_alone, ()),
    "robot.lengths": (_five_bar_lengths, ("robot.base",)),
    "uncertainty": (_rprpr_uncertainty, ("robot.mechanism",)),
}

"""The task: a robot, a path and a timing law, as frozen dataclasses of exact numbers.

A ``Task`` is what the loader hands to the core; it is already validated (positive
a1, non-negative masses, a path that meets ``from``/``to``, ...), so the core never
sees a bad task. Numbers are ``flint.fmpq`` (exact rationals), polynomials
``flint.fmpq_poly``. Lengths in m, masses in kg, inertias in kg m^2, times in s.

No field holds a default value of the task file (gravity 9.81, zero margins, ...): their
one home is ``io.schema.TASK`` (``Spec.default``), which the loader applies.
"""

from __future__ import annotations

import math
from dataclasses import field
from fractions import Fraction
from functools import cached_property
from typing import Any, Protocol, overload

from flint import fmpq, fmpq_poly

from .actuation import REVOLUTE
from .dataclass import dataclass
from .five_bar import RPRPR, FiveBar
from .link import Link as Link  # (its home is link.py, shared with five_bar.py)
from .numbers import polynomial, rational_text


@dataclass(frozen=True)
class Robot:
    """Fixed link length a1 = |AB| (A at the origin, B at (a1, 0)), gravity g along -y,
    the moving links 2 (leg A, revolute side), 3 (leg A, at E), 4 and 5 (leg B), and the
    actuation scheme: ``"revolute"`` (the paper: torques T1, T2 [N m] at A and B) or
    ``"prismatic"`` (forces F1, F2 [N] in the legs' prismatic joints s1, s2).

    ``mechanism`` is ``"rprpr"`` (all of the above) or ``"5R"``, the all-revolute
    five-bar, whose parameters are ``five_bar`` (``model.five_bar.FiveBar``); a 5R's
    ``a1`` is its |AB| and its ``links`` are its links 1..4, the same as ``five_bar``'s,
    and its ``actuation`` is revolute (motors at A and B)."""

    a1: fmpq
    links: dict[int, Link]
    gravity: fmpq
    actuation: str = REVOLUTE
    mechanism: str = RPRPR
    five_bar: FiveBar | None = None


@dataclass(frozen=True)
class Checks:
    """The user's margins: |dy/dx| > min_slope and speed > min_speed at a singular
    instant; torque_limit = (|T1| max, |T2| max) in N m or None; strict gates also on
    the torque limit (and on every finding); unbounded_torque "fail" (unbounded torques
    at a singular instant fail the task) or "warn" (accepted: a warning, failing only in
    strict mode); ``rules``: the level chosen for a rule (rule id -> "error", "warn" or
    "ignore", ``rules.with_levels``), from the task's ``checks.ignore`` and
    ``checks.warn`` (each with the reason the file gives) and the repository's
    configuration; ``peak``: the report asks for the certified torque peak.
    """

    min_slope: fmpq
    min_speed: fmpq
    torque_limit: tuple[fmpq, fmpq] | None
    strict: bool
    unbounded_torque: str
    rules: dict[str, str]
    peak: bool


class _Absolute:
    """``Piece.x`` or ``Piece.y``: the polynomial given, or (given as None) the piece's
    local form composed with u = t - start, exactly, when first read. A planner's segments
    come in local form, and most of them are audited in it alone: their polynomials in
    absolute time (long rationals once t is far from 0) are made only where read."""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name, self.slot, self.index = name, "_" + name, 0 if name == "x" else 1

    @overload
    def __get__(self, obj: None, owner: Any = None) -> _Absolute: ...
    @overload
    def __get__(self, obj: Piece, owner: Any = None) -> fmpq_poly: ...
    def __get__(self, obj: Piece | None, owner: Any = None) -> fmpq_poly | _Absolute:
        if obj is None:
            raise AttributeError(self.name)  # no default: the field is required
        value: fmpq_poly | None = getattr(obj, self.slot)
        if value is None:
            assert obj.local is not None, f"a piece needs {self.name} or its local form"
            value = obj.local[self.index](fmpq_poly([-obj.start, 1]))
            object.__setattr__(obj, self.slot, value)
        return value

    def __set__(self, obj: Piece, value: fmpq_poly | None) -> None:
        object.__setattr__(obj, self.slot, value)  # not through __dict__: none is made


class LocalForm(Protocol):
    """A piece's local form held otherwise than as polynomials (a planner's segment on
    integers: ``waypoints.Segment``): its polynomials are made when first read."""

    def polys(self) -> tuple[fmpq_poly, fmpq_poly]: ...


class _Local:
    """``Piece.local``: the pair of polynomials given, or None, or a ``LocalForm`` whose
    polynomials are made when first read (``Piece.form`` keeps it)."""

    def __get__(self, obj: Piece | None, owner: Any = None) -> tuple[fmpq_poly, fmpq_poly] | None:
        if obj is None:
            return None
        value: tuple[fmpq_poly, fmpq_poly] | None = getattr(obj, "_local")  # noqa: B009
        if value is None and obj.form is not None:
            value = obj.form.polys()
            object.__setattr__(obj, "_local", value)
        return value

    def __set__(self, obj: Piece, value: tuple[fmpq_poly, fmpq_poly] | LocalForm | None) -> None:
        given = value is not None and not isinstance(value, _Local)
        form = given and not isinstance(value, tuple)
        object.__setattr__(obj, "_local", value if given and not form else None)
        object.__setattr__(obj, "_form", value if form else None)


@dataclass(frozen=True)
class Uncertainty:
    """What the real robot may differ by from the task's model (``docs/robust.md``):
    ``links`` maps a link i = 2..5 to the relative half-widths (mass, inertia, r) of its
    parameters (0 <= each < 1; a link not named is exact); ``acceleration`` bounds the
    end point's acceleration tracking error on each axis [m/s^2]; ``period`` is the
    controller's sample period [s]: a saturation window no longer than it is tolerated."""

    links: dict[int, tuple[fmpq, fmpq, fmpq]]
    acceleration: fmpq
    period: fmpq
    # where it is declared, for messages: the task file's (line, column) of the key's
    # value, or ``origin``, the configuration's ``file:line`` when it comes from there
    where: tuple[int, int] = field(default=(0, 0), compare=False, repr=False)
    origin: str = field(default="", compare=False, repr=False)

    def __post_init__(self) -> None:
        """A ValueError naming the first value out of its range (the task file's reader
        checks the same, each on its own located line)."""
        if not isinstance(self.links, dict):
            raise ValueError(f"Uncertainty: links must be a dict, not {type(self.links).__name__}")
        for i, rel in self.links.items():
            if isinstance(i, bool) or i not in (2, 3, 4, 5):
                raise ValueError(f"Uncertainty: links[{i!r}]: expected a link 2, 3, 4 or 5")
            if not isinstance(rel, tuple | list) or len(rel) != 3:
                raise ValueError(
                    f"Uncertainty: links[{i}]: expected (mass, inertia, r) half-widths,"
                    f" found {rel!r}"
                )
            for name, v in zip(("mass", "inertia", "r"), rel, strict=True):
                q = _fraction(v, f"links[{i}] {name}")
                if not 0 <= q < 1:
                    raise ValueError(
                        f"Uncertainty: links[{i}] {name}: expected a relative half-width"
                        f" >= 0 and < 1 (0 % to 100 %), found {v}"
                    )
        for name, v in (("acceleration", self.acceleration), ("period", self.period)):
            if _fraction(v, name) < 0:
                raise ValueError(f"Uncertainty: {name}: expected a number >= 0, found {v}")

    def exact(self) -> Uncertainty:
        """The same with every number an exact rational (``fmpq``): a ``Fraction``, an int
        or a float (its binary value) given from Python is converted."""

        def q(v: object) -> fmpq:
            if isinstance(v, fmpq):
                return v
            n, d = Fraction(v).as_integer_ratio()  # type: ignore[call-overload]
            return fmpq(n, d)

        links = {int(i): (q(m), q(j), q(r)) for i, (m, j, r) in self.links.items()}
        return Uncertainty(
            links, q(self.acceleration), q(self.period), where=self.where, origin=self.origin
        )

    @property
    def zero(self) -> bool:
        """No uncertainty at all (a box of radius zero)."""
        return self.acceleration == 0 and all(v == 0 for t in self.links.values() for v in t)


def _fraction(v: object, what: str) -> Fraction:
    """``v`` (an fmpq, a Fraction, an int or a finite float) as a Fraction; else a
    ValueError naming ``what``."""
    if isinstance(v, fmpq):
        return Fraction(int(v.p), int(v.q))
    if isinstance(v, bool) or not isinstance(v, int | float | Fraction):
        raise ValueError(f"Uncertainty: {what}: expected a number, found {v!r}")
    if isinstance(v, float) and not math.isfinite(v):
        raise ValueError(f"Uncertainty: {what}: expected a finite number, found {v}")
    return Fraction(v)


@dataclass(frozen=True)
class Piece:
    """One piece of a piecewise-polynomial motion: for ``start`` <= t <= ``end`` the end
    point is at (``x``(t), ``y``(t)), polynomials in *absolute* time t (exact rationals).

    ``path`` is y = p(x) when the task gives the path (then ``y`` = p(x(t)) exactly), and
    None when the task gives the end point's motion directly (``motion.pieces``,
    ``motion.waypoints``). ``line`` is the 1-based line in the task file (or the row of a
    waypoint CSV, then ``file`` names it) where the piece ends, 0 when unknown; findings
    at the knot ``end`` point there. ``local``, when given, is (x, y) again as
    polynomials in the local time t - ``start`` (the same motion, exactly: what a planner's
    segment is written in, with shorter coefficients), which the engine uses where it works
    in local time; it takes no part in comparisons. With ``local`` given, ``x`` and ``y``
    may be given as None: they are then made from it when first read (``_Absolute``);
    ``local`` may itself be given as a ``LocalForm`` (``form``), its polynomials then
    made when first read.
    ``smooth`` is how many derivatives of (x, y) (1: velocity, 2: and acceleration) the
    piece continues, by its construction, from the piece before at ``start`` (a waypoint
    segment ends at its waypoint's p, v, a exactly, where the next one starts): the knot
    there has no such jump without an evaluation; 0 when not known so.
    """

    start: fmpq
    end: fmpq
    x: _Absolute = _Absolute()
    y: _Absolute = _Absolute()
    path: fmpq_poly | None = None
    line: int = 0
    file: str = ""
    local: _Local = field(default=_Local(), compare=False, repr=False)
    smooth: int = field(default=0, compare=False, repr=False)

    @property
    def form(self) -> LocalForm | None:
        """The ``LocalForm`` the piece's ``local`` was given as, or None."""
        form: LocalForm | None = getattr(self, "_form")  # noqa: B009  (set by ``_Local``)
        return form

    def __repr__(self) -> str:
        """``<Piece 0 <= t <= 5/2: x(t) = ..., y(t) = ...>`` (polynomials in t, exact)."""
        return (
            f"<Piece {rational_text(self.start)} <= t <= {rational_text(self.end)}:"
            f" x(t) = {polynomial(self.x, 't')}, y(t) = {polynomial(self.y, 't')}>"
        )


@dataclass(frozen=True)
class Task:
    """An audited motion over 0 <= t <= duration.

    The paper's form: the end point follows y = path(x) with x = x_of_t(t), one
    polynomial each. A piecewise motion (a piecewise or trapezoidal timing law, the
    end point's pieces, waypoints) gives ``pieces`` instead, consecutive from t = 0 to
    ``duration``; then ``x_of_t`` is None, and ``path`` is the path y(x) when the task
    gives one, else None. ``motion`` is the pieces in both cases.

    ``law`` records how the motion was given ("quintic", "cubic", "explicit",
    "trapezoidal", "pieces" (timing.x as pieces), "motion" (motion.pieces) or
    "waypoints"); ``lines`` maps dotted key paths (``path.y``, ``timing``) to their
    1-based line in the task file, so that findings can point back at the file.
    """

    name: str
    robot: Robot
    path: fmpq_poly | None
    x_of_t: fmpq_poly | None
    duration: fmpq
    checks: Checks
    law: str = "explicit"
    lines: dict[str, int] = field(default_factory=dict)
    source: str = ""
    pieces: tuple[Piece, ...] = ()
    uncertainty: Uncertainty | None = None  # None: the exact model (today's verdicts)

    def __repr__(self) -> str:
        """One line: ``<Task 'name': y(x) = ..., x(t) = ..., 0 <= t <= 5 s (quintic),
        from FILE>``; a piecewise motion by its number of pieces (``motion`` holds them)."""
        parts = []
        if self.path is not None:
            parts.append(f"y(x) = {polynomial(self.path, 'x')}")
        if self.x_of_t is not None and not self.pieces:
            parts.append(f"x(t) = {polynomial(self.x_of_t, 't')}")
        elif self.pieces:
            n = len(self.pieces)
            what = "x(t)" if self.path is not None else "(x(t), y(t))"
            parts.append(f"{what} in {n} piece{'s' if n != 1 else ''}")
        parts.append(f"0 <= t <= {rational_text(self.duration)} s ({self.law})")
        source = f", from {self.source}" if self.source else ""
        return f"<Task {self.name!r}: {', '.join(parts)}{source}>"

    @cached_property
    def motion(self) -> tuple[Piece, ...]:
        """The motion as consecutive pieces from t = 0 to ``duration``: ``pieces``, or the
        one piece y = path(x_of_t(t)) of the paper's form (composed once per task)."""
        if self.pieces:
            return self.pieces
        assert self.path is not None and self.x_of_t is not None
        x, line = self.x_of_t, self.lines.get("timing", 0)
        return (Piece(fmpq(0), self.duration, x, self.path(x), self.path, line),)

    @property
    def knots(self) -> tuple[fmpq, ...]:
        """The interior break times of a piecewise motion (none for one polynomial)."""
        return tuple(p.end for p in self.motion[:-1])

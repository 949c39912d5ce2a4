"""What one process keeps of pure exact work between audits: a bounded store per kind of
result (``Kept``), keyed by the exact data the result is made from (``exact_key``).

A planner's batch, a repair's candidates, a motion that repeats itself and several timings
of one path redo the same exact work: a robot's constants as balls, the expansions about a
rational singular instant, the zone form there, a path's factorisation. Each is a pure
function of exact values, so it is made once and kept by those values: two inputs share a
result only when every value it is made from is the same number (``exact_key``).

A store holds at most ``most`` results, the oldest made dropped first; a result is stored
only once it is complete (an interrupt while making it stores nothing); what is stored is
immutable or frozen by the store's user (a read-only array, a tuple), so no audit can
change another's. A forked worker's copy is keyed the same way as its parent's, so it is
right in either. ``clear()`` empties every store: for timing an audit from cold, and for
tests that count an audit's work."""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Any, Generic, TypeVar

from flint import fmpq, fmpq_poly

from ...model.task import Robot
from .mechanism import of

Made = TypeVar("Made")


class Kept(Generic[Made]):
    """At most ``most`` results, each made once by its exact key (``get``)."""

    def __init__(self, most: int) -> None:
        self.most = most
        self._made: dict[Hashable, Made] = {}
        STORES.append(self)

    def get(self, key: Hashable, make: Callable[[], Made]) -> Made:
        """The result kept for ``key``, else ``make()``, kept (the oldest dropped when full)."""
        try:
            return self._made[key]
        except KeyError:
            pass
        made = make()
        if len(self._made) >= self.most:
            del self._made[next(iter(self._made))]
        self._made[key] = made
        return made

    def __len__(self) -> int:
        return len(self._made)

    def clear(self) -> None:
        self._made.clear()


STORES: list[Kept[Any]] = []
BY_IDENTITY: list[dict[Any, Any]] = []  # what is kept by an object's identity (``also``)


def also(by_identity: dict[Any, Any]) -> dict[Any, Any]:
    """``by_identity`` (results kept for the object last given) emptied by ``clear`` too."""
    BY_IDENTITY.append(by_identity)
    return by_identity


def clear() -> None:
    """Empty every store: the next audit makes everything afresh."""
    for store in STORES:
        store.clear()
    for d in BY_IDENTITY:
        d.clear()


def exact_key(v: Any) -> Hashable:
    """A value as a key: a record by its type and fields, a mapping by its sorted items, a
    tuple or list item by item, an exact rational as its numerator and denominator (flint's
    own hash of an fmpq costs ten times as much), a polynomial over Q as its numerator's
    coefficients and its denominator, a name or another number as it is. Two values have
    the same key only when they are the same exact values (a field added to a record is in
    its key too)."""
    if type(v) is fmpq:
        return fmpq, v.p, v.q
    if type(v) is fmpq_poly:
        return fmpq_poly, tuple(v.numer().coeffs()), v.denom()
    if isinstance(v, dict):
        return tuple((k, exact_key(x)) for k, x in sorted(v.items()))
    if isinstance(v, (tuple, list)):
        return type(v), tuple(exact_key(x) for x in v)
    if hasattr(v, "__dataclass_fields__"):
        return type(v), tuple((k, exact_key(x)) for k, x in vars(v).items())
    return v


def robot_key(robot: Robot) -> Hashable:
    """The robot's exact identity: the mechanism that drives it, and every field of the
    robot (its scheme's and mechanism's names, a1, gravity, each link's mass, inertia
    and r, a 5R's own parameters) by name and exact value (``exact_key``)."""
    return of(robot), exact_key(robot)


__all__ = ["BY_IDENTITY", "STORES", "Kept", "also", "clear", "exact_key", "robot_key"]

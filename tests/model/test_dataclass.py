"""``model.dataclass``: the same classes as ``dataclasses.dataclass`` makes, made faster.

Each kind of record rprpr declares is made twice, by the standard library and by
``model.dataclass``, and the two are compared on what a user of the class can see:
the signature of ``__init__`` (names, annotations, defaults), ``repr``, ``==``, ``hash``,
what a frozen instance refuses and the words it says so with, ``fields``, ``replace``,
``asdict``, ``__match_args__`` and the parameters; then every record of the package
against a twin the standard library makes from its fields.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import pkgutil
import sys
from collections.abc import Callable
from dataclasses import field
from typing import Any

import pytest

import rprpr
from rprpr.model.dataclass import dataclass as fast

FAST = sys.version_info < (3, 13)  # where model.dataclass makes the methods itself


def kinds(decorate: Callable[..., Any]) -> dict[str, type]:
    """The kinds of record rprpr declares, made by ``decorate``."""

    @decorate(frozen=True)
    class Point:
        """A frozen record with defaults, a field left out of ==, hash and repr, and a
        factory."""

        x: int
        y: float = 0.5
        where: tuple[int, int] = field(default=(0, 0), compare=False, repr=False)
        tags: list[str] = field(default_factory=list)

    @decorate(frozen=True)
    class Checked:
        """A frozen record that checks itself after ``__init__``."""

        a: int
        b: int = field(default=1, repr=False)
        seen: list[int] = field(default_factory=list, compare=False)

        def __post_init__(self) -> None:
            if self.a < 0:
                raise ValueError("a < 0")
            self.seen.append(self.a)

    @decorate
    class Run:
        """A mutable record: no hash."""

        names: list[str] = field(default_factory=list)
        count: int = 0

    @decorate(frozen=True)
    class Own:
        """A frozen record with its own == (and so the generated hash)."""

        q: int

        def __eq__(self, other: object) -> bool:
            return isinstance(other, Own) and other.q % 7 == self.q % 7

    @decorate(frozen=True)
    class OwnHash:
        """A frozen record with its own hash."""

        q: int

        def __hash__(self) -> int:
            return 7

    @decorate(frozen=True, eq=False)
    class Identity:
        """Compared by identity."""

        q: int

    @decorate(repr=False)
    class Quiet:
        """No generated repr."""

        q: int

    @decorate(frozen=True)
    class Empty:
        """No fields."""

    @decorate(frozen=True)
    class Nested:
        """A record that holds records (and itself, through a list)."""

        inner: Any
        more: list[Any] = field(default_factory=list, hash=False)

    @decorate(frozen=True)
    class Undocumented:
        a: int
        b: str = "b"

    return {c.__name__: c for c in (Point, Checked, Run, Own, OwnHash, Identity, Quiet, Empty,
                                    Nested, Undocumented)}  # fmt: skip


STD, OURS = kinds(dataclasses.dataclass), kinds(fast)
SAMPLES: dict[str, list[tuple[tuple[Any, ...], dict[str, Any]]]] = {
    "Point": [((1,), {}), ((1, 0.5), {}), ((1,), {"where": (3, 4)}), ((2, float("nan")), {}),
              ((1,), {"tags": ["a"]})],
    "Checked": [((1,), {}), ((1, 2), {}), ((3,), {"b": 4})],
    "Run": [((), {}), ((["a"], 2), {})],
    "Own": [((1,), {}), ((8,), {}), ((2,), {})],
    "OwnHash": [((1,), {}), ((2,), {})],
    "Identity": [((1,), {}), ((1,), {})],
    "Quiet": [((1,), {}), ((1,), {})],
    "Empty": [((), {}), ((), {})],
    "Nested": [((1,), {}), ((None, [1, 2]), {})],
    "Undocumented": [((1,), {}), ((1, "c"), {})],
}  # fmt: skip


def _seen(kind: dict[str, type], name: str) -> list[Any]:
    """What a user sees of the record ``name`` made by ``kind``, in plain values."""
    cls = kind[name]
    made = [cls(*a, **k) for a, k in SAMPLES[name]]
    seen: list[Any] = [
        str(inspect.signature(cls)),
        inspect.signature(cls.__init__).parameters["self"].name,
        dict(cls.__init__.__annotations__),
        cls.__doc__,
        cls.__match_args__,
        cls.__hash__ is None,
        [
            (
                f.name,
                f.type,
                f.default,
                f.default_factory,
                f.init,
                f.repr,
                f.hash,
                f.compare,
                f.kw_only,
                f.metadata,
            )
            for f in dataclasses.fields(cls)
        ],
        {s: getattr(cls.__dataclass_params__, s) for s in ("init", "repr", "eq", "frozen")},
        {n: cls.__dict__.get(n, "absent") for n in ("x", "y", "where", "tags", "b", "count")},
    ]
    for i, a in enumerate(made):
        shown = cls.__dataclass_params__.repr  # type: ignore[attr-defined]
        seen.append(repr(a).replace(cls.__qualname__, cls.__name__) if shown else "object")
        seen.append([a == b for b in made] + [a != b for b in made] + [a == 1])
        try:
            seen.append("identity" if cls.__hash__ is object.__hash__ else hash(a))
        except TypeError as e:  # no hash, or a field's value has none
            seen.append(str(e))
        seen.append(dataclasses.asdict(a) if name != "Nested" else None)
        seen.append(repr(dataclasses.replace(a)) == repr(a))
        attempts = [(setattr, ("x", 2)), (delattr, ("x",)), (setattr, ("other", 2))]
        for act, args in attempts:
            try:
                act(a, *args)
                seen.append((i, "allowed"))
            except Exception as e:
                seen.append((i, type(e).__name__, str(e)))
    return seen


@pytest.mark.parametrize("name", sorted(STD))
def test_each_kind_of_record_is_the_standard_librarys(name: str) -> None:
    assert _seen(OURS, name) == _seen(STD, name)


def test_a_record_that_holds_itself_prints_as_the_standard_librarys() -> None:
    out = []
    for kind in (STD, OURS):
        a = kind["Nested"](1)
        a.more.append(a)
        out.append(repr(a).replace(kind["Nested"].__qualname__, "Nested"))
    assert out[0] == out[1] == "Nested(inner=1, more=[...])"


def test_post_init_runs_and_raises_as_declared() -> None:
    for kind in (STD, OURS):
        assert kind["Checked"](5).seen == [5]
        with pytest.raises(ValueError, match="a < 0"):
            kind["Checked"](-1)


def test_bad_declarations_are_refused_with_the_standard_librarys_words() -> None:
    def declare(decorate: Callable[..., Any], body: str) -> str:
        namespace: dict[str, Any] = {"field": field, "decorate": decorate}
        source = f"from __future__ import annotations\n@decorate(frozen=True)\nclass C:\n{body}"
        try:
            exec(source, namespace)
        except (TypeError, ValueError) as e:
            return f"{type(e).__name__}: {e}"
        return "made"

    bodies = [
        "    a: int = 0\n    b: int\n",  # no default after a default
        "    a: list = []\n",  # a mutable default
        "    a = field(default=1)\n",  # a field without an annotation
        "    a: int\n    def __setattr__(self, n, v): pass\n",  # frozen with its own setattr
    ]
    for body in bodies:
        assert declare(fast, body) == declare(dataclasses.dataclass, body) != "made"


@pytest.mark.skipif(not FAST, reason="from Python 3.13 on, the standard library's own")
def test_the_plain_kinds_are_made_here_not_by_the_standard_library() -> None:
    for cls in OURS.values():
        made = [cls.__dict__[m] for m in ("__repr__", "__setattr__") if m in cls.__dict__]
        assert all(m.__module__ == fast.__module__ for m in made), cls
    assert OURS["Point"].__repr__.__module__ == fast.__module__


def _records() -> list[type]:
    """Every dataclass the package declares."""
    found = []
    for info in pkgutil.walk_packages(rprpr.__path__, "rprpr."):
        if info.name.endswith("__main__") or ".render.sheet" in info.name:
            continue  # sheet needs matplotlib (an extra)
        module = importlib.import_module(info.name)
        for value in vars(module).values():
            if (
                isinstance(value, type)
                and value.__module__ == info.name
                and dataclasses.is_dataclass(value)
            ):
                found.append(value)
    return found


def _twin(cls: type) -> type:
    """The standard library's dataclass of ``cls``'s fields, parameters and __post_init__."""
    params = cls.__dataclass_params__  # type: ignore[attr-defined]
    namespace: dict[str, Any] = {
        "__annotations__": {f.name: f.type for f in dataclasses.fields(cls)},
        "__doc__": cls.__doc__,
        "__module__": cls.__module__,
        "__qualname__": cls.__qualname__,
    }
    for f in dataclasses.fields(cls):
        namespace[f.name] = field(
            default=f.default, default_factory=f.default_factory, init=f.init, repr=f.repr,
            hash=f.hash, compare=f.compare, metadata=f.metadata,
        )  # fmt: skip
    if "__post_init__" in cls.__dict__:
        namespace["__post_init__"] = cls.__dict__["__post_init__"]
    return dataclasses.dataclass(  # type: ignore[no-any-return]
        type(cls.__name__, (), namespace),
        init=params.init, repr=params.repr, eq=params.eq, frozen=params.frozen,
    )  # fmt: skip


RECORDS = _records()


def test_the_package_declares_its_records_through_model_dataclass() -> None:
    assert len(RECORDS) > 40
    for cls in RECORDS:
        source = inspect.getsource(sys.modules[cls.__module__])
        assert "from dataclasses import dataclass" not in source, cls.__module__


@pytest.mark.parametrize("cls", RECORDS, ids=lambda c: f"{c.__module__}.{c.__qualname__}")
def test_every_record_of_the_package_has_the_standard_librarys_signature(cls: type) -> None:
    twin = _twin(cls)
    assert inspect.signature(cls) == inspect.signature(twin)
    assert cls.__init__.__annotations__ == twin.__init__.__annotations__  # type: ignore[misc]
    assert cls.__match_args__ == twin.__match_args__  # type: ignore[attr-defined]
    p, q = cls.__dataclass_params__, twin.__dataclass_params__  # type: ignore[attr-defined]
    assert repr(p) == repr(q)

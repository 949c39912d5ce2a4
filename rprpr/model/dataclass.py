"""``dataclass``: the standard library's decorator, made in a fraction of its time.

Every record of rprpr is a dataclass, and ``rprpr check`` makes some forty of them at
start-up: Python 3.11 and 3.12 compile each one's ``__init__``, ``__repr__``, ``__eq__``,
``__hash__``, ``__setattr__`` and ``__delattr__`` from source text, six compilations a
class, ~0.6 ms, most of what importing the engine costs. Here only ``__init__`` is
compiled (from the same text as the standard library's, so the same signature, defaults,
annotations and speed); the other methods are shared functions over the class's field
names that do what the generated ones do, with the same results (``repr``, ``==``,
``hash``, ``FrozenInstanceError`` and its message). The class is a dataclass in every
other respect: ``dataclasses.fields``, ``replace``, ``asdict`` and ``is_dataclass``
read the same ``__dataclass_fields__`` and ``__dataclass_params__``.

Only the plain case is made here: ``init``, ``repr``, ``eq`` and ``frozen`` chosen,
string annotations (``from __future__ import annotations``), no dataclass among the
bases, no ``ClassVar``, ``InitVar`` or ``KW_ONLY``, fields in ``__init__`` with their
defaults last. Anything else, and any Python from 3.13 on (which
compiles a class's methods in one pass itself), is handed to ``dataclasses.dataclass``
unchanged. For type checkers this is ``dataclasses.dataclass`` itself.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from dataclasses import dataclass as dataclass
else:
    import dataclasses
    import operator
    from _thread import get_ident

    _FAST = sys.version_info < (3, 13)  # the standard library's layout this mirrors
    _PLAIN = {"init", "repr", "eq", "frozen"}  # the options made here
    _MARKS = ("ClassVar", "InitVar", "KW_ONLY")  # annotations left to the standard library
    _OWN = ("__setattr__", "__delattr__", "__slots__", "__abstractmethods__")

    def dataclass(cls=None, /, **options):
        """``dataclasses.dataclass`` (the same arguments), as the module says."""

        def wrap(cls):
            if _FAST and _PLAIN.issuperset(options):
                made = _make(cls, **options)
                if made is not None:
                    return made
            return dataclasses.dataclass(cls, **options)

        return wrap if cls is None else wrap(cls)

    def _fields(cls):
        """The fields of ``cls`` as the standard library finds them, or None where it is
        not the plain case (the class untouched)."""
        if any(n in cls.__dict__ for n in _OWN):
            return None
        if any(hasattr(b, "__dataclass_fields__") for b in cls.__mro__[1:]):
            return None
        # as the standard library of 3.11 and 3.12 reads them (only these get here)
        annotations = cls.__dict__.get("__annotations__", {})  # noqa: RUF063
        for name, value in cls.__dict__.items():
            if isinstance(value, dataclasses.Field) and name not in annotations:
                return None  # the standard library's error
        fields = {}
        seen_default = False
        for name, kind in annotations.items():
            if not isinstance(kind, str) or any(m in kind for m in _MARKS) or name == "self":
                return None
            default = getattr(cls, name, dataclasses.MISSING)
            if isinstance(default, dataclasses.Field):
                f = default
                if not f.init or f.kw_only not in (dataclasses.MISSING, False):
                    return None
            else:
                if isinstance(default, type(dataclasses.Field.name)):  # a slot's descriptor
                    default = dataclasses.MISSING
                f = dataclasses.field(default=default)
            if f.default.__class__.__hash__ is None:
                return None  # a mutable default: the standard library's error
            has_default = f.default is not dataclasses.MISSING
            if has_default or f.default_factory is not dataclasses.MISSING:
                seen_default = True
            elif seen_default:
                return None  # a field without a default after one with: the same
            fields[name] = f
        for name, f in fields.items():  # only now that the class is ours: change it
            f.name, f.type, f.kw_only = name, annotations[name], False
            f._field_type = dataclasses._FIELD
        return fields

    def _make(cls, *, init=True, repr=True, eq=True, frozen=False):
        fields = _fields(cls)
        if fields is None:
            return None
        for f in fields.values():  # a field() as the class attribute: its default, or none
            if isinstance(getattr(cls, f.name, None), dataclasses.Field):
                if f.default is dataclasses.MISSING:
                    delattr(cls, f.name)
                else:
                    setattr(cls, f.name, f.default)
        cls.__dataclass_params__ = _params(init, repr, eq, frozen)
        cls.__dataclass_fields__ = fields
        explicit = cls.__dict__.get("__hash__", dataclasses.MISSING)
        has_explicit_hash = not (
            explicit is dataclasses.MISSING or (explicit is None and "__eq__" in cls.__dict__)
        )
        listed = list(fields.values())
        if init:
            _new(cls, "__init__", _init(cls, listed, frozen))
        if repr:
            _new(cls, "__repr__", _repr([f.name for f in listed if f.repr]))
        if eq:
            _new(cls, "__eq__", _eq(_getter([f.name for f in listed if f.compare])))
        if frozen:
            names = frozenset(fields)
            _new(cls, "__setattr__", _frozen_setattr(cls, names))
            _new(cls, "__delattr__", _frozen_delattr(cls, names))
        if eq and not has_explicit_hash:
            if frozen:
                hashed = [f.name for f in listed if (f.compare if f.hash is None else f.hash)]
                _new(cls, "__hash__", _hash(_getter(hashed)), replace=True)
            else:
                cls.__hash__ = None
        if not cls.__doc__:  # the standard library's: the class's name and signature
            import inspect

            try:
                signature = str(inspect.signature(cls)).replace(" -> None", "")
            except (TypeError, ValueError):
                signature = ""
            cls.__doc__ = cls.__name__ + signature
        _new(cls, "__match_args__", tuple(fields))
        return cls

    def _params(init, repr, eq, frozen):
        values = {
            "init": init, "repr": repr, "eq": eq, "order": False, "unsafe_hash": False,
            "frozen": frozen, "match_args": True, "kw_only": False, "slots": False,
            "weakref_slot": False,
        }  # fmt: skip
        names = dataclasses._DataclassParams.__init__.__code__.co_varnames[1:]
        made = dataclasses._DataclassParams.__init__.__code__.co_argcount - 1
        return dataclasses._DataclassParams(*(values[n] for n in names[:made]))

    def _new(cls, name, value, *, replace=False):
        """``value`` as the attribute ``name`` of ``cls`` unless the class has its own."""
        if name in cls.__dict__ and not replace:
            return
        if callable(value) and hasattr(value, "__qualname__"):
            value.__qualname__ = f"{cls.__qualname__}.{name}"
        setattr(cls, name, value)

    def _init(cls, fields, frozen):
        """``__init__`` compiled from the standard library's text for these fields."""
        scope = {f"_type_{f.name}": f.type for f in fields}
        scope.update(
            MISSING=dataclasses.MISSING,
            _HAS_DEFAULT_FACTORY=dataclasses._HAS_DEFAULT_FACTORY,
            __dataclass_builtins_object__=object,
        )
        params, body = ["self"], []
        for f in fields:
            value = f.name
            if f.default_factory is not dataclasses.MISSING:
                scope[f"_dflt_{f.name}"] = f.default_factory
                value = f"_dflt_{f.name}() if {f.name} is _HAS_DEFAULT_FACTORY else {f.name}"
                params.append(f"{f.name}:_type_{f.name}=_HAS_DEFAULT_FACTORY")
            elif f.default is not dataclasses.MISSING:
                scope[f"_dflt_{f.name}"] = f.default
                params.append(f"{f.name}:_type_{f.name}=_dflt_{f.name}")
            else:
                params.append(f"{f.name}:_type_{f.name}")
            if frozen:
                body.append(f"__dataclass_builtins_object__.__setattr__(self,{f.name!r},{value})")
            else:
                body.append(f"self.{f.name}={value}")
        if hasattr(cls, "__post_init__"):
            body.append("self.__post_init__()")
        scope["_return_type"] = None
        lines = "\n".join(f"  {b}" for b in body or ["pass"])
        text = (
            f"def __create_fn__({', '.join(scope)}):\n"
            f" def __init__({','.join(params)})->_return_type:\n{lines}\n"
            " return __init__"
        )
        module = sys.modules.get(cls.__module__)
        namespace = {}
        # not this module's __future__ annotations: the annotations are the field types
        code = compile(text, "<string>", "exec", dont_inherit=True)
        exec(code, module.__dict__ if module is not None else {}, namespace)
        return namespace["__create_fn__"](**scope)

    def _getter(names):
        """The tuple of these attributes of an object (as the generated methods form it)."""
        if len(names) > 1:
            return operator.attrgetter(*names)
        if names:
            one = operator.attrgetter(names[0])
            return lambda obj: (one(obj),)
        return lambda obj: ()

    def _repr(names):
        running = set()

        def __repr__(self):
            key = id(self), get_ident()
            if key in running:
                return "..."
            running.add(key)
            try:
                inner = ", ".join(f"{n}={getattr(self, n)!r}" for n in names)
                return f"{self.__class__.__qualname__}({inner})"
            finally:
                running.discard(key)

        return __repr__

    def _eq(values):
        def __eq__(self, other):
            if other.__class__ is self.__class__:
                return values(self) == values(other)
            return NotImplemented

        return __eq__

    def _hash(values):
        def __hash__(self):
            return hash(values(self))

        return __hash__

    def _frozen_setattr(cls, names):
        def __setattr__(self, name, value):
            if type(self) is cls or name in names:
                raise dataclasses.FrozenInstanceError(f"cannot assign to field {name!r}")
            super(cls, self).__setattr__(name, value)

        return __setattr__

    def _frozen_delattr(cls, names):
        def __delattr__(self, name):
            if type(self) is cls or name in names:
                raise dataclasses.FrozenInstanceError(f"cannot delete field {name!r}")
            super(cls, self).__delattr__(name)

        return __delattr__

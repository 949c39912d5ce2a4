"""The repository's configuration of ``rprpr check``: ``[tool.rprpr]`` in ``pyproject.toml``,
or the top level of ``rprpr.toml`` / ``.rprpr.toml``, found as ruff finds its own.

Discovery: from the working directory upward, the first directory holding ``.rprpr.toml``,
``rprpr.toml`` or a ``pyproject.toml`` with a ``[tool.rprpr]`` table (in that order) is
the project's root and its file the configuration; ``--config FILE`` names one instead,
``--isolated`` uses none. Paths and globs in it are relative to the root.

Every value has one source: the built-in default, the configuration file, or the command
line (which wins); ``Settings.sources`` records which, ``--show-settings`` prints it. The
task-file defaults (``torque_limit``, ``min_slope``, ``min_speed``, ``strict``, ``peak``) yield to a
task's own ``checks:``; the rule levels (``select``, ``ignore``, ``warn``, ``error``) to
a task's ``checks.ignore`` / ``checks.warn`` (``configure``).

The file is read through the capped reader (``io.reading``: 1 MiB, a FIFO or a device
refused), its numbers by the task file's rules (``io.expression.parse_decimal``: 40
digits, an exponent within ±30); every way it can be wrong is one ``InputError`` naming
the file, the line and the key (exit 2).

Plain Python (tomllib, fractions): reading the configuration imports neither numpy nor the
engine.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import field, replace
from typing import TYPE_CHECKING, Any

from ..model.dataclass import dataclass
from ..model.defaults import DEFAULT_SAMPLES
from ..model.rules import ALL, RULES, SelectorError, levels
from .errors import InputError

if TYPE_CHECKING:  # the rest is imported when a configuration is read: --help stays light
    from fractions import Fraction

    from ..model.task import Task
    from .uncertainty import UncertaintyDefault

CONFIG_FILES = (".rprpr.toml", "rprpr.toml", "pyproject.toml")  # looked for in this order
TASK_GLOBS = ("*.rprpr.yaml", "*.rprpr.yml")  # what a task file is called, by default
# never searched (as ruff): besides these, every hidden file and directory (.git, .venv ...)
ALWAYS_EXCLUDED = ("build", "dist", "node_modules", "site-packages", "venv", "__pypackages__")
FORMATS = ("text", "concise", "json", "junit", "github", "sarif", "gitlab", "html")
DEFAULT_BUDGET = 10.0  # seconds of work per task
DEFAULT = "default"
COMMAND_LINE = "command line"

# key -> (kind, built-in default); the order is that of --show-settings
KEYS: dict[str, tuple[str, Any]] = {
    "paths": ("paths", (".",)),
    "include": ("globs", TASK_GLOBS),
    "exclude": ("globs", ()),
    "select": ("rules", (ALL,)),
    "ignore": ("rules", ()),
    "warn": ("rules", ()),
    "error": ("rules", ()),
    "strict": ("bool", None),
    "peak": ("bool", None),
    "torque_limit": ("limits", None),
    "min_slope": ("margin", None),
    "min_speed": ("margin", None),
    "uncertainty": ("uncertainty", None),
    "samples": ("samples", DEFAULT_SAMPLES),
    "jobs": ("jobs", 1),
    "budget": ("budget", DEFAULT_BUDGET),
    "format": ("format", "text"),
}


@dataclass(frozen=True)
class Settings:
    """The resolved configuration: each key's value (``values``), where it came from
    (``sources``: "default", the configuration file, or "command line"), the project
    root (paths and globs are relative to it) and the configuration file (None: none)."""

    values: dict[str, Any]
    sources: dict[str, str]
    root: str
    file: str | None = None

    def __getitem__(self, key: str) -> Any:
        return self.values[key]

    @property
    def rule_levels(self) -> dict[str, str]:
        """The level the configuration gives each rule it changes (``rules.levels``)."""
        return levels(self["select"], self["ignore"], self["warn"], self["error"])

    def task_defaults(self) -> TaskDefaults:
        return TaskDefaults(
            min_slope=self["min_slope"],
            min_speed=self["min_speed"],
            torque_limit=self["torque_limit"],
            strict=self["strict"],
            rules=self.rule_levels,
            peak=self["peak"],
            uncertainty=self["uncertainty"],
        )

    def selection(self, force: bool = False) -> FileSelection:
        return FileSelection(tuple(self["include"]), tuple(self["exclude"]), self.root, force)


@dataclass(frozen=True)
class TaskDefaults:
    """What the configuration sets in every task: each value None leaves the task's own;
    a task's ``checks:`` key wins over the configuration's."""

    min_slope: Fraction | None = None
    min_speed: Fraction | None = None
    torque_limit: tuple[Fraction, Fraction] | None = None
    strict: bool | None = None
    rules: dict[str, str] = field(default_factory=dict)
    peak: bool | None = None  # compute the certified torque peak (checks.peak)
    uncertainty: UncertaintyDefault | None = None  # a task's own ``uncertainty:`` wins


@dataclass(frozen=True)
class FileSelection:
    """Which files are tasks: a file named in ``include`` and not in ``exclude`` (globs:
    without a ``/`` a file or folder name, with one a path relative to ``root``); hidden
    files and folders and ``ALWAYS_EXCLUDED`` never. ``force``: files named on the command
    line are selected too (else a file named is always checked)."""

    include: tuple[str, ...] = TASK_GLOBS
    exclude: tuple[str, ...] = ()
    root: str = "."
    force: bool = False

    def excluded(self, path: str) -> bool:
        """Whether ``path`` (a file or folder) is excluded: hidden, built-in or configured."""
        name = os.path.basename(os.path.normpath(path))
        if name.startswith(".") and name not in (".", ".."):
            return True
        if name in ALWAYS_EXCLUDED:
            return True
        return _matches(self._relative(path), name, self.exclude)

    def included(self, path: str) -> bool:
        """Whether the file ``path`` is a task file by name (``include``)."""
        return _matches(self._relative(path), os.path.basename(path), self.include)

    def _relative(self, path: str) -> str:
        try:
            rel = os.path.relpath(os.path.abspath(path), os.path.abspath(self.root))
        except (OSError, ValueError):  # no working directory, another drive
            from pathlib import PurePath

            return PurePath(path).as_posix()
        return rel.replace(os.sep, "/")  # normal already (relpath): pathlib's as_posix


def _matches(rel: str, name: str, globs: Sequence[str]) -> bool:
    import fnmatch

    for g in globs:
        g = g.rstrip("/")
        if "/" in g:
            if fnmatch.fnmatchcase(rel, g.removeprefix("./")):
                return True
        elif fnmatch.fnmatchcase(name, g):
            return True
    return False


# -- finding and reading the file ----------------------------------------------------------
MAX_CONFIG_BYTES = 1 << 20  # 1 MiB, as a task file: a configuration is a few lines


def find_config(start: str | None = None) -> str | None:
    """The configuration that applies in ``start`` (the working directory): the first
    ``CONFIG_FILES`` from there upward (a ``pyproject.toml`` only with ``[tool.rprpr]``).
    A folder on the way that cannot be searched (no permission) is an ``InputError``:
    a configuration there can neither be read nor ruled out."""
    try:
        folder = os.path.realpath(start or os.getcwd())
    except OSError:
        return None
    while True:  # the folder, then each parent up to the root
        for name in CONFIG_FILES:
            candidate = os.path.join(folder, name)
            if not _is_file(candidate):
                continue
            if name != "pyproject.toml" or _has_table(candidate):
                return candidate
        parent = os.path.dirname(folder)
        if parent == folder:
            return None
        folder = parent


def _is_file(path: str) -> bool:
    """Whether ``path`` is a regular file (after links); an ``InputError`` when that
    cannot be told (a folder on the way without search permission)."""
    import errno
    import stat

    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except OSError as e:
        if e.errno in (errno.EACCES, errno.EPERM):
            raise InputError(
                f"{os.path.dirname(path)}: cannot look for a configuration file there"
                f" ({e.strerror or e}); give --config FILE or --isolated"
            ) from None
        return False  # none there (ENOENT, ENOTDIR, ELOOP, a name too long ...)
    except ValueError:
        return False


def _has_table(pyproject: str) -> bool:
    try:
        doc = _parsed(pyproject, _read(pyproject))
    except InputError:
        return False  # a broken pyproject.toml that may not be rprpr's: not this one
    return isinstance(doc.get("tool"), dict) and "rprpr" in doc["tool"]


class _Float(str):
    """A TOML float as its literal text (``parse_float``): read by the task file's number
    rules (``_number``), never by ``float`` or ``Decimal`` first."""


def _read(file: str) -> str:
    """The text of the configuration ``file``, through the capped reader (1 MiB; a FIFO
    or a device is refused, never waited on)."""
    from ..io.reading import ReadProblem, read_file

    try:
        data = read_file(file, MAX_CONFIG_BYTES, "a configuration file (TOML)")
    except ReadProblem as e:
        if e.message == "no such file":
            raise InputError(f"{file}: no such configuration file") from None
        why = e.message.removeprefix("cannot read the file: ")
        raise InputError(f"{file}: cannot read the configuration: {why}") from None
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        raise InputError(
            f"{file}:{line}: cannot read the configuration: not UTF-8 text (byte"
            f" 0x{data[e.start]:02x} at offset {e.start})"
        ) from None


def _parsed(file: str, text: str) -> dict[str, Any]:
    """The TOML document ``text`` of ``file``; every way it can fail is one located
    ``InputError``: a syntax error, an integer beyond Python's 4,300 digits, nesting
    deeper than the parser's recursion."""
    import tomllib

    try:
        return tomllib.loads(text, parse_float=_Float)
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"{file}: invalid TOML: {e}") from None
    except ValueError:  # int(): more than sys.get_int_max_str_digits() digits
        import sys

        limit = sys.get_int_max_str_digits()
        where = _line_matching(text, "[0-9][0-9_]{" + str(limit) + ",}")
        raise InputError(
            f"{file}{where}: invalid TOML: an integer with more than {limit} digits"
        ) from None
    except RecursionError:
        where = _line_matching(text, r"[\[{][ \t]*[\[{][ \t]*[\[{]")
        raise InputError(
            f"{file}{where}: invalid TOML: arrays or tables nested too deeply"
        ) from None


def _line_matching(text: str, pattern: str) -> str:
    """``:LINE`` of the first match of ``pattern`` in ``text`` ('' when none)."""
    import re

    found = re.search(pattern, text)
    return f":{text.count(chr(10), 0, found.start()) + 1}" if found else ""


def _is_pyproject(file: str) -> bool:
    """Whether the configuration ``file`` is a pyproject.toml (its last component)."""
    return os.path.basename(os.path.normpath(file)) == "pyproject.toml"


def _table(file: str) -> tuple[dict[str, Any], str]:
    """The rprpr keys of ``file`` (``[tool.rprpr]`` of a pyproject.toml, else the top
    level) and its text."""
    text = _read(file)
    doc = _parsed(file, text)
    if _is_pyproject(file):
        tool = doc.get("tool", {})
        table = tool.get("rprpr", {}) if isinstance(tool, dict) else {}
        if not isinstance(table, dict):
            raise InputError(f"{file}{_line_of(text, 'rprpr', None)}: [tool.rprpr] must be a table")
        return table, text
    return doc, text


def _line_of(text: str, key: str, table: str | None) -> str:
    """``:LINE`` of ``key = ...`` in ``text`` (below the header ``[table]`` when given):
    where a value of the configuration is written ('' when it cannot be told, as for a
    dotted key)."""
    import re

    start = 0
    if table is not None:
        header = re.search(r"(?m)^[ \t]*\[[ \t]*" + re.escape(table) + r"[ \t]*\]", text)
        if header is None:
            return ""
        start = header.end()
    quoted = re.escape(key)
    found = re.compile(rf"(?m)^[ \t]*({quoted}|\"{quoted}\"|'{quoted}')[ \t]*=").search(text, start)
    return f":{text.count(chr(10), 0, found.start()) + 1}" if found else ""


def load_settings(
    config: str | None = None,
    isolated: bool = False,
    overrides: Mapping[str, Any] | None = None,
    cwd: str | None = None,
) -> Settings:
    """The settings of a run: the built-in defaults, then the configuration file
    (``config``, else the one ``find_config`` finds; none when ``isolated``), then
    ``overrides`` (the command line's options that were given; None values ignored).
    An unknown key or rule, or a bad value, is an ``InputError`` naming it (exit 2)."""
    file = None if isolated else (config or find_config(cwd))
    values = {k: default for k, (_, default) in KEYS.items()}
    sources = dict.fromkeys(KEYS, DEFAULT)
    root = _root(file, cwd)
    if file is not None:
        pyproject = _is_pyproject(file)
        where = "[tool.rprpr]" if pyproject else "the configuration"
        table, text = _table(file)
        for key, raw in table.items():
            line = _line_of(text, key, "tool.rprpr" if pyproject else None)
            if key not in KEYS:
                raise InputError(f"{file}{line}: unknown key {key!r} in {where}{_near(key, KEYS)}")
            values[key] = _checked(key, raw, f"{file}{line}: {key}")
            sources[key] = file
    for key, raw in (overrides or {}).items():
        if raw is not None:
            values[key] = raw
            sources[key] = COMMAND_LINE
    if file is not None and sources["paths"] == file:  # relative to the root, as given
        values["paths"] = tuple(
            p if os.path.isabs(p) else os.path.relpath(os.path.join(root, p))
            for p in values["paths"]
        )
    settings = Settings(values, sources, root, file)
    try:
        settings.rule_levels  # noqa: B018  (validates the rule selectors together)
    except SelectorError as e:
        raise InputError(f"{file or 'the command line'}: {e}") from None
    return settings


def with_rules(
    settings: Settings,
    select: Sequence[str] = (),
    extend_select: Sequence[str] = (),
    ignore: Sequence[str] = (),
) -> Settings:
    """``settings`` under the command line's rule selectors, as ruff's ``--select``,
    ``--extend-select`` and ``--ignore``: ``select`` (when given) replaces the
    configuration's ``select`` and, starting afresh, its ``ignore``; ``extend_select``
    adds to ``select``; ``ignore`` adds to ``ignore``. The selectors then resolve as the
    configuration's (``rules.levels``: ids, names, the start of ids; the most specific
    wins). A selector that names no rule is an ``InputError`` naming the option."""
    for option, given in (("--select", select), ("--extend-select", extend_select),
                          ("--ignore", ignore)):  # fmt: skip
        for selector in given:
            try:
                levels(select=[selector])
            except SelectorError as e:
                raise InputError(f"{option}: {e}") from None
    if not (select or extend_select or ignore):
        return settings
    values, sources = dict(settings.values), dict(settings.sources)

    def extended(key: str, base: tuple[str, ...], more: Sequence[str], fresh: bool) -> None:
        values[key] = (*base, *more)
        if fresh or (sources[key] == DEFAULT and not base):
            sources[key] = COMMAND_LINE
        elif more:
            sources[key] = f"{sources[key]} + {COMMAND_LINE}"

    fresh = bool(select)
    extended("select", tuple(select) if fresh else settings["select"], extend_select, fresh)
    extended("ignore", () if fresh else settings["ignore"], ignore, fresh)
    out = replace(settings, values=values, sources=sources)
    try:
        out.rule_levels  # noqa: B018  (validates the rule selectors together)
    except SelectorError as e:
        raise InputError(f"the command line: {e}") from None
    return out


def _root(file: str | None, cwd: str | None) -> str:
    """The project root: the configuration's folder, else the working directory (as
    given, when it was deleted under the run)."""
    try:
        return os.path.dirname(os.path.abspath(file)) if file else os.path.abspath(cwd or ".")
    except OSError:
        return os.path.dirname(file) if file else (cwd or ".")


def _near(key: str, known: Mapping[str, Any]) -> str:
    from ..io.messages import near

    meant = near(key.replace("-", "_"), known)
    return f" (did you mean {meant[0]!r}?)" if meant else f"; known keys: {', '.join(known)}"


def _checked(key: str, raw: Any, where: str) -> Any:
    """The value of ``key`` as the settings hold it; an ``InputError`` naming ``where``."""
    kind = KEYS[key][0]
    if kind in ("paths", "globs", "rules"):
        if not isinstance(raw, list) or not all(_text(x) and x for x in raw):
            raise InputError(f"{where}: expected a list of strings, found {_toml(raw)}")
        if kind == "rules":
            for selector in raw:
                try:
                    levels(select=[selector])
                except SelectorError as e:
                    raise InputError(f"{where}: {e}") from None
        return tuple(raw)
    if kind == "bool":
        if not isinstance(raw, bool):
            raise InputError(f"{where}: expected true or false, found {_toml(raw)}")
        return raw
    if kind == "format":
        if raw not in FORMATS:
            raise InputError(f"{where}: expected one of {', '.join(FORMATS)}, found {_toml(raw)}")
        return raw
    if kind == "limits":
        if not isinstance(raw, list) or len(raw) != 2:
            raise InputError(f"{where}: expected [|T1| limit, |T2| limit] in N m")
        pair = tuple(_number(x, where, positive=True) for x in raw)
        return pair
    if kind == "margin":
        return _number(raw, where, positive=False)
    if kind == "uncertainty":
        from .uncertainty import read

        return read(raw, where, _number, _toml)
    bounds = {"samples": (2, 1_000_000), "jobs": (0, 256)}
    if kind in bounds:
        low, high = bounds[kind]
        if isinstance(raw, bool) or not isinstance(raw, int) or not low <= raw <= high:
            raise InputError(f"{where}: expected an integer from {low} to {high}")
        return raw
    number = _number(raw, where, positive=False)  # budget
    if number > 1_000_000:
        raise InputError(f"{where}: expected at most 1000000 seconds")
    return float(number)


def _text(value: Any) -> bool:
    """Whether ``value`` is a TOML string (not a float's text, ``_Float``)."""
    return isinstance(value, str) and not isinstance(value, _Float)


def _number(raw: Any, where: str, *, positive: bool) -> Fraction:
    """An exact number of the configuration (a TOML integer or float, taken by its text
    under the task file's number rules: ``io.expression.parse_decimal``, at most 40
    digits and an exponent within ±30): > 0 when ``positive``, else >= 0."""
    from fractions import Fraction

    from ..io.expression import parse_decimal
    from ..model.errors import ExpressionError

    if isinstance(raw, bool) or not isinstance(raw, int | _Float):
        raise InputError(f"{where}: expected a number, found {_toml(raw)}")
    try:  # an int here has at most 4,300 digits (tomllib's limit): str() is cheap
        q = parse_decimal(raw.replace("_", "") if isinstance(raw, _Float) else str(raw))
    except ExpressionError as e:
        raise InputError(f"{where}: {e.message}") from None
    value = Fraction(int(q.p), int(q.q))
    if value < 0 or (positive and value == 0):
        raise InputError(f"{where}: expected a number {'>' if positive else '>='} 0")
    return value


def _toml(value: Any) -> str:
    """A value as TOML writes it (for messages and ``--show-settings``)."""
    from decimal import Decimal
    from fractions import Fraction

    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml(v)}" for k, v in value.items()) + "}"
    if hasattr(value, "origin"):  # the uncertainty (cli.uncertainty.UncertaintyDefault)
        return str(value.text)
    if isinstance(value, _Float):
        return str.__str__(value)
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    if isinstance(value, Fraction):
        return str(value.numerator) if value.denominator == 1 else str(float(value))
    if isinstance(value, Decimal):
        return str(value)
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def show(settings: Settings) -> Iterator[str]:
    """The lines of ``--show-settings``: each key as TOML, with where it came from; then
    the level of each rule."""
    yield f"# configuration: {settings.file or '(none)'}"
    yield f"# root: {settings.root}"
    width = max(len(k) for k in KEYS)
    for key in KEYS:
        value = settings[key]
        text = "(unset: each task's own)" if value is None else _toml(value)
        yield f"{key:<{width}} = {text}  # {settings.sources[key]}"
    chosen = settings.rule_levels
    yield "# rules (a task's checks.ignore / checks.warn win over these)"
    for rule in RULES.values():
        if rule.id == "RPR001":
            continue
        default = "warn (error if strict)" if rule.strict_only else "error"
        level = chosen.get(rule.id)
        text = default if level is None else level
        yield f"{rule.id} {rule.name:<22} {text}"


# -- a task under the configuration --------------------------------------------------------
def configure(task: Task, d: TaskDefaults) -> Task:
    """``task`` with the configuration's defaults where its file gives no value (a key the
    file gives is in ``task.lines``), and its rule levels: the configuration's, then the
    task's own (``checks.ignore``, ``checks.warn``, ``checks.unbounded_torque``);
    ``--warn-unbounded`` is the audit's (``AuditOptions.warn_unbounded``). The
    configuration's ``uncertainty`` applies to a task that declares none; a task then
    audited with an uncertainty and no torque limit is a ``TaskFileError``
    (``uncertainty.needs_limit``)."""
    if d.uncertainty is None and task.uncertainty is None:  # the common case, at once
        return _checks(task, d)
    from .uncertainty import apply, needs_limit

    task = _checks(apply(task, d.uncertainty), d)
    needs_limit(task)
    return task


def _checks(task: Task, d: TaskDefaults) -> Task:
    """``task`` with the configuration's ``checks`` defaults and rule levels."""
    from flint import fmpq

    def exact(q: Fraction) -> fmpq:
        return fmpq(q.numerator, q.denominator)

    given = task.lines
    checks = task.checks
    changes: dict[str, Any] = {}
    if d.min_slope is not None and "checks.min_slope" not in given:
        changes["min_slope"] = exact(d.min_slope)
    if d.min_speed is not None and "checks.min_speed" not in given:
        changes["min_speed"] = exact(d.min_speed)
    if d.torque_limit is not None and "checks.torque_limit" not in given:
        changes["torque_limit"] = (exact(d.torque_limit[0]), exact(d.torque_limit[1]))
    if d.strict is not None and "checks.strict" not in given:
        changes["strict"] = d.strict
    if d.peak is not None and "checks.peak" not in given:
        changes["peak"] = d.peak
    rules = dict(d.rules)
    if "checks.unbounded_torque" in given:  # the task's own choice for RPR201
        rules["RPR201"] = "warn" if checks.unbounded_torque == "warn" else "error"
    rules.update(checks.rules)
    if rules != checks.rules:
        changes["rules"] = rules
    if not changes:
        return task
    return replace(task, checks=replace(checks, **changes))

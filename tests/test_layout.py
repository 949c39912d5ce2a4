"""The layout of the package: dependencies point one way and never go round in a circle.

The stages, in the order the data flows, and what each may import of rprpr (besides
itself and ``rprpr._version``)::

    cli    -> render, report, repair, engine, io, model
    render -> report, engine, model
    report -> engine, model
    repair -> engine, model      (the second use case: task -> audit -> changes -> task)
    engine -> model
    io     -> model
    model  -> (nothing)

Every import counts: at module level, inside functions (lazy imports), and under
``if TYPE_CHECKING:`` (a type-only import upward still couples a lower stage to a higher
one). The package root ``rprpr/__init__.py`` (the lazy public API), ``rprpr/api.py`` (the
result the public ``audit`` returns, with its report and HTML table), ``rprpr/__main__.py``
and ``rprpr/_version.py`` stand outside the stages.

And no part grows past what a reader holds at once: no module over 600 lines, no function
over 60, no class over 300 (``too_long``).
"""

from __future__ import annotations

import ast
import collections
import functools
import gc
from collections.abc import Iterator, Mapping
from pathlib import Path

import pytest

from .cli.forked import fresh_probe
from .conftest import ROOT

PACKAGE = ROOT / "rprpr"

ALLOWED: dict[str, set[str]] = {
    "cli": {"render", "report", "repair", "engine", "io", "model"},
    "render": {"report", "engine", "model"},
    "report": {"engine", "model"},
    "repair": {"engine", "model"},
    "engine": {"model"},
    "io": {"model"},
    "model": set(),
}
OUTSIDE = {"rprpr", "rprpr.__main__", "rprpr._version", "rprpr.api"}  # outside the stages
ANYONE_MAY_IMPORT = {"rprpr._version"}  # a leaf: the version string only

Graph = dict[str, set[str]]  # module -> the rprpr modules it imports


def modules(root: Path = PACKAGE) -> dict[str, Path]:
    """Every module of the package under ``root``, by dotted name."""
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root.parent).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = path
    return out


# the nodes the rules below read: imports, and what a size is counted of (all statements)
_READ = (ast.Import, ast.ImportFrom, ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)
# the fields that hold statements: a statement lies only in another's (or a module's, an
# except clause's, a match case's) lists of statements, never inside an expression
_BODIES = frozenset({"body", "orelse", "finalbody", "handlers", "cases"})


def _statements(tree: ast.AST) -> Iterator[ast.AST]:
    """``ast.walk(tree)`` without the expressions: the statements of ``tree`` (and the
    except clauses and match cases between them), in ``ast.walk``'s order (breadth
    first, each node's children in the order of its fields). Every ancestor of a
    statement is one of these, so each statement has the depth and the place among
    its level that ``ast.walk`` gives it; the expressions, ~90 % of a tree's nodes,
    are not visited."""
    todo = collections.deque([tree])
    while todo:
        node = todo.popleft()
        for name in node._fields:
            if name in _BODIES:
                todo.extend(getattr(node, name))
        yield node


@functools.cache
def _nodes(source: str) -> tuple[ast.AST, ...]:
    """Every node of the syntax tree of ``source`` that a rule reads (``_READ``), in
    ``ast.walk``'s order (``_statements``), parsed once per test process (the rules below
    read the package's modules many times, and only read them). The collector waits
    while a tree is built: a tree holds no reference cycle, and collecting only walked it."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        return tuple(n for n in _statements(ast.parse(source)) if isinstance(n, _READ))
    finally:
        if enabled:
            gc.enable()


@pytest.fixture(scope="module", autouse=True)
def _forget_the_trees() -> Iterator[None]:
    """The syntax trees (~350,000 objects) dropped once the module's tests are done: kept,
    they would be walked by every later full garbage collection of the test process."""
    yield
    _nodes.cache_clear()


def imported(name: str, source: str, is_package: bool, known: set[str]) -> Iterator[str]:
    """The modules of ``known`` that the module ``name`` imports anywhere in ``source``
    (``from . import x`` names the submodule ``x`` when there is one)."""
    package = name if is_package else name.rpartition(".")[0]
    for node in _nodes(source):
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names if a.name in known)
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join([*anchor, *([base] if base else [])])
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                if sub in known:
                    yield sub
                elif base in known:
                    yield base


def graph_of(sources: Mapping[str, tuple[str, bool]]) -> Graph:
    """The import graph of ``sources`` (name -> (source, is_package)), rprpr modules only."""
    known = set(sources)
    return {
        name: set(imported(name, src, is_pkg, known)) - {name}
        for name, (src, is_pkg) in sources.items()
    }


def package_graph() -> Graph:
    return graph_of(
        {
            name: (path.read_text(encoding="utf-8"), path.name == "__init__.py")
            for name, path in modules().items()
        }
    )


def stage(name: str) -> str | None:
    """The stage of the module ``name`` (``rprpr.engine.audit`` -> ``engine``)."""
    parts = name.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in ALLOWED else None


def upward(graph: Graph) -> list[str]:
    """Every import that breaks the direction, as "importer -> imported"."""
    bad = []
    for name, targets in sorted(graph.items()):
        if name in OUTSIDE:
            continue
        here = stage(name)
        for target in sorted(targets):
            there = stage(target)
            if target in ANYONE_MAY_IMPORT or there == here:
                continue
            if here is None or there is None or there not in ALLOWED[here]:
                bad.append(f"{name} -> {target}")
    return bad


def cycles(graph: Graph) -> list[list[str]]:
    """The import circles of ``graph``: its strongly connected components of more than one
    module (Tarjan), each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


# -- the package -------------------------------------------------------------------------
def test_every_module_lives_in_a_stage() -> None:
    strays = [n for n in modules() if n not in OUTSIDE and stage(n) is None]
    assert strays == []
    assert {stage(n) for n in modules()} - {None} == set(ALLOWED)


def test_dependencies_point_one_way() -> None:
    assert upward(package_graph()) == []


def test_no_import_circles() -> None:
    assert cycles(package_graph()) == []


def test_the_version_is_a_leaf() -> None:
    assert package_graph()["rprpr._version"] == set()


def test_the_graph_sees_lazy_type_only_and_relative_imports() -> None:
    g = package_graph()
    assert "rprpr.engine.audit" in g["rprpr.cli.check"]  # inside check_one
    assert "rprpr.report.run" in g["rprpr.report.exit"]  # under TYPE_CHECKING
    assert "rprpr.render.sheet" in g["rprpr.render.animation"]  # from . import sheet
    assert "rprpr.cli.main" in g["rprpr.__main__"]
    assert "rprpr.repair" in g["rprpr.cli.repair"]  # inside the command, lazily
    assert "rprpr.engine.audit" in g["rprpr.repair"]


# -- the rule itself: it catches what it is for ------------------------------------------
SYNTHETIC = {
    "rprpr": ("", True),
    "rprpr.model": ("", True),
    "rprpr.model.task": ("", False),
    "rprpr.engine": ("", True),
    "rprpr.engine.audit": ("from ..model.task import Task\n", False),
    "rprpr.report": ("", True),
    "rprpr.report.run": ("", False),
    "rprpr.cli": ("", True),
    "rprpr.cli.main": ("from ..report import run\n", False),
}


def _with(name: str, source: str) -> Graph:
    return graph_of({**SYNTHETIC, name: (source, False)})


def test_the_statement_walk_reads_what_ast_walk_reads_in_its_order() -> None:
    """``_statements`` finds every import and definition, in every kind of block, in the
    order ``ast.walk`` finds them (what the rules report is listed in that order)."""
    source = (
        "import a\n"
        "try:\n    import b\nexcept E:\n    import c\n"
        "    def f():\n        class K:\n            import d\n            x = lambda: 1\n"
        "else:\n    import e\nfinally:\n    from . import g\n"
        "try:\n    pass\nexcept* E:\n    import g2\n"
        "match x:\n    case 1:\n        import h\n        def q(): pass\n"
        "while w:\n    import i\nelse:\n    import j\n"
        "for x in y:\n    import k\nelse:\n    import l\n"
        "with m:\n    import n\n"
        "async def z():\n    async for a in b:\n        import o\n"
        "    async with c:\n        import p\n"
        "if TYPE_CHECKING:\n    import r\nelif s:\n    import t\nelse:\n"
        "    @dec\n    class C(B):\n        def u(self):\n            import v\n"
    )
    tree = ast.parse(source)
    walked = [n for n in ast.walk(tree) if isinstance(n, _READ)]
    assert [n for n in _statements(tree) if isinstance(n, _READ)] == walked
    assert len(walked) == 24


def test_a_clean_synthetic_package_passes() -> None:
    g = graph_of(SYNTHETIC)
    assert g["rprpr.cli.main"] == {"rprpr.report.run"}
    assert upward(g) == [] and cycles(g) == []


@pytest.mark.parametrize(
    "source",
    [
        "from ..engine.audit import audit\n",  # module level
        "def f():\n    from ..engine import audit\n",  # lazy, inside a function
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import rprpr.engine.audit\n",
    ],
)
def test_an_upward_import_fails(source: str) -> None:
    assert upward(_with("rprpr.model.task", source)) == ["rprpr.model.task -> rprpr.engine.audit"]


@pytest.mark.parametrize("importer", ["rprpr.engine.audit", "rprpr.report.run", "rprpr.model.task"])
def test_repair_sits_above_the_engine_and_below_the_command_line(importer: str) -> None:
    repair = {"rprpr.repair": ("from ..engine.audit import audit\n", True)}
    source = "from ..repair import repair\n"
    g = graph_of({**SYNTHETIC, **repair, importer: (source, False)})
    assert upward(g) == [f"{importer} -> rprpr.repair"]
    g = graph_of({**SYNTHETIC, **repair, "rprpr.cli.main": (source, False)})
    assert upward(g) == []


def test_importing_the_package_root_from_a_stage_fails() -> None:
    assert upward(_with("rprpr.engine.audit", "from .. import audit\n")) == [
        "rprpr.engine.audit -> rprpr"
    ]


def test_a_circle_within_a_stage_fails() -> None:
    g = graph_of(
        {
            **SYNTHETIC,
            "rprpr.report.run": ("def f():\n    from . import exit\n", False),
            "rprpr.report.exit": ("from .run import Run\n", False),
        }
    )
    assert upward(g) == []
    assert cycles(g) == [["rprpr.report.exit", "rprpr.report.run"]]


# -- start-up probes: fresh processes, forked from one interpreter ------------------------
# Each probe asks what a fresh process running it imports. They all run in one interpreter
# with the suite's other start-up probes (``tests.cli.forked.fresh_probe``, read through the
# session fixture ``fresh``), each in a child forked from it: first those that start bare,
# then, once it has imported the dependencies the others start from (``FLOOR``, which those
# probes import first and subtract), the rest: the dependencies' start-up (~0.2 CPU-s) is
# paid once, not once a probe.
FLOOR = "numpy, flint, yaml, click, rich.console, rich.table"


def _probe(name: str, floored: bool, code: str) -> None:
    """A probe of this module, run in ROOT, from FLOOR when ``floored``."""
    fresh_probe(f"test_layout {name}", FLOOR if floored else "", code, ROOT)


@pytest.fixture
def probed(fresh: dict[str, tuple[int, str, str]]) -> dict[str, tuple[int, str, str]]:
    """Each probe's (exit status, standard output, standard error), by its name here."""
    return {k.removeprefix("test_layout "): v for k, v in fresh.items()}


# -- start-up: --version and --help load nothing heavy -----------------------------------
HEAVY = ("numpy", "flint", "yaml", "matplotlib", "rich")
STARTS = [["--version"], ["--help"], ["check", "--help"]]
for _argv in STARTS:
    _probe(
        f"start {_argv}",
        False,
        "import sys\n"
        "from rprpr.cli.main import main\n"
        "try:\n"
        f"    main({_argv!r})\n"
        "except SystemExit as e:\n"
        "    code = e.code\n"
        f"heavy = sorted(m for m in sys.modules if m.split('.')[0] in {HEAVY!r})\n"
        "deep = sorted(m for m in sys.modules if m.startswith(('rprpr.engine', 'rprpr.io',"
        " 'rprpr.render', 'rprpr.report.records', 'rprpr.report.run')))\n"
        "sys.stderr.write(f'EXIT={code} HEAVY={heavy} DEEP={deep}\\n')\n",
    )


@pytest.mark.parametrize("argv", STARTS)
def test_version_and_help_load_no_engine_numpy_flint_or_yaml(
    argv: list[str], probed: dict[str, tuple[int, str, str]]
) -> None:
    _, stdout, stderr = probed[f"start {argv}"]
    assert stderr.strip().splitlines()[-1] == "EXIT=0 HEAVY=[] DEEP=[]", stderr
    assert ("rprpr, version" in stdout) == (argv == ["--version"])


# -- start-up: check loads only what the task in hand needs ---------------------------------
BALLS = ("balls", "certified", "envelope", "zones", "batch", "sampling", "repair")
NEEDS = [
    ("case1_crossing", []),  # unbounded torques, no limit: no pass, no ball machinery
    ("paper_path2", ["balls", "certified", "envelope", "zones"]),  # its limit needs passes
]
for _config, _ in NEEDS:
    # check_one is what a worker runs per task (the parent imports the audit before
    # forking; these modules a task loads on demand)
    _probe(
        f"check_one {_config}",
        True,
        # what rprpr adds to its dependencies' own imports (an older numpy imports
        # numpy.polynomial itself)
        "import sys, numpy, flint, yaml, click\n"
        "floor = set(sys.modules)\n"
        "from rprpr.cli.check import check_one\n"
        "from rprpr.cli.options import CheckOptions\n"
        f"kind, *_ = check_one('configs/{_config}.rprpr.yaml', CheckOptions())\n"
        f"got = sorted(m.split('.')[-1] for m in sys.modules if m.split('.')[-1] in {BALLS!r}"
        " and m.startswith(('rprpr.engine', 'rprpr.repair')))\n"
        "got += sorted(m for m in set(sys.modules) - floor if m.startswith(('numpy.polynomial',"
        " 'multiprocessing')))\n"
        "sys.stderr.write(f'KIND={kind} LOADED={got}\\n')\n",
    )


@pytest.mark.parametrize(("config", "loaded"), NEEDS)
def test_check_imports_the_ball_machinery_only_for_a_task_that_needs_a_pass(
    config: str, loaded: list[str], probed: dict[str, tuple[int, str, str]]
) -> None:
    _, _, stderr = probed[f"check_one {config}"]
    assert stderr.strip().splitlines()[-1] == f"KIND=report LOADED={loaded}", stderr


# -- inside io: the loader's pipeline runs one way ----------------------------------------
# Each module of the loader's pipeline imports only modules before it in this order (the
# walk knows neither its readers nor its rules: the loader hands them over).
PIPELINE = (
    "messages",
    "scalars",
    "source",
    "yaml_nodes",
    "walk",
    "readers",
    "build",
    "cross_rules",
    "loader",
)


def test_the_loaders_pipeline_imports_only_earlier_steps() -> None:
    g = package_graph()
    steps = [f"rprpr.io.{m}" for m in PIPELINE]
    later = [
        f"{a} -> {b}" for i, a in enumerate(steps) for b in sorted(g[a]) if b in steps[i + 1 :]
    ]
    assert later == []
    assert "rprpr.io.walk" in g["rprpr.io.readers"]  # the rule sees these imports


_probe(
    "messages",
    False,
    "import sys, rprpr.io.messages\n"
    "print(sorted(m for m in ('yaml', 'flint', 'numpy') if m in sys.modules))\n",
)


def test_the_messages_load_no_yaml_flint_or_numpy(
    probed: dict[str, tuple[int, str, str]],
) -> None:
    _, stdout, stderr = probed["messages"]
    assert stdout.strip() == "[]", stderr


# modules no `check` of a task file needs in rprpr's own process (the worker imports the ball
# machinery on demand: above): repair, the plots and the HTML sheet, the schema validator;
# and of the standard library and numpy, what costs start-up and a check does without: the
# workers are forked without multiprocessing, paths are strings (os.path), the guides in
# double precision evaluate without numpy.polynomial, traceback waits for a bug
NOT_FOR_CHECK = (
    "multiprocessing", "pathlib", "urllib", "numpy.polynomial", "json", "difflib", "traceback",
    "jsonschema", "matplotlib", "scipy", "sympy", "mpmath", "rprpr.repair", "rprpr.cli.repair",
    "rprpr.engine.certified", "rprpr.engine.robust", "rprpr.render.html", "rprpr.render.sheet",
    *(f"rprpr.engine.bounds.{m}" for m in ("approach", "batch", "boxes", "envelope", "ladders",
                                           "limits", "near", "search")),
    "rprpr.render.json", "rprpr.cli.plot", "rprpr.cli.export",
    # the readers of waypoints and of planner motions: a task that has them loads them
    "rprpr.io.waypoint_csv", "rprpr.model.waypoints", "rprpr.model.motion",
)  # fmt: skip


CHECKED = ["case1_crossing", "paper_path2"]
for _config in CHECKED:
    _probe(
        f"check {_config}",
        True,
        # what the check adds to its dependencies' own imports (an editable install's
        # finder may bring pathlib; an older numpy imports numpy.polynomial, an older
        # click or rich traceback)
        f"import sys, {FLOOR}\n"
        "before = set(sys.modules)\n"
        "from rprpr.cli.main import main\n"
        "try:\n"
        f"    main(['check', 'configs/{_config}.rprpr.yaml'])\n"
        "except SystemExit as e:\n"
        "    code = e.code\n"
        f"got = sorted(m for m in set(sys.modules) - before if m.startswith({NOT_FOR_CHECK!r}))\n"
        "sys.stderr.write(f'EXIT={code} LOADED={got}\\n')\n",
    )


@pytest.mark.parametrize("config", CHECKED)
def test_check_of_a_shipped_config_imports_no_repair_plot_schema_or_balls_before_forking(
    config: str, probed: dict[str, tuple[int, str, str]]
) -> None:
    _, _, stderr = probed[f"check {config}"]
    exit_code = {"case1_crossing": 1, "paper_path2": 0}[config]  # unbounded torques fail
    assert stderr.strip().splitlines()[-1] == f"EXIT={exit_code} LOADED=[]", stderr


# -- inside engine: its three layers, one way -------------------------------------------------
# exact (the paper in rational arithmetic) <- certified (floats with proofs) <- bounds
# (grid-free verdicts) <- the audit's own modules (pieces, findings, audit) directly in engine/.
ENGINE_LAYERS: dict[str, set[str]] = {
    "exact": set(),
    "certified": {"exact"},
    "bounds": {"certified", "exact"},
    "": {"bounds", "certified", "exact"},  # engine/pieces.py, findings.py, audit.py
}


def engine_layer(name: str) -> str | None:
    """``rprpr.engine.exact.roots`` -> ``exact``; ``rprpr.engine.audit`` -> ``""``."""
    parts = name.split(".")
    if parts[:2] != ["rprpr", "engine"] or len(parts) < 3:
        return None
    return parts[2] if parts[2] in ENGINE_LAYERS else ""


def engine_upward(graph: Graph) -> list[str]:
    bad = []
    for name, targets in sorted(graph.items()):
        here = engine_layer(name)
        if here is None:
            continue
        for target in sorted(targets):
            there = engine_layer(target)
            if there is None or there == here:
                continue
            if there not in ENGINE_LAYERS[here]:
                bad.append(f"{name} -> {target}")
    return bad


def test_the_engines_layers_import_only_the_layers_below() -> None:
    g = package_graph()
    assert engine_upward(g) == []
    for layer in ("exact", "certified", "bounds"):  # each layer is a package with modules
        assert any(engine_layer(m) == layer for m in g if m != f"rprpr.engine.{layer}")
    assert "rprpr.engine.exact.roots" in g["rprpr.engine.certified.zones"]  # the rule sees these


def test_the_engine_layer_rule_catches_an_upward_import() -> None:
    fake = {
        "rprpr.engine.exact.singular": ("from ..certified.balls import Ball\n", False),
        "rprpr.engine.certified.balls": ("", False),
        "rprpr.engine.bounds.search": ("from ...engine import audit\n", False),
        "rprpr.engine.audit": ("", False),
    }
    assert engine_upward(graph_of(fake)) == [
        "rprpr.engine.bounds.search -> rprpr.engine.audit",
        "rprpr.engine.exact.singular -> rprpr.engine.certified.balls",
    ]


# -- sizes: no module over 600 lines, no function over 60, no class over 300 ---------------
MAX_MODULE, MAX_FUNCTION, MAX_CLASS = 600, 60, 300
# "module:name" (or "module" alone) -> why it may stay longer; empty: every part of rprpr
# keeps to the sizes (a part that must not says why here, for its reader to judge)
LONG_ALLOWED: dict[str, str] = {}


def too_long(sources: Mapping[str, str], allowed: Mapping[str, str] = LONG_ALLOWED) -> list[str]:
    """Every module (by its lines), function or class (from its ``def`` or ``class`` line
    to its last) of ``sources`` (dotted name -> text) longer than its size allows."""
    bad = []
    for name, text in sorted(sources.items()):
        lines = len(text.splitlines())
        if lines > MAX_MODULE and name not in allowed:
            bad.append(f"{name}: module of {lines} lines (at most {MAX_MODULE})")
        for node in _nodes(text):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                continue
            most = MAX_CLASS if isinstance(node, ast.ClassDef) else MAX_FUNCTION
            size = (node.end_lineno or node.lineno) - node.lineno + 1
            if size > most and f"{name}:{node.name}" not in allowed:
                bad.append(f"{name}:{node.lineno}: {node.name} of {size} lines (at most {most})")
    return bad


def test_no_module_function_or_class_is_too_long() -> None:
    sources = {name: path.read_text(encoding="utf-8") for name, path in modules().items()}
    assert too_long(sources) == []
    assert all(
        name.split(":")[0] in sources for name in LONG_ALLOWED
    )  # no excuse outlives its module


def _lines(n: int, indent: str = "    ") -> str:
    return "".join(f"{indent}x{i} = {i}\n" for i in range(n))


def test_the_size_rule_catches_a_long_module_function_or_class() -> None:
    # def line + body: 60 lines pass, 61 fail; a class likewise at 300, a module at 600
    fine = {
        "m.f": "def f():\n" + _lines(MAX_FUNCTION - 1),
        "m.c": "class C:\n" + _lines(MAX_CLASS - 1),
        "m.m": _lines(MAX_MODULE, ""),
    }
    assert too_long(fine) == []
    long = {
        "m.f": "def f():\n" + _lines(MAX_FUNCTION),
        "m.c": "class C:\n" + _lines(MAX_CLASS),
        "m.m": _lines(MAX_MODULE + 1, ""),
        "m.n": "class C:\n    async def g(self):\n" + _lines(MAX_FUNCTION, "        "),
    }
    assert too_long(long) == [
        "m.c:1: C of 301 lines (at most 300)",
        "m.f:1: f of 61 lines (at most 60)",
        "m.m: module of 601 lines (at most 600)",
        "m.n:2: g of 61 lines (at most 60)",
    ]
    assert too_long(long, {"m.c:C": "", "m.f:f": "", "m.m": "", "m.n:g": ""}) == []


def private_imports(sources: Mapping[str, str]) -> list[str]:
    """Every ``from <rprpr module> import _name``: a private name read from another
    module (what another module reads is public, or it stays in its module)."""
    bad = []
    for name, source in sorted(sources.items()):
        for node in _nodes(source):
            if isinstance(node, ast.ImportFrom) and (
                node.level or (node.module or "").startswith("rprpr")
            ):
                bad += [
                    f"{name}: {a.name}"
                    for a in node.names
                    if a.name.startswith("_") and not a.name.endswith("__")  # dunders are public
                ]
    return bad


def test_no_private_name_is_imported_across_modules() -> None:
    sources = {n: p.read_text(encoding="utf-8") for n, p in modules().items()}
    assert private_imports(sources) == []
    assert private_imports({"rprpr.x": "from .y import _z, w\n"}) == ["rprpr.x: _z"]

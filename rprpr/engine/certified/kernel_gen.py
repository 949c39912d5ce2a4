"""The compiled ball kernel's C source, generated from the Python formulas themselves.

    python -m rprpr.engine.certified.kernel_gen           # rewrites rprpr/_kernel.c
    python -m rprpr.engine.certified.kernel_gen --check   # exit 1 if the file differs

Nothing here runs when rprpr audits: this module writes ``rprpr/_kernel.c``, which the
build compiles (``setup.py``, optional) and ``kernel.py`` calls. The formulas are not
restated in C. ``Stacked.legs``, ``Stacked.torques`` and ``balls.horner`` run, on balls
and on jets of balls (``jets.Jet``), over *recording* balls (``Sym``): each ball
operation they perform (+, -, ×, ÷, negation, √, a row taken) is written down with its
operands in the order numpy's path gets them, and each one is emitted as the C
statements of the same IEEE-754 operations, in the same order, that ``balls.Ball``
performs on numpy arrays (its radius bound and padding: ``balls.py``'s docstring). The
build compiles it with ``-ffp-contract=off`` and no fast-math, so every result is the
same double as numpy's, bit for bit (tests/engine/certified/test_kernel.py checks it on
random balls, and the enclosures against an mpmath reference). The C forms of the five
ball operations (``_MUL``, ``_ADD`` ... below) are the one part written twice; the test
holds them to ``balls.py``.

The kernel computes one column (one time or box) at a time; a value is one scalar ball
per row (1 row, or the two legs' rows 0 and 1). Inputs are read through the buffer
protocol with their own strides (0 where numpy broadcasts), outputs are written into one
preallocated float64 array."""

from __future__ import annotations

import hashlib
import sys
from pathlib import Path
from typing import Any

import numpy as np

from ..exact.regressor_form import LINKS
from . import balls
from . import jets as jets_
from .balls import Ball
from .jets import Jet
from .kernel_c import BOX_MAX, FORM_BOUNDS, HEAD, HORNER, RUNTIME, TAIL
from .kernel_c_bounds import BOUNDS

OUT = Path(__file__).resolve().parents[2] / "_kernel.c"


class Graph:
    """The scalar ball operations of one kernel, in order (identical ones shared: the
    same operation on the same operands gives the same doubles)."""

    def __init__(self) -> None:
        self.ops: list[tuple[Any, ...]] = []
        self.index: dict[tuple[Any, ...], int] = {}

    def node(self, *op: Any) -> int:
        if op not in self.index:
            self.index[op] = len(self.ops)
            self.ops.append(op)
        return self.index[op]

    def const(self, m: float, r: float) -> int:
        return self.node("const", float(m).hex(), float(r).hex())


class Sym(Ball):
    """A recording ball: one node of ``graph`` per row (1 or 2 rows)."""

    __slots__ = ("graph", "rows")

    def __init__(self, graph: Graph, rows: list[int]) -> None:
        self.graph = graph
        self.rows = rows

    # the operand a Ball operation would make of ``o`` (``Ball.coerce``)
    def _operand(self, o: Any) -> Sym | None:
        if isinstance(o, Sym):
            return o
        if isinstance(o, Jet):
            return None
        if not isinstance(o, (int, float, np.floating, np.integer, Ball)):
            return None
        b = Ball.coerce(o)
        m, r = np.asarray(b.mid, dtype=float), np.asarray(b.rad, dtype=float)
        if m.ndim == 0 and r.ndim == 0:
            return Sym(self.graph, [self.graph.const(float(m), float(r))])
        mm, rr = np.broadcast_arrays(m, r)
        if mm.shape != (2, 1):
            raise ValueError(f"a constant of shape {mm.shape} in a traced formula")
        return Sym(self.graph, [self.graph.const(mm[i, 0], rr[i, 0]) for i in range(2)])

    def _op(self, name: str, a: Sym, b: Sym) -> Sym:
        n = max(len(a.rows), len(b.rows))
        ra = a.rows * n if len(a.rows) == 1 else a.rows
        rb = b.rows * n if len(b.rows) == 1 else b.rows
        return Sym(self.graph, [self.graph.node(name, x, y) for x, y in zip(ra, rb, strict=True)])

    def _binary(self, name: str, o: Any, reflected: bool) -> Any:
        b = self._operand(o)
        if b is None:
            return NotImplemented
        return self._op(name, b, self) if reflected else self._op(name, self, b)

    def __add__(self, o: Any) -> Any:
        return self._binary("add", o, False)

    def __radd__(self, o: Any) -> Any:  # as __rmul__
        return self._binary("add", o, isinstance(o, Ball))

    def __sub__(self, o: Any) -> Any:
        return self._binary("sub", o, False)

    def __rsub__(self, o: Any) -> Any:
        return self._binary("sub", o, True)

    def __mul__(self, o: Any) -> Any:
        return self._binary("mul", o, False)

    def __rmul__(self, o: Any) -> Any:
        # a Ball on the left: numpy's path runs left.__mul__(self); a number: self.__mul__
        return self._binary("mul", o, isinstance(o, Ball))

    def __truediv__(self, o: Any) -> Any:
        return self._binary("div", o, False)

    def __rtruediv__(self, o: Any) -> Any:
        return self._binary("div", o, True)

    def __neg__(self) -> Sym:
        return Sym(self.graph, [self.graph.node("neg", r) for r in self.rows])

    def sqrt(self) -> Sym:
        return Sym(self.graph, [self.graph.node("sqrt", r) for r in self.rows])

    def __getitem__(self, index: Any) -> Sym:
        if isinstance(index, int) and len(self.rows) == 2:
            return Sym(self.graph, [self.rows[index]])
        if index == slice(None, None, -1) and len(self.rows) == 2:
            return Sym(self.graph, self.rows[::-1])
        raise ValueError(f"a traced formula takes {index!r} of a ball of {len(self.rows)} rows")

    def __abs__(self) -> Ball:
        raise ValueError("abs in a traced formula")


# -- the C forms of balls.Ball's operations (each: the same IEEE operations, in order) --
_C = {k: float(v).hex() for k, v in (("U", balls.U), ("ETA", balls.ETA), ("GROW", balls._GROW),
                                     ("PAD", balls._PAD), ("TINY", balls.TINY),
                                     ("SQ", 1 + 4 * balls.U), ("DOWN", balls._DOWN),
                                     ("FOURU", 4 * balls.U))}  # fmt: skip

# (a, b -> c): mid m{c}, radius r{c}; t, u: scratch
_SUM = "t = r{a} + r{b}; u = fabs(m{c}) * U; t = t + u; t = t * GROW; r{c} = t + PAD;"
_ADD = "m{c} = m{a} + m{b}; " + _SUM
_SUB = "m{c} = m{a} - m{b}; " + _SUM
_MUL = (
    "m{c} = m{a} * m{b}; t = fabs(m{a}) + r{a}; t = t * r{b}; u = fabs(m{b}) * r{a}; t = t + u;"
    " u = fabs(m{c}) * U; u = u + ETA; t = t + u; t = t * GROW; r{c} = t + PAD;"
)
_DIV = (
    "b = fabs(m{b}); m{c} = m{a} / m{b}; t = r{a} * b; u = fabs(m{a}) * r{b}; t = t + u;"
    " t = t + TINY; t = t / b; t = t + TINY; u = b - r{b}; t = t / u; u = fabs(m{c}) * U;"
    " u = u + ETA; t = t + u; t = t * GROW; r{c} = t + PAD;"
    " m{c} = b > r{b} ? m{c} : NAN; r{c} = b > r{b} ? r{c} : INFINITY;"
)
_NEG = "m{c} = -m{a}; r{c} = r{a};"
_SQRT = (
    "m{c} = sqrt(m{a} > 0 ? m{a} : 0.0);"
    " t = (r{a} * SQ) / m{c}; t = m{a} > 0 ? t : INFINITY; u = sqrt(r{a}); t = nanmin(t, u);"
    " u = m{a} + r{a}; u = sqrt(nanmax(u, 0.0)); t = m{a} > 0 ? t : u;"
    " u = U * m{c}; t = t + u; t = t * GROW; r{c} = t + PAD;"
    " b = m{a} + r{a}; m{c} = b < 0 ? NAN : m{c}; r{c} = b < 0 ? INFINITY : r{c};"
)
_FORMS = {"add": _ADD, "sub": _SUB, "mul": _MUL, "div": _DIV, "neg": _NEG, "sqrt": _SQRT}


def emit(graph: Graph, outputs: list[int], load: dict[int, tuple[str, str]]) -> list[str]:
    """C statements computing the nodes ``outputs`` need (inputs read by ``load``)."""
    need = _needed(graph, outputs)
    lines = []
    for k in sorted(need):
        op = graph.ops[k]
        if op[0] == "in":
            m, r = load[k]
            lines.append(f"double m{k} = {m}, r{k} = {r};")
        elif op[0] == "const":
            lines.append(f"const double m{k} = {_literal(op[1])}, r{k} = {_literal(op[2])};")
        else:
            args = dict(zip("ab", op[1:], strict=False))
            lines.append(f"double m{k}, r{k}; " + _FORMS[op[0]].format(c=k, **args))
    return lines


def _literal(h: str) -> str:
    v = float.fromhex(h)
    if v != v:
        return "NAN"
    if v in (float("inf"), float("-inf")):
        return "INFINITY" if v > 0 else "-INFINITY"
    return h


# -- the kernels ------------------------------------------------------------------------
class Kernel:
    """One traced kernel: its input slots (balls of 1 or 2 rows), its outputs (balls)."""

    def __init__(self, name: str) -> None:
        self.name = name
        self.graph = Graph()
        self.slots: list[int] = []  # rows of each input slot

    def ball(self, rows: int) -> Sym:
        k = len(self.slots)
        self.slots.append(rows)
        return Sym(self.graph, [self.graph.node("in", k, i) for i in range(rows)])

    def jet(self, rows: int) -> Jet:
        return Jet(self.ball(rows), self.ball(rows))

    def source(self, outputs: list[Any]) -> str:
        """The C function ``k_<name>``: every column j of n, the outputs' rows (mids then
        radii, output by output) into out[(row) * n + j]. Columns go BLK at a time: the
        block's inputs read (with their strides) into contiguous arrays, every column
        of the block computed by one loop without branches (which the compiler may run
        on several columns at once: the same IEEE operations on each), the outputs
        copied out."""
        ids = [r for o in outputs for r in o.rows]
        used = sorted(k for k in _needed(self.graph, ids) if self.graph.ops[k][0] == "in")
        load, gather = {}, []
        for i, k in enumerate(used):
            op = self.graph.ops[k]
            load[k] = (f"I[{2 * i}][c]", f"I[{2 * i + 1}][c]")
            gather.append(f"I[{2 * i}][c] = LD(in[{op[1]}].m, {op[2]}, j);")
            gather.append(f"I[{2 * i + 1}][c] = LD(in[{op[1]}].r, {op[2]}, j);")
        body = emit(self.graph, ids, load)
        store, row = [], 0
        for o in outputs:
            for r in o.rows:
                store.append(f"O[{row}][c] = m{r};")
                store.append(f"O[{row + len(o.rows)}][c] = r{r};")
                row += 1
            row += len(o.rows)
        self.rows_out = [len(o.rows) for o in outputs]
        lines = [
            f"static void k_{self.name}(Py_ssize_t n, const Slot *in, double *out)",
            "{",
            f"    double I[{max(2 * len(used), 1)}][BLK], O[{row}][BLK];",
            "    for (Py_ssize_t j0 = 0; j0 < n; j0 += BLK) {",
            "        int nb = n - j0 < BLK ? (int)(n - j0) : BLK;",
            "        for (int c = 0; c < nb; c++) {",
            "            Py_ssize_t j = j0 + c;",
            *(f"            {s}" for s in gather),
            "        }",
            "        for (int c = 0; c < nb; c++) {",
            "            double t, u, b;",
            "            (void)b;",
            *(f"            {s}" for s in body + store),
            "        }",
            f"        for (int q = 0; q < {row}; q++)",
            "            memcpy(out + q * n + j0, O[q], (size_t)nb * sizeof(double));",
            "    }",
            "}",
        ]
        return "\n".join(lines)


def _needed(graph: Graph, outputs: list[int]) -> set[int]:
    """The nodes the outputs need."""
    need: set[int] = set()
    stack = list(outputs)
    while stack:
        k = stack.pop()
        if k in need:
            continue
        need.add(k)
        op = graph.ops[k]
        if op[0] in _FORMS:
            stack.extend(op[1:])
    return need


def _stacked(kernel: Kernel, prismatic: bool) -> Any:
    """A ``Stacked`` whose robot constants are the kernel's first seven inputs (``sign``
    is the same for every robot: a constant)."""
    from .stacked import Stacked

    st = object.__new__(Stacked)
    st.base = kernel.ball(2)
    st.a1 = kernel.ball(1)
    st.m, st.r, st.K, st.G, st.mg = (kernel.ball(2) for _ in range(5))
    g = kernel.graph
    st.sign = Sym(g, [g.const(1.0, 0.0), g.const(-1.0, 0.0)])
    st.prismatic = prismatic
    return st


LEG_FIELDS = ("s", "cos", "sin", "s_d", "th_d", "s_dd", "th_dd")


def kernels() -> list[tuple[Kernel, list[Any]]]:
    """Every kernel and its outputs (the order ``kernel.py`` reads them in).

    legs_{ball,jet}: inputs base, a1, m, r, K, G, mg (Stacked's constants), then x, ẋ, ẍ,
    y, ẏ, ÿ (balls, or jets: value then derivative); outputs the seven fields of
    ``equations.Leg`` (2 rows; jets: value then derivative).
    torques_{ball,jet}_{revolute,prismatic}: the same constants, then the seven Leg
    fields and y; outputs T (2 rows) and δ (``Stacked.torques(lg, y)``).
    torques_at_{ball,jet}_{revolute,prismatic}: the same inputs and δ; output T
    (``Stacked.torques(lg, y, delta=δ)``).
    efforts_{ball,jet}_{revolute,prismatic}: the constants, then x, ẋ, ẍ, y, ẏ, ÿ; output T
    (``Stacked.efforts``: the legs and the torques in one call).
    efforts_at_{ball,jet}_{revolute,prismatic}: the same inputs and λ1, λ2; output T
    (``Stacked.efforts_at``: the legs and the torques at λ given, in one call).
    formulas_{revolute,prismatic}: inputs the robot's parameters (``motion.PARAMS``), then
    x, ẋ, ẍ, y, ẏ, ÿ; outputs ``CertifiedMotion.formulas``' values but its arguments
    (``motion.COMPUTED``).
    regressor_{ball,jet}_{revolute,prismatic}: inputs a1, g, then x, ẋ, ẍ, y, ẏ, ÿ;
    outputs the robust regressor's entries (``_regressors``).
    y_values, y_jets: y's derivatives of ``jets.y_values``/``y_jets`` (``_chain``).
    horner: inputs acc, x, c; output acc·x + c (one step of ``balls.horner``)."""
    from ..exact import equations as dyn

    out: list[tuple[Kernel, list[Any]]] = []
    for jets in (False, True):
        kind = "jet" if jets else "ball"
        k = Kernel(f"legs_{kind}")
        st = _stacked(k, False)
        args = [k.jet(1) if jets else k.ball(1) for _ in range(6)]
        lg = st._legs(*args)
        res = [getattr(lg, f) for f in LEG_FIELDS]
        out.append((k, _flat(res)))
        for prismatic in (False, True):
            k = Kernel(f"torques_{kind}_{'prismatic' if prismatic else 'revolute'}")
            st = _stacked(k, prismatic)
            fields = [k.jet(2) if jets else k.ball(2) for _ in LEG_FIELDS]
            y = k.jet(1) if jets else k.ball(1)
            T, delta = st._torques(dyn.Leg(*fields), y)
            out.append((k, _flat([T, delta])))
            k = Kernel(f"torques_at_{kind}_{'prismatic' if prismatic else 'revolute'}")
            st = _stacked(k, prismatic)
            fields = [k.jet(2) if jets else k.ball(2) for _ in LEG_FIELDS]
            y = k.jet(1) if jets else k.ball(1)
            given = k.jet(1) if jets else k.ball(1)
            T, _ = st._torques(dyn.Leg(*fields), y, delta=given)
            out.append((k, _flat([T])))
            out.append(_efforts(jets, prismatic))
            out.append(_efforts(jets, prismatic, at=True))
    out += _formulas()
    out += _regressors()
    out += [_chain(name, n) for name, n in (("y_values", 5), ("y_jets", 7))]
    k = Kernel("horner")
    acc, x, c = k.ball(1), k.ball(1), k.ball(1)
    step = balls._horner([c, acc], x)  # acc·x + c: the loop's one step
    out.append((k, [step]))
    return out


def _formulas() -> list[tuple[Kernel, list[Any]]]:
    """formulas_{revolute,prismatic}: ``CertifiedMotion.formulas`` on recording balls."""
    from types import SimpleNamespace

    from ..exact import equations as dyn
    from .motion import COMPUTED, PARAMS, CertifiedMotion

    out: list[tuple[Kernel, list[Any]]] = []
    for mech in dyn.MECHANISMS.values():  # the RPRPR's schemes
        k = Kernel(f"formulas_{mech.name}")
        params = dyn.Params(**{f: k.ball(1) for f in PARAMS}, mechanism=mech)
        kin = [k.ball(1) for _ in range(6)]
        fake = SimpleNamespace(params=params, mech=mech)  # the motion's parts formulas reads
        got = CertifiedMotion._formulas(fake, *kin)  # type: ignore[arg-type]
        out.append((k, [got[name] for name in COMPUTED]))
    return out


def _efforts(jets: bool, prismatic: bool, at: bool = False) -> tuple[Kernel, list[Any]]:
    """efforts_{ball,jet}_{scheme}: ``Stacked.efforts``, the legs then the torques; with
    ``at``, efforts_at_{ball,jet}_{scheme}: the same at λ1, λ2 given (two inputs more)."""
    kind = "jet" if jets else "ball"
    name = "efforts_at" if at else "efforts"
    k = Kernel(f"{name}_{kind}_{'prismatic' if prismatic else 'revolute'}")
    st = _stacked(k, prismatic)
    kin = [k.jet(1) if jets else k.ball(1) for _ in range(6)]
    lam = tuple(k.jet(1) if jets else k.ball(1) for _ in range(2)) if at else None
    T, _ = st._torques(st._legs(*kin), kin[3], lam)
    return k, _flat([T])


def _chain(name: str, n: int) -> tuple[Kernel, list[Any]]:
    """y_values, y_jets: ``jets.y_values``/``jets.y_jets`` on n balls of one row."""
    k = Kernel(name)
    return k, getattr(jets_, name)(*(k.ball(1) for _ in range(n)))


def _regressors() -> list[tuple[Kernel, list[Any]]]:
    """regressor_{ball,jet}_{revolute,prismatic}: inputs a1, g, then x, ẋ, ẍ, y, ẏ, ÿ
    (balls, or jets: value then derivative); outputs ``robust.regressor.regressor_balls``'
    array [effort, ``BASIS``, error part] entry by entry, in C order (an entry the closed
    form leaves out: the exact zero numpy's array holds), a jet's values first, then its
    derivatives (a ball entry's derivative: the exact zero)."""
    from ..exact import equations as dyn
    from ..exact.regressor_form import regressor_columns

    out: list[tuple[Kernel, list[Any]]] = []
    for jets in (False, True):
        for mech in dyn.MECHANISMS.values():  # the RPRPR's schemes
            k = Kernel(f"regressor_{'jet' if jets else 'ball'}_{mech.name}")
            a1, g = k.ball(1), k.ball(1)
            p = dyn.Params(a1, g, *(None,) * 12, mech)
            kin = [k.jet(1) if jets else k.ball(1) for _ in range(6)]
            cols = regressor_columns(p, kin, dyn.hypot)
            zero = Sym(k.graph, [k.graph.const(0.0, 0.0)])
            entries = [b for row in cols for entry in row for b in entry]
            if not jets:
                out.append((k, [zero if b is None else b for b in entries]))
                continue
            vs = [zero if b is None else b if isinstance(b, Sym) else b.v for b in entries]
            ds = [zero if b is None or isinstance(b, Sym) else b.d for b in entries]
            out.append((k, vs + ds))
    return out


def _flat(values: list[Any]) -> list[Any]:
    """The traced outputs as recorded balls (a jet: its value, then its derivative)."""
    flat: list[Any] = []
    for v in values:
        flat.extend([v.v, v.d] if isinstance(v, Jet) else [v])
    for s in flat:
        assert isinstance(s, Sym), s
    return flat


def source() -> str:
    """The whole C file."""
    parts = [HEAD, DIGEST_LINE]
    parts += [f"#define {k} {v}" for k, v in _C.items()]
    for name, q in (("LINKS_M", 1), ("LINKS_MR", 2), ("LINKS_J", 3)):  # regressor_form.LINKS
        cols = ", ".join(str(-1 if row[q] is None else row[q]) for row in LINKS)
        parts.append(f"#define {name} {{{cols}}}")
    parts.append(RUNTIME)
    specs = []
    for k, outs in kernels():
        parts.append(k.source(outs))
        parts.append("")
        if k.name == "horner":
            continue
        rows = ", ".join(str(r) for r in k.slots)
        parts.append(f"static const int rows_{k.name}[] = {{{rows}}};")
        nout = 2 * sum(k.rows_out)
        specs.append(f'    {{"{k.name}", k_{k.name}, {len(k.slots)}, rows_{k.name}, {nout}}},')
    parts.append(HORNER)
    parts.append(BOUNDS)
    parts.append(BOX_MAX)
    parts.append(FORM_BOUNDS)
    parts.append("static const Spec SPECS[] = {")
    parts += specs
    parts.append("};")
    parts.append(TAIL.replace("NSPECS", str(len(specs))))
    body = "\n".join(parts)
    return body.replace(DIGEST_LINE, digest_line(body), 1)


DIGEST_LINE = '#define KERNEL_DIGEST ""'  # the source's own digest (kernel.py: a stale build)


def digest_line(body: str) -> str:
    """The line that names the source: a digest of the file with that line left empty."""
    return f'#define KERNEL_DIGEST "{hashlib.sha256(body.encode()).hexdigest()[:16]}"'


def main(argv: list[str]) -> int:
    text = source()
    if "--check" in argv:
        same = OUT.exists() and OUT.read_text(encoding="utf-8") == text
        if not same:
            print(f"{OUT} differs from its generator: run python -m {__spec__.name}")
        return 0 if same else 1
    OUT.write_text(text, encoding="utf-8")
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))

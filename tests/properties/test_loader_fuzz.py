"""Property-based tests of the loader and the polynomial parser (hypothesis).

* Whatever text or bytes arrive, ``parse_task`` returns a valid ``Task`` or raises
  ``TaskFileError``; nothing else escapes (no KeyError, RecursionError, crash, hang).
* A random polynomial expression tree, written out with the grammar's precedence (and
  random spacing, ``^``/``**`` and redundant parentheses), parses to exactly the
  polynomial computed independently here with ``fractions.Fraction`` -- or, when the tree
  breaks a rule (degree cap, division by zero or by a non-constant), to that error.
* Numbers are taken by their text: a random decimal is read as exactly that decimal.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from rprpr.io.expression import MAX_DEGREE, parse_polynomial
from rprpr.io.loader import parse_task
from rprpr.model.errors import ExpressionError, TaskFileError

FUZZ = settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])

GOOD = """\
name: good
robot:
  a1: 6
  gravity: 9.81
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
path:
  y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2
  from: [2, -1]
  to: [4, 1]
timing:
  duration: 5
  law: quintic
checks:
  torque_limit: [300, 300]
"""


def _only_task_file_errors(data: bytes | str) -> None:
    try:
        task = parse_task(data, "fuzz.yaml")
    except TaskFileError as e:
        assert e.file == "fuzz.yaml"
        assert str(e).startswith("fuzz.yaml")
        assert "\n" not in str(e) and "\r" not in str(e)  # one line, whatever the input
        return
    # whatever is accepted is a task the engine can trust
    assert task.robot.a1 > 0 and task.duration > 0
    assert all(
        v >= 0 for link in task.robot.links.values() for v in (link.mass, link.inertia, link.r)
    )
    assert max(task.path.degree(), 0) * max(task.x_of_t.degree(), 0) <= MAX_DEGREE


# -- random input: only TaskFileError -----------------------------------------------------------


@FUZZ
@given(st.text(max_size=400))
@example("[" * 100_000)
@example("a: &a [*a]\n")
@example("robot: &r {a1: *r}\npath: 1\ntiming: 1\n")
@example("? [a, b]\n: 1\n")
@example("robot: {a1: 6, links: {2: {mass: 1, inertia: 1, r: 1, mass: 2}}}")
@example("\ud800")
@example("\ufeff\ufeff")
@example("%YAML 1.2\n---\nrobot: 1\n")
@example("%TAG ! tag:yaml.org,2002:python/object:\n---\nrobot: !os.system x\n")
def test_random_text_raises_only_task_file_error(text: str) -> None:
    _only_task_file_errors(text)


@FUZZ
@given(st.binary(max_size=400))
@example(b"\xff\xfe" + "robot: 1".encode("utf-16-le"))
@example(b"\xef\xbb\xbf" + GOOD.encode())
@example(b"robot: \xc3")
def test_random_bytes_raise_only_task_file_error(data: bytes) -> None:
    _only_task_file_errors(data)


# YAML-ish tokens: random task-shaped documents reach far deeper into the loader than
# random characters do.
_TOKENS = [
    "\n",
    "\n  ",
    "\n    ",
    " ",
    ": ",
    "- ",
    "{",
    "}",
    "[",
    "]",
    ", ",
    "&a ",
    "*a",
    "&b ",
    "*b",
    "<<: ",
    "!!python/object/apply:os.system ",
    "!!str ",
    "!!float ",
    "!!int ",
    "!!binary ",
    "!custom ",
    "? ",
    "---\n",
    "...\n",
    "# c\n",
    '"',
    "'",
    "|\n  ",
    ">\n  ",
    "name",
    "robot",
    "a1",
    "gravity",
    "links",
    "2",
    "3",
    "4",
    "5",
    "mass",
    "inertia",
    "r",
    "path",
    "y",
    "from",
    "to",
    "timing",
    "duration",
    "law",
    "x",
    "checks",
    "min_slope",
    "min_speed",
    "torque_limit",
    "strict",
    "quintic",
    "cubic",
    "true",
    "no",
    "null",
    "~",
    "0",
    "-1",
    "6",
    "0.5",
    ".nan",
    "-.inf",
    "1e3",
    "010",
    "0x1f",
    "1:30",
    "2001-01-01",
    "x^2",
    "t^3",
    "x**61",
    "1/0",
    "(x - 3)",
    "__import__('os')",
    "sin(x)",
    "2x",
    "*",
    "/",
]


@FUZZ
@given(st.lists(st.sampled_from(_TOKENS), max_size=60))
def test_random_yaml_shaped_text_raises_only_task_file_error(tokens: list[str]) -> None:
    _only_task_file_errors("".join(tokens))


@FUZZ
@given(
    st.lists(
        st.tuples(st.integers(0, len(GOOD)), st.integers(0, 8), st.sampled_from(_TOKENS)),
        min_size=1,
        max_size=4,
    )
)
def test_mutated_valid_task_raises_only_task_file_error(edits: list[tuple[int, int, str]]) -> None:
    text = GOOD
    for at, cut, insert in edits:
        at = min(at, len(text))
        text = text[:at] + insert + text[at + cut :]
    _only_task_file_errors(text)


@FUZZ
@given(st.text(alphabet="0123456789.eExt+-*/^() \t_a", max_size=80))
@example("x" + "^2" * 30)
@example("(" * 60 + "x" + ")" * 60)
@example("9" * 4000)
@example("0." + "0" * 3990 + "1")
@example("(((10^60)^60)^60)^60")
@example("1e" + "9" * 50)
@example("x^" + "0" * 50 + "2")
def test_random_expression_raises_only_expression_error(text: str) -> None:
    try:
        parse_polynomial(text, "x")
    except ExpressionError as e:
        assert 0 <= e.offset <= len(text)


# -- random valid polynomials: exact values -------------------------------------------------------

Poly = list[Fraction]  # coefficients, low degree first, no trailing zeros; [] is 0


def _trim(p: Poly) -> Poly:
    p = list(p)
    while p and p[-1] == 0:
        p.pop()
    return p


def _deg(p: Poly) -> int:
    return len(p) - 1  # -1 for the zero polynomial, as flint has it


def _add(p: Poly, q: Poly, sign: int = 1) -> Poly:
    n = max(len(p), len(q))
    return _trim(
        [(p[i] if i < len(p) else 0) + sign * (q[i] if i < len(q) else 0) for i in range(n)]
    )


def _mul(p: Poly, q: Poly) -> Poly:
    out = [Fraction(0)] * max(len(p) + len(q) - 1, 0)
    for i, a in enumerate(p):
        for j, b in enumerate(q):
            out[i + j] += a * b
    return _trim(out)


class Rejected(Exception):
    """The tree breaks a rule of the grammar; ``kind`` says which."""

    def __init__(self, kind: str) -> None:
        self.kind = kind


@dataclass(frozen=True)
class Num:
    mantissa: int
    places: int  # digits after the point
    exp: int  # power of ten, written as e<exp>
    style: int  # how to write it

    def text(self) -> str:
        digits = str(self.mantissa).rjust(self.places + 1, "0")
        whole, frac = digits[: len(digits) - self.places], digits[len(digits) - self.places :]
        s = f"{whole}.{frac}" if self.places else whole
        if self.style == 1 and not self.places:
            s += "."  # "5." is five
        if self.style == 2 and whole == "0" and self.places:
            s = s[1:]  # ".5"
        if self.exp or self.style == 3:
            s += ("e" if self.style != 4 else "E") + str(self.exp)
        return s

    def value(self) -> Poly:
        return _trim([Fraction(self.mantissa, 10**self.places) * Fraction(10) ** self.exp])


@dataclass(frozen=True)
class Var:
    def value(self) -> Poly:
        return [Fraction(0), Fraction(1)]


@dataclass(frozen=True)
class Bin:
    op: str
    left: object
    right: object


@dataclass(frozen=True)
class Neg:
    sign: str
    child: object


@dataclass(frozen=True)
class Pow:
    base: object
    n: int
    star: bool


def evaluate(node: object) -> Poly:
    """The exact polynomial of ``node``, evaluated as the parser does (left to right)."""
    if isinstance(node, Num | Var):
        return node.value()
    if isinstance(node, Neg):
        v = evaluate(node.child)
        return v if node.sign == "+" else [-c for c in v]
    if isinstance(node, Pow):
        b = evaluate(node.base)
        if _deg(b) > 0 and _deg(b) * node.n > MAX_DEGREE:
            raise Rejected("cap")
        out: Poly = [Fraction(1)]
        for _ in range(node.n):
            out = _mul(out, b)
        return out
    assert isinstance(node, Bin)
    p, q = evaluate(node.left), evaluate(node.right)
    if node.op in "+-":
        return _add(p, q, 1 if node.op == "+" else -1)
    if node.op == "*":
        if _deg(p) + _deg(q) > MAX_DEGREE:
            raise Rejected("cap")
        return _mul(p, q)
    if _deg(q) > 0:
        raise Rejected("non-constant")
    if not q:
        raise Rejected("zero")
    return [c / q[0] for c in p]


# precedence: 1 sum, 2 product, 3 unary, 4 power, 5 atom
def _prec(node: object) -> int:
    if isinstance(node, Bin):
        return 1 if node.op in "+-" else 2
    if isinstance(node, Neg):
        return 3
    if isinstance(node, Pow):
        return 4
    return 5


_SPACES = st.sampled_from(["", " ", "  ", "\t"])  # built once: not at every draw
_ONE_IN_TEN = st.integers(0, 9)


def render(node: object, var: str, draw: st.DrawFn) -> str:
    """``node`` as text: parentheses where the grammar needs them, sometimes where it does not."""
    sp = lambda: draw(_SPACES)  # noqa: E731

    def sub(child: object, need: int) -> str:
        s = render(child, var, draw)
        if _prec(child) < need or draw(_ONE_IN_TEN) == 0:
            s = f"({sp()}{s}{sp()})"
        return s

    if isinstance(node, Num):
        return node.text()
    if isinstance(node, Var):
        return var
    if isinstance(node, Neg):
        return f"{node.sign}{sp()}{sub(node.child, 3)}"
    if isinstance(node, Pow):
        return f"{sub(node.base, 5)}{sp()}{'**' if node.star else '^'}{sp()}{node.n}"
    assert isinstance(node, Bin)
    if node.op in "+-":
        return f"{sub(node.left, 1)}{sp()}{node.op}{sp()}{sub(node.right, 2)}"
    return f"{sub(node.left, 2)}{sp()}{node.op}{sp()}{sub(node.right, 3)}"


_nums = st.builds(
    Num, st.integers(0, 10**6), st.integers(0, 4), st.integers(-3, 3), st.integers(0, 4)
)
_leaves = st.one_of(_nums, st.just(Var()), st.just(Var()))


def _extend(children: st.SearchStrategy[object]) -> st.SearchStrategy[object]:
    return st.one_of(
        st.builds(Bin, st.sampled_from("+-*/"), children, children),
        st.builds(Neg, st.sampled_from("+-"), children),
        st.builds(Pow, children, st.integers(0, 6), st.booleans()),
    )


_trees = st.recursive(_leaves, _extend, max_leaves=14)


@settings(max_examples=300, deadline=None)
@given(tree=_trees, var=st.sampled_from(["x", "t"]), data=st.data())
def test_random_polynomial_parses_to_the_exact_polynomial(
    tree: object, var: str, data: st.DataObject
) -> None:
    text = render(tree, var, data.draw)
    try:
        expected = evaluate(tree)
    except Rejected as r:
        try:
            parse_polynomial(text, var)
        except ExpressionError as e:
            word = {
                "cap": f"cap of {MAX_DEGREE}",
                "zero": "division by zero",
                "non-constant": "non-constant",
            }
            assert word[r.kind] in e.message, (text, e.message)
            return
        raise AssertionError(f"{text!r} should be rejected ({r.kind})") from None
    got = parse_polynomial(text, var)
    assert [Fraction(int(c.p), int(c.q)) for c in got.coeffs()] == expected, text


# every fraction in [-100, 100] with a denominator up to 50, as st.fractions(-100, 100,
# max_denominator=50) draws them, but from two integer strategies built once (st.fractions
# builds and validates a new strategy at every draw: most of this test's time)
COEFFICIENTS = st.builds(
    lambda u, q: Fraction(u * q // 50, q), st.integers(-5000, 5000), st.integers(1, 50)
)


@settings(max_examples=100, deadline=None)
@given(st.lists(COEFFICIENTS, min_size=1, max_size=8))
def test_coefficient_list_round_trips(coeffs: list[Fraction]) -> None:
    terms = " + ".join(f"({c.numerator}/{c.denominator})*x^{k}" for k, c in enumerate(coeffs))
    got = parse_polynomial(terms, "x")
    assert [Fraction(int(c.p), int(c.q)) for c in got.coeffs()] == _trim(coeffs)


# -- numbers by their text ------------------------------------------------------------------------


@settings(max_examples=100, deadline=None)
@given(
    a1=st.floats(1e-3, 1e4, allow_nan=False, allow_infinity=False),
    mass=st.decimals("0", "1000", places=6, allow_nan=False, allow_infinity=False),
)
def test_numbers_are_read_exactly_as_written(a1: float, mass: object) -> None:
    a1_text, mass_text = repr(a1), str(mass)
    assume("e" not in mass_text.lower())
    text = GOOD.replace("  a1: 6", f"  a1: {a1_text}").replace(
        "{mass: 2.0, inertia: 0.10", f"{{mass: {mass_text}, inertia: 0.10", 1
    )
    task = parse_task(text)
    assert Fraction(int(task.robot.a1.p), int(task.robot.a1.q)) == Fraction(
        a1_text
    )  # decimal, not binary
    m = task.robot.links[2].mass
    assert Fraction(int(m.p), int(m.q)) == Fraction(mass_text)
    assert task.robot.links[2].inertia * 10 == 1  # 0.10 is exactly 1/10

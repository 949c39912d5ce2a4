"""An independent reference for the 5R five-bar: kinematics and dynamics by brute force.

Written apart from rprpr's engine (it imports nothing from ``rprpr``) and apart from the
derived formulas of ``docs/five-bar.md`` (``theory.py`` holds those; this module does not
import it), so that a test comparing the two checks the derivation.

The robot: A = (0, 0), B = (a, 0); link 1 (A to the elbow C, length l1) and link 2 (B to the
elbow D, length l2) are driven by the motors at A and B; link 3 (C to E, length l3) and
link 4 (D to E, length l4) meet at the end point E. Link i has mass m_i, centroidal inertia
I_i and its centre of mass G_i on the link at distance r_i from its inner joint (A, B, C, D).
Gravity g points along -y. The torques T1, T2 act on links 1 and 2 (counterclockwise
positive), their reactions on the ground.

* The motion: x(t), y(t) polynomials with rational coefficients, expanded about an instant
  t0 as truncated power series (``Jet``) with exact rational coefficients when t0 is
  rational, so every time derivative is exact Taylor arithmetic (no finite differences).
* The elbows: C = (K1 E + e1 √D1 E⊥)/|E|², K1 = (l1² + |E|² - l3²)/2,
  D1 = l1²|E|² - K1², E⊥ = (-y, x); D = B + (K2 W + e2 √D2 W⊥)/|W|² with W = E - B
  (e1 = +1 puts C to the left of AE, e2 = +1 puts D to the left of BE). The series of √D
  is exact when D's value at t0 is a rational square, else mpmath at ``DPS`` digits.
* Each link's angular velocity is ω = (r × ṙ)/|r|² for its vector r (C - A, D - B, E - C,
  E - D), its angular acceleration the series' derivative; each centre of mass
  G = inner + (r_i/l_i) r, its acceleration the series' second derivative.
* The torques by Newton-Euler: the twelve equations of the four bodies (force and moment
  about G for each) in the twelve unknowns (the pin forces at A, B, C, D, E and T1, T2),
  solved by mpmath's LU at ``DPS`` digits. At a Type II instant this system is singular;
  near one it is ill conditioned, which the working precision absorbs.
* ``energy``: kinetic plus potential energy of the four links, a series in t, for the
  power balance T1 θ1' + T2 θ2' = dE/dt.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from math import factorial, isqrt
from typing import Any

import mpmath
from mpmath.libmp import from_int, fzero, mpf_div

from ..lu import lu_solve

DPS = 60  # working digits of mpmath for everything not exact


try:  # GMP's rationals for the series' exact arithmetic (the same rationals, faster)
    from gmpy2 import mpq as _Q
except ImportError:  # pragma: no cover - gmpy2 is in the test extra
    _Q = Fraction
_QT: type = type(_Q(0))
_RATIONAL = (Fraction, _QT)
_EXACT = (Fraction, int, _QT)
_EXACT_TYPES = frozenset(_EXACT)
_MPF = mpmath.mpf


def _exact(v: Any) -> bool:
    """isinstance(v, _EXACT), the usual types first (Fraction's is an ABC: slow to test)."""
    t = type(v)
    return t in _EXACT_TYPES or (t is not _MPF and isinstance(v, _EXACT))


def _q(v: Any) -> Any:
    """A Fraction as the series' exact type (an mpq); anything else as it is."""
    return _Q(v) if type(v) is Fraction and _QT is not Fraction else v


def _frac(v: Any) -> Any:
    """An mpq as a Fraction (what the series give their callers); anything else as it is."""
    if isinstance(v, _QT) and _QT is not Fraction:
        return Fraction(int(v.numerator), int(v.denominator))
    return v


def mp(v: Any) -> Any:
    """v as an mpf (a Fraction rounded correctly at the current precision): its
    numerator rounded to an mpf, divided by its denominator, as mpf(p) / q does, in
    mpmath's own raw operations."""
    t = type(v)
    if t is _QT or t is Fraction or (t is not _MPF and isinstance(v, _RATIONAL)):
        ctx = mpmath.mp
        if not v:
            return ctx.make_mpf(fzero)  # 0/q: mpf 0 at any precision
        prec, rnd = ctx._prec_rounding
        num = from_int(v.numerator, prec, rnd)
        return ctx.make_mpf(mpf_div(num, from_int(v.denominator), prec, rnd))
    return mpmath.mpf(v)


def _sqrt(v: Any) -> Any:
    """√v: exact for a Fraction that is a rational square, else an mpf."""
    if v < 0:
        raise ValueError("E is out of a leg's reach (D1 or D2 < 0): no elbow")
    if isinstance(v, _RATIONAL):
        p, q = isqrt(v.numerator), isqrt(v.denominator)
        if p * p == v.numerator and q * q == v.denominator:
            return type(v)(p, q)
    return mpmath.sqrt(mp(v))


def _coerce(a: Any, b: Any) -> tuple[Any, Any]:
    """Fractions meet mpf as mpf; two Fractions stay exact."""
    if _exact(a) and _exact(b):
        return a, b
    if _exact(a):
        a = mp(a)
    if _exact(b):
        b = mp(b)
    return a, b


def _floats(c: list[Any]) -> list[Any]:
    """The coefficients c with every Fraction (or int) as an mpf: what ``_coerce`` makes
    of each of them where it meets an mpf, made once per series."""
    return [v if type(v) is _MPF else mp(v) if _exact(v) else v for v in c]


class Jet:
    """A truncated power series c0 + c1 τ + ... + c_{n-1} τ^{n-1} in τ = t - t0.

    Its coefficients are all exact (rationals: ``exact``) or not; an operation on two
    exact series is exact, any other meets at mpf (a rational rounded once, as
    ``_coerce`` does), in plain mpf arithmetic on lists. The exact coefficients are kept
    as GMP rationals (mpq) and given to callers as Fractions (``c``)."""

    __slots__ = ("_c", "_f", "_fr", "exact")

    def __init__(self, c: Sequence[Any], exact: bool | None = None) -> None:
        if exact is None:
            c = [_q(v) for v in c]
            exact = all(_exact(v) for v in c)
        self._c = list(c)
        self.exact = exact
        self._f: tuple[int, list[Any]] | None = None
        self._fr: list[Any] | None = None

    @property
    def c(self) -> list[Any]:
        """The coefficients: Fractions (or ints) where exact, else mpf."""
        if self._fr is None:
            self._fr = [_frac(v) for v in self._c]
        return self._fr

    def floats(self) -> list[Any]:
        """The coefficients as mpf (``_floats``), made once per working precision."""
        prec = mpmath.mp.prec
        if self._f is None or self._f[0] != prec:
            self._f = (prec, _floats(self._c))
        return self._f[1]

    @staticmethod
    def lift(v: Any, n: int) -> Jet:
        return v if isinstance(v, Jet) else Jet([v] + [Fraction(0)] * (n - 1))

    def _lists(self, o: Any) -> tuple[list[Any], list[Any], bool]:
        """The two series' coefficients, to the shorter's length, as rationals when both
        are exact, else as mpf; and whether they are exact."""
        o = Jet.lift(o, len(self._c))
        n = min(len(self._c), len(o._c))
        if self.exact and o.exact:
            return self._c[:n], o._c[:n], True
        return self.floats()[:n], o.floats()[:n], False

    def __add__(self, o: Any) -> Jet:
        a, b, exact = self._lists(o)
        return Jet([p + q for p, q in zip(a, b, strict=True)], exact)

    __radd__ = __add__

    def __neg__(self) -> Jet:
        return Jet([-p for p in self._c], self.exact)

    def __sub__(self, o: Any) -> Jet:
        return self + (-Jet.lift(o, len(self._c)))

    def __rsub__(self, o: Any) -> Jet:
        return Jet.lift(o, len(self._c)) - self

    def __mul__(self, o: Any) -> Jet:
        if not isinstance(o, Jet):
            if self.exact and _exact(o):
                o = _q(o)
                return Jet([p * o for p in self._c], True)
            o = mp(o) if _exact(o) else o
            return Jet([p * o for p in self.floats()], False)
        a, b, exact = self._lists(o)
        out = []
        for k in range(len(a)):
            s = a[0] * b[k]  # 0 + x is x, exactly, in either arithmetic
            for i in range(1, k + 1):
                s = s + a[i] * b[k - i]
            out.append(s)
        return Jet(out, exact)

    __rmul__ = __mul__

    def __truediv__(self, o: Any) -> Jet:
        if not isinstance(o, Jet):
            return self * _inv(o)
        a, b, exact = self._lists(o)
        inv = _inv(o._c[0])  # 1/b0 exact when b0 is, then rounded (as _coerce rounds it)
        if not exact and isinstance(inv, _RATIONAL):
            inv = mp(inv)
        q: list[Any] = []
        for k in range(len(a)):
            s = a[k]
            for i in range(k):
                s = s + -(q[i] * b[k - i])
            q.append(s * inv)
        return Jet(q, exact)

    def __rtruediv__(self, o: Any) -> Jet:
        return Jet.lift(o, len(self._c)) / self

    def sqrt(self) -> Jet:
        s0 = _sqrt(self._c[0])
        inv = _inv(2 * s0)  # exact when s0 is, then rounded (as _coerce rounds it)
        if self.exact and isinstance(s0, _RATIONAL):
            c, s = self._c, [s0]
        else:
            c, s = self.floats(), [mp(s0) if isinstance(s0, _RATIONAL) else s0]
            inv = mp(inv) if isinstance(inv, _RATIONAL) else inv
        for k in range(1, len(c)):
            acc = c[k]
            for i in range(1, k):
                acc = acc + -(s[i] * s[k - i])
            s.append(acc * inv)
        return Jet(s)

    def dt(self) -> Jet:
        """d/dt, one order shorter."""
        return Jet([k * self._c[k] for k in range(1, len(self._c))], self.exact)

    def d(self, k: int) -> Any:
        """The k-th time derivative at t0 (exact, or at ``DPS`` digits)."""
        with mpmath.workdps(DPS):
            return factorial(k) * self.c[k]


def _add(p: Any, q: Any) -> Any:
    p, q = _coerce(p, q)
    return p + q


def _mul(p: Any, q: Any) -> Any:
    p, q = _coerce(p, q)
    return p * q


def _inv(p: Any) -> Any:
    if isinstance(p, _QT):
        return _Q(1) / p
    return Fraction(1) / p if _exact(p) else 1 / p


# -- the robot and the motion ---------------------------------------------------------------
@dataclass(frozen=True)
class FiveBar:
    """Base a = |AB|, link lengths l = (l1, l2, l3, l4), masses m, centroidal inertias I,
    centres of mass r (from each link's inner joint), gravity g (along -y)."""

    a: Fraction
    length: tuple[Fraction, Fraction, Fraction, Fraction]
    mass: tuple[Fraction, Fraction, Fraction, Fraction]
    inertia: tuple[Fraction, Fraction, Fraction, Fraction]
    r: tuple[Fraction, Fraction, Fraction, Fraction]
    g: Fraction


Vec = tuple[Any, Any]


def cross(u: Vec, v: Vec) -> Any:
    return u[0] * v[1] - u[1] * v[0]


def dot(u: Vec, v: Vec) -> Any:
    return u[0] * v[0] + u[1] * v[1]


def _poly_jet(coeffs: Sequence[Fraction], t0: Any, n: int) -> Jet:
    """The polynomial Σ coeffs[k] t^k expanded about t0: n Taylor coefficients."""
    if _exact(t0):  # exact: in the series' rationals
        t, cs = _q(t0), [_q(c) for c in coeffs]
        exact = []
        for k in range(n):
            e: Any = _Q(0)
            for j in range(k, len(cs)):
                e = e + cs[j] * _binom(j, k) * t ** (j - k)
            exact.append(e)
        return Jet(exact, True)
    out = []
    for k in range(n):
        s: Any = Fraction(0)
        for j in range(k, len(coeffs)):
            s = _add(s, _mul(coeffs[j] * _binom(j, k), _pow(t0, j - k)))
        out.append(s)
    return Jet(out)


def _binom(j: int, k: int) -> int:
    return factorial(j) // (factorial(k) * factorial(j - k))


def _pow(t: Any, k: int) -> Any:
    return t**k if isinstance(t, Fraction) else mp(t) ** k


@dataclass(frozen=True)
class Motion:
    """E(t) = (x(t), y(t)), polynomials in t (coefficients from the constant up)."""

    x: tuple[Fraction, ...]
    y: tuple[Fraction, ...]

    def at(self, t0: Any, n: int) -> tuple[Jet, Jet]:
        return _poly_jet(self.x, t0, n), _poly_jet(self.y, t0, n)


def elbows(rb: FiveBar, E: tuple[Any, Any], modes: tuple[int, int]) -> tuple[Vec, Vec]:
    """The elbows C and D of the working modes (e1, e2) at the end point E (any numbers or
    jets): C = (K1 E + e1 √D1 E⊥)/|E|², D = B + (K2 W + e2 √D2 W⊥)/|W|², W = E - B."""
    if not isinstance(E[0], Jet):
        C, D = elbows(rb, (Jet.lift(E[0], 1), Jet.lift(E[1], 1)), modes)
        return (C[0].c[0], C[1].c[0]), (D[0].c[0], D[1].c[0])
    l1, l2, l3, l4 = rb.length
    x, y = E
    R1 = x * x + y * y
    K1 = (R1 + l1 * l1 - l3 * l3) * Fraction(1, 2)
    s1 = (l1 * l1 * R1 - K1 * K1).sqrt()
    C = ((K1 * x - modes[0] * s1 * y) / R1, (K1 * y + modes[0] * s1 * x) / R1)
    wx, wy = x - rb.a, y
    R2 = wx * wx + wy * wy
    K2 = (R2 + l2 * l2 - l4 * l4) * Fraction(1, 2)
    s2 = (l2 * l2 * R2 - K2 * K2).sqrt()
    D = (rb.a + (K2 * wx - modes[1] * s2 * wy) / R2, (K2 * wy + modes[1] * s2 * wx) / R2)
    return C, D


def delta(C: Vec, D: Vec, E: Vec) -> Any:
    """δ = (E - C) × (E - D): zero at a Type II (parallel) singularity."""
    return cross((E[0] - C[0], E[1] - C[1]), (E[0] - D[0], E[1] - D[1]))


# -- the state of the four links at an instant ------------------------------------------------
@dataclass(frozen=True)
class Links:
    """Series of the joints A, B, C, D, E and, per link i = 1..4, its inner joint, its
    vector r_i (inner to outer joint), its angular velocity ω_i and its centre G_i."""

    joints: dict[str, tuple[Jet, Jet]]
    inner: tuple[str, str, str, str]
    vec: tuple[Vec, Vec, Vec, Vec]
    omega: tuple[Jet, Jet, Jet, Jet]
    com: tuple[Vec, Vec, Vec, Vec]


def links(rb: FiveBar, motion: Motion, t0: Any, modes: tuple[int, int], n: int = 5) -> Links:
    """The links' series about t0 (n terms of E; ω one term fewer)."""
    with mpmath.workdps(DPS):
        return _links(rb, motion, t0, modes, n)


def _links(rb: FiveBar, motion: Motion, t0: Any, modes: tuple[int, int], n: int) -> Links:
    x, y = motion.at(t0, n)
    C, D = elbows(rb, (x, y), modes)
    zero = Jet.lift(Fraction(0), n)
    A = (zero, zero)
    B = (zero + rb.a, zero)
    E = (x, y)
    J = {"A": A, "B": B, "C": C, "D": D, "E": E}
    inner = ("A", "B", "C", "D")
    outer = ("C", "D", "E", "E")
    vec, omega, com = [], [], []
    for i in range(4):
        p, q = J[inner[i]], J[outer[i]]
        r = (q[0] - p[0], q[1] - p[1])
        rdot = (r[0].dt(), r[1].dt())
        omega.append(cross(r, rdot) / (rb.length[i] * rb.length[i]))
        rho = rb.r[i] / rb.length[i]
        com.append((p[0] + r[0] * rho, p[1] + r[1] * rho))
        vec.append(r)
    return Links(J, inner, tuple(vec), tuple(omega), tuple(com))  # type: ignore[arg-type]


def _val(j: Any) -> Any:
    return mp(j._c[0]) if isinstance(j, Jet) else mp(j)


def _rate(j: Jet, k: int) -> Any:
    """``mp(j.d(k))`` at the working precision (``DPS`` in ``newton_euler``): k! c_k, exact
    for a rational c_k (the same rational as its Fraction), then rounded once."""
    return mp(factorial(k) * j._c[k])


def newton_euler(rb: FiveBar, lk: Links) -> dict[str, Any]:
    """T1, T2 and the pin forces by the Newton-Euler equations of the four bodies.

    Unknowns (12): F_A, F_B (ground on links 1, 2), F_C (link 1 on link 3), F_D (link 2 on
    link 4), F_E (link 4 on link 3), T1, T2. Per body: m a_G = Σ F - m g ĵ and
    I α = Σ (P - G) × F + T.
    """
    with mpmath.workdps(DPS):
        col = {"FA": 0, "FB": 2, "FC": 4, "FD": 6, "FE": 8, "T1": 10, "T2": 11}
        # body i: [(force name, sign, point)], torque name
        bodies = (
            ([("FA", 1, "A"), ("FC", -1, "C")], "T1"),
            ([("FB", 1, "B"), ("FD", -1, "D")], "T2"),
            ([("FC", 1, "C"), ("FE", 1, "E")], None),
            ([("FD", 1, "D"), ("FE", -1, "E")], None),
        )
        M = [[mpmath.mpf(0)] * 12 for _ in range(12)]
        rhs = [mpmath.mpf(0)] * 12
        for i, (forces, torque) in enumerate(bodies):
            G = lk.com[i]
            gx, gy = _val(G[0]), _val(G[1])
            ax, ay = _rate(G[0], 2), _rate(G[1], 2)
            alpha = _rate(lk.omega[i], 1)
            mass, inertia = mp(rb.mass[i]), mp(rb.inertia[i])
            for name, sign, point in forces:
                P = lk.joints[point]
                px, py = _val(P[0]) - gx, _val(P[1]) - gy
                k = col[name]
                M[3 * i][k] += sign
                M[3 * i + 1][k + 1] += sign
                M[3 * i + 2][k] += -sign * py  # (P - G) × F = px Fy - py Fx
                M[3 * i + 2][k + 1] += sign * px
            if torque is not None:
                M[3 * i + 2][col[torque]] = mpmath.mpf(1)
            rhs[3 * i] = mass * ax
            rhs[3 * i + 1] = mass * ay + mass * mp(rb.g)
            rhs[3 * i + 2] = inertia * alpha
        sol = lu_solve(M, rhs)
        out = {name: (sol[k], sol[k + 1]) for name, k in col.items() if name.startswith("F")}
        out["T1"], out["T2"] = sol[10], sol[11]
        return out


def energy(rb: FiveBar, lk: Links) -> Jet:
    """Kinetic plus potential energy of the four links, a series in t."""
    with mpmath.workdps(DPS):
        return _energy(rb, lk)


def _energy(rb: FiveBar, lk: Links) -> Jet:
    total: Any = Fraction(0)
    for i in range(4):
        G = lk.com[i]
        vx, vy = G[0].dt(), G[1].dt()
        w = lk.omega[i]
        kin = (vx * vx + vy * vy) * (rb.mass[i] / 2) + w * w * (rb.inertia[i] / 2)
        total = kin + G[1] * (rb.mass[i] * rb.g) + total
    return total


def torques(rb: FiveBar, motion: Motion, t: Any, modes: tuple[int, int]) -> tuple[Any, Any]:
    """(T1, T2) at time t by Newton-Euler."""
    out = newton_euler(rb, links(rb, motion, t, modes, n=3))
    return out["T1"], out["T2"]


def rational_unit(s: Fraction) -> tuple[Fraction, Fraction]:
    """The rational point ((1 - s²)/(1 + s²), 2s/(1 + s²)) of the unit circle."""
    return ((1 - s * s) / (1 + s * s), 2 * s / (1 + s * s))


def lined_up(
    sigma: int, s: tuple[Fraction, Fraction, Fraction], l1: Fraction, l3: Fraction, l4: Fraction
) -> tuple[Fraction, Fraction, Vec, Vec, Vec, tuple[int, int]]:
    """A rational Type II pose built from the geometry: C = l1 c, E = C + l3 u,
    D = E - σ l4 u (so E - D = σ (l4/l3)(E - C)), D = B + l2 v with B on the x-axis, for the
    rational unit vectors c, u, v of ``s``. Returns (a, l2, C, D, E, (e1, e2))."""
    c, u, v = (rational_unit(p) for p in s)
    C = (l1 * c[0], l1 * c[1])
    E = (C[0] + l3 * u[0], C[1] + l3 * u[1])
    D = (E[0] - sigma * l4 * u[0], E[1] - sigma * l4 * u[1])
    if D[1] / v[1] < 0:
        v = (-v[0], -v[1])
    l2 = D[1] / v[1]
    a = D[0] - l2 * v[0]
    e1 = 1 if cross(E, C) > 0 else -1  # C to the left of AE
    W = (E[0] - a, E[1])
    e2 = 1 if cross(W, (D[0] - a, D[1])) > 0 else -1  # D to the left of BE
    return a, l2, C, D, E, (e1, e2)

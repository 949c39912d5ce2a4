"""The 5R at one instant t_s of a motion, exactly: the point's number field, the four
working modes' δ there, the expansions about t_s (docs/five-bar.md §4-6).

t_s is rational or a root of an irreducible f (K = Q[t]/(f), ``series.NumberField``);
the elbows add √D1(t_s), √D2(t_s) (``radicals``). The expansions in ε = t - t_s run the
formulas of ``five_bar`` on exact series: over Q (``QSeries``) when t_s is rational and
both discriminants are rational squares there (the elbows rational: everything is a
rational number), else over K(r1, r2) (``radicals.Rad``), where zero is still decided
exactly and values are reported as certified balls.
"""

from __future__ import annotations

import math
from typing import Any

from flint import arb, ctx, fmpq, fmpq_poly

from ...model.dataclass import dataclass
from . import five_bar as fb
from .radicals import Rad, Tower
from .roots import RootAt
from .series import KElem, NumberField, QSeries, Series, taylor

MODES = ((1, 1), (1, -1), (-1, 1), (-1, -1))


class Point:
    """An instant t_s (local time) of a motion: exact values of polynomials there (``fmpq``
    when t_s is rational, else ``KElem``) and their balls."""

    def __init__(self, f: fmpq_poly, exact: fmpq | None, at: RootAt) -> None:
        self.exact = exact
        self.at = at
        self.field = NumberField(f, at) if exact is None else None

    def val(self, p: fmpq_poly) -> Any:
        if self.field is None:
            return p(self.exact)
        return self.field.elem(p)

    def ball(self, v: Any, prec: int) -> arb:
        """A scalar of this point (fmpq or KElem) as a ball at ``prec`` bits."""
        if isinstance(v, KElem):
            return v.field.evaluate(v.p, prec)
        with ctx.workprec(prec):
            return arb(v)

    def one(self) -> Any:
        return fmpq(1) if self.field is None else self.field.elem(1)


def tower(point: Point, conj: fb.Conjugates) -> Tower:
    """K(√D1, √D2) at the point, from the composed conjugates' polynomials."""
    return Tower(point.val(conj.D1), point.val(conj.D2), point.ball)


def deltas(point: Point, conj: fb.Conjugates, tw: Tower) -> dict[tuple[int, int], Rad]:
    """δ_e |E|² |E - B|² for the four working modes e at the point (exact, in K(r1, r2))."""
    P = [point.val(q) for q in (conj.P0, conj.P1, conj.P2, conj.P3)]
    return {e: Rad(tw, (P[0], P[1] * e[0], P[2] * e[1], P[3] * (e[0] * e[1]))) for e in MODES}


def singular_modes(conj: dict[tuple[int, int], Rad], modes: tuple[int, int]) -> tuple[bool, bool]:
    """(the robot's δ vanishes, another mode's does too) at a root of S₊ S₋, where the
    product of the four vanishes: by ball evaluation (the robot's ball excludes zero: not
    singular; the three others exclude it: singular alone), else exactly."""
    own = conj[modes]
    others = [c for e, c in conj.items() if e != modes]
    prec = 64
    while prec <= 1024:
        if not own.ball(prec).contains(0):
            return False, False
        if not any(c.ball(prec).contains(0) for c in others):
            return True, False
        prec *= 2
    if not own.is_zero():
        return False, False
    return True, any(c.is_zero() for c in others)


@dataclass(frozen=True)
class Expansion:
    """The §5 terms as exact series about t_s (n terms), and how they were made."""

    d: fb.FiveBarDynamics
    rational: bool  # over Q (QSeries): every value a rational number
    tower: Tower | None


def expansion(
    p: fb.FiveBarParams, point: Point, X: fmpq_poly, Y: fmpq_poly, modes: tuple[int, int],
    n: int, tw: Tower,
) -> Expansion:  # fmt: skip
    """The dynamics about t_s as series of n terms (docstring of the module)."""
    cx, cy = taylor(X, n + 2), taylor(Y, n + 2)
    ex = [point.val(c) for c in cx]
    ey = [point.val(c) for c in cy]
    roots = _rational_roots(point, tw)
    if roots is not None:

        def kind(c: list[Any]) -> Any:
            return QSeries(c)

        def root(D: Any, i: int) -> Any:
            return D.sqrt_with(roots[i - 1])

    else:

        def kind(c: list[Any]) -> Any:
            return Series([tw.of(v) for v in c])

        def root(D: Any, i: int) -> Any:
            head = [v.a[0] for v in D.c]  # D(t_s) = D_i
            g = (Series(head) * tw.inverse_D(i)).sqrt_with(point.one())  # √(D/D(t_s))
            return Series([tw.root(i, v) for v in g.c])

    series = []
    for e in (ex, ey):
        series += [
            kind(e[:n]),
            kind([(k + 1) * e[k + 1] for k in range(n)]),
            kind([(k + 1) * (k + 2) * e[k + 2] for k in range(n)]),
        ]
    x, xd, xdd, y, yd, ydd = series
    leg1, leg2 = fb.legs(p, modes, x, xd, xdd, y, yd, ydd, root)
    return Expansion(fb.dynamics(leg1, leg2, p), roots is not None, None if roots else tw)


def _rational_roots(point: Point, tw: Tower) -> tuple[fmpq, fmpq] | None:
    """(√D1, √D2) at a rational t_s where both are rational, else None."""
    if point.exact is None:
        return None
    out = []
    for D in tw.D:
        num, den = int(D.p), int(D.q)
        a, b = math.isqrt(num), math.isqrt(den)
        if a * a != num or b * b != den:
            return None
        out.append(fmpq(a, b))
    return out[0], out[1]


def is_zero(v: Any) -> bool:
    return v.is_zero() if isinstance(v, Rad) else v == 0


def sign(v: Any) -> int:
    return v.sign() if isinstance(v, Rad) else (v > 0) - (v < 0)


def valuation(s: Any) -> int:
    """The index of the first nonzero coefficient of an exact series (its length if none)."""
    for i, c in enumerate(s.c):
        if not is_zero(c):
            return i
    return len(s.c)


def value(v: Any) -> fmpq | arb:
    """An exact scalar of an expansion as a rational (over Q) or a ball of 128 bits."""
    if isinstance(v, Rad):
        q = v.rational()
        if q is not None:
            return q
        return arb(0) if v.is_zero() else _accurate(v)
    return fmpq(v)


def _accurate(v: Rad) -> arb:
    prec = 128
    while True:
        b = v.ball(prec)
        if b.rel_accuracy_bits() >= 64 or prec > 4096:
            return b
        prec *= 2


@dataclass(frozen=True)
class Dynamics:
    """What the audit reads of the expansion at an instant of order k: δ^(k)(t_s), the
    line-up σ, the residuals w^(j)(t_s) for j < k (σ frozen), how many hold from the
    first, and the limit torques (T1, T2) when all k hold (α = ν^(k)/δ^(k))."""

    delta_k: Any
    sigma: int
    residuals: tuple[Any, ...]
    conditions_met: int
    limit: tuple[Any, Any] | None


def read(e: Expansion, k: int) -> Dynamics:
    """The consistency and high-order conditions (§6) and the limit at order k."""
    d = e.d
    d1, d2 = d.leg1.d, d.leg2.d
    sigma = sign((d1[0] * d2[0] + d1[1] * d2[1]).c[0])
    w = fb.consistency(d, sigma)
    residuals = tuple(w.c[j] * math.factorial(j) for j in range(k))
    met = 0
    while met < k and is_zero(residuals[met]):
        met += 1
    limit = _limit(e, k) if met == k else None
    return Dynamics(
        value(d.delta.c[k] * math.factorial(k)), sigma, tuple(value(r) for r in residuals),
        met, limit,
    )  # fmt: skip


def _limit(e: Expansion, k: int) -> tuple[Any, Any]:
    """(T1, T2) at t_s with α = ν^(k)/δ^(k) (l'Hôpital, §6): exact over Q; over K(r1, r2)
    T = (A δ^(k) + B ν^(k))/δ^(k) with T = A + B α, its numerator exact and the one
    division made in ball arithmetic."""
    d = e.d
    D, N = d.delta.c[k], d.nu.c[k]
    if e.rational:
        T = fb.efforts(d, N / D)
        return T[0].c[0], T[1].c[0]
    A = fb.efforts(d, 0)
    B = fb.efforts(d, 1)
    out = []
    with ctx.workprec(128):
        for a, b in zip(A, B, strict=True):
            a0 = a.c[0]
            numerator = a0 * D + (b.c[0] - a0) * N
            zero = is_zero(numerator)
            out.append(arb(0) if zero else arb(value(numerator)) / arb(value(D)))
    return out[0], out[1]

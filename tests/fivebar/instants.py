"""The 5R's Type II instants along a motion, by the reference: the roots of S_σ(E(t)).

For each line-up curve σ = ±1 (locus.py), S_σ(x(t), y(t)) is a polynomial in t with
rational coefficients; its real roots in [t0, t1] are isolated exactly by sympy, each with
the multiplicity of its irreducible factor. A root is an instant of the robot in working
modes e iff δ_e vanishes there (the four δ's evaluated at 60 digits at the root: the
robot's is below 10^-40, or it is not an instant). Its order is read two ways: the
multiplicity of the root in S_σ(E(t)) (valid when the other three δ's and S_{-σ} are
nonzero there) and the first nonzero Taylor coefficient of δ_e(t) about the root (always
valid); ``Instant`` carries both.
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from typing import Any

import mpmath
import sympy as sp

from .locus import curve_at
from .reference import DPS, FiveBar, Jet, Motion, delta, elbows, mp

MODES = ((1, 1), (1, -1), (-1, 1), (-1, -1))
ZERO = mpmath.mpf(10) ** -40


@dataclass(frozen=True)
class Instant:
    t: Any  # the exact root (a sympy number: Rational or CRootOf)
    sigma: int  # the line-up: -1 E between the elbows, +1 C and D on one side
    multiplicity: int  # of t in S_σ(E(t))
    order: int  # of δ_e(t) at t, from its Taylor series
    others: tuple[Any, ...]  # |δ| of the three other working modes at t


def _rat(q: Fraction) -> sp.Rational:
    return sp.Rational(q.numerator, q.denominator)


def _series_order(rb: FiveBar, motion: Motion, t: Any, modes: tuple[int, int]) -> int:
    """The index of δ_e's first Taylor coefficient about t above 10^-30 (at most 6)."""
    n = 8
    with mpmath.workdps(DPS):
        xs, ys = motion.at(t, n)
        C, D = elbows(rb, (xs, ys), modes)
        d = delta(C, D, (xs, ys))
        assert isinstance(d, Jet)
        for k, c in enumerate(d.c[: n - 1]):
            if abs(mp(c)) > mpmath.mpf(10) ** -30:
                return k
    return n - 1


@lru_cache(maxsize=64)
def _roots(rb: FiveBar, motion: Motion, t0: Fraction, t1: Fraction) -> tuple[Any, ...]:
    """(root, σ, multiplicity) for the real roots of S₊(E(t)) and S₋(E(t)) in [t0, t1]."""
    t = sp.Symbol("t")
    # x(t), y(t) as Polys over QQ: S_σ(x(t), y(t)) is then Poly arithmetic, the same
    # polynomial as curve(σ) with x(t), y(t) substituted and expanded
    xt = sp.Poly([_rat(c) for c in reversed(motion.x)], t, domain="QQ")
    yt = sp.Poly([_rat(c) for c in reversed(motion.y)], t, domain="QQ")
    params = [_rat(p) for p in (rb.a, *rb.length)]
    out = []
    for sigma in (1, -1):
        P = curve_at(sigma, *params, xt, yt)
        if P.is_zero:
            raise ValueError("the path runs along a line-up curve")
        for f, m in P.factor_list()[1]:
            f = sp.Poly(f, t)
            if not f.count_roots(_rat(t0), _rat(t1)):
                continue  # no real root in [t0, t1] (Sturm): none to compare
            for r in f.real_roots():
                if _rat(t0) <= r <= _rat(t1):
                    out.append((r, sigma, m))
    return tuple(out)


@lru_cache(maxsize=1024)
def _decimal(r: Any) -> str:
    """The irrational root r (a CRootOf of ``_roots``, which keeps each) to DPS + 10 digits,
    once per root: sympy refines it to 70 digits in tens of milliseconds."""
    return str(sp.N(r, DPS + 10))


def singular_instants(
    rb: FiveBar, motion: Motion, modes: tuple[int, int], t0: Fraction, t1: Fraction
) -> list[Instant]:
    """The robot's Type II instants in [t0, t1], in time order."""
    found = []
    for r, sigma, m in _roots(rb, motion, t0, t1):
        with mpmath.workdps(DPS):
            if r.is_Rational:
                tr: Any = Fraction(int(r.p), int(r.q))  # exact: δ is exactly 0
            else:
                tr = mpmath.mpf(_decimal(r))
            xs, ys = motion.at(tr, 1)
            size = {}
            for e in MODES:
                try:
                    d = delta(*elbows(rb, (xs, ys), e), (xs, ys))
                    size[e] = abs(mp(d.c[0]))
                except ValueError:
                    size[e] = mpmath.inf  # E out of a leg's reach in this mode
        if size[modes] > ZERO:
            continue
        order = _series_order(rb, motion, tr, modes)
        others = tuple(size[e] for e in MODES if e != modes)
        found.append(Instant(r, sigma, m, order, others))
    if len(found) < 2:
        return found  # in time order already (sympy's roots are slow to evaluate)
    return sorted(found, key=lambda i: sp.N(i.t, 30))

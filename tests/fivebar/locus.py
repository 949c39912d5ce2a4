"""The 5R's Type II locus in sympy, from the elbows' closed form (docs/five-bar.md §2).

δ·|E|²·|E - B|² = P0 + e1 P1 √D1 + e2 P2 √D2 + e1 e2 P3 √(D1 D2), with
R1 = |E|², R2 = |E - B|², K1 = (l1² + R1 - l3²)/2, K2 = (l2² + R2 - l4²)/2,
D1 = l1² R1 - K1², D2 = l2² R2 - K2², E·W = x(x - a) + y², E × W = a y (W = E - B):
P0 = (R1 - K1)(R2 - K2) a y, P1 = (R2 - K2)(E·W), P2 = -(R1 - K1)(E·W), P3 = a y.
``norm`` multiplies the four conjugates (e1, e2 = ±1) without radicals: first over e1,
(P0 + e2 P2 √D2)² - D1 (P1 + e2 P3 √D2)² = A0 + e2 A1 √D2, then over e2, A0² - D2 A1².
``curve(σ)`` is the closed form of the line-up curves: E - D = σ (l4/l3)(E - C).
"""

from __future__ import annotations

from functools import cache
from typing import Any

import sympy as sp
from sympy import QQ
from sympy.polys.rings import ring

x, y = sp.symbols("x y", real=True)


def _parts(a: Any, l1: Any, l2: Any, l3: Any, l4: Any) -> dict[str, Any]:
    R1 = x**2 + y**2
    R2 = (x - a) ** 2 + y**2
    K1 = (l1**2 + R1 - l3**2) / 2
    K2 = (l2**2 + R2 - l4**2) / 2
    EW = x * (x - a) + y**2
    return {
        "R1": R1, "R2": R2, "D1": l1**2 * R1 - K1**2, "D2": l2**2 * R2 - K2**2,
        "P0": (R1 - K1) * (R2 - K2) * a * y, "P1": (R2 - K2) * EW,
        "P2": -(R1 - K1) * EW, "P3": a * y,
    }  # fmt: skip


def conjugates(a: Any, l1: Any, l2: Any, l3: Any, l4: Any) -> dict[str, Any]:
    """P0..P3, D1, D2, R1, R2 as sympy expressions."""
    return _parts(a, l1, l2, l3, l4)


def norm(a: Any, l1: Any, l2: Any, l3: Any, l4: Any, *gens: Any) -> sp.Poly:
    """Π over the four working modes of δ·|E|²|E - B|², a polynomial (Poly in x, y and
    any symbols among the parameters, listed in gens)."""
    R, *_ = ring([x, y, *gens], QQ)  # sympy's sparse polynomials: the same products
    p = {k: R(v) for k, v in _parts(a, l1, l2, l3, l4).items()}
    A0 = p["P0"] ** 2 + p["P2"] ** 2 * p["D2"] - p["D1"] * (p["P1"] ** 2 + p["P3"] ** 2 * p["D2"])
    A1 = 2 * p["P0"] * p["P2"] - 2 * p["D1"] * p["P1"] * p["P3"]
    return sp.Poly.from_dict(dict(A0**2 - p["D2"] * A1**2), x, y, *gens, domain=QQ)


def product(factors: list[Any], *gens: Any) -> sp.Poly:
    """The product of sympy expressions in x, y (and the symbols gens) as a Poly over QQ,
    multiplied as sympy's sparse polynomials."""
    R, *_ = ring([x, y, *gens], QQ)
    out = R(1)
    for f in factors:
        out *= R(f)
    return sp.Poly.from_dict(dict(out), x, y, *gens, domain=QQ)


@cache
def curve(sigma: int, a: Any, l1: Any, l2: Any, l3: Any, l4: Any) -> Any:
    """S_σ = l4² k1² R2 - 2σ l3 l4 k1 k2 (E·W) + l3² k2² R1 - 4 l3² l4² (a y)², with
    k1 = R1 + l3² - l1², k2 = R2 + l4² - l2²: zero iff some unit u has |E - l3 u| = l1 and
    |E - σ l4 u - B| = l2 (the distal links lined up, E - D = σ (l4/l3)(E - C)). Expanded
    once per robot in a test process (sympy expressions never change)."""
    return sp.expand(curve_at(sigma, a, l1, l2, l3, l4, x, y))


def curve_at(sigma: int, a: Any, l1: Any, l2: Any, l3: Any, l4: Any, X: Any, Y: Any) -> Any:
    """S_σ at the point (X, Y), unexpanded: any values that add and multiply (sympy
    expressions, or Polys in t for S_σ along a motion)."""
    R1 = X**2 + Y**2
    R2 = (X - a) ** 2 + Y**2
    EW = X * (X - a) + Y**2
    k1 = R1 + l3**2 - l1**2
    k2 = R2 + l4**2 - l2**2
    return (
        l4**2 * k1**2 * R2
        - 2 * sigma * l3 * l4 * k1 * k2 * EW
        + l3**2 * k2**2 * R1
        - 4 * l3**2 * l4**2 * a**2 * Y**2
    )

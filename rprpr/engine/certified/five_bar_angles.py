"""The motors' angles of a 5R motion, continuous: θ_i = the principal angle of the elbow
vector c_i (C - A, D - B) plus 2π for each time c_i has crossed the negative x-axis.

The crossings are decided exactly. c_y R = K y + e √D u (``exact.five_bar.leg``), so c_y
can only vanish at a root of P = K² y² - D u², the product over both working modes, a
polynomial in t; between two consecutive roots of P its sign is constant and is decided
by balls at a rational time there (it is not zero there). At a root where that sign
changes, c_y has crossed 0 in the robot's mode, and c_x = ±l (its sign from a ball at the
root) says whether it crossed the negative axis: from + to - the angle passes π upward
(+2π after), from - to + downward (-2π after). Exactly at a crossing, the angle is the
limit from before it (as the RPRPR's θ on its cut).
"""

from __future__ import annotations

import math
from itertools import pairwise
from typing import Any

from flint import arb, ctx, fmpq, fmpq_poly

from ..exact.roots import real_roots_in
from .five_bar import FiveBarMotion, exact_ends

MAX_BITS = 4096


class Crossing:
    """A time at which the elbow vector crosses the negative x-axis: its exact time (or
    None) and a ball of it (refined on demand), the turn (+1 or -1) and the sign of c_y
    before it."""

    def __init__(self, exact: fmpq | None, at: Any, turn: int, before: int) -> None:
        self.exact = exact
        self.at = at
        self.turn = turn
        self.before = before

    def compare(self, t: fmpq) -> int:
        """-1 when the crossing is before t, 0 at t, 1 after it (decided exactly)."""
        if self.exact is not None:
            return (self.exact > t) - (self.exact < t)
        bits = 64
        while True:
            lo, hi = exact_ends(self.at(bits))
            if hi < t:
                return -1
            if lo > t:
                return 1
            bits *= 2  # an irrational root is never a rational t


def _leg_polys(m: FiveBarMotion, i: int) -> tuple[fmpq_poly, fmpq_poly, fmpq_poly, fmpq_poly]:
    """u, y, K, D of leg i as polynomials in t (u = E - base)."""
    p = m.exact
    lp, ld = p.l[i - 1], p.l[i + 1]
    x, y = m.polys[0], m.polys[3]
    u = x if i == 1 else x - p.a
    R = u * u + y * y
    K = (R + (lp * lp - ld * ld)) / 2
    return u, y, K, R * (lp * lp) - K * K


def _sign(m: FiveBarMotion, i: int, t: Any, part: str) -> int:
    """The sign of c_y R (``part`` "y") or c_x R ("x") of leg i in its mode at the ball
    or rational t (0 when not decided at the highest precision)."""
    u, y, K, D = _leg_polys(m, i)
    e = m.modes[i - 1]
    bits = 128
    while bits <= MAX_BITS:
        with ctx.workprec(bits):
            tb = arb(t) if isinstance(t, fmpq) else t(bits)
            uv, yv, Kv, Dv = (_at(q, tb) for q in (u, y, K, D))
            s = Dv.sqrt() * e
            v = Kv * yv + s * uv if part == "y" else Kv * uv - s * yv
        if v > 0:
            return 1
        if v < 0:
            return -1
        bits *= 2
    return 0


def _at(q: fmpq_poly, t: arb) -> arb:
    out = arb(0)
    for c in reversed(q.coeffs()):
        out = out * t + arb(c)
    return out


def crossings(m: FiveBarMotion, i: int) -> list[Crossing]:
    """The times in (0, t_f] at which leg i's elbow vector crosses the negative x-axis
    (at t_f: reached, with the turn 0, for the limit there)."""
    u, y, K, D = _leg_polys(m, i)
    P = K * K * y * y - D * u * u
    if P.is_zero():
        return []
    found = real_roots_in(P, m.duration)
    bits = 128
    while True:
        with ctx.workprec(bits):
            roots = sorted(((_ends(exact, at, bits), exact, at) for exact, at in found),
                           key=lambda r: r[0][0])  # fmt: skip
        bounds = [b for b, _, _ in roots]
        if all(a[1] < b[0] for a, b in pairwise(bounds)):
            break
        if bits >= MAX_BITS:  # distinct roots, so only a bug leaves two overlapping
            raise AssertionError(f"two roots of P not told apart at {bits} bits")
        bits *= 2
    edges = [fmpq(0), *(e for b in bounds for e in b), m.duration]
    gaps = [
        _sign(m, i, (lo + hi) / 2, "y") if lo < hi else 0
        for lo, hi in zip(edges[::2], edges[1::2], strict=True)
    ]  # the sign of c_y before each root, and after the last
    out = []
    for j, (_, exact, at) in enumerate(roots):
        before, after = gaps[j], gaps[j + 1]
        if not before or before == after:
            continue
        if _sign(m, i, exact if exact is not None else at, "x") < 0:
            out.append(Crossing(exact, at, (1 if before > 0 else -1) if after else 0, before))
    return out


def _ends(exact: fmpq | None, at: Any, bits: int) -> tuple[fmpq, fmpq]:
    """Rationals around a root of P: the root itself when rational, else its ball's ends
    at ``bits``."""
    return (exact, exact) if exact is not None else exact_ends(at(bits))


def turns(cross: list[Crossing], t: fmpq, principal: float) -> float:
    """The continuous angle at the exact time t from its principal value: 2π times the
    turns of the crossings before t added; at a crossing, the limit from before it."""
    n = 0
    for c in cross:
        k = c.compare(t)
        if k < 0:
            n += c.turn
        elif k == 0:
            return c.before * math.pi + 2 * math.pi * n
    return principal + 2 * math.pi * n

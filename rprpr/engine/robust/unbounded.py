"""The worst case over the box is unbounded next to E at A or B: a proof, and its bound.

Where the motion passes a base joint (E at A: leg 1, s1 = 0; E at B: leg 2, s2 = 0) the
nominal efforts stay bounded (the audit's ``certified.through``), but an acceleration
tracking error e does not: the leg's angular acceleration holds
    θ_i'' = (u (v'' + e_y) - v (u'' + e_x) - 2 s s' θ') / s²,
whose gradient in e is n_i / s_i, n_i = (-sin θ_i, cos θ_i) a unit vector. Every effort is
affine in e (``docs/robust.md``), so at one time t and one point π of the box
    max over e = ±e_c of |E_j(t, π, e)| >= |e_c · ∇_e E_j|,
and over the square's corners e_c the largest |e_c · g| is a |g|_1 >= a |g|_2. The
gradient, from the equations (``exact.equations``; M_ii, N_i depend on the position and
velocity only; ∇F1 = m3 (cos θ1, sin θ1), ∇F2 = m5 (cos θ2, sin θ2) through s_i'';
|δ| = a1 |sin θ_i| / s_other since y = s_i sin θ_i):

* revolute, leg i at its base: T_i = M_ii θ_i'' + N_i - s_i (...) · λ with λ = μ/δ and
  |∇μ_k|_2 <= m3 + m5, so
      |∇T_i|_2 >= M_ii / s_i - 2 (m3 + m5) s_i s_other / (a1 |sin θ_i|);
* prismatic, leg 1 at A: F2 = d.F2 - (V1 + cos(θ1 - θ2) V2) / δ with V_k = U_k / s_k,
  ∇V1 = M11 n1 / s1², ∇V2 = M33 n2 / s2², so
      |∇F2|_2 >= M11 s2 / (a1 |sin θ1| s1²) - m5 - M33 / (a1 |sin θ1| s2);
  leg 2 at B, the same with the legs' roles swapped, for F1.

So with, over a span of time on one side of t_A, lower bounds of M_ii and of |sin θ_i|
above 0 and upper bounds of the rest, sup over the box of |E_j(t)| >= a (c / s_i^p - k)
(p = 1 revolute, 2 prismatic), which grows without limit as t -> t_A (s_i -> 0): the
worst-case peak of E_j is infinite, proven. The span's bounds come from the motion's
exact Taylor coefficients about t_A in ball arithmetic, with u = x - x_base and y
factored by φ = ε^k (ε = t - t_A, k the order to which both vanish), so that nothing
divides by a ball holding 0: s_i = |φ| r, r = |(u/φ, y/φ)|, sin θ_i = ±(y/φ)/r. A path
tangent to AB at the base joint (sin θ_i -> 0: δ vanishes too) is not proven here.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from flint import arb, arb_poly, ctx, fmpq

from ...model.dataclass import dataclass
from ...model.numbers import to_float
from ...model.task import Task
from ..exact.mechanism import of
from ..exact.series import taylor
from .windows import Box, round_down, round_up

PREC = 128
WIDTHS = 40  # spans of 2^-j of the reach tried, j = 0..WIDTHS-1


@dataclass(frozen=True)
class Pole:
    """A proof that sup over the box of |E_j| is infinite next to E at a base joint: for
    every time t with ε = t - t_A of the sign ``side`` and |ε| <= ``width``, s_i(t) <=
    ``s_max`` and sup over the box of |E_j(t)| >= a (``coef`` / s_i(t)^``order`` -
    ``rest``), a lower bound that grows without limit as t -> t_A."""

    effort: int  # j: 0 (T1, F1) or 1 (T2, F2)
    leg: int  # i: 1 (E at A) or 2 (E at B)
    t: float  # t_A, absolute [s] (the nearest double)
    side: int  # -1, +1
    width: float  # [s]
    order: int  # p
    coef: float  # c > 0
    rest: float  # k >= 0
    s_max: float
    a: fmpq  # the acceleration bound [m/s²], exact

    def lower(self, s: float) -> float:
        """The proven lower bound at a time where s_i = ``s`` (0 < s <= ``s_max``), rounded
        down (a double)."""
        return round_down(arb(self.a) * (arb(self.coef) / arb(s) ** self.order - arb(self.rest)))


def poles(task: Task, parts: Sequence[Any], box: Box,
          spans: Sequence[tuple[float, float]] = ()) -> list[Pole]:  # fmt: skip
    """Every proof ``Pole`` of an unbounded worst case the motion's passages through A or
    B give (none without an acceleration error), on the sides of each passage that lie
    in its piece and outside the proven windows ``spans`` (absolute)."""
    if box.a == 0:
        return []
    out = []
    with ctx.workprec(PREC):
        for p in parts:
            for k in p.motion.kinematic:
                t_abs = to_float(p.origin) + k.time.hi
                for side in (-1, 1):
                    got = _side(task, p, k, side, box, t_abs, spans)
                    if got is not None:
                        out.append(got)
    return out


def _side(task: Task, p: Any, k: Any, side: int, box: Box, t_abs: float,
          spans: Sequence[tuple[float, float]]) -> Pole | None:  # fmt: skip
    """The proof on one side of the passage ``k`` of the piece ``p``: on the widest span
    of 2^-j of the reach (the distance to the piece's end) that lies outside the proven
    windows and on which the bounds hold, else None."""
    traj = p.traj
    lo, hi = to_float(p.start - p.origin), to_float(p.end - p.origin)
    if not lo <= k.time.hi <= hi:
        return None
    reach = (hi - k.time.hi) if side > 0 else (k.time.hi - lo)
    reach = reach * (1 - 1e-9) - 2 * k.time.err  # t_A + ε stays in the piece
    if not reach > 0:
        return None
    base = fmpq(0) if k.leg == 1 else traj.a1
    other = traj.a1 if k.leg == 1 else fmpq(0)
    minimal = None if k.time.exact is not None else _minimal(traj.x - base, traj.y, k.time)
    if k.time.exact is None and minimal is None:
        return None
    cu, cy, co = (_coeffs(q, k.time, minimal) for q in (traj.x - base, traj.y, traj.x - other))
    order = min(_order(cu), _order(cy))
    if order == 0 or (order >= len(cu) and order >= len(cy)):  # not there, or sits at it
        return None
    motion = (cu[order:] or [arb(0)], cy[order:] or [arb(0)], co, cy, order)
    for j in range(WIDTHS):
        w = reach * 2.0**-j
        near, far = sorted((t_abs - w, t_abs + w))
        if any(s0 <= far and near <= s1 for s0, s1 in spans):
            continue  # a proven window about: those times are not the peak's
        got = _bound(task.robot, k.leg, motion, arb(0).union(arb(side * w)))
        if got is not None:
            effort, p_order, coef, rest, s_max = got
            return Pole(effort, k.leg, t_abs, side, w, p_order, coef, rest, s_max, box.a)
    return None


def _bound(robot: Any, leg: int, motion: tuple[Any, ...], eps: arb
           ) -> tuple[int, int, float, float, float] | None:  # fmt: skip
    """(the effort, p, c, k, s_max) of the module's bound over the span of ε ``eps``, from
    ``motion`` = (a, b: u and y over ε^order; the Taylor coefficients of the other leg's
    u and of y; order), or None where a bound it needs does not hold there."""
    a, b, co, cy, order = motion
    L = robot.links
    legs = (L[3], L[2], L[5], L[4]) if leg == 1 else (L[5], L[4], L[3], L[2])
    own, own_base, oth, oth_base = legs  # the passing leg's links, the other leg's
    A, B = _horner(a, eps), _horner(b, eps)
    r = (A * A + B * B).sqrt()
    if not r > 0:
        return None
    sin = abs(B) / r
    beta = sin.lower()
    if not beta > 0:
        return None
    s_max = (abs(eps) ** order * r).upper()
    s = arb(0).union(s_max)  # s_i over the span
    U = _horner(co, eps)
    s_other = (U * U + _horner(cy, eps) ** 2).sqrt()
    if not s_other > 0:
        return None
    d = abs(s - arb(own.r)).lower()  # |s_i - r| >= d over the span (a square >= d²)
    M = (arb(own_base.mass) * arb(own_base.r) ** 2 + arb(own_base.inertia)
         + arb(own.mass) * d * d + arb(own.inertia))  # fmt: skip
    M_other = (arb(oth_base.mass) * arb(oth_base.r) ** 2 + arb(oth_base.inertia)
               + arb(oth.mass) * (s_other - arb(oth.r)) ** 2 + arb(oth.inertia))  # fmt: skip
    M0 = M.lower()
    if not M0 > 0:
        return None
    a1 = arb(robot.a1)
    if of(robot).name == "revolute":
        coef = M0
        rest = 2 * (arb(L[3].mass) + arb(L[5].mass)) * s_max * s_other / (a1 * beta)
        effort, p_order = leg - 1, 1
    else:
        coef = (M0 * s_other.lower() / (a1 * sin.upper())).lower()
        rest = arb(oth.mass) + M_other / (a1 * beta * s_other.lower())
        effort, p_order = 2 - leg, 2
    if not (coef > 0 and rest.is_finite()):
        return None
    return effort, p_order, round_down(coef), round_up(rest.upper()), round_up(s_max)


def _minimal(u: Any, y: Any, e: Any) -> Any:
    """The minimal polynomial of the irrational exact time e, a common root of u and y:
    the one irreducible factor of gcd(u, y) whose ball at e holds 0 (e is a root of the
    gcd, so of one factor; the others' balls excluding 0 prove which), or None."""
    common = u.gcd(y) if not y.is_zero() else u
    factors = [f for f, _ in common.factor()[1] if f.degree() >= 1]
    for prec in (256, 512, 1024, 2048, 4096):
        t = e.at(prec)
        hits = [f for f in factors if arb_poly(f.coeffs())(t).contains(0)]
        if len(hits) == 1:
            return hits[0]
    return None


def _coeffs(poly: Any, e: Any, minimal: Any) -> list[arb]:
    """The Taylor coefficients of ``poly`` about the exact time ``e`` (balls; exact zeros
    where the coefficient vanishes there exactly)."""
    cs = taylor(poly, max(poly.degree(), 0) + 1)
    if e.exact is not None:
        return [arb(c(e.exact)) for c in cs]
    t = e.at(PREC + 64)
    # c(e) = (c mod f)(e) with f the minimal polynomial of e: zero exactly when c mod f is
    return [arb(0) if (c % minimal).is_zero() else arb_poly((c % minimal).coeffs())(t)
            for c in cs]  # fmt: skip


def _order(c: list[arb]) -> int:
    """The index of the first coefficient not exactly zero (the vanishing order)."""
    for i, v in enumerate(c):
        if not v.is_zero():
            return i
    return len(c)


def _horner(c: list[arb], x: arb) -> arb:
    v = arb(0)
    for ci in reversed(c):
        v = v * x + ci
    return v

"""The real roots of a polynomial in an interval [0, t_f], isolated and refined exactly.

An irreducible factor f of y(t) of degree >= 2 has only simple, irrational roots, so none
of them is 0, t_f or any other rational. They are isolated with rational arithmetic
only, by the continued-fraction method of Vincent, Collins and Akritas (Descartes' rule
of signs on Möbius transforms of f, with the local-max-quadratic lower bound on the
positive roots to jump ahead): no floating point and no precision to guess, and no
effort spent on the complex roots or on roots outside [0, t_f]. Clustered roots (two
roots 10^-300 apart) cost a few dozen steps, not thousands of bits of precision.

Each root then sits in an open interval (lo, hi) with rational ends at which f has
opposite signs. ``IsolatedRoot.ball(prec)`` narrows it by bisection (exact signs) and
interval Newton steps (arb balls around rational points) until its relative width is
below 2^-prec, keeping the narrowest interval found, and returns the interval as a ball.
Every step is a short call into flint at a precision tied to what was asked: no single
call escalates its precision on its own, so a slow analysis can be stopped between steps.

Conventions: polynomials are flint's (coefficients low -> high), rationals ``fmpq``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial

from flint import arb, arb_poly, ctx, fmpq, fmpq_poly, fmpz, fmpz_poly

Mobius = tuple[fmpz, fmpz, fmpz, fmpz]  # (a, b, c, d): x -> (a x + b) / (c x + d)
RootAt = Callable[[int], arb]  # working precision in bits -> ball containing the root

JUMP_SCALE_BITS = 4  # a lower bound of 2^4 or more is used by scaling x, not by shifting


def _integral(f: fmpq_poly) -> fmpz_poly:
    """f times its denominator, divided by the content: an integer polynomial with the
    same roots and (as the factor is positive) the same signs."""
    z = fmpz_poly([int(c) for c in (f * f.denom()).coeffs()])
    content = abs(z.content())
    return z if content == 1 else fmpz_poly([c // content for c in z.coeffs()])


def _variations(p: fmpz_poly) -> int:
    """The sign variations of p's coefficients (Descartes' bound on its positive roots)."""
    count, last = 0, 0
    for c in p.coeffs():
        if c:
            s = 1 if c > 0 else -1
            if s == -last:
                count += 1
            last = s
    return count


def _scaled(p: fmpz_poly, bits: int) -> fmpz_poly:
    """p(2^bits x)."""
    return fmpz_poly([c << (bits * i) for i, c in enumerate(p.coeffs())])


def _shifted(p: fmpz_poly) -> fmpz_poly:
    """p(x + 1) (a Taylor shift)."""
    return p(fmpz_poly([1, 1]))


def _inverted(p: fmpz_poly, degree: int) -> fmpz_poly:
    """(x + 1)^n p(1/(x + 1)), n = degree: its positive roots are the images of p's roots
    in (0, 1)."""
    c = p.coeffs()
    return _shifted(fmpz_poly((c + [fmpz(0)] * (degree + 1 - len(c)))[::-1]))


def _lower_bound_bits(p: fmpz_poly) -> int | None:
    """k such that every positive root of p is >= 2^k (p(0) != 0), from the
    local-max-quadratic upper bound on the positive roots of x^n p(1/x) (Akritas,
    Strzeboński, Vigklas 2008), rounded up to a power of two with bit lengths; None when p
    has no positive root by that bound's reckoning (no sign change)."""
    c = [int(v) for v in p.coeffs()][::-1]  # x^n p(1/x): the roots inverted
    if c[-1] < 0:
        c = [-v for v in c]
    n = len(c) - 1
    used = [1] * (n + 1)  # the LMQ weights: 2^t for the t-th use of a positive coefficient
    best: int | None = None
    for i in range(n):
        if c[i] >= 0:
            continue
        bound: int | None = None
        for j in range(i + 1, n + 1):
            if c[j] <= 0:
                continue
            # (2^t |c_i| / c_j)^(1/(j - i)) < 2^ceil((t + bits(c_i) - bits(c_j) + 1)/(j - i))
            e = used[j] + (-c[i]).bit_length() - c[j].bit_length() + 1
            k = -((-e) // (j - i))
            if bound is None or k < bound:
                bound, arg = k, j
        if bound is not None:
            used[arg] += 1
            best = bound if best is None else max(best, bound)
    return None if best is None else -best


def isolate(f: fmpq_poly, duration: fmpq) -> list[tuple[fmpq, fmpq]]:
    """Disjoint open intervals (lo, hi) with rational ends in [0, t_f], in increasing
    order, each holding exactly one root of f and together all of f's roots in (0, t_f);
    f is square-free with no root at 0 or t_f (an irreducible f of degree >= 2)."""
    n = f.degree()
    # t = t_f u, u = 1/(1 + x): the roots in (0, t_f) are the positive roots in x of
    # (1 + x)^n h(1/(1 + x)), h(u) = f(t_f u)
    p = _inverted(_integral(f(fmpq_poly([0, duration]))), n)
    found: list[tuple[fmpq, fmpq]] = []
    stack: list[tuple[fmpz_poly, Mobius]] = [(p, (fmpz(0), fmpz(1), fmpz(1), fmpz(1)))]
    while stack:
        p, m = stack.pop()
        v = _variations(p)
        if v == 0:
            continue
        if v == 1:
            found.append(_u_interval(m, duration))
            continue
        k = _lower_bound_bits(p)
        if k is not None and k >= JUMP_SCALE_BITS:  # jump: x -> 2^k x, then x -> x + 1
            p, m = _scaled(p, k), (m[0] << k, m[1], m[2] << k, m[3])
            p, m = _shifted(p), (m[0], m[0] + m[1], m[2], m[2] + m[3])
        elif k is not None and k >= 0:  # x -> x + 2^k
            s = fmpz(1) << k
            p, m = p(fmpz_poly([s, 1])), (m[0], m[0] * s + m[1], m[2], m[2] * s + m[3])
        # split at x = 1: roots in (1, inf) are those of p(x + 1), in (0, 1) of
        # (x + 1)^n p(1/(x + 1)); x = 1 itself is a rational point, never a root
        stack.append((_shifted(p), (m[0], m[0] + m[1], m[2], m[2] + m[3])))
        stack.append((_inverted(p, n), (m[1], m[0] + m[1], m[3], m[2] + m[3])))
    return sorted(found)


def real_roots_in(
    f: fmpq_poly, duration: fmpq, *, simple: bool = False
) -> list[tuple[fmpq | None, RootAt]]:
    """The real roots of f in [0, t_f]: (the root when it is rational, else None;
    precision -> certified ball), by the irreducible factors of f over Q in flint's
    order, each factor's roots in increasing order. A rational root is exact; an
    irrational one is isolated and refined with rational arithmetic (``IsolatedRoot``:
    its interval narrows as higher precisions are asked for, and is kept). ``simple``: f
    is irreducible, or square-free with no rational root, and is isolated as it is."""
    if f.degree() < 1:
        return []
    parts = [f] if simple else [g for g, _ in f.factor()[1] if g.degree() >= 1]
    out: list[tuple[fmpq | None, RootAt]] = []
    for g in parts:
        if g.degree() == 1:
            r = -g[0] / g[1]
            if 0 <= r <= duration:
                out.append((r, partial(_exact_ball, r)))
            continue
        out += [(None, IsolatedRoot(g, lo, hi).ball) for lo, hi in isolate(g, duration)]
    return out


def _exact_ball(r: fmpq, prec: int) -> arb:
    """The rational root r as a ball (at the working precision)."""
    return arb(r)


def _u_interval(m: Mobius, duration: fmpq) -> tuple[fmpq, fmpq]:
    """The t-interval of the x-interval (0, inf) under m, in t = t_f u."""
    a, b, c, d = m
    u0 = fmpq(b, d)  # x = 0
    u1 = fmpq(a, c)  # x -> inf
    lo, hi = (u0, u1) if u0 < u1 else (u1, u0)
    return lo * duration, hi * duration


class IsolatedRoot:
    """One simple root r of f in the open interval (lo, hi), at whose rational ends f has
    opposite signs; ``ball`` narrows the interval on demand by quadratic interval
    refinement (Abbott 2006; Kerber and Sagraloff 2011): the secant through the ends,
    snapped to a grid of N cells, names a cell that signs then confirm (the interval
    shrinks N-fold and N is squared: quadratic convergence) or not (N -> sqrt N, and a
    bisection at N = 2). The interval's ends are rationals and every sign is certified
    (a ball that excludes zero, else the exact value): a root in a cluster costs a few
    more steps, never an unbounded precision."""

    def __init__(self, f: fmpq_poly, lo: fmpq, hi: fmpq) -> None:
        self._g = _integral(f)
        self.lo, self.hi = lo, hi
        self._g_lo, self._g_hi = self._value(lo), self._value(hi)
        self._cells = 4
        if _sgn(self._g_lo) == _sgn(self._g_hi):
            raise ValueError("not an isolating interval of a simple root")

    def _accurate(self, prec: int) -> bool:
        return self.lo > 0 and (self.hi - self.lo) * (fmpz(1) << prec) <= self.lo

    def ball(self, prec: int) -> arb:
        """A ball containing r, of relative radius at most about 2^-prec."""
        while not self._accurate(prec):
            self._step()
        old = ctx.prec
        ctx.prec = prec + 8
        try:
            return arb(self.lo).union(arb(self.hi))
        finally:
            ctx.prec = old

    def _value(self, t: fmpq) -> arb:
        """g(t) as a ball that excludes zero (t is rational, so g(t) != 0): evaluated in
        ball arithmetic at a precision a little above t's size, doubled twice, then
        exactly."""
        prec = max(int(t.p).bit_length(), int(t.q).bit_length()) + 64
        old = ctx.prec
        try:
            for _ in range(3):
                ctx.prec = prec
                v = arb_poly(self._g.coeffs())(arb(t))
                if not v.contains(0):
                    return v
                prec *= 2
            exact = fmpq_poly(self._g.coeffs())(t)
            if exact == 0:
                raise ValueError("a rational root of an irreducible polynomial of degree >= 2")
            ctx.prec = 64
            return arb(exact)
        finally:
            ctx.prec = old

    def _step(self) -> None:
        n = self._cells
        if n <= 2:
            self._bisect()
            self._cells = 4
            return
        lo, w = self.lo, (self.hi - self.lo) / n
        mid = lo + _secant_cell(self._g_lo, self._g_hi, n) * w
        g_mid = self._value(mid)
        if _sgn(g_mid) == _sgn(self._g_lo):  # r > mid: is it in (mid, mid + w)?
            a, b, g_a = mid, mid + w, g_mid
            g_b = self._value(b) if b < self.hi else self._g_hi
            success = _sgn(g_b) != _sgn(g_a)
        else:  # r < mid: is it in (mid - w, mid)?
            a, b, g_b = mid - w, mid, g_mid
            g_a = self._value(a) if a > lo else self._g_lo
            success = _sgn(g_a) != _sgn(g_b)
        if success:
            self.lo, self.hi, self._g_lo, self._g_hi = a, b, g_a, g_b
            self._cells = n * n
        else:
            self._cells = math.isqrt(n)

    def _bisect(self) -> None:
        mid = (self.lo + self.hi) / 2  # rational, so never the (irrational) root
        g_mid = self._value(mid)
        if _sgn(g_mid) == _sgn(self._g_lo):
            self.lo, self._g_lo = mid, g_mid
        else:
            self.hi, self._g_hi = mid, g_mid


def _secant_cell(g_lo: arb, g_hi: arb, n: int) -> int:
    """k in 1 .. n - 1 nearest to where the secant through (0, g_lo), (n, g_hi) meets zero
    (any k is correct; a good one makes the step succeed)."""
    old = ctx.prec
    ctx.prec = n.bit_length() + 32
    try:
        x = (arb(n) * g_lo / (g_lo - g_hi)).mid()
        k = int(x.floor().unique_fmpz()) if x.is_finite() else n // 2
    finally:
        ctx.prec = old
    return min(max(k, 1), n - 1)


def _sgn(v: arb) -> int:
    """The sign of a ball that excludes zero."""
    return 1 if v > 0 else -1


def max_abs(p: fmpq_poly, a: fmpq, b: fmpq) -> tuple[float, float]:
    """(M, t): an upper bound M of max |p(t)| over a <= t <= b, within about 1e-15 of
    the maximum, and a time t where it is reached (to about 1e-15 of b - a).

    The maximum is at a or b or at a root of p' in between: the rational roots of p'
    exactly (its linear factors over Q), the others isolated in (a, b) by ``isolate``
    (an irreducible factor of degree >= 2 has no rational root), narrowed by exact
    bisection, and |p| bounded over each root's interval in arb. Exact values are
    rounded up to a double."""
    best = [(abs(p(a)), a), (abs(p(b)), b)]
    out = [(_up_float(v), float(t)) for v, t in best]
    g = p.derivative()
    if not g.is_zero():
        for fac, _ in g.factor()[1]:
            if fac.degree() == 1:
                c = fac.coeffs()
                r = -c[0] / c[1]
                if a < r < b:
                    out.append((_up_float(abs(p(r))), float(r)))
                continue
            h = fac(fmpq_poly([a, 1]))  # in u = t - a
            for lo, hi in isolate(h, b - a):
                lo, hi = _narrowed(h, lo, hi, (b - a) / fmpq(2**64))
                out.append((_arb_abs_upper(p, a + lo, a + hi), float(a + (lo + hi) / 2)))
    return max(out)


def _narrowed(h: fmpq_poly, lo: fmpq, hi: fmpq, width: fmpq) -> tuple[fmpq, fmpq]:
    """The root of h in (lo, hi) (opposite signs at the ends) in an interval of at most
    ``width``, by exact bisection."""
    s_lo = _sign_q(h(lo))
    while hi - lo > width:
        mid = (lo + hi) / 2
        s = _sign_q(h(mid))
        if s == 0:
            return mid, mid
        if s == s_lo:
            lo = mid
        else:
            hi = mid
    return lo, hi


def _sign_q(v: fmpq) -> int:
    return (v > 0) - (v < 0)


def _arb_abs_upper(p: fmpq_poly, lo: fmpq, hi: fmpq) -> float:
    """An upper bound of |p| over [lo, hi] (arb at 128 bits), as a double rounded up."""
    old = ctx.prec
    ctx.prec = 128
    try:
        t = arb((lo + hi) / 2, (hi - lo) / 2)
        v = arb_poly([arb(c) for c in p.coeffs()])(t)
        return _up_float(abs(v).upper())
    finally:
        ctx.prec = old


def _up_float(v: fmpq | arb) -> float:
    """A double >= v (v >= 0): 0 for an exact 0."""
    if isinstance(v, fmpq) and v == 0:
        return 0.0
    f = float(v) if isinstance(v, fmpq) else float(v.mid() + v.rad())
    return math.nextafter(f, math.inf)

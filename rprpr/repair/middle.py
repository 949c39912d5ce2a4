"""The box's middle (pure): with declared uncertainty, the acceleration a repair sets at a
crossing is aimed where the consistency residual's interval over the box is centred on 0
(``docs/robust.md``, *Repair*).

The residual at t_s is affine in the acceleration z that the repair sets (ẍ under the
paper's scheme, ÿ under the prismatic one): R(z) = K(π) z + B(π, e) for parameters π in
the box and errors e within the bound, with K of one sign over the box (K = ±(m3 + m5)
at a revolute crossing). Its bounds lo(z), hi(z) over the box then move alike with z
(both up when K > 0), and max |R| = max(hi, -lo) is least where lo(z) + hi(z) = 0:
the interval centred on 0.
The nominal consistent value z0 (``consistency``) centres it when the box is symmetric
about the nominal residual (an acceleration error alone, or masses alone: m ranges over
m(1 ± ρ)); the products m r and m r² are not (m r over m r (1 ± ρ)², centred on
m r (1 + ρ²)), so with r uncertain the middle lies off z0, by O(ρ²).

The near-crossing torque is about s_i |R| s1 s2 / (a1 |ẏ| |t - t_s|), so the least
max |R| gives the shortest worst-case window to leading order; the repaired motion's
proven window is then reported, not assumed. The target is a short decimal within
1e-6 of the interval's width of the middle; z0 itself (exact nominal consistency, no
pole of the nominal model) whenever it is that close.
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction

from flint import fmpq

from ..engine.robust.proofs import residual_at
from ..model.task import Task, Uncertainty

CLOSE = 1e-6  # of the interval's width: a middle this close to z0 is z0
ROUNDS = 12  # secant steps on lo + hi (piecewise linear: a few suffice)


def middle(task: Task, x: fmpq, xd: fmpq, yd: fmpq, z0: fmpq, other: fmpq, axis: str) -> fmpq:
    """The acceleration to set at the crossing (x, 0) with velocity (ẋ, ẏ): ``z0`` (the
    nominal consistent one) moved to the box's middle. ``axis`` "x": z is ẍ and ``other``
    ÿ; "y": z is ÿ and ``other`` ẍ. ``z0`` when the task declares no uncertainty."""
    u = task.uncertainty
    if u is None or u.zero:
        return z0

    def state(z: fmpq) -> tuple[fmpq, ...]:
        return (x, xd, z, yd, other) if axis == "x" else (x, xd, other, yd, z)

    def bounds(z: fmpq, box: Uncertainty) -> tuple[float, float]:
        lo, hi = residual_at(task.robot, box, state(z))
        return float(lo.mid()), float(hi.mid())

    lo, hi = bounds(z0, u)
    width = hi - lo
    if not width > 0 or abs(lo + hi) <= CLOSE * width:
        return z0
    nominal = Uncertainty({i: (fmpq(0),) * 3 for i in u.links}, fmpq(0), u.period)
    slope = bounds(z0 + 1, nominal)[0] - bounds(z0, nominal)[0]  # K at the nominal π
    if slope == 0:
        return z0
    z = _centre(lambda v: sum(bounds(_q(v), u)), float(z0), lo + hi, slope)
    worst = max(hi, -lo)
    tol = CLOSE * width / abs(2 * slope)
    if z is None or abs(z - float(z0)) <= tol:
        return z0
    target = _short(z, tol)
    lo1, hi1 = bounds(target, u)
    return target if max(hi1, -lo1) < worst else z0


def _centre(g: Callable[[float], float], z0: float, g0: float, slope: float) -> float | None:
    """The root of g (lo + hi: monotone, piecewise linear) by secant steps from z0,
    the first step by the nominal slope (g's is about twice it); None when it fails."""
    za, ga = z0, g0
    zb = z0 - g0 / (2 * slope)
    for _ in range(ROUNDS):
        gb = g(zb)
        if gb == 0 or gb == ga:
            return zb
        za, ga, zb = zb, gb, zb - gb * (zb - za) / (gb - ga)
        if abs(zb - za) <= 1e-15 * max(1.0, abs(zb)):
            return zb
    return zb if abs(g(zb)) < abs(g0) else None


def _short(z: float, tol: float) -> fmpq:
    """The decimal with the fewest significant digits within ``tol`` of ``z``."""
    for digits in range(1, 18):
        d = Fraction(f"{z:.{digits - 1}e}")
        if abs(float(d) - z) <= tol:
            return fmpq(d.numerator, d.denominator)
    return _q(z)


def _q(v: float) -> fmpq:
    return fmpq(*v.as_integer_ratio())

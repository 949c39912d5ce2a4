"""T1, T2 and their time derivatives in arb scalars at a handful of times, and the
motion's Taylor coefficients about its singular instants in arb (``Scalars._origin``,
read by the pole bands, ``poles.pole_bands``).

One arb evaluation of the formulas at a point costs ~0.06-0.1 ms. The crossings of a
limit check are bracketed by vectorised point passes instead (``limits._bracket``): with
the compiled kernel a pass costs ~0.1 ms whatever its number of points, and the passes
serve every crossing of a motion at once.

The series of x(t), y(t) about a time come from their exact Taylor coefficients about an
exact time t_0 (the nearest singular instant, else t = 0) by Horner in ε + τ, ε = t - t_0
(``taylor_forms.series_at``); flint's ``arb_series`` evaluated on a ball of ε encloses
f^(j)(ξ)/j! for every ξ of the ball in its coefficient j, so the series of T truncated
after two terms gives T and T' at a point (``Scalars.slope``). Near t_s, δ and μ are
evaluated from series whose vanishing terms are exactly zero (t_s rational) or balls of
radius ~2^-128 (t_s a real root), so the quotient μ/δ keeps its digits at every time
where |t - t_s|^m is far above that."""

from __future__ import annotations

from functools import cached_property
from typing import Any

from flint import arb, ctx

from ..certified.balls import hypot
from ..certified.motion import CertifiedMotion
from ..certified.taylor_forms import TAYLOR_PREC, coef, series_at, taylor_at_instant
from ..exact.series import taylor

Pair = tuple[arb, arb]


class Scalars:
    """T1, T2 of one motion in arb at float times (module docstring); None where the
    formulas fail (a square root or a quotient over a ball that reaches 0: at a pole, at
    A or B)."""

    def __init__(self, motion: CertifiedMotion) -> None:
        self.motion = motion
        self._origins: dict[int, tuple[arb, list[list[arb]]]] = {}
        self._times = [e.hi for _, e in motion.instants]

    @cached_property
    def _params(self) -> Any:
        """The robot's numbers in arb, made once, when a series first needs them (the
        pole bands read only ``_origin``)."""
        with ctx.workprec(TAYLOR_PREC):
            return self.motion.mech.params(self.motion.robot, arb)

    def _origin(self, t: float) -> tuple[arb, list[list[arb]]]:
        """(t_0, Taylor coefficients of x and y about t_0): the nearest instant, else 0."""
        k = -1
        if self._times:
            k = min(range(len(self._times)), key=lambda j: abs(self._times[j] - t))
        if k not in self._origins:
            old = ctx.prec
            ctx.prec = TAYLOR_PREC
            try:
                if k < 0:
                    t0 = arb(0)
                    coeffs = [[arb(c(0)) for c in taylor(p, max(p.degree(), 0) + 1)]
                              for p in (self.motion.traj.x, self.motion.traj.y)]  # fmt: skip
                else:
                    s, e = self.motion.instants[k]
                    t0 = arb(e.exact) if e.exact is not None else e.at(TAYLOR_PREC)
                    coeffs = taylor_at_instant(self.motion, s, TAYLOR_PREC)
            finally:
                ctx.prec = old
            self._origins[k] = (t0, coeffs)
        return self._origins[k]

    def _series(self, t: arb, mid: float, n: int) -> tuple[Any, Any] | None:
        """T1, T2 as series of n terms about every time of the ball t (None on failure)."""
        t0, coeffs = self._origin(mid)
        old_prec, old_cap = ctx.prec, ctx.cap
        ctx.prec, ctx.cap = TAYLOR_PREC, n + 2
        try:
            X, Xd, Xdd, Y, Yd, Ydd = series_at(coeffs, t - t0, n)
            ctx.cap = n
            m = self.motion.mech
            p = self._params
            l1, l2 = m.legs(p, X, Xd, Xdd, Y, Yd, Ydd, hypot)
            d = m.dynamics(l1, l2, p)
            delta = m.delta(p, Y, l1, l2)
            T1, T2 = m.efforts(d, d.mu1 / delta, d.mu2 / delta)
            return T1, T2
        except (ValueError, ZeroDivisionError):
            return None
        finally:
            ctx.prec, ctx.cap = old_prec, old_cap

    def point(self, t: float) -> Pair | None:
        """T1(t), T2(t) as arb balls at the float time t."""
        got = self.slope(t, 1)
        return None if got is None else got[0]

    def slope(self, t: float, n: int = 2) -> tuple[Pair, Pair] | None:
        """((T1, T2), (T1', T2')) at the float time t (n = 1: the derivatives not
        computed, returned as the values)."""
        got = self._series(arb(t), t, n)
        if got is None:
            return None
        v = (coef(got[0], 0), coef(got[1], 0))
        d = (coef(got[0], 1), coef(got[1], 1)) if n > 1 else v
        return (v, d) if all(x.is_finite() for x in (*v, *d)) else None

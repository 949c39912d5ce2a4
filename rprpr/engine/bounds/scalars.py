"""T1, T2 and their time derivatives in arb scalars at a handful of times: the points
that bracket a crossing of |T_i| = L_i in the limit check (``Scalars.bracket``).

A ball pass over vectors costs its numpy calls (~2-3 ms for the values at points,
whatever their number); one arb evaluation of the formulas at a point costs ~0.06-0.1 ms.
Where a few points are wanted (a few crossings, each bracketed by Newton's method in a
handful of steps), arb is the cheaper proof.

The series of x(t), y(t) about a time come from their exact Taylor coefficients about an
exact time t_0 (the nearest singular instant, else t = 0) by Horner in ε + τ, ε = t - t_0
(``taylor_forms.series_at``); flint's ``arb_series`` evaluated on a ball of ε encloses
f^(j)(ξ)/j! for every ξ of the ball in its coefficient j, so the series of T truncated
after two terms gives T and T' at a point (``Scalars.slope``). Near t_s, δ and μ are
evaluated from series whose vanishing terms are exactly zero (t_s rational) or balls of
radius ~2^-128 (t_s a real root), so the quotient μ/δ keeps its digits at every time
where |t - t_s|^m is far above that (the limit check's resolution is 1e-9 t_f); where a
ball is too wide to tell, the point decides nothing and the bracket is bisected."""

from __future__ import annotations

import math
from typing import Any

from flint import arb, ctx

from ..certified.balls import Ball, hypot
from ..certified.motion import CertifiedMotion
from ..certified.taylor_forms import TAYLOR_PREC, coef, series_at, taylor_at_instant
from ..exact.series import taylor

Pair = tuple[arb, arb]
STEPS = 40  # Newton steps of a bracketing (``Scalars.bracket``), at most


class Scalars:
    """T1, T2 of one motion in arb at float times (module docstring); None where the
    formulas fail (a square root or a quotient over a ball that reaches 0: at a pole, at
    A or B)."""

    def __init__(self, motion: CertifiedMotion) -> None:
        self.motion = motion
        self._origins: dict[int, tuple[arb, list[list[arb]]]] = {}
        self._times = [e.hi for _, e in motion.instants]
        with ctx.workprec(TAYLOR_PREC):  # the robot's numbers in arb, once
            self._params = motion.mech.params(motion.robot, arb)

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

    def bracket(
        self, i: int, limit: float, a: float, z: float, res: float, t: float
    ) -> tuple[float, float]:
        """A crossing of |T_i| = limit in the box between a (|T_i| <= limit there) and z
        (> limit), |T_i| monotone between, bracketed by arb scalars: Newton's method on
        f = |T_i| - limit (T_i and T_i' at a point, ``slope``) chooses the points,
        each point's certified value moves a or z to it (on the side it proves); once a
        step is shorter than ``res``, the points 0.45 res either side of the estimate close
        the bracket (the one beyond it alone, when t is an end of the bracket and the step
        is at most res/2: the bracket is then within 0.95 res). A step outside (a, z), or
        a failed evaluation, bisects. From the estimate t; returns (a, z), within ``res``
        of each other unless STEPS did not suffice."""
        for _ in range(STEPS):
            if abs(z - a) <= res:
                break
            got = self.slope(t)
            est = 0.5 * a + 0.5 * z
            if got is not None:
                v = Ball.of_arb(got[0][i])
                d = float(got[1][i].mid())
                a, z = _moved(t, v, limit, a, z)
                est = 0.5 * a + 0.5 * z  # the bisection, where Newton's step falls outside
                f = abs(float(v.mid)) - limit
                step = -f / (math.copysign(1.0, float(v.mid)) * d) if d != 0.0 else math.inf
                if math.isfinite(step) and (t + step - a) * (z - t - step) > 0:
                    est = t + step
                if abs(step) < res:  # close: points either side decide
                    sign = math.copysign(1.0, z - a)
                    probes = [est - 0.45 * res * sign, est + 0.45 * res * sign]
                    if t in (a, z) and abs(step) <= 0.5 * res:  # t is an end: one probe
                        away = sign if t == a else -sign  # beyond est, from t
                        probes = [est + 0.45 * res * away, est - 0.45 * res * away]
                    for p in probes:
                        if abs(z - a) <= res:
                            break
                        if (p - a) * (z - p) > 0:
                            w = self.point(p)
                            if w is not None:
                                a, z = _moved(p, Ball.of_arb(w[i]), limit, a, z)
                    est = 0.5 * a + 0.5 * z
            if not (est - a) * (z - est) > 0:
                break
            t = est
        return a, z


def _moved(t: float, v: Ball, limit: float, a: float, z: float) -> tuple[float, float]:
    """The bracket (a below the limit, z above it) moved to t where t lies strictly
    between them and the certified value v = T_i(t) decides its side."""
    if (t - a) * (z - t) > 0:
        if float(v.upper_abs()) <= limit:
            return t, z
        if float(v.lower_abs()) > limit:
            return a, t
    return a, z

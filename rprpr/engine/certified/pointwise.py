"""The parts of a certified motion that take one time alone, and what a certified value
is (``motion.CertifiedMotion`` is made of the parts: each declares what it reads).

* ``Angles``: the continuous angle θ of a leg (``motion`` module docstring, step 2).
* ``AtInstants``: the values exactly at a rational singular instant (step 5).
* ``Refinement``: a sample evaluated again alone in arb at the exact t (step 4).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np
from flint import arb, ctx, fmpq

from ...model.dataclass import dataclass
from ...model.numbers import number
from ...model.task import Robot
from ..exact.mechanism import Mechanism
from ..exact.singular import SingularAnalysis, SingularInstant, expansion, legs
from ..exact.trajectory import Trajectory
from .balls import ETA, Ball, U, hypot
from .zones import ExactTime

TOL = 1e-9  # the mixed error every certified value meets
START_PREC = 128  # bits of the arb refinement, to start with
MAX_PREC = 4096  # ... doubled up to this

# reason codes of a sample with values that are not finite (0: every value certified);
# where several apply, the first of UNCERTIFIED, BEYOND_DOUBLE, then the one that makes
# values undefined (POLE, AT_A, AT_B before ON_LINE)
OK, POLE, AT_A, AT_B, ON_LINE, UNCERTIFIED, BEYOND_DOUBLE = 0, 1, 2, 3, 4, 5, 6
REASONS = {
    OK: "",
    POLE: "a singular instant with unbounded torques (a pole of λ2): λ2, T1, T2 undefined",
    AT_A: "the end point is at A (s1 = 0): θ1, its rates, δ, λ and T undefined",
    AT_B: "the end point is at B (s2 = 0): θ2, its rates, δ, λ and T undefined",
    ON_LINE: "the path lies on y = 0 (δ ≡ 0): λ and T undefined",
    UNCERTIFIED: f"not certified to {number(TOL)} at {MAX_PREC} bits: no value",
    BEYOND_DOUBLE: "beyond the double range: |value| > 1.8e308 (certified)",
}
DBL_MAX = float(np.finfo(float).max)

FIELDS = (
    "x", "y", "x_dot", "y_dot", "x_ddot", "y_ddot",
    "theta1", "s1", "theta2", "s2",
    "theta1_dot", "s1_dot", "theta2_dot", "s2_dot",
    "theta1_ddot", "s1_ddot", "theta2_ddot", "s2_ddot",
    "delta", "delta_dot", "lambda1", "lambda2", "T1", "T2",
)  # fmt: skip
LEG1 = ("theta1", "theta1_dot", "s1_dot", "theta1_ddot", "s1_ddot")
LEG2 = ("theta2", "theta2_dot", "s2_dot", "theta2_ddot", "s2_ddot")
DYNAMIC = ("delta", "delta_dot", "lambda1", "lambda2", "T1", "T2")

Values = dict[str, Ball]


@dataclass
class Cut:
    """An exact instant at which y = 0 on a leg's branch cut (see ``sampling._cuts``)."""

    time: ExactTime
    after: int  # sign of y just after
    crossing: bool


class Angles:
    """The continuous angle of each leg, for ``CertifiedMotion`` (a part of it)."""

    traj: Trajectory

    if TYPE_CHECKING:

        @property
        def cuts(self) -> dict[int, list[Cut]]: ...

    def theta(self, leg: int, t: np.ndarray, u: Ball, v: Ball) -> Ball:
        """The continuous angle of leg ``leg`` at the float times t (module docstring)."""
        vm = np.array(v.mid + 0 * t, dtype=float)
        um = u.mid + 0 * t
        behind = ~(u.lower() > 0)
        for j in np.nonzero(v.contains_zero() & behind & np.isfinite(vm))[0]:
            sy = self._sign_y(float(t[j]))  # the branch side, decided exactly
            vm[j] = abs(vm[j]) if sy >= 0 else -abs(vm[j])
        raw = np.arctan2(vm, um)
        size = np.maximum(np.abs(um), np.abs(vm))
        rho = (u.rad + v.rad) * (1 + 4 * U)
        prop = np.where(rho < size, (np.pi / 2 * (1 + 4 * U)) * rho / size, np.inf)
        # Ball additions round their radii upward: the allowance and the propagation
        principal = Ball.exact(raw) + Ball(0.0, prop) + Ball(0.0, (16 * U) * np.abs(raw) + 16 * ETA)
        return self._on_branch(leg, t, principal)

    def _on_branch(self, leg: int, t: np.ndarray, principal: Ball) -> Ball:
        """The principal angle moved to the continuous branch: -2π·(sign of y after) past
        each crossing of the leg's cut; exactly on the cut, the limit from the left."""
        half_turns = np.zeros(len(t))
        mid, rad = principal.mid.copy(), principal.rad.copy()
        for c in self.cuts[leg]:
            cmp = c.time.compare(t)
            at = cmp == 0
            mid[at] = (-c.after if c.crossing else c.after) * np.pi
            rad[at] = U * np.pi
            if c.crossing:
                half_turns[cmp > 0] -= 2 * c.after
        if not half_turns.any():
            return Ball(mid, rad)
        return Ball(mid, rad) + Ball(np.pi, U * np.pi) * half_turns  # π ± u π ∋ π

    def _sign_y(self, t: float) -> int:
        v = self.traj.y(fmpq(*t.as_integer_ratio()))
        return (v > 0) - (v < 0)


class AtInstants:
    """The values exactly at a singular instant, for ``CertifiedMotion`` (a part of it)."""

    traj: Trajectory
    robot: Robot
    mech: Mechanism
    analysis: SingularAnalysis
    _limits: dict[int, tuple[Ball, Ball, Ball, Ball]]  # λ1, λ2, T1, T2 per instant

    def _at_instant(
        self, s: SingularInstant, j: int, value: dict[str, np.ndarray],
        radius: dict[str, np.ndarray], reason: np.ndarray, undefined: dict[str, np.ndarray],
    ) -> None:  # fmt: skip
        """Values at t == t_s exactly: δ = 0 and the exact limits of λ and T."""
        value["delta"][j], radius["delta"][j] = 0.0, 0.0
        lam1, lam2, T1, T2 = self._limits_at(s)
        for name, b in (("lambda1", lam1), ("lambda2", lam2), ("T1", T1), ("T2", T2)):
            value[name][j], radius[name][j] = float(b.mid), float(b.rad)
        if not s.torque_bounded:
            reason[j] = POLE
            pole = "lambda2" if self.mech.automatic == 0 else "lambda1"
            for name in (pole, "T1", "T2"):
                undefined[name][j] = True

    def _limits_at(self, s: SingularInstant) -> tuple[Ball, Ball, Ball, Ball]:
        """λ1, λ2, T1, T2 at a rational t_s, exact (NaN balls where a pole)."""
        key = self.analysis.instants.index(s)
        if key not in self._limits:
            m = s.order
            X, Xd, Xdd, Y, Yd, Ydd = expansion(
                self.traj, self.analysis.hints(s).field, m + 1, exact=s.t_rational
            )
            sx = 1 if X.c[0] > 0 else -1
            sxa = 1 if X.c[0] - self.traj.a1 > 0 else -1
            mech = self.mech
            p = mech.params(self.robot)
            l1, l2 = legs(mech, p, X, Xd, Xdd, Y, Yd, Ydd, sx, sxa)
            d = mech.dynamics(l1, l2, p)
            mu = (d.mu1, d.mu2)
            auto = mech.automatic  # μ_auto = O(ε^m): always bounded
            pole = Ball(np.nan, np.inf)
            lam: list[Any] = [None, None]
            lam[auto] = mu[auto].c[m] / d.delta.c[m]
            lam_b = [pole, pole]
            lam_b[auto] = Ball.of_rational(lam[auto])
            T = [pole, pole]
            if s.torque_bounded:
                lam[1 - auto] = mu[1 - auto].c[m] / d.delta.c[m]
                lam_b[1 - auto] = Ball.of_rational(lam[1 - auto])
                T1, T2 = mech.efforts(d, lam[0], lam[1])
                T = [Ball.of_rational(T1.c[0]), Ball.of_rational(T2.c[0])]
            self._limits[key] = (lam_b[0], lam_b[1], T[0], T[1])
        return self._limits[key]


class Refinement(Angles):
    """A sample refined alone in arb, for ``CertifiedMotion`` (a part of it)."""

    traj: Trajectory
    robot: Robot
    mech: Mechanism
    analysis: SingularAnalysis

    def _refine(
        self, t: float, j: int, value: dict[str, np.ndarray], radius: dict[str, np.ndarray],
        undefined: dict[str, np.ndarray], reason: np.ndarray,
    ) -> None:  # fmt: skip
        """Values at t alone in arb, the precision doubled until each one is certified;
        a value certified beyond the double range becomes ±inf (BEYOND_DOUBLE)."""
        todo = [n for n in FIELDS if not radius[n][j] <= TOL * (1 + abs(value[n][j]))]
        todo = [n for n in todo if not undefined[n][j]]
        prec = START_PREC
        beyond = False
        while todo and prec <= MAX_PREC:
            got, raw = self._arb_point(t, prec)
            for n in list(todo):
                b = got.get(n)
                if b is not None and bool(b.certified(TOL)):
                    value[n][j], radius[n][j] = float(b.mid), float(b.rad)
                    todo.remove(n)
                elif n in raw and _beyond_double(raw[n]):
                    value[n][j] = math.inf if raw[n] > 0 else -math.inf
                    radius[n][j] = math.inf
                    todo.remove(n)
                    beyond = True
            prec *= 2
        for n in todo:
            undefined[n][j] = True
        if todo:
            reason[j] = UNCERTIFIED
        elif beyond:
            reason[j] = BEYOND_DOUBLE

    def _arb_point(self, t: float, prec: int) -> tuple[Values, dict[str, arb]]:
        """``arb_point``, and the arb values themselves (all but θ)."""
        tq = fmpq(*t.as_integer_ratio())
        traj = self.traj
        exact = [p(tq) for p in (traj.x, traj.xd, traj.xdd, traj.y, traj.yd, traj.ydd)]
        old = ctx.prec
        ctx.prec = prec
        try:
            x, xd, xdd, y, yd, ydd = (arb(v) for v in exact)
            a1 = arb(traj.a1)
            out: dict[str, Any] = {"x": x, "x_dot": xd, "x_ddot": xdd, "y": y,
                                   "y_dot": yd, "y_ddot": ydd}  # fmt: skip
            u2 = x - a1
            s1, s2 = hypot(x, y), hypot(u2, y)
            out["s1"], out["s2"] = s1, s2
            if not (s1 > 0 and s2 > 0):
                return {n: Ball.of_arb(v) for n, v in out.items()}, out
            mech = self.mech
            p = mech.params(self.robot, arb)
            leg1, leg2 = mech.legs(p, x, xd, xdd, y, yd, ydd, hypot)
            d = mech.dynamics(leg1, leg2, p)
            delta = mech.delta(p, y, leg1, leg2)
            out["delta"] = delta
            out["delta_dot"] = mech.delta_rate(p, y, yd, leg1, leg2)
            out.update(
                theta1_dot=leg1.th_d,
                s1_dot=leg1.s_d,
                theta2_dot=leg2.th_d,
                s2_dot=leg2.s_d,
                theta1_ddot=leg1.th_dd,
                s1_ddot=leg1.s_dd,
                theta2_ddot=leg2.th_dd,
                s2_ddot=leg2.s_dd,
            )
            if not self.analysis.on_singular_line and (delta > 0 or delta < 0):
                lam1, lam2 = d.mu1 / delta, d.mu2 / delta
                T1, T2 = mech.efforts(d, lam1, lam2)
                out.update(lambda1=lam1, lambda2=lam2, T1=T1, T2=T2)
            balls = {n: Ball.of_arb(v) for n, v in out.items()}
            ta = np.array([t])
            for leg, u in ((1, x), (2, u2)):
                raw = arb.atan2(y, u)  # y is exact: its sign is known (y = 0: π behind)
                b = self._on_branch(leg, ta, Ball.of_arb(raw)[None])
                balls[f"theta{leg}"] = Ball(b.mid[0], b.rad[0])
            return balls, out
        finally:
            ctx.prec = old


def _beyond_double(a: arb) -> bool:
    """True when the arb ball is certified to the mixed tolerance and every member
    exceeds the largest double in magnitude."""
    return bool(a.is_finite() and a.rad() <= TOL * abs(a.mid()) and abs(a).lower() > DBL_MAX)

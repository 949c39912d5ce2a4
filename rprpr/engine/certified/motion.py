"""Certified values of the motion, joints, δ, λ and torques at given times.

Every value returned for a time t (a float, taken as its exact binary value) is within a
proven bound of the true value of the paper's formulas at t: the mixed error
|value - true| <= TOL (1 + |value|), TOL = 1e-9; or it is NaN with a reason code.

How (all choices depend on t alone, never on the other times asked for):

1. **A vectorised ball pass** (``balls.Ball``, rigorous under round-to-nearest): x, x', x''
   by Horner from the exact coefficients rounded to balls; y(t) likewise, recentred on
   the middle of the span, when the task gives no path; else y = p(x) with the path
   recentred, y = q(x - c) where q(w) = p(c + w) is formed exactly in Q and c is a short
   dyadic number in the middle of the x range (this keeps Horner well conditioned); near
   each exact root t_s of y (Type II instants, E at A or B), y and x also from their exact
   Taylor polynomials about t_s in ε = t - t_s, with ε taken from a double-double t_s
   plus a proven residual, and the tighter of the two balls kept. Then the paper's formulas
   (``equations.leg``/``dynamics``/``torques``) run unchanged on balls, with δ in its
   product form δ = -a1 y/(s1 s2) (eq. 29), δ' = -a1/(s1 s2) (y' - y (s1'/s1 + s2'/s2)),
   λ = μ/δ (eqs. 30-31).
2. **θ** from ``numpy.arctan2`` with an allowance of 8 ulp for the C library (glibc's
   documented maximum error of atan2 is 1 ulp; numpy's vectorised loops stay within 4),
   plus the propagated input error: every point of the box mid ± rad lies in the disc of
   radius ρ = r_u + r_v about (u, v), whose angle differs by at most arcsin(ρ/|M|) <=
   (π/2) ρ/max(|u|, |v|). Where the ball of y contains 0 behind the base joint, the sign
   of y(t) is decided exactly in Q, so the branch is never guessed. θ is continuous: the
   principal value is shifted by 2π after each exact instant at which the leg's line
   crosses its cut (y = 0 behind A for leg 1, behind B for leg 2); exactly at such an
   instant θ takes its limit from the left (``sampling._continuous_angle``'s semantics,
   decided exactly instead of by a width).
3. **Near a singular instant**, where λ = μ/δ fails the acceptance, λ is taken from the
   instant's zone form (``zones.Zone``: the Taylor coefficients of μ and δ at t_s with the
   exactly vanishing ones dropped, and a proven remainder), which cancels nothing.
4. **Refinement**: a sample whose ball fails the acceptance (rad <= TOL (1 + |mid|)) is
   evaluated again alone in flint's arb at the exact t, with x(t), y(t) and their
   derivatives exact in Q, at 128 bits doubled up to 4096 until every value passes.
5. **Exactly at a singular instant** (t == t_s, only possible for a dyadic t_s): δ = 0;
   bounded: λ and T are the exact limits from the exact series (``singular``); a pole:
   λ2, T1, T2 NaN (reason POLE; λ1 = μ1/δ is always bounded, μ1 = O(ε^m)). E exactly at
   A or B: the leg's angle, rates, δ, λ and T NaN (reasons AT_A, AT_B). An irrational or
   non-dyadic t_s is never a float, so every float time gets finite certified values.
"""

from __future__ import annotations

import math
from collections.abc import Hashable
from functools import cached_property
from typing import Any

import numpy as np
from flint import arb, arb_poly, ctx, fmpq, fmpq_poly

from ...model.dataclass import dataclass
from ...model.numbers import to_float
from ...model.task import Robot
from ..exact import equations as dyn
from ..exact.kept import Kept, exact_key, robot_key
from ..exact.mechanism import of
from ..exact.series import taylor
from ..exact.singular import SingularAnalysis, SingularInstant
from ..exact.trajectory import Trajectory
from .balls import Ball, horner, hypot, poly_balls, polyval, quiet
from .kernel import INDEX, KERNEL
from .pointwise import (
    AT_A,
    AT_B,
    BEYOND_DOUBLE,
    DBL_MAX,
    DYNAMIC,
    FIELDS,
    LEG1,
    LEG2,
    MAX_PREC,
    OK,
    ON_LINE,
    POLE,
    REASONS,
    START_PREC,
    TOL,
    UNCERTIFIED,
    AtInstants,
    Cut,
    Refinement,
    Values,
)
from .shared import freeze, per_robot
from .zones import TAYLOR_PREC, ExactTime, Zone, make_zone, taylor_at_instant

# what ``formulas`` computes (the rest of its values are its arguments), in its order
COMPUTED = (
    "s1", "s2", "theta1_dot", "s1_dot", "theta2_dot", "s2_dot", "theta1_ddot", "s1_ddot",
    "theta2_ddot", "s2_ddot", "delta", "delta_dot", "lambda1", "lambda2", "T1", "T2",
)  # fmt: skip
PARAMS = ("a1", "g", "m2", "I2", "r2", "m3", "I3", "r3", "m4", "I4", "r4", "m5", "I5", "r5")


@dataclass(frozen=True)
class CertifiedSamples:
    """Certified values at the times ``t``: ``value[name]`` (floats, NaN where undefined
    or not certified, ±inf where the true value is proven beyond the double range),
    ``radius[name]`` (proven error bounds, <= TOL (1 + |value|); inf beside ±inf) and
    ``reason`` (one code per sample, ``REASONS``; 0 when every value is finite)."""

    t: np.ndarray
    value: dict[str, np.ndarray]
    radius: dict[str, np.ndarray]
    reason: np.ndarray

    def column(self, name: str) -> np.ndarray:
        return self.t if name == "t" else self.value[name]


# -- exact instants -------------------------------------------------------------------


def _instant_time(analysis: SingularAnalysis, s: SingularInstant) -> ExactTime:
    field = analysis.hints(s).field

    def at(prec: int) -> arb:
        return field.evaluate(fmpq_poly([0, 1]), prec)

    return ExactTime(s.t_rational, at)


@dataclass
class _Kinematic:
    time: ExactTime
    leg: int
    order: int
    y_sign: int


# -- polynomials in balls ---------------------------------------------------------------


def _poly3(p: fmpq_poly) -> tuple[list[Ball], list[Ball], list[Ball]]:
    d = p.derivative()
    return poly_balls(p), poly_balls(d), poly_balls(d.derivative())


def _tighter(a: Ball, b: Ball) -> Ball:
    """Of two enclosures of the same values, the narrower one elementwise."""
    pick = ~(b.rad < a.rad)
    return Ball(np.where(pick, a.mid, b.mid), np.where(pick, a.rad, b.rad))


def dyadic_middle(lo: float, hi: float) -> fmpq:
    """A short dyadic number near (lo + hi)/2 (12 significant bits)."""
    m = 0.5 * (lo + hi)
    if m == 0 or not math.isfinite(m):
        return fmpq(0)
    e = math.frexp(m)[1] - 12
    return fmpq(round(m / 2.0**e)) * fmpq(2) ** e if e >= 0 else fmpq(round(m * 2.0**-e), 2**-e)


@dataclass
class _Local:
    """Exact Taylor polynomials about an exact root t_s of y (in ε/h, h a power of 2)."""

    time: ExactTime
    he: int  # h = 2^he
    x: tuple[list[Ball], list[Ball], list[Ball]]
    y: tuple[list[Ball], list[Ball], list[Ball]]


# -- what one robot shares (``shared.per_robot``) ------------------------------------


def _ball_params(robot: Robot) -> dyn.Params:
    return of(robot).params(robot, Ball.of_rational)


# -- the motion ---------------------------------------------------------------------


class CertifiedMotion(AtInstants, Refinement):
    """Certified evaluation of one task's motion (``sample``); built once per task."""

    def __init__(self, traj: Trajectory, robot: Robot, analysis: SingularAnalysis) -> None:
        self.traj = traj
        self.robot = robot
        self.mech = of(robot)  # the robot's formulas (``mechanism``)
        self.analysis = analysis
        self.instants = [(s, _instant_time(analysis, s)) for s in analysis.instants]
        self.kinematic = self._kinematic()
        self._limits: dict[int, tuple[Ball, Ball, Ball, Ball]] = {}
        self._zones: dict[int, Zone | None] = {}

    # -- set-up (each part made when first read: a motion whose torques are unbounded
    # needs few of them) ------------------------------------------------------------------
    @cached_property
    def params(self) -> dyn.Params:
        return per_robot(self.robot, _ball_params)

    @cached_property
    def a1(self) -> Ball:
        return Ball.of_rational(self.traj.a1)

    @cached_property
    def x3(self) -> tuple[list[Ball], list[Ball], list[Ball]]:
        return _poly3(self.traj.x)

    @cached_property
    def center(self) -> fmpq:
        return self._center()

    @cached_property
    def t_center(self) -> fmpq:
        return dyadic_middle(0.0, to_float(self.traj.duration))

    @cached_property
    def recentred(self) -> fmpq_poly:
        """y = p(x) through the path recentred on x's range, p(c + w) exactly; without a
        path, y(t) itself recentred on the middle of the span, y(t) = r(t - c_t)."""
        if self.traj.path is not None:
            return self.traj.path(fmpq_poly([self.center, 1]))
        return self.traj.y(fmpq_poly([self.t_center, 1]))

    @cached_property
    def q3(self) -> tuple[list[Ball], list[Ball], list[Ball]] | None:
        return _poly3(self.recentred) if self.traj.path is not None else None

    @cached_property
    def y3(self) -> tuple[list[Ball], list[Ball], list[Ball]] | None:
        return _poly3(self.recentred) if self.traj.path is None else None

    @cached_property
    def locals(self) -> list[_Local]:
        """The Taylor polynomials about each exact root of y (made when first sampled)."""
        return [self._local(e) for _, e in self.instants] + [
            self._local(k.time) for k in self.kinematic
        ]

    def _center(self) -> fmpq:
        tf = to_float(self.traj.duration)
        ts = np.linspace(0.0, tf, 65)
        with quiet():  # coefficients beyond the double range: inf, and inf * 0 = NaN
            xs = polyval(ts, [to_float(c) for c in self.traj.x.coeffs()])
        xs = xs[np.isfinite(xs)]
        return dyadic_middle(float(xs.min()), float(xs.max())) if len(xs) else fmpq(0)

    def _kinematic(self) -> list[_Kinematic]:
        traj = self.traj
        out = []
        for leg, u in ((1, traj.x), (2, traj.x - traj.a1)):
            common = u if traj.y.is_zero() else u.gcd(traj.y)
            for e in ExactTime.roots(common, traj.duration):
                match = [k for k in self.analysis.kinematic if k.leg == leg]
                near = min(match, key=lambda k: abs(k.t - e.hi), default=None)
                order, ys = (near.order, self.analysis.kinematic_sign(near)) if near else (1, 1)
                out.append(_Kinematic(e, leg, order, ys))
        return out

    def _local(self, e: ExactTime) -> _Local:
        tf = to_float(self.traj.duration)
        he = math.frexp(tf)[1] if tf > 0 else 0
        out = []
        for p in (self.traj.x, self.traj.y):
            cs = taylor(p, max(p.degree(), 0) + 1)
            scale = [fmpq(2) ** (he * k) for k in range(len(cs))]  # h^k, exactly
            if e.exact is not None:
                coeffs = [Ball.of_rational(c(e.exact) * scale[k]) for k, c in enumerate(cs)]
            else:
                coeffs = [_arb_at(c, e, 256, scale[k]) for k, c in enumerate(cs)]
            with quiet():  # beyond the double range: unbounded balls
                d1 = [coeffs[k] * k for k in range(1, len(coeffs))] or [Ball.exact(0.0)]
                d2 = [d1[k] * k for k in range(1, len(d1))] or [Ball.exact(0.0)]
            out.append((coeffs, d1, d2))
        return _Local(e, he, out[0], out[1])

    @cached_property
    def cuts(self) -> dict[int, list[Cut]]:
        return {1: self._cuts(1), 2: self._cuts(2)}

    def _cuts(self, leg: int) -> list[Cut]:
        on_cut = (2,) if leg == 1 else (2, 3)
        cuts = [
            Cut(e, self.analysis.hints(s).y_leading_sign, s.order % 2 == 1)
            for s, e in self.instants
            if s.case.number in on_cut
        ]
        if leg == 2 and not self.traj.y.is_zero():  # on y = 0, E passing A stays on the cut
            cuts += [Cut(k.time, k.y_sign, k.order % 2 == 1) for k in self.kinematic if k.leg == 1]
        return sorted(cuts, key=lambda c: c.time.hi)

    # -- sampling --------------------------------------------------------------------
    def sample(self, t: np.ndarray, refine: bool = True) -> CertifiedSamples:
        """Certified values at the float times ``t`` [s] (module docstring); without
        ``refine``, values the ball pass and the zone forms do not certify are left NaN
        (reason UNCERTIFIED) instead of being refined in arb."""
        t = np.asarray(t, dtype=float)
        with quiet():
            balls = self.ball_pass(t)
        value = {n: np.array(b.mid + 0 * t, dtype=float) for n, b in balls.items()}
        radius = {n: np.array(b.rad + 0 * t, dtype=float) for n, b in balls.items()}
        reason = np.zeros(len(t), dtype=np.int8)
        undefined = {name: np.zeros(len(t), dtype=bool) for name in FIELDS}
        if self.analysis.on_singular_line:
            reason[:] = ON_LINE
            for name in ("lambda1", "lambda2", "T1", "T2"):
                undefined[name][:] = True
        for s, e in self.instants:
            for j in np.nonzero(e.compare(t) == 0)[0]:
                self._at_instant(s, int(j), value, radius, reason, undefined)
        for k in self.kinematic:
            for j in np.nonzero(k.time.compare(t) == 0)[0]:
                reason[j] = AT_A if k.leg == 1 else AT_B
                for name in (LEG1 if k.leg == 1 else LEG2) + DYNAMIC:
                    undefined[name][j] = True
        bad = self._failing(value, radius, undefined)
        if bad.any() and self.instants and not self.analysis.on_singular_line:
            with quiet():
                self._from_zones(t, bad & (reason == OK), value, radius)
            bad = self._failing(value, radius, undefined)
        for j in np.nonzero(bad)[0]:
            if refine:
                self._refine(float(t[j]), int(j), value, radius, undefined, reason)
                continue
            reason[j] = UNCERTIFIED  # defined values left NaN: said before the others
            for n in FIELDS:
                if not radius[n][j] <= TOL * (1.0 + abs(value[n][j])):
                    undefined[n][j] = True
        for n in FIELDS:
            value[n][undefined[n]] = np.nan
            radius[n][undefined[n]] = np.nan
        return CertifiedSamples(t, value, radius, reason)

    @staticmethod
    def _failing(
        value: dict[str, np.ndarray],
        radius: dict[str, np.ndarray],
        undefined: dict[str, np.ndarray],
    ) -> np.ndarray:
        """Samples with a defined value not yet certified."""
        bad = np.zeros(len(next(iter(value.values()))), dtype=bool)
        for n in FIELDS:
            ok = radius[n] <= TOL * (1.0 + np.abs(value[n]))
            bad |= ~ok & ~undefined[n]
        return bad

    def zone(self, k: int) -> Zone | None:
        """The zone form of λ about the k-th singular instant (``zones.make_zone``); about
        a rational instant, made once for every motion with the same exact data
        (``_zone_key``)."""
        if k not in self._zones:
            self._zones[k] = _kept_zone(self, self.instants[k][0])
        return self._zones[k]

    def _from_zones(
        self, t: np.ndarray, todo: np.ndarray, value: dict[str, np.ndarray],
        radius: dict[str, np.ndarray],
    ) -> None:  # fmt: skip
        """λ and T at samples near a singular instant from its zone form (no cancellation
        left), where that is narrower than the direct quotient."""
        times = np.array([e.hi for _, e in self.instants])
        near = np.argmin(np.abs(t[:, None] - times[None, :]), axis=1)
        for k in np.unique(near[todo]):
            idx = np.nonzero(todo & (near == k))[0]
            zone = self.zone(int(k))
            if zone is None:
                continue
            idx = idx[np.abs(t[idx] - zone.e.hi) <= 0.999 * zone.r]
            if not len(idx):
                continue
            lam = zone.lam(zone.e.eps(t[idx]))
            b = {
                n: Ball(value[n][idx], radius[n][idx])
                for n in ("x", "x_dot", "x_ddot", "y", "y_dot", "y_ddot")
            }
            p, mech = self.params, self.mech
            kin = (b["x"], b["x_dot"], b["x_ddot"], b["y"], b["y_dot"], b["y_ddot"])
            leg1, leg2 = mech.legs(p, *kin, hypot)
            T1, T2 = mech.efforts(mech.dynamics(leg1, leg2, p), lam[0], lam[1])
            for name, new in (("lambda1", lam[0]), ("lambda2", lam[1]), ("T1", T1), ("T2", T2)):
                better = new.rad < radius[name][idx]
                value[name][idx[better]] = new.mid[better]
                radius[name][idx[better]] = new.rad[better]

    def ball_pass(self, t: np.ndarray) -> Values:
        """Every quantity at the times ``t`` as balls (no refinement; call within
        ``balls.quiet()``). ``t`` may also be a ``Ball`` (intervals of time)."""
        tb = t if isinstance(t, Ball) else Ball.exact(t)
        x, xd, xdd, y, yd, ydd = self._end_point(tb)
        if isinstance(t, Ball):
            return self.formulas(x, xd, xdd, y, yd, ydd)  # over intervals: no angles
        x, xd, xdd, y, yd, ydd = self._locally(t, x, xd, xdd, y, yd, ydd)
        out = self.formulas(x, xd, xdd, y, yd, ydd)
        out["theta1"] = self.theta(1, t, x, y)
        out["theta2"] = self.theta(2, t, x - self.a1, y)
        return out

    def end_point(self, t: np.ndarray | Ball) -> tuple[Ball, ...]:
        """x, ẋ, ẍ, y, ẏ, ÿ at the float times ``t`` (or over the intervals of the ``Ball``
        ``t``) as balls (within ``balls.quiet()``), as ``ball_pass`` has them."""
        if isinstance(t, Ball):
            return self._end_point(t)
        return self._locally(t, *self._end_point(Ball.exact(t)))

    def _end_point(self, tb: Ball) -> tuple[Ball, ...]:
        xc, xdc, xddc = self.x3
        x = horner(xc, tb)
        xd = horner(xdc, tb)
        xdd = horner(xddc, tb)
        if self.y3 is None:
            assert self.q3 is not None
            w = x - self.center
            qc, q1c, q2c = self.q3
            q1 = horner(q1c, w)
            y = horner(qc, w)
            yd = q1 * xd
            ydd = horner(q2c, w) * xd * xd + q1 * xdd
        else:
            wt = tb - self.t_center
            y, yd, ydd = (horner(c, wt) for c in self.y3)
        return x, xd, xdd, y, yd, ydd

    def _locally(self, t: np.ndarray, *v: Ball) -> tuple[Ball, ...]:
        """x and y (with derivatives) from the Taylor polynomials about the nearest exact
        root of y, where that is tighter."""
        if not self.locals:
            return v
        roots = np.array([loc.time.hi for loc in self.locals])
        near = np.argmin(np.abs(t[:, None] - roots[None, :]), axis=1)
        out = [Ball(b.mid + 0 * t, b.rad + 0 * t) for b in v]  # full-length copies
        for i, loc in enumerate(self.locals):
            idx = np.nonzero(near == i)[0]
            if not len(idx):
                continue
            inv = np.ldexp(1.0, -loc.he)  # 1/h, exact (or inf: unbounded balls)
            r = loc.time.eps(t[idx]) * inv  # exact scaling by a power of 2
            for slot, (c, c1, c2) in ((0, loc.x), (3, loc.y)):
                vals = (horner(c, r), horner(c1, r) * inv, horner(c2, r) * inv * inv)
                for k in range(3):
                    cur = out[slot + k]
                    best = _tighter(cur[idx], vals[k])
                    cur.mid[idx] = best.mid
                    cur.rad[idx] = best.rad
        return tuple(out)

    def formulas(self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any) -> Values:
        """The paper's formulas on balls (all but θ, ``theta``): for the RPRPR, in one call
        of the compiled kernel where it is built (the same doubles, ``kernel.py``)."""
        got = _compiled_formulas(self, (x, xd, xdd, y, yd, ydd))
        if got is not None:
            return got
        return self._formulas(x, xd, xdd, y, yd, ydd)

    def _formulas(self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any) -> Values:
        """``formulas`` by numpy's ball operations (the description the kernel is made from)."""
        p, mech = self.params, self.mech
        leg1, leg2 = mech.legs(p, x, xd, xdd, y, yd, ydd, hypot)
        d = mech.dynamics(leg1, leg2, p)
        delta = mech.delta(p, y, leg1, leg2)  # product form (eq. 29 for the RPRPR)
        delta_dot = mech.delta_rate(p, y, yd, leg1, leg2)
        lam1 = d.mu1 / delta
        lam2 = d.mu2 / delta
        T1, T2 = mech.efforts(d, lam1, lam2)
        out = {
            "x": x, "y": y, "x_dot": xd, "y_dot": yd, "x_ddot": xdd, "y_ddot": ydd,
            "s1": leg1.s, "s2": leg2.s,
            "theta1_dot": leg1.th_d, "s1_dot": leg1.s_d, "theta2_dot": leg2.th_d,
            "s2_dot": leg2.s_d, "theta1_ddot": leg1.th_dd, "s1_ddot": leg1.s_dd,
            "theta2_ddot": leg2.th_dd, "s2_ddot": leg2.s_dd,
            "delta": delta, "delta_dot": delta_dot, "lambda1": lam1, "lambda2": lam2,
            "T1": T1, "T2": T2,
        }  # fmt: skip
        return out


_TRACED = {type(m) for m in dyn.MECHANISMS.values()}  # the schemes kernel_gen traces


def _compiled_formulas(motion: CertifiedMotion, kin: tuple[Any, ...]) -> Values | None:
    """``formulas`` in one call of the compiled kernel, or None where it does not apply (a
    mechanism other than the RPRPR's two schemes, arguments not balls, x not a vector, a
    shape the kernel does not take)."""
    spec = INDEX.get(f"formulas_{motion.mech.name}")
    x = kin[0]
    if (
        spec is None
        or type(motion.mech) not in _TRACED
        or not all(type(b) is Ball for b in kin)
        or x.mid.ndim != 1
    ):
        return None
    p = motion.params
    consts = tuple(a for f in PARAMS for b in (getattr(p, f),) for a in (b.mid, b.rad))
    n = x.mid.shape[0]
    out = np.empty((spec[1], n))
    if not KERNEL.run(spec[0], consts + tuple(a for b in kin for a in (b.mid, b.rad)), out, n):
        return None
    x, xd, xdd, y, yd, ydd = kin
    names = ("x", "y", "x_dot", "y_dot", "x_ddot", "y_ddot")
    got: Values = dict(zip(names, (x, y, xd, yd, xdd, ydd), strict=True))
    for i, name in enumerate(COMPUTED):
        got[name] = Ball._of(out[2 * i], out[2 * i + 1])
    return got


def _arb_at(c: fmpq_poly, e: ExactTime, prec: int, scale: fmpq) -> Ball:
    """c(t_s) · scale for the exact time e (scale exact), in arb."""
    old = ctx.prec
    ctx.prec = prec
    try:
        if c.degree() <= 0:
            return Ball.of_rational((c[0] if c.degree() == 0 else fmpq(0)) * scale)
        return Ball.of_arb(arb_poly(c.coeffs())(e.at(prec)) * arb(scale))
    finally:
        ctx.prec = old


__all__ = [  # what a certified value is (``pointwise``) stays importable from here
    "AT_A", "AT_B", "BEYOND_DOUBLE", "DBL_MAX", "FIELDS", "MAX_PREC", "OK", "ON_LINE", "POLE",
    "REASONS", "START_PREC", "TOL", "UNCERTIFIED", "CertifiedMotion", "CertifiedSamples",
]  # fmt: skip


# the zones about rational instants, by the exact data they are made from (``_zone_key``)
ZONES_KEPT = 64
_ZONES: Kept[Zone | None] = Kept(ZONES_KEPT)


def _kept_zone(motion: CertifiedMotion, s: SingularInstant) -> Zone | None:
    """``CertifiedMotion.zone`` about ``s``: about a rational instant the one kept for its
    exact data (frozen: read by every motion with those data), else made."""

    def made() -> Zone | None:
        return make_zone(motion, s, taylor_at_instant(motion, s, TAYLOR_PREC))

    def frozen() -> Zone | None:
        zone = made()
        if zone is not None:
            zone.stack()  # made now, frozen with the rest
        freeze(zone)
        return zone

    key = _zone_key(motion, s)
    return made() if key is None else _ZONES.get(key, frozen)


def _zone_key(motion: CertifiedMotion, s: SingularInstant) -> Hashable | None:
    """What ``zones.make_zone`` reads about the rational instant ``s`` of ``motion``, as
    exact values (``exact.kept``): the whole trajectory (x(t), y(t), the path or none, a1,
    t_f, the local origin and lead: how the end point is evaluated and which instants the
    motion keeps), the robot, the instants the motion keeps (rational times and orders),
    t_s, its order and the orders of μ there, and flint's working precision (the Taylor
    coefficients at t_s are rounded at it); None for an irrational t_s (its zone stays
    the motion's own)."""
    t = s.t_rational
    if t is None:
        return None
    kept = [(i.t_rational, i.order) for i in motion.analysis.instants]
    return (
        exact_key(motion.traj), robot_key(motion.robot), exact_key(kept), t.p, t.q, s.order,
        motion.analysis.hints(s).mu_valuations, ctx.prec,
    )  # fmt: skip

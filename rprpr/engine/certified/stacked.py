"""The two efforts stacked in rows 0 and 1, on balls or jets: what the bounds layer
(envelope, batch, the forms near instants) evaluates over boxes.

``stacked_form(robot)`` gives the form for the robot's mechanism: ``Stacked``, the RPRPR's
own (both legs in one run of ball operations, both actuation schemes), or, for any other
implementation of the mechanism interface (``engine/exact/mechanism.py``), ``Through`` its
``legs``, ``delta``, ``dynamics`` and ``efforts`` on the same balls or jets: slower, never
looser in what it proves. A mechanism with a stacked form of its own registers it in
``FORMS``."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from flint import fmpq

from ...model.task import Robot
from ..exact import equations as dyn
from ..exact.mechanism import of
from .balls import Ball, hypot, rational_parts, stack
from .jets import Jet
from .kernel import INDEX, KERNEL

_LEG_FIELDS = ("s", "cos", "sin", "s_d", "th_d", "s_dd", "th_dd")


def _pair(a: Any, b: Any) -> Ball:
    """The exact rationals a (leg 1, row 0) and b (leg 2, row 1) as a (2, 1) ball column:
    ``Ball.of_rational`` of each (the same doubles), stacked."""
    (pm, pr), (qm, qr) = (rational_parts(v if type(v) is fmpq else fmpq(v)) for v in (a, b))
    return Ball._of(np.array([[pm], [qm]]), np.array([[pr], [qr]]))


class Stacked:
    """T1, T2 (and δ) with the two legs stacked in rows 0 and 1, on balls or jets.

    The same equations as ``equations.leg``/``dynamics``/``torques`` (eqs. 7-14, 28-33),
    written once for both legs so that each operation runs on both at once (the cost of a
    ball operation on short vectors is its call, not its length: through ``equations``
    one pass takes 1.3-1.65 times as long; tests/engine/certified/test_stacked.py holds the two
    together), with the constant parts of eqs. (7), (9), (11), (13) summed exactly in Q:
        M_i = K_i + m_i d_i²,  d_i = s_i - r_i,  K = m2 r2² + I2 + I3 (leg 2: m4, r4, I4, I5),
        N_i = 2 m_i s_i' θ_i' d_i + (G_i + m_i g s_i) cos θ_i,  G = (m2 r2 - m3 r3) g,
        F_i = m_i (s_i'' - d_i θ_i'²) + m_i g sin θ_i   (M22 s1'' + N2, M44 s2'' + N4),
        μ1 = -(sin θ2 F1 + sin θ1 F2),  μ2 = cos θ2 F1 + cos θ1 F2,  δ = -a1 y/(s1 s2),
        T_i = M_i θ_i'' + N_i ± s_i (sin θ_i λ1 - cos θ_i λ2)   (+ for T1, - for T2),
    with m_i = m3, m5 and r_i = r3, r5. Under the prismatic scheme (``equations``), with
    V_i = (M_i θ_i'' + N_i)/s_i:
        μ1 = -(cos θ2 V1 + cos θ1 V2),  μ2 = -(sin θ1 V2 + sin θ2 V1),
        F_i ∓ (cos θ_i λ1 + sin θ_i λ2)   (- for F1, + for F2) are the efforts."""

    def __init__(self, r: Robot) -> None:
        L, g = r.links, r.gravity
        self.base = _pair(0, r.a1)  # u = x - base: (x, x - a1)
        self.a1 = Ball.of_rational(r.a1)
        self.m = _pair(L[3].mass, L[5].mass)
        self.r = _pair(L[3].r, L[5].r)
        self.K = _pair(
            L[2].mass * L[2].r ** 2 + L[2].inertia + L[3].inertia,
            L[4].mass * L[4].r ** 2 + L[4].inertia + L[5].inertia,
        )
        self.G = _pair((L[2].mass * L[2].r - L[3].mass * L[3].r) * g,
                       (L[4].mass * L[4].r - L[5].mass * L[5].r) * g)  # fmt: skip
        self.mg = _pair(L[3].mass * g, L[5].mass * g)
        self.sign = Ball.exact(np.array([[1.0], [-1.0]]))
        self.prismatic = isinstance(of(r), dyn.Prismatic)  # the RPRPR's two schemes
        self._consts = tuple(
            a
            for b in (self.base, self.a1, self.m, self.r, self.K, self.G, self.mg)
            for a in (b.mid, b.rad)
        )  # the compiled kernel's first inputs (``kernel_gen``)
        scheme = "prismatic" if self.prismatic else "revolute"
        self._kernels = {
            name: (INDEX.get(f"{name}_ball_{scheme}"), INDEX.get(f"{name}_jet_{scheme}"))
            for name in ("torques", "torques_at", "efforts", "efforts_at")
        }  # the compiled kernels of the scheme (``kernel_gen``): (on balls, on jets)

    def legs(self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any) -> dyn.Leg:
        """Both legs' joint values (rows 0 and 1), eqs. 41-42 (in one call of the compiled
        kernel where it is built: the same doubles, ``kernel.py``)."""
        if KERNEL is not None:
            args = (x, xd, xdd, y, yd, ydd)
            kernels = (INDEX.get("legs_ball"), INDEX.get("legs_jet"))
            got = _compiled(self._consts, args, args[0], 1, (2,) * 7, *kernels)
            if got is not None:
                return dyn.Leg(*got)
        return self._legs(x, xd, xdd, y, yd, ydd)

    def efforts(self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any) -> Any:
        """T (stacked rows) from x, ẋ, ẍ, y, ẏ, ÿ: ``torques(legs(...), y)``'s T, in one
        call of the compiled kernel where it is built (the same doubles: the legs and the
        torques traced as one run of ball operations, ``kernel_gen``)."""
        if KERNEL is not None:
            args = (x, xd, xdd, y, yd, ydd)
            got = _compiled(self._consts, args, args[0], 1, (2,), *self._kernels["efforts"])
            if got is not None:
                return got[0]
        return self.torques(self.legs(x, xd, xdd, y, yd, ydd), y)[0]

    def efforts_at(
        self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any, lam: tuple[Any, Any]
    ) -> Any:
        """T (stacked rows) from x, ẋ, ẍ, y, ẏ, ÿ at λ given (λ1, λ2: balls, or jets, of one
        row): ``torques(legs(...), y, lam)``'s T, in one call of the compiled kernel where
        it is built (the same doubles, ``kernel_gen``)."""
        if KERNEL is not None:
            args = (x, xd, xdd, y, yd, ydd, *lam)
            got = _compiled(self._consts, args, args[0], 1, (2,), *self._kernels["efforts_at"])
            if got is not None:
                return got[0]
        return self.torques(self.legs(x, xd, xdd, y, yd, ydd), y, lam)[0]

    def _legs(self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any) -> dyn.Leg:
        """``legs`` by numpy's ball operations (the description the kernel is made from)."""
        return dyn.leg(x - self.base, xd, xdd, y, yd, ydd, hypot)

    def delta(self, lg: dyn.Leg, y: Any) -> Any:
        """δ = -a1 y/(s1 s2) (eq. 29), from the stacked legs."""
        return -(self.a1 * y) / (lg.s[0] * lg.s[1])

    def torques(
        self, lg: dyn.Leg, y: Any, lam: tuple[Any, Any] | None = None, delta: Any = None
    ) -> tuple[Any, Any]:
        """(T stacked, δ) from the legs; λ given, or μ/δ (δ given, or eq. 29). Without λ
        and δ, in one call of the compiled kernel where it is built (the same doubles)."""
        if KERNEL is not None and lam is None:
            args = (*(getattr(lg, f) for f in _LEG_FIELDS), y)
            if delta is None:
                got = _compiled(self._consts, args, lg.s, 2, (2, 1), *self._kernels["torques"])
                if got is not None:
                    return got[0], got[1]
            else:
                k = self._kernels["torques_at"]
                got = _compiled(self._consts, (*args, delta), lg.s, 2, (2,), *k)
                if got is not None:
                    return got[0], delta
        return self._torques(lg, y, lam, delta)

    def _torques(
        self, lg: dyn.Leg, y: Any, lam: tuple[Any, Any] | None = None, delta: Any = None
    ) -> tuple[Any, Any]:
        """``torques`` by numpy's ball operations (the description the kernel is made from)."""
        d = lg.s - self.r
        M = self.K + self.m * (d * d)
        N = (self.m * 2) * (lg.s_d * lg.th_d * d) + (self.G + self.mg * lg.s) * lg.cos
        F = self.m * (lg.s_dd - d * (lg.th_d * lg.th_d)) + self.mg * lg.sin
        if delta is None:
            delta = self.delta(lg, y)
        if self.prismatic:
            U = M * lg.th_dd + N
            if lam is None:
                V = U / lg.s
                cV, sV = lg.cos * V[::-1], lg.sin * V[::-1]
                lam = (-(cV[0] + cV[1]) / delta, -(sV[0] + sV[1]) / delta)
            return F - self.sign * (lg.cos * lam[0] + lg.sin * lam[1]), delta
        if lam is None:
            sF, cF = lg.sin * F[::-1], lg.cos * F[::-1]
            lam = (-(sF[0] + sF[1]) / delta, (cF[0] + cF[1]) / delta)
        T = M * lg.th_dd + N + self.sign * (lg.s * (lg.sin * lam[0] - lg.cos * lam[1]))
        return T, delta


def _compiled(
    consts: tuple[Any, ...], args: tuple[Any, ...], anchor: Any, rows: int,
    layout: tuple[int, ...], ball: tuple[int, int] | None, jet: tuple[int, int] | None,
) -> list[Any] | None:  # fmt: skip
    """A kernel's outputs, balls or jets of balls, of as many rows as ``layout`` says (a
    legs kernel: the seven fields of ``Leg``, 2 rows each; a torques kernel: T, 2 rows,
    and δ, 1 row, unless δ was given), or None where it does not apply: the arguments not
    all balls or all jets, ``anchor`` (the argument every output depends on) not a vector
    (``rows`` 1) or two rows of vectors (2), or a shape the kernel does not take; numpy's
    path then runs."""
    kind = type(anchor)
    if kind is Jet:
        spec, anchor = jet, anchor.v.mid
        if not all(type(a) is Jet for a in args):
            return None
        flat = tuple(p for a in args for b in (a.v, a.d) for p in (b.mid, b.rad))
    elif kind is Ball:
        spec, anchor = ball, anchor.mid
        if not all(type(a) is Ball for a in args):
            return None
        flat = tuple(p for a in args for p in (a.mid, a.rad))
    else:
        return None
    if spec is None or anchor.ndim != rows or (rows == 2 and anchor.shape[0] != 2):
        return None
    n = anchor.shape[-1]
    out = np.empty((spec[1], n))
    if not KERNEL.run(spec[0], consts + flat, out, n):
        return None
    per = 2 if kind is Jet else 1  # balls per output: a jet's value and derivative
    balls, i = [], 0
    for r in (r for r in layout for _ in range(per)):
        if r == 2:
            balls.append(Ball._of(out[i : i + 2], out[i + 2 : i + 4]))
        else:
            balls.append(Ball._of(out[i], out[i + 1]))
        i += 2 * r
    if kind is Jet:
        return [Jet(balls[k], balls[k + 1]) for k in range(0, len(balls), 2)]
    return balls


def _rows(a: Any, b: Any) -> Any:
    """Two balls (or jets of balls) of one shape as one with rows 0 and 1."""
    if isinstance(a, Jet) or isinstance(b, Jet):
        a, b = Jet._of(a), Jet._of(b)
        return Jet(stack([a.v, b.v]), stack([a.d, b.d]))
    return stack([Ball.coerce(a), Ball.coerce(b)])


class General:
    """The stacked form of any mechanism, through its interface (``mechanism.Mechanism``):
    the same operations as ``equations`` runs for it, on balls or jets, the two efforts
    stacked in rows 0 and 1 afterwards. ``legs`` gives the pair of legs."""

    def __init__(self, r: Robot) -> None:
        self.mech = of(r)
        self.p = self.mech.params(r, Ball.of_rational)

    def legs(self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any) -> Any:
        return self.mech.legs(self.p, x, xd, xdd, y, yd, ydd, hypot)

    def delta(self, lg: Any, y: Any) -> Any:
        l1, l2 = lg
        return self.mech.delta(self.p, y, l1, l2)

    def efforts(self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any) -> Any:
        """The efforts (stacked rows) from x, ẋ, ẍ, y, ẏ, ÿ."""
        return self.torques(self.legs(x, xd, xdd, y, yd, ydd), y)[0]

    def efforts_at(
        self, x: Any, xd: Any, xdd: Any, y: Any, yd: Any, ydd: Any, lam: tuple[Any, Any]
    ) -> Any:
        """The efforts (stacked rows) from x, ẋ, ẍ, y, ẏ, ÿ at λ given."""
        return self.torques(self.legs(x, xd, xdd, y, yd, ydd), y, lam)[0]

    def torques(
        self, lg: Any, y: Any, lam: tuple[Any, Any] | None = None, delta: Any = None
    ) -> tuple[Any, Any]:
        """(efforts stacked, δ) from the legs; λ given, or μ/δ (δ given, or the mechanism's)."""
        l1, l2 = lg
        d = self.mech.dynamics(l1, l2, self.p)
        if delta is None:
            delta = self.delta(lg, y)
        if lam is None:
            lam = (d.mu1 / delta, d.mu2 / delta)
        return _rows(*self.mech.efforts(d, *lam)), delta


FORMS: dict[type, Callable[[Robot], Stacked | General]] = {
    dyn.Rprpr: Stacked
}  # a mechanism's class -> its own stacked form


def stacked_form(r: Robot) -> Stacked | General:
    """The stacked form for the robot's mechanism: its own (``FORMS``), or ``General``."""
    for cls in type(of(r)).__mro__:
        if cls in FORMS:
            return FORMS[cls](r)
    return General(r)

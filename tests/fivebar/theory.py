"""The 5R's dynamics as derived in ``docs/five-bar.md``, the formulas under test.

Imports only the power series, the robot's data and the elbows from ``reference.py`` (the
geometry both share); the dynamics here are the derivation's: the Lagrange rows of the
four angles (θ1, φ1, θ2, φ2) with φ_i the absolute angle of distal link 3 or 4, the
multiplier λ (the force leg 2 applies on leg 1 at E) split along the distal link 3,
λ = (ν/δ) u1 + (h1/l3) u1⊥, and the torques T1 = Θ1 - C⊥·λ, T2 = Θ2 + (D - B)⊥·λ (Θ the
proximal rows, ``Leg.R``).

Everything is written without angles: cos(φ1 - θ1) = C·(E - C)/(l1 l3),
sin(φ1 - θ1) = C × (E - C)/(l1 l3), cos θ1 = C_x/l1, cos φ1 = (E - C)_x/l3 (leg 2 the same
with D - B and E - D), and the joint rates come from the end point's velocity:
θ1' = (E - C)·E'/(C × E), φ1' = -C·E'/(C × E).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import mpmath

from .reference import DPS, FiveBar, Jet, Motion, Vec, cross, dot, elbows


@dataclass(frozen=True)
class Leg:
    """One leg's derived quantities (series in t): proximal and distal rates and
    accelerations, the distal row h (the moment about the elbow of the distal link's
    inertia and weight), the proximal row R (without the multiplier)."""

    w: Any
    W: Any
    wd: Any
    Wd: Any
    h: Any
    R: Any


def leg(rb: FiveBar, i: int, base: Vec, elbow: Vec, E: Vec, v: Vec, acc: Vec) -> Leg:
    """Leg i (0: links 1 and 3 from A; 1: links 2 and 4 from B)."""
    lp, ld = rb.length[i], rb.length[i + 2]
    mp_, md = rb.mass[i], rb.mass[i + 2]
    Ip, Id = rb.inertia[i], rb.inertia[i + 2]
    rp, rd = rb.r[i], rb.r[i + 2]
    g = rb.g
    c = (elbow[0] - base[0], elbow[1] - base[1])  # proximal vector
    e = (E[0] - base[0], E[1] - base[1])
    u = (E[0] - elbow[0], E[1] - elbow[1])  # distal vector
    k = cross(c, e)
    w = dot(u, v) / k
    W = -dot(c, v) / k
    b = (acc[0] + w * w * c[0] + W * W * u[0], acc[1] + w * w * c[1] + W * W * u[1])
    wd = dot(u, b) / k
    Wd = -dot(c, b) / k
    cos_ = dot(c, u) / (lp * ld)
    sin_ = cross(c, u) / (lp * ld)
    h = (
        (Id + md * rd * rd) * Wd
        + md * lp * rd * (cos_ * wd + sin_ * w * w)
        + md * g * u[0] * (rd / ld)
    )
    R = (
        (Ip + mp_ * rp * rp + md * lp * lp) * wd
        + md * lp * rd * (cos_ * Wd - sin_ * W * W)
        + (mp_ * rp + md * lp) * g * c[0] / lp
    )
    return Leg(w, W, wd, Wd, h, R)


@dataclass(frozen=True)
class Derived:
    """The derivation's quantities along a motion, series in t about an instant."""

    rb: FiveBar
    C: Vec
    D: Vec
    E: Vec
    legs: tuple[Leg, Leg]
    delta: Any  # δ = (E - C) × (E - D) = l3 l4 sin(φ2 - φ1)
    cos: Any  # cos(φ2 - φ1) = (E - C)·(E - D)/(l3 l4)
    nu: Any  # ν = l4 cos(φ2 - φ1) h1 + l3 h2, the numerator of λ's axial part

    def w(self, sigma: int) -> Any:
        """The reciprocity residual h1/l3 + σ h2/l4 with σ frozen (±1)."""
        with mpmath.workdps(DPS):
            return self.legs[0].h / self.rb.length[2] + self.legs[1].h * sigma / self.rb.length[3]

    def torques(self) -> tuple[Any, Any]:
        """T1 = Θ1 - C⊥·λ, T2 = Θ2 + (D - B)⊥·λ, λ = (ν/δ) u1 + (h1/l3) u1⊥ (δ ≠ 0)."""
        with mpmath.workdps(DPS):
            return self._torques()

    def limit(self, k: int) -> tuple[Any, Any]:
        """The torques' limit at an instant where δ has a zero of order k and ν one of
        order ≥ k: λ's axial part ν/δ → ν^(k)/δ^(k) (l'Hôpital, as the paper's eqs. 37-38)."""
        with mpmath.workdps(DPS):
            return self._torques(self.nu.c[k] / self.delta.c[k])

    def _torques(self, alpha: Any = None) -> tuple[Any, Any]:
        l3 = self.rb.length[2]
        u = ((self.E[0] - self.C[0]) / l3, (self.E[1] - self.C[1]) / l3)
        if alpha is None:
            alpha = self.nu / self.delta
        beta = self.legs[0].h / l3
        lam = (alpha * u[0] - beta * u[1], alpha * u[1] + beta * u[0])
        C, D, a = self.C, self.D, self.rb.a
        T1 = self.legs[0].R - (C[0] * lam[1] - C[1] * lam[0])
        T2 = self.legs[1].R + ((D[0] - a) * lam[1] - D[1] * lam[0])
        return T1, T2


def derive(rb: FiveBar, motion: Motion, t0: Any, modes: tuple[int, int], n: int = 3) -> Derived:
    """The derived quantities as series of n - 2 terms about t0 (n terms of E)."""
    with mpmath.workdps(DPS):
        return _derive(rb, motion, t0, modes, n)


def _derive(rb: FiveBar, motion: Motion, t0: Any, modes: tuple[int, int], n: int) -> Derived:
    x, y = motion.at(t0, n)
    E = (x, y)
    C, D = elbows(rb, E, modes)
    v = (x.dt(), y.dt())
    acc = (v[0].dt(), v[1].dt())
    zero = x * 0
    legs = (
        leg(rb, 0, (zero, zero), C, E, v, acc),
        leg(rb, 1, (zero + rb.a, zero), D, E, v, acc),
    )
    u1 = (E[0] - C[0], E[1] - C[1])
    u2 = (E[0] - D[0], E[1] - D[1])
    l3, l4 = rb.length[2], rb.length[3]
    cos_ = dot(u1, u2) / (l3 * l4)
    nu = cos_ * legs[0].h * l4 + legs[1].h * l3
    return Derived(rb, C, D, E, legs, cross(u1, u2), cos_, nu)


def value(j: Any) -> Any:
    """A series' value at its instant."""
    return j.c[0] if isinstance(j, Jet) else j

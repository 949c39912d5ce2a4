"""The mechanism seam: the one interface through which the engine meets its robot.

What is specific to a mechanism and its actuation scheme (inverse kinematics, the Type II
locus, δ, the dynamics, the efforts, the consistency condition, the physical parameters)
sits behind ``Mechanism``. The exact analysis (``singular``, ``knots``), the certified
evaluation (``certified``, ``zones``) and the findings reach the robot only through
``of(robot)``; a second mechanism or a scheme with other parameters is a new
implementation registered here, and those layers are not edited. The RPRPR's two schemes
are ``equations.Revolute`` and ``equations.Prismatic`` (shared machinery in
``equations.Rprpr``, the scheme's own primitives in each, as numpy.polynomial does).

The contract. "Num" is any number type with + - * / that the caller works in: ``fmpq``,
``series.Series``/``QSeries`` (exact, over Q or a number field), ``flint.arb``,
``arb_series``, ``acb``, ``balls.Ball``, numpy float arrays. A method returns numbers of
the type it is given, computed by the same operations in the same order for every type
(so that the certified and exact layers agree), and never branches on a value.

* ``name`` (str): the ``Robot.actuation`` value it is registered under.
* ``words`` (``model.actuation.Scheme``): how reports name its efforts (letter, unit,
  noun) and its consistency condition.
* ``automatic`` (0 or 1): the index of the μ that vanishes at every Type II instant
  (λ_automatic = μ/δ stays bounded there; the other λ carries any pole).
* ``params(robot, convert)`` -> ``equations.Params``: the physical parameters, each exact
  value of the task passed through ``convert`` (to a float, a ball, an arb; identity:
  exact): a1 [m], g [m/s^2], masses [kg], inertias [kg m^2], r [m]; the result carries
  the mechanism (``Params.mechanism``), so ``equations.dynamics`` and ``efforts`` find it.
* ``locus(x, y)`` -> polynomial: given x(t), y(t) as ``fmpq_poly``, a polynomial in t
  whose real roots are the Type II instants, with the order as multiplicity (RPRPR: y).
* ``legs(p, x, ẋ, ẍ, y, ẏ, ÿ, hypot, hypot2=None)`` -> (Leg, Leg): the inverse kinematics
  from the end point E = (x, y) [m] and its derivatives [m/s, m/s^2]: per leg s [m],
  cos θ, sin θ, s' [m/s], θ' [rad/s], s'' [m/s^2], θ'' [rad/s^2]. ``hypot(u, v)`` is the
  caller's |(u, v)| in its number type (a sign-chosen square root for series), ``hypot2``
  leg 2's when it differs.
* ``delta(p, y, leg1, leg2)`` -> Num: δ = sin(θ1 - θ2) (dimensionless) in the product
  form that does not cancel near the locus; ``delta_rate(p, y, ẏ, leg1, leg2)``: δ' [1/s].
* ``dynamics(leg1, leg2, p)`` -> ``equations.Dynamics``: the terms of the equations of
  motion with μ1, μ2 [N] (λ = μ/δ, eqs. 30-31) and δ; it carries the mechanism.
* ``efforts(d, λ1, λ2)`` -> (E1, E2): the actuators' efforts given λ [N] (N m for torques,
  N for forces, as ``words.unit`` says).
* ``consistency(d, σ, at)`` -> (numerator, denominator or None): the consistency residual
  at a Type II instant [N] as numerator/denominator (None: 1) from the values ``at(v)``
  of the series' terms at t_s, exactly when they are exact; σ is the case's cos θ1 cos θ2
  (Table 2). A zero numerator means consistent (eq. 34 for the revolute scheme).

A mechanism whose legs need a square root other than a distance takes a ``Root``,
``root(D, i)``: the caller's √D of leg i's discriminant D (a polynomial in x, y) in its
number type, where the RPRPR's take ``hypot``. The 5R five-bar (``five_bar``: elbows
from √D1, √D2, the working modes multiplying them) is written on it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

from ...model.actuation import Scheme
from ...model.task import Robot
from .equations import MECHANISMS, Dynamics, Leg, Params

Num = Any
Root = Callable[[Num, int], Num]  # (D_i, leg i = 1 or 2) -> √D_i in the caller's type


class Mechanism(Protocol):
    """A mechanism under one actuation scheme (the module docstring is its contract)."""

    @property
    def name(self) -> str: ...
    @property
    def words(self) -> Scheme: ...
    @property
    def automatic(self) -> int: ...

    def params(self, robot: Robot, convert: Callable[[Any], Any] = ...) -> Params: ...
    def locus(self, x: Any, y: Any) -> Any: ...
    def legs(
        self, p: Params, x: Num, xd: Num, xdd: Num, y: Num, yd: Num, ydd: Num,
        hypot: Callable[[Num, Num], Num], hypot2: Callable[[Num, Num], Num] | None = None,
    ) -> tuple[Leg, Leg]: ...  # fmt: skip
    def delta(self, p: Params, y: Num, leg1: Leg, leg2: Leg) -> Num: ...
    def delta_rate(self, p: Params, y: Num, yd: Num, leg1: Leg, leg2: Leg) -> Num: ...
    def dynamics(self, leg1: Leg, leg2: Leg, p: Params) -> Dynamics: ...
    def efforts(self, d: Dynamics, lambda1: Num, lambda2: Num) -> tuple[Num, Num]: ...
    def consistency(self, d: Dynamics, sigma: int, at: Callable[[Num], Any]) -> tuple[Any, Any]: ...


def of(robot: Robot) -> Mechanism:
    """The implementation that drives ``robot`` (by ``Robot.actuation``)."""
    m: Mechanism = MECHANISMS[robot.actuation]
    return m


def register(mechanism: Mechanism) -> Mechanism:
    """Make ``mechanism`` the implementation of robots whose ``actuation`` is its name."""
    MECHANISMS[mechanism.name] = mechanism
    return mechanism


__all__ = ["MECHANISMS", "Mechanism", "Root", "of", "register"]

"""The two actuation schemes of the RPRPR chain (``robot.actuation``) and their words.

* ``revolute`` (the paper): motors at A and B drive θ1, θ2 with torques T1, T2 [N m];
  the legs' prismatic joints s1, s2 are passive. Consistency at a Type II instant is
  eq. (34), σ F1 + F2 = 0.
* ``prismatic``: linear actuators drive s1, s2 with forces F1, F2 [N]; θ1, θ2 are
  passive. Consistency is the legs' moment balance about A and B, U1/s1 + σ U2/s2 = 0
  (``engine.equations``; docs/prismatic.md derives it).

The engine and the report keep the efforts under the paper's names (``T1``, ``T2``,
``torque_*``) for both schemes; renderers name them with ``Scheme``.
"""

from __future__ import annotations

from .dataclass import dataclass

REVOLUTE = "revolute"
PRISMATIC = "prismatic"
ACTUATIONS = (REVOLUTE, PRISMATIC)


@dataclass(frozen=True)
class Scheme:
    """How one scheme names its actuator efforts and its consistency condition."""

    name: str
    letter: str  # T or F: T1, T2 or F1, F2
    unit: str  # of the efforts
    noun: str  # "torques" or "forces"
    condition: str  # the consistency condition, in words
    column: str  # its column title in the check table
    cited: str  # the condition as a finding cites it


SCHEMES = {
    REVOLUTE: Scheme(REVOLUTE, "T", "N m", "torques", "eq. (34)", "eq.(34) [N]", "eq. 34"),
    PRISMATIC: Scheme(
        PRISMATIC, "F", "N", "forces", "moment balance", "moments [N]", "moment balance"
    ),
}

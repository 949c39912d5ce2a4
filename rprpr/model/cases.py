"""The paper's Tables 1-3: the three cases of a Type II singular configuration.

At a Type II singularity E lies on the line AB (y_E = 0, A at the origin, B at (a1, 0)):

====  ===============================  ======  ======  ==================
case  joint variables (Table 1)        σ (T2)  ψ (T3)  where E is
====  ===============================  ======  ======  ==================
1     θ1 = θ2 = 0                       1       1      x_E > a1 (beyond B)
2     θ1 = θ2 = π                       1      -1      x_E < 0 (behind A)
3     θ1 = 0 and θ2 = π                -1       1      0 < x_E < a1
====  ===============================  ======  ======  ==================

σ enters the consistency condition (34), ψ the velocity relations (43)-(44); in terms of
the angles σ = cos θ1 cos θ2 and ψ = cos θ1.
"""

from __future__ import annotations

from .dataclass import dataclass


@dataclass(frozen=True)
class Case:
    number: int
    sigma: int
    psi: int
    theta1: str
    theta2: str
    where: str


CASES = {
    1: Case(1, 1, 1, "0", "0", "beyond B (x > a1)"),
    2: Case(2, 1, -1, "π", "π", "behind A (x < 0)"),
    3: Case(3, -1, 1, "0", "π", "between A and B (0 < x < a1)"),
}


def case_of(sign_x: int, sign_x_minus_a1: int) -> Case:
    """The case of a singular point on y = 0 from the signs of x_E and x_E - a1 (both nonzero)."""
    if sign_x > 0 and sign_x_minus_a1 > 0:
        return CASES[1]
    if sign_x < 0:
        return CASES[2]
    return CASES[3]

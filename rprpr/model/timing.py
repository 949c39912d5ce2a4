"""The timing laws x_E(t) a task may name (eq. 49 and its cubic sibling), exact.

The rest-to-rest quintic x(t) = x0 + (x1 - x0)(10 τ^3 - 15 τ^4 + 6 τ^5), τ = t / t_f, with
zero velocity and acceleration at both ends; and the rest-to-rest cubic
x0 + (x1 - x0)(3 τ^2 - 2 τ^3), with zero velocity at both ends.
"""

from __future__ import annotations

from flint import fmpq, fmpq_poly

LAWS = ("quintic", "cubic")


def timing_law(law: str, x0: fmpq, x1: fmpq, duration: fmpq) -> fmpq_poly:
    """x_E(t) of a rest-to-rest ``law`` from x0 to x1 in ``duration`` seconds (exact)."""
    tau = fmpq_poly([0, 1 / duration])
    if law == "quintic":
        shape = 10 * tau**3 - 15 * tau**4 + 6 * tau**5  # eq. (49) for x0=2, x1=4, t_f=5
    elif law == "cubic":
        shape = 3 * tau**2 - 2 * tau**3
    else:
        raise ValueError(f"unknown timing law {law!r}; expected one of {', '.join(LAWS)}")
    return x0 + (x1 - x0) * shape

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
    if law not in _SHAPES:
        raise ValueError(f"unknown timing law {law!r}; expected one of {', '.join(LAWS)}")
    # x0 + (x1 - x0) sum_k c_k (t / t_f)^k, coefficient by coefficient
    scale = x1 - x0
    coeffs = [x0]
    for c in _SHAPES[law][1:]:
        scale /= duration
        coeffs.append(c * scale)
    return fmpq_poly(coeffs)


# the shape in tau = t / t_f, coefficients of tau^0, tau^1, ...
_SHAPES = {
    "quintic": (0, 0, 0, 10, -15, 6),  # 10 tau^3 - 15 tau^4 + 6 tau^5: eq. (49)
    "cubic": (0, 0, 3, -2),  # 3 tau^2 - 2 tau^3
}


def trapezoidal(x0: fmpq, x1: fmpq, duration: fmpq, cruise: fmpq) -> list[tuple[fmpq, fmpq_poly]]:
    """The trapezoidal (LSPB) law from x0 to x1 in ``duration`` s with cruise speed
    ``cruise`` = |dx/dt|, as pieces (end time, x(t) in absolute t), exact.

    Constant acceleration a = V / t_b up to the blend time t_b = (V t_f - D) / V
    (D = |x1 - x0|), cruise at V, then constant deceleration to rest at t_f; C1 at the
    knots t_b and t_f - t_b. V must lie in (D / t_f, 2 D / t_f]; at V = 2 D / t_f the
    cruise is empty and the law has two pieces (a triangular profile).
    """
    D = abs(x1 - x0)
    if D == 0 or not (D / duration < cruise <= 2 * D / duration):
        raise ValueError(
            f"cruise_speed {cruise} outside ({D / duration}, {2 * D / duration}]"
            if D
            else "a trapezoidal law needs path.from and path.to at different x"
        )
    sign = 1 if x1 > x0 else -1
    tb = (cruise * duration - D) / cruise
    acc = sign * cruise / tb
    t = fmpq_poly([0, 1])
    rise = x0 + acc / 2 * t**2
    pieces = [(tb, rise)]
    if 2 * tb < duration:  # x(t_b) = x0 + sign V t_b / 2
        pieces.append((duration - tb, x0 + sign * cruise * (t - tb / 2)))
    pieces.append((duration, x1 - acc / 2 * (duration - t) ** 2))
    return pieces

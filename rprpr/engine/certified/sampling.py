"""The motion and its inverse dynamics on a grid of times, every number certified.

``sample`` reads the certified evaluation of ``certified.CertifiedMotion``: each value at
a time t is within a proven bound of the true value of the paper's formulas at t (mixed
error <= ``certified.TOL`` (1 + |value|)), or NaN with a reason code (``REASONS``): a pole
of λ exactly at a singular instant, E at A or B, the path on the singular line. A value
at t depends on t alone, never on the other times of the grid.
"""

from __future__ import annotations

import numpy as np
from flint import fmpq

from ...model.dataclass import dataclass
from .motion import REASONS, CertifiedMotion

# the export columns, in order (SI units, angles in radians, θ continuous); the
# accelerations (for a controller's feed-forward) last, so earlier columns keep their place
COLUMNS = (
    "t", "x", "y", "x_dot", "y_dot", "theta1", "s1", "theta2", "s2",
    "theta1_dot", "s1_dot", "theta2_dot", "s2_dot", "delta", "delta_dot",
    "lambda1", "lambda2", "T1", "T2",
    "x_ddot", "y_ddot", "theta1_ddot", "s1_ddot", "theta2_ddot", "s2_ddot",
)  # fmt: skip

__all__ = ["COLUMNS", "REASONS", "Samples", "grid", "sample"]


@dataclass(frozen=True)
class Samples:
    """Sampled motion: one numpy array per quantity, all of the length of ``t``;
    ``reason`` holds one code of ``REASONS`` per sample (0: every value certified)."""

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    x_dot: np.ndarray
    y_dot: np.ndarray
    x_ddot: np.ndarray
    y_ddot: np.ndarray
    theta1: np.ndarray
    s1: np.ndarray
    theta2: np.ndarray
    s2: np.ndarray
    theta1_dot: np.ndarray
    s1_dot: np.ndarray
    theta2_dot: np.ndarray
    s2_dot: np.ndarray
    theta1_ddot: np.ndarray
    s1_ddot: np.ndarray
    theta2_ddot: np.ndarray
    s2_ddot: np.ndarray
    delta: np.ndarray
    delta_dot: np.ndarray
    lambda1: np.ndarray
    lambda2: np.ndarray
    T1: np.ndarray
    T2: np.ndarray
    reason: np.ndarray

    def column(self, name: str) -> np.ndarray:
        return getattr(self, name)

    def rows(self) -> np.ndarray:
        """The export columns as a 2-D array, one row per sample."""
        return np.column_stack([self.column(c) for c in COLUMNS])


def grid(duration: fmpq, n: int) -> np.ndarray:
    """n sample times t_i = i t_f/(n-1), i = 0..n-1, each the float nearest the exact value."""
    if n < 2:
        raise ValueError("at least 2 samples are needed")
    num, den = int(duration.p), int(duration.q)
    if num * (n - 1) < 2**53 and den * (n - 1) < 2**53:  # exact products, one rounding
        return np.arange(n) * float(num) / float((n - 1) * den)
    return np.array([(i * num) / ((n - 1) * den) for i in range(n)])


def sample(motion: CertifiedMotion, t: np.ndarray) -> Samples:
    """The motion, joints, δ, λ and torques at the times ``t`` (seconds), certified."""
    c = motion.sample(np.asarray(t, dtype=float))
    return Samples(t=c.t, reason=c.reason, **c.value)

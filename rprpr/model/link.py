"""A moving link's inertial parameters (``Link``), for the RPRPR and the 5R alike
(``model.task.Link`` is the same class)."""

from __future__ import annotations

from flint import fmpq

from .dataclass import dataclass


@dataclass(frozen=True)
class Link:
    """One moving link i = 2..5 (of a 5R: 1..4): mass m_i, centroidal inertia I_i, and
    r_i (Section 2; of a 5R: from the link's inner joint)."""

    mass: fmpq
    inertia: fmpq
    r: fmpq

"""The 5R five-bar (``robot.mechanism: 5R``): its exact parameters and its legs' reach.

A = (0, 0), B = (a, 0); link 1 (A to the elbow C, length l1) and link 2 (B to the elbow
D, length l2) are the proximal links, driven by the motors at A and B; link 3 (C to E,
l3) and link 4 (D to E, l4) are the distal links, meeting at the end point E
(docs/five-bar.md, §1). The working modes e1, e2 = ±1 choose the elbows (§2):

    K1 = (l1² + |E|² − l3²)/2,   D1 = l1²|E|² − K1²,   C = (K1 E + e1 √D1 E⊥)/|E|²,

and likewise D about B with W = E − B. Leg i reaches E iff D_i >= 0, i.e.
|l_p − l_d| <= |E − base_i| <= l_p + l_d; at D_i = 0 it is stretched or folded and its
two working modes coincide (a Type I singularity).
"""

from __future__ import annotations

from flint import fmpq

from .dataclass import dataclass
from .link import Link

RPRPR = "rprpr"  # robot.mechanism: the paper's RPRPR (the default)
FIVE_BAR = "5R"  # robot.mechanism: the all-revolute five-bar
MECHANISMS = (RPRPR, FIVE_BAR)
FIVE_BAR_LINKS = (1, 2, 3, 4)  # proximal at A, proximal at B, distal of leg 1, of leg 2


@dataclass(frozen=True)
class FiveBar:
    """A 5R five-bar: ``a`` = |AB| [m] (B at (a, 0)), ``lengths`` = (l1, l2, l3, l4) [m]
    (l1, l3: the leg at A, proximal and distal; l2, l4: the leg at B), ``modes`` =
    (e1, e2), each +1 or -1, the working modes at t = 0 (e1 = sign(E × C): +1 when C
    is to the left of AE; e2 = sign((E − B) × (D − B))), and ``links`` 1..4, each
    with its mass, centroidal inertia and r, the distance of its centre of mass from
    its inner joint (A, B, C, D for links 1, 2, 3, 4)."""

    a: fmpq
    lengths: tuple[fmpq, fmpq, fmpq, fmpq]
    modes: tuple[int, int]
    links: dict[int, Link]

    def __post_init__(self) -> None:
        """A ValueError naming the first parameter out of its range (the task file's
        reader checks the same, each on its own located line)."""
        if not self.a > 0:
            raise ValueError(f"FiveBar: a = |AB| must be > 0, found {self.a}")
        if len(self.lengths) != 4 or not all(length > 0 for length in self.lengths):
            raise ValueError(f"FiveBar: lengths must be four numbers > 0, found {self.lengths}")
        if len(self.modes) != 2 or any(type(e) is not int or e not in (1, -1) for e in self.modes):
            raise ValueError(f"FiveBar: modes must be two signs, +1 or -1, found {self.modes}")
        if sorted(self.links) != list(FIVE_BAR_LINKS):
            raise ValueError(f"FiveBar: links must be 1, 2, 3 and 4, found {sorted(self.links)}")

    def leg(self, i: int) -> tuple[fmpq, fmpq, fmpq]:
        """Leg i (1: at A, 2: at B): its base's x (0 or a), its proximal and distal lengths."""
        l1, l2, l3, l4 = self.lengths
        return (fmpq(0), l1, l3) if i == 1 else (self.a, l2, l4)

    def discriminant(self, i: int, x: fmpq, y: fmpq) -> fmpq:
        """D_i at E = (x, y), exactly: l_p² R − K², K = (l_p² + R − l_d²)/2, R = |E − base_i|²
        (docs/five-bar.md, §2). Leg i reaches E iff D_i >= 0; D_i = 0: stretched or folded."""
        base, proximal, distal = self.leg(i)
        r = (x - base) ** 2 + y**2
        k = (proximal**2 + r - distal**2) / 2
        return proximal**2 * r - k**2

    def annulus(self, i: int) -> tuple[fmpq, fmpq]:
        """The radii |l_p − l_d| <= |E − base_i| <= l_p + l_d of what leg i reaches."""
        _, proximal, distal = self.leg(i)
        return abs(proximal - distal), proximal + distal

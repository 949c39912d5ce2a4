"""The 5R robot as the engine takes it, built from the reference's ``FiveBar``.

``rprpr.model.five_bar.FiveBar`` (a, lengths, modes, links keyed 1..4 of ``Link``) is the
task side's description; where it is not there, a stand-in of the same shape is used, so
the engine is tested through the names it reads."""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from flint import fmpq, fmpq_poly

from rprpr.model.task import Link

from .reference import FiveBar as RefFiveBar
from .reference import Motion

try:  # the task side's description, when present
    from rprpr.model.five_bar import FiveBar  # type: ignore[import-not-found,unused-ignore]
except ImportError:

    @dataclass(frozen=True)
    class FiveBar:  # type: ignore[no-redef]
        a: fmpq
        lengths: tuple[fmpq, fmpq, fmpq, fmpq]
        modes: tuple[int, int]
        links: dict[int, Link]


def q(v: Fraction | int) -> fmpq:
    v = Fraction(v)
    return fmpq(v.numerator, v.denominator)


def robot(rb: RefFiveBar, modes: tuple[int, int]) -> Any:
    """The engine's robot for the reference's ``rb`` in working modes ``modes``."""
    links = {i + 1: Link(q(rb.mass[i]), q(rb.inertia[i]), q(rb.r[i])) for i in range(4)}
    return FiveBar(q(rb.a), tuple(q(v) for v in rb.length), modes, links)


def polys(m: Motion) -> tuple[fmpq_poly, fmpq_poly]:
    """The reference's motion as the engine's x(t), y(t)."""
    return fmpq_poly([q(c) for c in m.x]), fmpq_poly([q(c) for c in m.y])

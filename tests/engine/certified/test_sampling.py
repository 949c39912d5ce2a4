"""The sampler's internals stay inside the engine; ``AuditResult.resample`` still reads them."""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from rprpr.engine.audit import AuditResult, audit
from rprpr.engine.certified.sampling import Samples
from rprpr.engine.exact.singular import KinematicSingularity, SingularInstant
from rprpr.io.loader import load_task
from tests.conftest import CONFIGS


def test_singular_instant_holds_only_what_the_paper_and_the_reports_need() -> None:
    assert [f.name for f in fields(SingularInstant)] == [
        "t", "x", "t_exact", "case", "order", "delta_m", "slope", "speed",
        "slope_principle", "velocity_principle", "consistency_residual", "consistent",
        "conditions_met", "torque_at_singularity", "beyond_double_range", "knot", "sides",
    ]  # fmt: skip
    # what follows from the stored fields is derived, never stored twice
    for name in ("y", "delta_derivatives", "conditions_required", "kind", "torque_bounded"):
        assert isinstance(getattr(SingularInstant, name), property)
    assert [f.name for f in fields(KinematicSingularity)] == [
        "t", "x", "y", "leg", "order", "beyond_double_range",
    ]  # fmt: skip


def test_the_audit_result_stores_only_what_it_cannot_derive() -> None:
    assert [f.name for f in fields(AuditResult)] == [
        "task", "strict", "torque_peak", "torque_limit", "closest_approach", "findings",
        "grid_size", "analysis", "parts", "knot_jumps", "peak_computed", "robust", "robust_peak",
    ]  # fmt: skip
    r = audit(load_task(CONFIGS / "piecewise_timing.rprpr.yaml"), samples=11)
    assert r.singularities is r.analysis.instants
    assert r.kinematic_singularities is r.analysis.kinematic
    assert r.knots == tuple(k.t for k in r.knot_jumps) and len(r.knots) >= 1
    assert r.trajectory is r.parts[0].traj


def test_resample_on_the_grid_reproduces_the_audit_bit_for_bit() -> None:
    # paper path 1: a third-order instant whose neighbours take λ from the Laurent series,
    # so the sampler's private record of the instant must reach ``resample``
    r = audit(load_task(CONFIGS / "paper_path1.rprpr.yaml"), samples=201)
    (s,) = r.singularities
    assert s.order == 3
    again = r.resample(r.samples.t)
    for f in fields(Samples):
        assert np.array_equal(getattr(again, f.name), getattr(r.samples, f.name), equal_nan=True)

"""The work of the torque verdicts, pinned: the vectorised ball passes of an audit.

A pass is one evaluation of the formulas on a vector of balls: ``Envelope._pass`` (over
boxes, with derivatives), ``Envelope._values`` (at points, or over boxes without
derivatives), ``CertifiedMotion.ball_pass``, ``Batch._pass`` and ``Batch._values``, and
the probes that choose a zone's width (``zones._needed``). A pass costs its calls, not
its length, so the count is the cost of a verdict in a form
that does not depend on the machine. Each task is audited three ways: by default (its
own checks: no peak), with the peak (``--peak``), and under a [300, 300] torque limit
without the peak. A change that costs passes shows here; one that saves them updates
the tables on purpose.

The limit column rose by 2 (1 for a1_1km) on the tasks whose crossings were bracketed
by Newton's method in arb scalars (not counted as passes): they are now bracketed by
vectorised point passes (``limits._bracket``, two passes for all of a motion's
crossings), each ~0.1 ms with the compiled kernel against ~0.2 ms per crossing and
Newton step in arb: the hard mix under the [300, 300] limit cost ~0.2 s less CPU per
300 tasks in process (brackets 0.43 s -> 0.20 s), more passes and less time.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

import pytest
from flint import fmpq

from rprpr.engine.audit import audit
from rprpr.engine.bounds import batch, envelope
from rprpr.engine.certified import motion as certified
from rprpr.engine.certified import zones
from rprpr.engine.exact import kept
from rprpr.io.loader import load_task, parse_task
from rprpr.model.task import Task
from tests.conftest import CONFIGS
from tests.corpora.test_hard_input import HARD

# per shipped config: (default, --peak, [300, 300] limit)
SHIPPED = {
    "case1_crossing": (0, 0, 4),
    "case2_crossing": (0, 0, 4),
    "example1_repaired": (0, 9, 5),
    "motion_pieces": (2, 20, 2),
    "paper_path1": (0, 0, 6),
    "paper_path2": (1, 5, 1),
    "piecewise_timing": (5, 11, 5),
    "prismatic_crossing": (1, 3, 1),
    "touch": (0, 0, 6),
    "trapezoidal": (5, 11, 5),
    "waypoints": (2, 20, 2),
    "waypoints_csv": (6, 18, 6),
    "zero_speed_crossing": (0, 0, 6),
}

# per task of the hard corpus (tests/corpora/test_hard_input.py): the same three
CORPUS = {
    "a1_1cm": (0, 7, 1),
    "a1_1km": (0, 5, 5),
    "degree_60_with_17_digit_coefficients": (0, 0, 81),
    "duration_1e6_s": (0, 5, 1),
    "ending_at_B": (0, 2, 1),
    "instant_at_t0_from_rest": (0, 0, 4),
    "instant_at_t0_moving": (0, 0, 4),
    "instant_at_tf_at_rest": (0, 0, 14),
    "instant_at_tf_moving": (0, 0, 4),
    "irrational_touches": (0, 0, 12),
    "masses_1e-9_kg": (0, 3, 1),
    "masses_1e9_kg": (0, 5, 4),
    "multiplicity_60": (0, 7, 18),
    "multiplicity_9_linear": (0, 5, 2),
    "multiplicity_9_quintic": (0, 0, 6),
    "path_on_the_singular_line": (0, 0, 11),
    "standing_still_on_the_line": (0, 0, 11),
    "three_within_5_microseconds": (0, 0, 9),
    "through_A": (0, 4, 1),
    "through_B": (0, 2, 1),
    "touch_at_zero_speed": (0, 0, 6),
    "touching_the_line_at_A": (0, 0, 11),
    "twelve_crossings": (0, 0, 14),
    "two_2p5e-12_s_apart": (0, 0, 4),
}


def _passes(task: Task, monkeypatch: pytest.MonkeyPatch) -> tuple[int, int, int]:
    count = [0]

    def counting(f: Callable[..., Any]) -> Callable[..., Any]:
        def counted(*a: Any, **k: Any) -> Any:
            count[0] += 1
            return f(*a, **k)

        return counted

    for owner, name in (
        (envelope.Envelope, "_pass"),
        (envelope.Envelope, "_values"),
        (certified.CertifiedMotion, "ball_pass"),
        (batch.Batch, "_pass"),
        (batch.Batch, "_values"),
        (zones, "_needed"),
    ):
        monkeypatch.setattr(owner, name, counting(getattr(owner, name)))
    checks = dataclasses.replace(task.checks, torque_limit=(fmpq(300), fmpq(300)))
    got = []
    for t, peak in ((task, False), (task, True), (dataclasses.replace(task, checks=checks), False)):
        count[0] = 0
        kept.clear()  # an audit's own work, none kept from an audit before
        audit(t, samples=11, peak=peak)
        got.append(count[0])
    return got[0], got[1], got[2]


@pytest.mark.parametrize("name", sorted(SHIPPED))
def test_the_ball_passes_of_each_shipped_config_are_pinned(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    assert _passes(load_task(CONFIGS / f"{name}.rprpr.yaml"), monkeypatch) == SHIPPED[name]


@pytest.mark.parametrize("name", sorted(HARD))
def test_the_ball_passes_of_each_hard_corpus_task_are_pinned(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    task = parse_task(HARD[name].text, f"{name}.yaml")
    assert _passes(task, monkeypatch) == CORPUS[name]


def test_a_limit_far_above_the_torques_is_decided_in_one_coarse_pass(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # paper path 2's torques peak at 66.1 and 60.6 N m (tests/engine/bounds/test_envelope.py,
    # against the mpmath reference): a [300, 300] limit is proven by the values over the
    # first partition's boxes alone, no derivative, no point value, no second pass
    from tests.engine.certified.test_motion import _config, _motion

    calls: list[str] = []
    for name in ("_pass", "_values"):
        f = getattr(envelope.Envelope, name)

        def counted(self: Any, *a: Any, _f: Any = f, _n: str = name, **k: Any) -> Any:
            calls.append(_n)
            return _f(self, *a, **k)

        monkeypatch.setattr(envelope.Envelope, name, counted)
    env = envelope.Envelope(_motion(_config("paper_path2.rprpr.yaml")))
    checks = env.limit_violations((300, 300))
    assert all(c.passed is True and c.windows == () for c in checks)
    assert calls == ["_values"]
    # just below the peak of T1 the same first pass cannot decide: the full pass follows
    calls.clear()
    t1, t2 = env.limit_violations((66, 300))
    assert t1.passed is False and t2.passed is True
    assert calls[:2] == ["_values", "_pass"]

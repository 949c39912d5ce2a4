"""The robust repair's early refusal (``docs/robust.md``, *Repair*): it stops at once only
when what still fails is RPR205 at the task's own failing instants with the residual
aimed there (the window is the box's spread), and its advice names only what the box
declares.

Path 2 under linear actuators with a 100 kN limit, ±1 % on every link, no tracking error
and a 0.1 ms period: the first candidate's aim at t = 2.5 s is right, but it makes a new
crossing near t = 3.29 s whose window fails; that is the candidate's to fix, not the
box's spread, and a later candidate passes.
"""

from __future__ import annotations

import pytest

from rprpr import parse_task
from rprpr.repair import NoRepair, passes, repair
from tests.conftest import CONFIGS

P2 = (CONFIGS / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")


def _task(actuation: str, limit: int, links: str, a: str, period: str) -> str:
    text = P2.replace("torque_limit: [300, 300]", f"torque_limit: [{limit}, {limit}]")
    if actuation:
        text = text.replace("robot:\n", f"robot:\n  actuation: {actuation}\n", 1)
    return text + f"uncertainty:\n  links: {links}\n  acceleration: {a}\n  period: {period}\n"


def test_a_window_at_an_instant_the_candidate_made_does_not_stop_the_repair() -> None:
    task = parse_task(_task("prismatic", 100000, "1%", "0", "0.0001"))
    r = repair(task)
    assert r.changed and passes(r.after)  # strict, RPR201 left to RPR205
    assert [f.rule for f in r.after.findings if f.rule == "RPR205"] == []
    (s,) = r.after.singularities
    assert s.t == 2.5
    assert r.after.robust[0].window < 1e-4


def test_a_window_of_the_masses_alone_stops_it_without_naming_a_tracking_error() -> None:
    """Path 2 is consistent at its nominal masses; ±5 % on them alone gives a window of
    tens of µs, longer than a 1 µs period: the spread of the masses, which no acceleration
    at t_s removes."""
    task = parse_task(_task("", 300, "5%", "0", "0.000001"))
    with pytest.raises(NoRepair) as e:
        repair(task)
    why = str(e.value)
    assert "RPR205" in why and "spread over the declared box" in why
    assert "track" not in why and "tracking error's part" not in why
    assert "identify the masses better" in why and "cross AB faster" in why

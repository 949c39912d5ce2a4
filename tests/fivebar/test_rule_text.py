"""``rprpr rule`` says what the rules the 5R shares with the RPRPR mean for a 5R (its
Type II curves, the speed, a leg stretched or folded, the path along a curve, the
reciprocity and higher-order conditions), in one line each that points to
docs/five-bar.md, and says nothing of the 5R for the rules it does not share."""

from __future__ import annotations

import pytest

from rprpr.model.rules import RULES
from tests.conftest import run_cli

WORDS = {
    "RPR101": ("S₊ or S₋", "∇S·E' = 0", "tan α", "checks.min_slope", "transversally"),
    "RPR102": ("E' = 0", "checks.min_speed"),
    "RPR103": ("stretched or folded", "l1 + l3", "working mode is lost", "stops there"),
    "RPR104": ("runs along S₊ or S₋", "lined up"),
    "RPR201": ("w = h1/l3 + σ h2/l4 = 0", "reciprocal", "w^(k-1) = 0", "σ frozen"),
}


@pytest.mark.parametrize("rule", sorted(RULES))
def test_a_shared_rule_explains_itself_for_a_5r(rule: str) -> None:
    code, out, err = run_cli("rule", rule)
    assert (code, err) == (0, "")
    lines = [ln for ln in out.splitlines() if ln.startswith("For a 5R")]
    if rule not in WORDS:
        assert lines == []
        return
    (line,) = lines
    assert line.startswith("For a 5R (robot.mechanism: 5R): ")
    assert line.endswith(" See docs/five-bar.md.")
    for w in WORDS[rule]:
        assert w in line, w
    # after "Why it matters", before the level
    order = [out.index(s) for s in ("Why it matters:", "For a 5R", "Level:")]
    assert order == sorted(order)

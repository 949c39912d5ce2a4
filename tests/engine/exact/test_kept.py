"""rprpr/engine/exact/kept.py: the exact work one process keeps between audits.

What is kept must never change a report: a task audited after others (whose expansions,
zone forms and factorisations are kept) reports exactly what it reports audited alone with
nothing kept, whatever came before it. The tasks below share a path and differ in one
thing each that the kept results are made from (gravity, actuation, timing, the path
given as x(t), y(t)), so a key that missed that thing would hand one task another's
result."""

from __future__ import annotations

import json
from typing import Any

import pytest
from flint import ctx, fmpq, fmpq_poly

from rprpr.engine.audit import audit
from rprpr.engine.bounds import approach
from rprpr.engine.certified import motion as certified
from rprpr.engine.certified import shared
from rprpr.engine.exact import kept, singular
from rprpr.engine.pieces import parts
from rprpr.io.loader import load_task, parse_task
from rprpr.model.task import Task
from rprpr.report.records import task_report
from tests.conftest import CONFIGS

PATH2 = (CONFIGS / "paper_path2.rprpr.yaml").read_text(encoding="utf-8")
DIRECT = """\
name: path 2 as x(t), y(t)
robot:
  a1: 6
  gravity: 9.81
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
motion:
  pieces:
    - until: 5
      x: 12/3125*t^5 - 6/125*t^4 + 4/25*t^3 + 2
      y: 6912/152587890625*t^15 - 10368/6103515625*t^14 + 32832/1220703125*t^13 \
- 11232/48828125*t^12 + 10944/9765625*t^11 - 145728/48828125*t^10 + 8128/1953125*t^9 \
- 3312/390625*t^8 + 576/15625*t^7 - 192/3125*t^6 + 156/15625*t^5 - 78/625*t^4 \
+ 52/125*t^3 - 1
checks:
  torque_limit: [300, 300]
"""
NEAR_MISS = (
    PATH2.replace("y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2", "y: 0.1*x^2 - 0.6*x + 1.0")
    .replace("from: [2, -1]", "from: [2, 0.2]")
    .replace("to: [4, 1]", "to: [4, 0.2]")
)


def twins() -> dict[str, Task]:
    """Path 2 (eq. 51, quintic), and tasks that differ from it in one thing each."""
    texts = {
        "path2": PATH2,
        "gravity 0": PATH2.replace("gravity: 9.81 ", "gravity: 0    "),
        "prismatic": PATH2.replace("  a1: 6 ", "  actuation: prismatic\n  a1: 6 "),
        "slower": PATH2.replace("duration: 5 ", "duration: 10"),
        "heavier link 3": PATH2.replace("3: {mass: 1.0,", "3: {mass: 1.5,"),
        "as x(t), y(t)": DIRECT,
        "near miss": NEAR_MISS,  # never meets AB: its closest approach (R~'s factors)
        "near miss, slower": NEAR_MISS.replace("duration: 5", "duration: 10"),  # R~ the same
        "near miss, tilted": NEAR_MISS.replace("0.6*x + 1.0", "0.5*x + 0.9")
        .replace("[2, 0.2]", "[2, 0.3]")
        .replace("[4, 0.2]", "[4, 0.5]"),
    }
    assert len(set(texts.values())) == len(texts)  # each replacement took
    out = {name: parse_task(text, f"{name}.yaml") for name, text in texts.items()}
    for name in ("paper_path1", "zero_speed_crossing", "case1_crossing", "touch"):
        out[name] = load_task(CONFIGS / f"{name}.rprpr.yaml")
    return out


def report(task: Task) -> str:
    """Every field of the task's JSON report, with the peak (the zones' reader)."""
    r = audit(task, samples=21, peak=True)
    return json.dumps(task_report(r, "task.yaml"), sort_keys=True)


def test_a_task_reports_the_same_after_any_others_as_alone() -> None:
    tasks = twins()
    alone = {}
    for name, task in tasks.items():
        kept.clear()
        alone[name] = report(task)
    assert len(set(alone.values())) == len(alone)  # every twin reports something of its own
    for order in (list(tasks), list(reversed(tasks))):
        kept.clear()
        for name in order:
            assert report(tasks[name]) == alone[name], name
    assert len(singular._MADE) and len(certified._ZONES) and len(approach._FACTORED)


def test_each_thing_the_results_are_made_from_is_in_its_key() -> None:
    tasks = twins()
    names = ("path2", "gravity 0", "prismatic", "slower", "heavier link 3", "near miss")
    robots = {kept.robot_key(tasks[name].robot) for name in names}
    assert len(robots) == 4  # path 2's, without gravity, prismatic, a heavier link 3
    assert kept.robot_key(tasks["path2"].robot) == kept.robot_key(tasks["slower"].robot)
    assert kept.exact_key(fmpq(1, 2)) != kept.exact_key(fmpq(2, 4) + fmpq(1, 4))
    assert kept.exact_key(fmpq(1, 2)) != kept.exact_key(fmpq(1, 3))
    assert kept.exact_key(fmpq(1, 2)) == kept.exact_key(fmpq(2, 4))
    assert kept.exact_key(fmpq_poly([1, 2], 3)) != kept.exact_key(fmpq_poly([1, 2], 5))
    assert kept.exact_key((fmpq(1),)) != kept.exact_key([fmpq(1)])
    assert kept.exact_key(1) != kept.exact_key(fmpq(1))  # a name's number, an exact one


def _zone_keys(task: Task) -> list[Any]:
    out = []
    for p in parts(task, lambda stage: None)[0]:
        m = p.motion
        out += [certified._zone_key(m, s) for s in m.analysis.instants]
    return out


def test_a_zone_is_kept_by_the_trajectory_the_robot_and_flints_precision() -> None:
    tasks = twins()
    path2 = _zone_keys(tasks["path2"])
    assert path2 and all(k is not None for k in path2)  # t_s = 2.5, rational
    for name in ("slower", "as x(t), y(t)", "gravity 0", "prismatic", "heavier link 3"):
        assert _zone_keys(tasks[name]) != path2, name  # (x(t), y(t) the same, no path)
    old = ctx.prec
    try:
        ctx.prec = old + 64
        assert _zone_keys(tasks["path2"]) != path2
    finally:
        ctx.prec = old


def _expansion_keys(task: Task) -> set[Any]:
    kept.clear()
    audit(task, samples=21)
    return set(singular._MADE._made)


def test_the_expansions_are_kept_by_x_and_y_about_the_instant_and_the_robot() -> None:
    """Path 2 and the same x(t) with y + (x - 3)^3/2 (eq. 51 plus a cubic term: the same
    crossing at t_s = 2.5 with the same slope), and path 2 without gravity."""
    tasks = twins()
    cubic = PATH2.replace("0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2", "1.3*x^3 - 11.7*x^2 + 35.3*x - 35.7")
    cubic = cubic.replace("[2, -1]", "[2, -1.5]").replace("[4, 1]", "[4, 1.5]")
    path2 = _expansion_keys(tasks["path2"])
    assert path2
    assert _expansion_keys(parse_task(cubic, "cubic.yaml")).isdisjoint(path2)
    assert _expansion_keys(tasks["gravity 0"]).isdisjoint(path2)
    assert _expansion_keys(tasks["path2"]) == path2


def test_a_store_keeps_the_newest_and_clear_empties_every_store() -> None:
    store: kept.Kept[int] = kept.Kept(2)
    try:
        _store_keeps_the_newest(store)
    finally:
        kept.STORES.remove(store)


def _store_keeps_the_newest(store: kept.Kept[int]) -> None:
    made: list[str] = []

    def make(key: str) -> int:
        made.append(key)
        return len(made)

    assert [store.get(k, lambda k=k: make(k)) for k in "aab"] == [1, 1, 2]
    assert store.get("c", lambda: make("c")) == 3 and len(store) == 2  # "a" dropped
    assert store.get("a", lambda: make("a")) == 4
    assert made == ["a", "b", "c", "a"]
    with pytest.raises(ZeroDivisionError):
        store.get("d", lambda: 1 // 0)  # an interrupted make keeps nothing
    assert len(store) == 2
    assert store in kept.STORES and shared._BY_KEY in kept.STORES
    audit(load_task(CONFIGS / "paper_path2.rprpr.yaml"), samples=21)
    assert shared._LAST  # the per-robot forms of the robot last given, by identity
    kept.clear()
    assert all(len(s) == 0 for s in kept.STORES) and not shared._LAST


def test_a_kept_zone_is_read_only() -> None:
    kept.clear()
    audit(load_task(CONFIGS / "paper_path2.rprpr.yaml"), samples=21, peak=True)
    zones = [z for z in certified._ZONES._made.values() if z is not None]
    assert zones
    balls = [b for z in zones for b in (*z.num[0], *z.num[1], *z.den, *z.stack())]
    assert balls and not any(a.flags.writeable for b in balls for a in (b.mid, b.rad))

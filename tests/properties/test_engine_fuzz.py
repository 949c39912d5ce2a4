"""Fuzzing the engine (hypothesis, derandomized): every valid task is audited, nothing raised.

Two sources of tasks: valid task files mutated at their numbers and expressions (values
swapped for extreme ones: 1e±30 and their powers, forty-digit numbers, zero masses, high
powers of clustered factors), and tasks built from random extreme parts. Whatever loads
is audited at 51 samples within the default work budget in CPU time (10 s; a deadline in
wall time would turn a busy machine into a failure), its report is strict JSON (no
NaN, no infinity), every instant lies in [0, t_f] and every quantity listed as beyond the
double range is printed as a finite number.
"""

from __future__ import annotations

import json
import re
import time

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rprpr.engine.audit import audit
from rprpr.io.loader import parse_task
from rprpr.model.errors import TaskFileError
from rprpr.model.numbers import to_float
from rprpr.report.records import task_report

FUZZ = settings(
    max_examples=60,
    derandomize=True,
    deadline=None,  # bounded in CPU time below, not in wall time
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much],
)

VALID = """\
name: fuzz
robot:
  a1: 6
  gravity: 9.81
  links:
    2: {mass: 2.0, inertia: 0.10, r: 0.5}
    3: {mass: 1.0, inertia: 0.05, r: 0.5}
    4: {mass: 2.0, inertia: 0.10, r: 0.5}
    5: {mass: 1.0, inertia: 0.05, r: 0.5}
path:
  y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2
timing:
  duration: 5
  x: 2 + 0.4*t
checks:
  torque_limit: [300, 300]
"""

NUMBERS = [
    "0", "1", "3", "6", "0.5", "1e30", "1e-30", "2e-30", "1" + "0" * 39, "0.1e-29",
    "(1e30)^6", "(1e30)^13", "1/(1e30)^7", "123456789012345678901234567890",
]  # fmt: skip
EXPRESSIONS = [
    "x - 3", "(x - 3)^60", "(1000000*x - 3000000)^60", "x^20 - 2*(1e30*x - 1)^2",
    "x^60 - 2*(1e30*x - 1)^2", "(x^2 - 2)^30", "(x - 3)*(x - 3.000000000001)", "x*(x - 6)",
    "(x^4 - 10*x^2 + 1)^15", "x^2 - 2/(1e30)^13", "0*x", "(x - 3)*(1e30)^13",
]  # fmt: skip
MOTIONS = ["t", "t + 1", "2 + 0.4*t", "(1e30)^11*t + 2", "t - 1/(1e30)^3", "t^3 - t", "3"]


def _audits_cleanly(source: str) -> None:
    """``source`` loads, or is a TaskFileError; a task that loads is audited cleanly.

    A text already found clean in this process is not audited again: the mutations draw
    the same text now and then (a third to a half of the mutated examples: a value put
    back, the same swap drawn twice), and the same text is the same case."""
    if source in _CLEAN:
        return
    try:
        task = parse_task(source, "fuzz.yaml")
    except TaskFileError:
        _CLEAN.add(source)
        return
    start = time.process_time()
    r = audit(task, samples=51)
    assert time.process_time() - start < BUDGET  # CPU seconds: deaf to a busy machine
    report = json.loads(json.dumps(task_report(r, "fuzz.yaml"), allow_nan=False))
    t_f = to_float(task.duration)
    for s in r.singularities + r.kinematic_singularities:
        assert 0 <= s.t <= t_f
    for s in r.singularities:
        assert s.order >= 1 and 0 <= s.conditions_met <= s.conditions_required == s.order
        assert s.torque_bounded == (s.torque_at_singularity is not None)
    for b in report["beyond_double_range"]:
        assert _SCIENTIFIC.fullmatch(b["value"]), b  # "1.41421e+400": never "inf" or "0"
    assert report["verdict"] in ("pass", "fail")
    _CLEAN.add(source)


_CLEAN: set[str] = set()  # the texts ``_audits_cleanly`` has passed in this process


BUDGET = 10.0  # CPU seconds: the default work budget of ``rprpr check``
_SCIENTIFIC = re.compile(r"-?[1-9](\.\d*[1-9])?e[+-]\d{2,}")
_NUMBER = re.compile(r"(?<![\w.^])\d+(\.\d+)?(?![\w.])")


@FUZZ
@given(st.data())
def test_mutated_valid_tasks_audit_cleanly(data: st.DataObject) -> None:
    lines = VALID.splitlines(keepends=True)
    for _ in range(data.draw(st.integers(1, 4))):
        i = data.draw(st.integers(0, len(lines) - 1))
        line = lines[i]
        if line.startswith("  y:"):
            lines[i] = f"  y: {data.draw(st.sampled_from(EXPRESSIONS))}\n"
        elif line.startswith("  x:"):
            lines[i] = f"  x: {data.draw(st.sampled_from(MOTIONS))}\n"
        else:
            spans = [
                m.span() for m in _NUMBER.finditer(line) if not line.startswith(("    ", "name"))
            ]
            spans += [m.span() for m in _NUMBER.finditer(line) if line.startswith("    ")][1:]
            if spans:
                a, b = data.draw(st.sampled_from(spans))
                lines[i] = line[:a] + data.draw(st.sampled_from(NUMBERS)) + line[b:]
    _audits_cleanly("".join(lines))


@FUZZ
@given(
    y=st.sampled_from(EXPRESSIONS),
    x=st.sampled_from(MOTIONS),
    duration=st.sampled_from(["1e-30", "2e-30", "5", "1e30", "0.001"]),
    a1=st.sampled_from(["6", "1e-30", "1e30", "3"]),
    mass=st.sampled_from(["0", "1e-30", "1", "1e30"]),
    gravity=st.sampled_from(["0", "9.81", "1e30"]),
)
def test_tasks_of_extreme_parts_audit_cleanly(
    y: str, x: str, duration: str, a1: str, mass: str, gravity: str
) -> None:
    links = "".join(f"    {i}: {{mass: {mass}, inertia: {mass}, r: 0.5}}\n" for i in (2, 3, 4, 5))
    _audits_cleanly(
        f"name: fuzz\nrobot:\n  a1: {a1}\n  gravity: {gravity}\n  links:\n{links}"
        f"path:\n  y: {y}\ntiming:\n  duration: {duration}\n  x: {x}\n"
    )

"""The 5R's certified layers against the Newton-Euler reference (reference.py, mpmath at
60 digits; it imports nothing from rprpr): the samples, the grid-free torque peak, the
torque limit's windows, and what ``rprpr check``, ``rprpr export`` and the Python API
report of them.

The motions are test_check's (the a = 14 robot with the rational singular pose, consistent
and inconsistent transversal crossings, a tangential touch and a stop on the curve, all
at t_s = 1/8 here, a double, so that a sample falls on the instant) and a straight line
of test_dynamics' robot that crosses the Type II curve at an irrational time. What the
engine proves is checked against the reference's own values: each sample holds the
reference's value within its certified error; the peak's bracket holds the reference's
maximum (dense evaluation and golden-section refinement); each limit window's brackets
hold the reference's crossings (sign changes and bisection of |T_i| - L_i).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from fractions import Fraction as Q
from functools import cache, partial
from pathlib import Path
from typing import Any

import mpmath
import numpy as np
import pytest
from flint import fmpq, fmpq_poly

from rprpr.engine.certified.five_bar import FiveBarMotion
from rprpr.engine.certified.five_bar_samples import POLE, TYPE_ONE, sample
from rprpr.engine.certified.sampling import grid
from rprpr.engine.exact.five_bar_instants import analyse
from rprpr.engine.five_bar_certified import limit_check, torque_peak
from tests.cli.forked import fresh_probe

from .reference import DPS, FiveBar, Motion, elbows, links, mp, newton_euler, torques
from .reference import delta as ref_delta
from .standin import polys, q, robot
from .test_check import MODES, ROBOT, motions
from .test_dynamics import ROBOT as UNIT

TOL = 1e-9  # the samples' certified mixed error
TS = Q(1, 8)  # t_s of test_check's motions, moved here
TF = Q(1, 4)
LINE = Motion((Q(1, 5), Q(1)), (Q(3, 5),))  # test_engine_instants' straight line


@cache
def case(name: str) -> tuple[FiveBar, Motion, tuple[int, int], Q, Q]:
    """(robot, motion in its own time, modes, t0, t_f): absolute time t = local t0 + t."""
    if name == "line":
        return UNIT, LINE, (1, -1), Q(0), Q(1)
    return ROBOT, motions()[name], MODES, -TS, TF


@cache
def certified(name: str) -> FiveBarMotion:
    rb, m, modes, t0, tf = case(name)
    x, y = polys(m)
    shift = fmpq_poly([q(t0), 1])
    X, Y = x(shift), y(shift)
    a = analyse(robot(rb, modes), q(rb.g), X, Y, fmpq(0), q(tf))
    return FiveBarMotion(robot(rb, modes), q(rb.g), X, Y, q(tf), a.instants)


@cache
def ref_torques(name: str, t: Q) -> tuple[Any, Any]:
    """(T1, T2) at the time t by the reference."""
    T1, T2, _ = ref_state(name, t)
    return T1, T2


@cache
def ref_state(name: str, t: Q) -> tuple[Any, Any, Any]:
    """(T1, T2, α) at the time t by the reference: α = F_E·(E - C)/l3, the axial part of
    the force of link 4 on link 3 at E."""
    rb, m, modes, t0, _ = case(name)
    with mpmath.workdps(DPS):
        lk = links(rb, m, t + t0, modes, n=3)
        out = newton_euler(rb, lk)
        C, E = lk.joints["C"], lk.joints["E"]
        d = [mp(E[k].c[0]) - mp(C[k].c[0]) for k in (0, 1)]
        alpha = (out["FE"][0] * d[0] + out["FE"][1] * d[1]) / mp(rb.length[2])
        return out["T1"], out["T2"], alpha


def close(v: float, ref: Any) -> bool:
    with mpmath.workdps(DPS):
        return bool(abs(mpmath.mpf(v) - ref) <= TOL * (1 + abs(ref)))


def test_the_cases_cross_as_the_tests_say() -> None:
    got = {n: [(s.t_exact, s.order, s.bounded) for s in certified(n).instants]
           for n in ("consistent", "inconsistent", "tangent", "stop")}  # fmt: skip
    t = fmpq(1, 8)
    assert got == {
        "consistent": [(t, 1, True)], "inconsistent": [(t, 1, False)],
        "tangent": [(t, 2, True)], "stop": [(t, 2, True)],
    }  # fmt: skip
    line = certified("line").instants
    assert len(line) == 1 and line[0].t_exact is None and not line[0].bounded


# -- samples ------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["consistent", "inconsistent", "tangent", "stop", "line"])
def test_samples_hold_the_references_values(name: str) -> None:
    rb, m, modes, t0, tf = case(name)
    fm = certified(name)
    ts = np.concatenate([grid(q(tf), 17), [float(TS) + 1e-7, float(TS) - 2**-40]])
    got = sample(fm, ts)
    for j, t in enumerate(ts.tolist()):
        T = Q(t)
        if name != "line" and T == TS:
            continue  # test_samples_at_the_instant
        assert got.reason[j] == 0, (t, got.reason[j])
        ref = ref_state(name, T)
        assert close(got.T1[j], ref[0]) and close(got.T2[j], ref[1]), (t, got.T1[j], ref)
        assert close(got.alpha[j], ref[2])
        with mpmath.workdps(DPS):
            E = tuple(mp(j.c[0]) for j in m.at(T + t0, 1))
            C, D = elbows(rb, E, modes)
            th1 = mpmath.atan2(C[1], C[0])
            th2 = mpmath.atan2(D[1], D[0] - rb.a)
            d = ref_delta(C, D, E)
        assert close(got.theta1[j], th1) and close(got.theta2[j], th2)
        assert close(got.delta[j], d) and close(got.x[j], E[0]) and close(got.y[j], E[1])


@pytest.mark.parametrize("name", ["consistent", "tangent", "stop", "inconsistent"])
def test_samples_at_the_instant_are_the_limits_or_marked_unbounded(name: str) -> None:
    got = sample(certified(name), np.array([float(TS)]))
    if name == "inconsistent":
        assert got.reason[0] == POLE
        assert math.isnan(got.T1[0]) and math.isnan(got.T2[0]) and math.isnan(got.alpha[0])
        return
    assert got.reason[0] == 0 and got.delta[0] == 0.0
    eps = Q(1, 10**25)  # the reference's own limit: both sides, 0/0 absorbed by 60 digits
    lo, hi = ref_state(name, TS - eps), ref_state(name, TS + eps)
    for i, v in enumerate((got.T1[0], got.T2[0], got.alpha[0])):
        assert close(v, (lo[i] + hi[i]) / 2)


def test_samples_past_a_stretched_leg_are_marked_type_one() -> None:
    rb, _, modes, _, _ = case("consistent")
    far = Motion((Q(10), Q(40)), (Q(10),))  # E leaves leg 2's reach (|E - B| > 26)
    x, y = polys(far)
    fm = FiveBarMotion(robot(rb, modes), q(rb.g), x, y, fmpq(1), ())
    got = sample(fm, np.array([0.0, 1.0]))
    assert got.reason.tolist() == [0, TYPE_ONE]
    assert math.isnan(got.T1[1]) and got.x[1] == 50.0


# -- the peak -----------------------------------------------------------------------------
def ref_max(name: str, i: int, lo: Q, hi: Q, n: int = 60) -> Any:
    """max |T_i| over [lo, hi] by the reference: n + 1 points (t_s avoided by 10^-25),
    then golden-section search about the best."""

    def f(t: Q) -> Any:
        T = t
        if name != "line" and T == TS:
            T += Q(1, 10**25)
        return abs(ref_torques(name, T)[i])

    return maximum(f, lo, hi, n)


def maximum(f: Callable[[Q], Any], lo: Q, hi: Q, n: int) -> Any:
    """max of f over [lo, hi]: n + 1 points, then golden-section search about the best,
    at doubles (f takes each exactly)."""
    ts = [lo + (hi - lo) * Q(k, n) for k in range(n + 1)]
    vals = [f(t) for t in ts]
    k = max(range(n + 1), key=lambda j: vals[j])
    a, b = float(ts[max(k - 1, 0)]), float(ts[min(k + 1, n)])
    g = (math.sqrt(5) - 1) / 2
    best = vals[k]
    for _ in range(30):
        c, d = a + (b - a) * (1 - g), a + (b - a) * g
        fc, fd = f(Q(c)), f(Q(d))
        best = max(best, fc, fd)
        if fc >= fd:
            b = d
        else:
            a = c
    return best


# The reference's maxima (``ref_max``: ~120 Newton-Euler evaluations at 60 digits each)
# are stored beside this file by their case (the motion, the joint, the span, the grid),
# like the crossings below: the reference's values never change. Written by ``python -m
# tests.fivebar.test_certified``; a slow test recomputes every stored case, and a case not
# stored (a new one, or one whose motion changed) is computed here.
MAXIMA = Path(__file__).with_name("peak_maxima_reference.json")
PEAK_NAMES = ["consistent", "tangent", "stop"]


@cache
def _stored_maxima() -> dict[str, str]:
    return json.loads(MAXIMA.read_text(encoding="utf-8")) if MAXIMA.exists() else {}


def _maximum_key(name: str, i: int, lo: Q, hi: Q, n: int) -> str:
    return repr(("maximum", name, case(name)[1], i, str(lo), str(hi), n))


def maximum_cases() -> list[tuple[str, Callable[[], Any]]]:
    """(key, the reference's computation) of every maximum the peak tests read."""
    spans = [(Q(0), TF, 60), (TS - Q(1, 1000), TS + Q(1, 1000), 40)]
    return [
        (_maximum_key(name, i, lo, hi, n), partial(ref_max, name, i, lo, hi, n))
        for name in PEAK_NAMES
        for lo, hi, n in spans
        for i in (0, 1)
    ]


def stored_max(name: str, i: int, lo: Q, hi: Q, n: int = 60) -> Any:
    """``ref_max``: stored, or computed when not."""
    return stored_maximum(_maximum_key(name, i, lo, hi, n), partial(ref_max, name, i, lo, hi, n))


def stored_maximum(key: str, compute: Callable[[], Any]) -> Any:
    """The reference's maximum of the case ``key``: stored, or computed when not."""
    row = _stored_maxima().get(key)
    if row is None:
        return compute()
    with mpmath.workdps(40):  # the 30 digits stored, read back as written
        return mpmath.mpf(row)


@pytest.mark.parametrize("name", PEAK_NAMES)
def test_the_peak_brackets_the_references_maximum(name: str) -> None:
    peaks = torque_peak(certified(name))
    for i, p in enumerate(peaks):
        ref = stored_max(name, i, Q(0), TF)
        assert p.certified and p.upper - p.value <= 1e-6 * p.value + 1e-9
        assert p.value <= ref + TOL * (1 + ref) and ref <= p.upper, (p, ref)
        assert close(p.value, abs(ref_torques(name, Q(p.t))[i]) - TOL)  # attained at t


@pytest.mark.parametrize("name", PEAK_NAMES)
def test_the_peak_about_a_bounded_instant_is_finite_and_right(name: str) -> None:
    span = (TS - Q(1, 1000), TS + Q(1, 1000))
    peaks = torque_peak(certified(name), span=(q(span[0]), q(span[1])))
    for i, p in enumerate(peaks):
        ref = stored_max(name, i, *span, n=40)
        assert math.isfinite(p.upper) and p.certified, p
        assert p.value <= ref + TOL * (1 + ref) and ref <= p.upper, (p, ref)


@pytest.mark.parametrize("name", ["inconsistent", "line"])
def test_the_peak_at_a_pole_is_infinite_at_the_instant(name: str) -> None:
    fm = certified(name)
    peaks = torque_peak(fm)
    assert all(p.value == p.upper == math.inf and p.t == fm.instants[0].t for p in peaks)


# -- the limit ----------------------------------------------------------------------------
# The reference's crossings of |T_i| = limit (bisections of Newton-Euler's torques at 60
# digits: seconds each) are stored beside this file by their case (the motion, the
# joint, the limit, the span): the reference's values never change. Written by
# ``python -m tests.fivebar.test_certified``; a slow test recomputes every stored case,
# and a case not stored (a new one, or one whose motion changed) is computed here.
CROSSINGS = Path(__file__).with_name("limit_crossings_reference.json")


@cache
def _stored_crossings() -> dict[str, list[str]]:
    return json.loads(CROSSINGS.read_text(encoding="utf-8")) if CROSSINGS.exists() else {}


def _encode(roots: list[Any]) -> list[str]:
    return [mpmath.nstr(r, 30) for r in roots]


def stored(key: str, compute: Callable[[], list[Any]]) -> list[Any]:
    """The reference's crossings of the case ``key``: stored, or computed when not."""
    rows = _stored_crossings().get(key)
    return compute() if rows is None else _decode(rows)


def _decode(rows: list[str]) -> list[Any]:
    with mpmath.workdps(40):  # the 30 digits stored, read back as written
        return [mpmath.mpf(r) for r in rows]


LIMITS = [
    ("consistent", (60.0, 40.0)), ("inconsistent", (300.0, 250.0)), ("line", (30.0, 20.0)),
    ("stop", (80.0, 18.0)),
]  # fmt: skip


def _limit_span(name: str) -> tuple[Q, float | None]:
    """t_f of the case and its pole (the step holding it is left out), if any."""
    fm = certified(name)
    poles = [s.t for s in fm.instants if not s.bounded]
    return Q(int(fm.duration.p), int(fm.duration.q)), (poles[0] if poles else None)


def crossing_cases() -> list[tuple[str, Callable[[], list[Any]]]]:
    """(key, the reference's computation) of every case of the limit tests here."""
    out = []
    for name, limit in LIMITS:
        tf, pole = _limit_span(name)
        for i in (0, 1):
            key = repr(("one piece", name, case(name)[1], i, limit[i], str(tf), pole))
            out.append((key, partial(_ref_crossings, name, i, limit[i], tf, pole)))
    return out


def ref_crossings(name: str, i: int, limit: float, tf: Q, pole: float | None) -> list[Any]:
    key = repr(("one piece", name, case(name)[1], i, limit, str(tf), pole))
    return stored(key, partial(_ref_crossings, name, i, limit, tf, pole))


def _ref_crossings(name: str, i: int, limit: float, tf: Q, pole: float | None) -> list[Any]:
    """The times at which |T_i| = limit by the reference: sign changes of |T_i| - limit
    on 120 steps (the pole left out), each bisected to 2^-70 t_f."""

    def g(t: Q) -> Any:
        return abs(ref_torques(name, t)[i]) - limit

    n = 120
    ts = [tf * Q(k, n) for k in range(n + 1)]
    ts = [t for t in ts if pole is None or abs(float(t) - pole) > 1e-6]
    return bisected(g, ts, pole)


def bisected(g: Callable[[Q], Any], ts: list[Q], pole: float | None = None) -> list[Any]:
    """The roots of g in every step of ``ts`` where g changes sign (a step holding the
    ``pole`` left out), each bisected 64 times: the lower end of its last bracket."""
    out = []
    vals = [g(t) for t in ts]
    for a, b, ga, gb in zip(ts, ts[1:], vals, vals[1:], strict=False):
        if (ga > 0) == (gb > 0):
            continue
        if pole is not None and a < pole < b:
            continue
        for _ in range(64):
            c = (a + b) / 2
            if (g(c) > 0) == (ga > 0):
                a = c
            else:
                b = c
        out.append(mpmath.mpf(a.numerator) / a.denominator)
    return out


@pytest.mark.parametrize(("name", "limit"), LIMITS)
def test_limit_windows_bracket_the_references_crossings(
    name: str, limit: tuple[float, float]
) -> None:
    fm = certified(name)
    poles = [s.t for s in fm.instants if not s.bounded]
    checks = limit_check(fm, limit)
    tf, pole = _limit_span(name)
    for i, c in enumerate(checks):
        ref = ref_crossings(name, i, limit[i], tf, pole)
        brackets = [(w.start_lo, w.start_hi) for w in c.windows if w.start_hi > 0]
        brackets += [(w.end_lo, w.end_hi) for w in c.windows if w.end_lo < float(tf) - 1e-15]
        assert len(brackets) == len(ref), (c, ref)
        for (lo, hi), r in zip(sorted(brackets), ref, strict=True):
            assert lo <= r <= hi and hi - lo <= c.resolution * 1.01, (lo, r, hi)
        assert c.passed is (not ref and not poles)
        assert [w.pole for w in c.windows].count(True) == len(poles)


def test_a_limit_above_the_peak_passes() -> None:
    fm = certified("consistent")
    checks = limit_check(fm, (1000.0, 1000.0))
    assert all(c.passed is True and not c.windows for c in checks)


# -- rprpr check, export and the Python API -----------------------------------------------
def _task(folder: Path, name: str, extra: str) -> Path:
    from .test_check import task_file

    return task_file(folder, name, motions()[name], extra)


def test_check_reports_the_peak_and_the_limit_as_the_rprprs(tmp_path: Path) -> None:
    from .test_check import check_json

    path = _task(tmp_path, "inconsistent", "checks:\n  torque_limit: [300, 250]\n")
    code, rep = check_json(path, "--peak")
    assert code == 1
    assert rep["torque_peak"] is None  # infinite: JSON's null, as the RPRPR's
    assert [c["passed"] for c in rep["torque_limit"]] == [False, False]
    assert [c["pole"] for c in rep["torque_limit"]] == [[True], [True]]
    sat = rep["singularities"][0]["saturation"]
    assert [s["limit"] for s in sat] == [300.0, 250.0]
    rules = [f["rule"] for f in rep["findings"]]
    assert rules == ["RPR201", "RPR202"]
    assert "|T1| > 300 N m for" in rep["findings"][1]["message"]

    path = _task(tmp_path, "consistent", "checks:\n  torque_limit: [1000, 1000]\n")
    code, rep = check_json(path, "--peak")
    assert code == 0 and rep["torque_peak_certified"] is True
    assert [c["passed"] for c in rep["torque_limit"]] == [True, True]


def test_export_writes_the_5rs_columns_with_the_references_values(tmp_path: Path) -> None:
    from tests.conftest import run_cli

    path = _task(tmp_path, "consistent", "")
    out = tmp_path / "s.csv"
    code, _, err = run_cli("export", str(path), "-o", str(out), "--samples", "5")
    assert (code, err) == (0, f"rprpr: wrote {out} (5 samples)\n")
    lines = out.read_text().splitlines()
    assert lines[0].startswith("# rprpr ") and "7 = a leg stretched or folded" in lines[0]
    head = lines[1].split(",")
    assert head[:6] == ["t", "x", "y", "x_dot", "y_dot", "theta1"] and head[-1] == "reason"
    m = motions()["consistent"]
    for row in lines[2:]:
        v = dict(zip(head, row.split(","), strict=True))
        t = Q(float(v["t"]))
        with mpmath.workdps(DPS):
            ref = torques(ROBOT, m, t - Q(1, 10), MODES)
        assert close(float(v["T1"]), ref[0]) and close(float(v["T2"]), ref[1])


def test_the_api_gives_samples_and_the_report(tmp_path: Path) -> None:
    import rprpr

    path = _task(tmp_path, "stop", "checks:\n  peak: true\n")
    result = rprpr.audit(rprpr.load_task(path), samples=3)
    assert result.samples.T1.shape == (3,) and result.samples.reason.tolist() == [0, 0, 0]
    report = result.to_dict()
    assert report["torque_peak_certified"] is True and report["mechanism"] == "5R"
    assert report["torque_peak"][0] == result.torque_peak[0].value


LAYERS = [
    ("", []),  # the exact verdicts alone: no ball machinery
    ("checks:\n  torque_limit: [1000, 1000]\n", ["certified.five_bar", "five_bar_certified"]),
]


def _layers_probe(extra: str, folder: Path) -> str:
    """A fresh process's check of a task (written into ``folder``) with ``extra``: the
    certified and bounds modules it loaded, on standard error."""
    path = _task(folder, "consistent", extra)
    return (
        "import sys\n"
        "from rprpr.cli.check import check_one\n"
        "from rprpr.cli.options import CheckOptions\n"
        f"kind, *_ = check_one({str(path)!r}, CheckOptions())\n"
        "got = sorted(m.removeprefix('rprpr.engine.') for m in sys.modules"
        " if m.startswith(('rprpr.engine.certified.', 'rprpr.engine.bounds.',"
        " 'rprpr.engine.five_bar_certified')))\n"
        "sys.stderr.write(f'KIND={kind} LOADED={got}\\n')\n"
    )


for _extra, _ in LAYERS:  # start-up probes (``tests.cli.forked.fresh_probe``), in the clone
    fresh_probe(
        f"test_certified layers {_extra!r}",
        "numpy, flint, yaml, click, rich.console",
        partial(_layers_probe, _extra),
        Path(__file__).resolve().parents[2],
    )


@pytest.mark.parametrize(("extra", "loaded"), LAYERS)
def test_check_loads_the_certified_layers_only_for_a_task_that_asks(
    extra: str, loaded: list[str], fresh: dict[str, tuple[int, str, str]]
) -> None:
    import ast

    _, _, stderr = fresh[f"test_certified layers {extra!r}"]
    last = stderr.strip().splitlines()[-1]
    assert last.startswith("KIND=report LOADED=")
    got = ast.literal_eval(last.split("LOADED=")[1])
    assert [m for m in got if "five_bar" in m] == loaded
    if not extra:  # the plain records of the verdicts only (every check imports them)
        assert got == ["bounds.verdicts"], got


def test_the_json_export_names_the_5rs_instants_columns_and_units(tmp_path: Path) -> None:
    import json

    from tests.conftest import run_cli

    path = _task(tmp_path, "inconsistent", "")
    code, out, err = run_cli("export", str(path), "--format", "json", "--samples", "3")
    assert (code, err) == (0, "")
    doc = json.loads(out)
    (s,) = doc["singularities"]
    assert (s["t"], s["modes"], s["sigma"], s["order"], s["pole_order"]) == (0.1, [1, -1], -1, 1, 1)
    assert doc["units"]["delta"] == "m^2" and doc["units"]["alpha"] == "N"
    assert doc["columns"][-1] == "reason" and len(doc["rows"]) == 3
    assert doc["reasons"]["1"].startswith("a Type II instant with unbounded torques")


DEXTAR = FiveBar(
    Q(1, 5), (Q(1, 5), Q(1, 5), Q(3, 10), Q(3, 10)),
    (Q(1, 4), Q(1, 4), Q(3, 20), Q(3, 20)), (Q(83, 100000),) * 2 + (Q(9, 8000),) * 2,
    (Q(1, 10), Q(1, 10), Q(3, 20), Q(3, 20)), Q(981, 100),
)  # fmt: skip


@pytest.mark.parametrize(
    "m",
    [  # E moves down and left: the elbow C (mode +1, left of AE) passes the negative
        # x-axis, where the principal angle jumps from π to -π; in the second, exactly at
        # t = 1/4 (a sample): C = (-0.2, 0) when E = (-0.02, 0.24)
        Motion((Q(-1, 20), Q(-3, 10)), (Q(3, 10), Q(-9, 25))),
        Motion((Q(-1, 50) + Q(3, 40), Q(-3, 10)), (Q(6, 25) + Q(9, 100), Q(-9, 25))),
    ],
)
def test_the_motors_angles_are_continuous_across_the_negative_axis(m: Motion) -> None:
    x, y = polys(m)
    fm = FiveBarMotion(robot(DEXTAR, (1, -1)), q(DEXTAR.g), x, y, fmpq(1, 2), ())
    ts = grid(fmpq(1, 2), 41)
    got = sample(fm, ts)
    assert (got.reason == 0).all()
    assert np.abs(np.diff(got.theta1)).max() < 0.2 and np.abs(np.diff(got.theta2)).max() < 0.2
    assert got.theta1[0] < math.pi < got.theta1[-1]  # crossed, not wrapped
    for j, t in enumerate(ts.tolist()):
        with mpmath.workdps(DPS):
            E = tuple(mp(jet.c[0]) for jet in m.at(Q(t), 1))
            C, D = elbows(DEXTAR, E, (1, -1))
            for v, ref in ((got.theta1[j], mpmath.atan2(C[1], C[0])),
                           (got.theta2[j], mpmath.atan2(D[1], D[0] - DEXTAR.a))):  # fmt: skip
                turns = round((v - float(ref)) / (2 * math.pi))
                assert close(v, ref + 2 * mpmath.pi * turns), (t, v, ref)


def test_two_rational_crossings_closer_than_a_double_are_told_apart() -> None:
    """Leg 1's elbow C is at (-13, 0) (on the negative x-axis) where E is on the circle
    of radius 13 about it: at s = 1/2 and s = 1/2 + 2^-70 of its rational parametrisation,
    P1 and P2. E runs along the chord P1 P2, through P1 at t1 = 1/8 and P2 at t2 = t1 + ε:
    C dips below the axis between them (the chord is inside the circle). The two times
    are rational roots of P closer than a double tells apart; the crossings are both,
    exact, with opposite turns, as the reference's elbows (mpmath) say c_y changes sign."""
    from rprpr.engine.certified.five_bar_angles import crossings

    eps = Q(1, 2**70)

    def on_circle(s: Q) -> tuple[Q, Q]:
        return (-13 + 13 * (1 - s * s) / (1 + s * s), 13 * 2 * s / (1 + s * s))

    p1, p2 = on_circle(Q(1, 2)), on_circle(Q(1, 2) + eps)
    t1, t2 = Q(1, 8), Q(1, 8) + eps
    v = ((p2[0] - p1[0]) / eps, (p2[1] - p1[1]) / eps)
    m = Motion((p1[0] - v[0] * t1, v[0]), (p1[1] - v[1] * t1, v[1]))
    x, y = polys(m)
    fm = FiveBarMotion(robot(ROBOT, MODES), q(ROBOT.g), x, y, fmpq(1, 4), ())
    got = crossings(fm, 1)
    assert [c.exact for c in got] == [q(t1), q(t2)]
    with mpmath.workdps(200):
        signs = []
        for t in (t1 - eps, (t1 + t2) / 2, t2 + eps):
            E = tuple(mp(j.c[0]) for j in m.at(t, 1))
            C, _ = elbows(ROBOT, E, MODES)
            signs.append(int(mpmath.sign(C[1])))
            assert C[0] < 0
    assert signs[0] == signs[2] == -signs[1] != 0
    # c_y from + to - on the negative axis: the angle passes π upward (+1), and back
    assert [(c.before, c.turn) for c in got] == [(signs[0], signs[0]), (signs[1], signs[1])]


def _all_crossing_cases() -> list[tuple[str, Callable[[], list[Any]]]]:
    from . import test_certified_pieces

    return crossing_cases() + test_certified_pieces.crossing_cases()


@pytest.mark.slow  # Newton-Euler at 60 digits, bisected at every crossing of every case
def test_the_stored_crossings_are_the_references() -> None:
    cases = _all_crossing_cases()
    assert {k for k, _ in cases} == set(_stored_crossings())  # every stored case is live
    for key, compute in cases:
        assert _encode(compute()) == _stored_crossings()[key], key


def _all_maximum_cases() -> list[tuple[str, Callable[[], Any]]]:
    from . import test_certified_pieces

    return maximum_cases() + test_certified_pieces.maximum_cases()


@pytest.mark.slow  # Newton-Euler at 60 digits, dense and golden-section about each maximum
def test_the_stored_maxima_are_the_references() -> None:
    cases = _all_maximum_cases()
    assert {k for k, _ in cases} == set(_stored_maxima())  # every stored case is live
    for key, compute in cases:
        assert _encode([compute()]) == [_stored_maxima()[key]], key


def _write_crossings() -> None:
    table = {key: _encode(compute()) for key, compute in _all_crossing_cases()}
    for rows in table.values():  # the tests read back the digits stored
        assert _encode(_decode(rows)) == rows
    CROSSINGS.write_text(json.dumps(table, indent=1) + "\n", encoding="utf-8")


def _write_maxima() -> None:
    table = {key: _encode([compute()])[0] for key, compute in _all_maximum_cases()}
    for row in table.values():  # the tests read back the digits stored
        assert _encode(_decode([row])) == [row]
    MAXIMA.write_text(json.dumps(table, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    _write_crossings()
    _write_maxima()

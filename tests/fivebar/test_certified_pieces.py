"""The 5R's certified layers on a motion of several pieces against the Newton-Euler
reference (reference.py, mpmath at 60 digits; it imports nothing from rprpr).

The motion is test_check's consistent crossing (its instant at t_s = 1/10, bounded) cut
at the knot K = 3/20, the second piece with y raised by 2 (t - K)³ (continuous to the
acceleration at K, a piece of its own polynomials): the reference evaluates each piece on
its own span. The peak's bracket must hold the reference's maximum over both pieces; a
limit window that runs across the knot must hold the reference's crossings on each side
of it (and the next window's); the exported rows of each piece the reference's torques.
"""

from __future__ import annotations

from collections.abc import Callable
from fractions import Fraction as Q
from functools import cache, partial
from itertools import pairwise
from pathlib import Path
from typing import Any

import mpmath
import sympy as sp

from tests.conftest import run_cli

from .reference import DPS, Motion, torques
from .test_certified import bisected, maximum, stored, stored_maximum
from .test_check import MODES, ROBOT, TF, TS, absolute, check_json, motions
from .test_pieces import pieces_file

TOL = 1e-9  # the samples' certified mixed error
K = Q(3, 20)  # the knot
LIMIT = (60.0, 40.0)


def _raised(m: Motion, c: Q) -> Motion:
    """m with y raised by c (t - K)³ (absolute time)."""
    t = sp.Symbol("t")
    y = sum(sp.Rational(a.numerator, a.denominator) * t**i for i, a in enumerate(m.y))
    p = sp.Poly(y + sp.Rational(c.numerator, c.denominator) * (t - sp.Rational(3, 20)) ** 3, t)
    return Motion(m.x, tuple(Q(int(a.p), int(a.q)) for a in reversed(p.all_coeffs())))


@cache
def pieces() -> tuple[tuple[Q, Q, Motion], ...]:
    m = absolute(motions()["consistent"])
    return ((Q(0), K, m), (K, TF, _raised(m, Q(2))))


def _task(folder: Path, checks: str = "") -> Path:
    path = pieces_file(folder, "two", [(b, m) for _, b, m in pieces()])
    path.write_text(path.read_text() + checks)
    return path


def holding(t: Q) -> Motion:
    """The piece holding t (the later one at the knot; the last one at the double of t_f,
    just above it)."""
    return next(m for a, _, m in reversed(pieces()) if a <= t)


@cache
def ref(m: Motion, t: Q) -> tuple[Any, Any]:
    if t == TS:
        t += Q(1, 10**25)  # the bounded instant: the limit
    with mpmath.workdps(DPS):
        return torques(ROBOT, m, t, MODES)


def ref_max(i: int, lo: Q, hi: Q, m: Motion, n: int = 60) -> Any:
    """max |T_i| over [lo, hi] of the piece m: n + 1 points, then golden-section search."""

    def f(t: Q) -> Any:
        return abs(ref(m, t)[i])

    return maximum(f, lo, hi, n)


def _maximum_key(i: int, lo: Q, hi: Q, m: Motion, n: int = 60) -> str:
    return repr(("maximum over a piece", i, str(lo), str(hi), m, n))


def maximum_cases() -> list[tuple[str, Callable[[], Any]]]:
    """(key, the reference's computation) of the peak test's maxima here (stored beside
    test_certified, ~360 Newton-Euler evaluations at 60 digits)."""
    return [(_maximum_key(i, a, b, m), partial(ref_max, i, a, b, m)) for i in (0, 1)
            for a, b, m in pieces()]  # fmt: skip


def stored_max(i: int, lo: Q, hi: Q, m: Motion) -> Any:
    """``ref_max``: stored beside test_certified, or computed when not."""
    return stored_maximum(_maximum_key(i, lo, hi, m), partial(ref_max, i, lo, hi, m))


def crossing_cases() -> list[tuple[str, Callable[[], list[Any]]]]:
    """(key, the reference's computation) of the limit test's cases here."""
    return [(_crossings_key(i), partial(_ref_crossings, i, LIMIT[i])) for i in (0, 1)]


def _crossings_key(i: int) -> str:
    return repr(("two pieces", pieces(), i, LIMIT[i]))


def ref_crossings(i: int, limit: float) -> list[Any]:
    """The reference's crossings of |T_i| = limit (stored beside test_certified)."""
    assert limit == LIMIT[i]
    return stored(_crossings_key(i), partial(_ref_crossings, i, limit))


def _ref_crossings(i: int, limit: float) -> list[Any]:
    """The times at which |T_i| = limit by the reference, on each piece apart: sign
    changes of |T_i| - limit on 60 steps of its span, each bisected 64 times."""
    out = []
    for lo, hi, m in pieces():

        def g(t: Q, m: Motion = m) -> Any:
            return abs(ref(m, t)[i]) - limit

        out += bisected(g, [lo + (hi - lo) * Q(k, 60) for k in range(61)])
    return out


def close(v: float, r: Any) -> bool:
    with mpmath.workdps(DPS):
        return bool(abs(mpmath.mpf(v) - r) <= TOL * (1 + abs(r)))


def test_the_peak_brackets_the_references_maximum_over_both_pieces(tmp_path: Path) -> None:
    code, rep = check_json(_task(tmp_path), "--peak")
    assert code == 0 and rep["torque_peak_certified"] is True
    for i, value in enumerate(rep["torque_peak"]):
        each = [stored_max(i, a, b, m) for a, b, m in pieces()]
        top = max(each)
        assert each[1] > each[0]  # the peak is on the second piece: the max is over both
        assert value <= top + TOL * (1 + top) <= value * (1 + 2e-6) + 1e-9, (value, each)
        t = Q(rep["torque_peak_t"][i])
        assert close(value, abs(ref(holding(t), t)[i]) - TOL)  # attained at its time


def test_a_limit_window_across_the_knot_brackets_the_crossings_on_each_side(
    tmp_path: Path,
) -> None:
    checks = f"checks:\n  torque_limit: [{LIMIT[0]:g}, {LIMIT[1]:g}]\n"
    _, rep = check_json(_task(tmp_path, checks))
    for i, c in enumerate(rep["torque_limit"]):
        r = ref_crossings(i, LIMIT[i])
        assert c["passed"] is False and c["pole"] == [False, False]
        first, _ = c["exceeded"]
        assert first[0] < float(K) < first[1]  # one window across the knot, joined
        brackets = [b for w in c["crossings"] for b in w if b[0] < float(TF) - 1e-15]
        assert len(brackets) == len(r) == 3, (brackets, r)
        assert sum(x < float(K) for x in r) == 1  # a crossing on each side of the knot
        for (lo, hi), x in zip(brackets, r, strict=True):
            assert lo <= x <= hi and hi - lo <= c["resolution"] * 1.01, (lo, x, hi)


def test_export_rows_on_each_piece_hold_the_references_torques(tmp_path: Path) -> None:
    out = tmp_path / "s.csv"
    code, _, err = run_cli("export", str(_task(tmp_path)), "-o", str(out), "--samples", "9")
    assert (code, err) == (0, f"rprpr: wrote {out} (9 samples)\n")
    lines = out.read_text().splitlines()
    head = lines[1].split(",")
    rows = [dict(zip(head, row.split(","), strict=True)) for row in lines[2:]]
    assert sum(Q(float(v["t"])) > K for v in rows) == 2  # rows on both pieces
    for v in rows:
        t = Q(float(v["t"]))
        assert v["reason"] == "0"
        T = ref(holding(t), t)
        assert close(float(v["T1"]), T[0]) and close(float(v["T2"]), T[1]), (t, v, T)


# -- waypoints: pieces in their local time, a pole inside segment 2 -------------------------
def _waypoints(folder: Path, checks: str = "") -> tuple[Path, list[tuple[Q, Q, Motion]]]:
    from .test_pieces import WAYPOINTS, _quintic, _row, robot_text

    rows = "".join(
        f"    - {{t: {r[0]}, p: [{r[1]}, {r[2]}], v: [{r[3]}, {r[4]}], a: [{r[5]}, {r[6]}]}}\n"
        for r in map(_row, WAYPOINTS)
    )
    path = folder / "wp.rprpr.yaml"
    path.write_text(f"name: wp\n{robot_text()}motion:\n  waypoints:\n{rows}{checks}")
    segments = [
        (w0[0], w1[0], Motion(_quintic(w0, w1, 0), _quintic(w0, w1, 1)))
        for w0, w1 in pairwise(WAYPOINTS)
    ]
    return path, segments


def test_waypoints_peak_is_infinite_at_the_pole_and_the_limit_window_holds_it(
    tmp_path: Path,
) -> None:
    """The waypoints' segment 2 crosses the pose inconsistently at an irrational time:
    the peak is infinite there, and each torque's limit fails with one window holding the
    pole, inside segment 2 (the reference's |T| past the limit on either side of it)."""
    path, segments = _waypoints(tmp_path, "checks:\n  torque_limit: [3000, 3000]\n")
    code, rep = check_json(path, "--peak")
    assert code == 1 and rep["torque_peak"] is None
    (s,) = [s for s in rep["singularities"] if s["t_exact"] is None]
    lo, hi, m = segments[1]

    def above(t: float, i: int) -> bool:
        with mpmath.workdps(DPS):
            return bool(abs(torques(ROBOT, m, Q(t), MODES)[i]) > 3000)

    for i, c in enumerate(rep["torque_limit"]):
        assert c["passed"] is False and c["pole"] == [True]
        ((a, b),) = c["exceeded"]
        assert float(lo) < a < s["t"] < b < float(hi)
        (start, end) = c["crossings"][0]
        assert end[1] - end[0] <= c["resolution"] * 1.01 >= start[1] - start[0]
        # the reference crosses the limit in each bracket (1e-7 on either side of it)
        assert not above(start[0] - 1e-7, i) and above(start[1] + 1e-7, i)
        assert above(end[0] - 1e-7, i) and not above(end[1] + 1e-7, i)


def test_waypoints_export_rows_hold_the_references_torques(tmp_path: Path) -> None:
    path, segments = _waypoints(tmp_path)
    out = tmp_path / "s.csv"
    code, _, err = run_cli("export", str(path), "-o", str(out), "--samples", "6")
    assert (code, err) == (0, f"rprpr: wrote {out} (6 samples)\n")
    lines = out.read_text().splitlines()
    head = lines[1].split(",")
    for row in lines[2:]:
        v = dict(zip(head, row.split(","), strict=True))
        t = Q(float(v["t"]))
        m = next(m for a, _, m in reversed(segments) if a <= t)  # the later one at a knot
        assert v["reason"] == "0"
        with mpmath.workdps(DPS):
            T = torques(ROBOT, m, t, MODES)
        assert close(float(v["T1"]), T[0]) and close(float(v["T2"]), T[1]), (t, v, T)

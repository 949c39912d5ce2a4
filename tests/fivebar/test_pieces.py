"""``rprpr check`` on 5R motions of several pieces, against the references of this folder.

The robot and motions are test_check's (the a = 14, links-13 robot, its rational singular
pose E = (63/5, 49/5) at t_s = 1/10 in working modes (+1, -1), σ = -1). The pieces are
written as ``motion.pieces``, ``timing.x`` pieces under a path y = p(x), and waypoints
(inline and from a CSV file); the reference's instants (instants.py: sympy's exact real
roots of S_σ(E(t)) on each piece's span, the robot's own δ at 60 digits, its order from
δ's series) are computed on each piece's polynomials, written here apart from the
engine (the waypoints' quintic segments solved by sympy from their end conditions), and
Newton-Euler (reference.py) says on which side of a knot the torques stay bounded.
"""

from __future__ import annotations

import itertools
from fractions import Fraction as Q
from functools import cache
from pathlib import Path
from typing import Any

import mpmath
import pytest
import sympy as sp

from tests.conftest import run_cli

from .instants import Instant, singular_instants
from .reference import DPS, Motion, torques
from .test_check import (
    MODES,
    ROBOT,
    TF,
    TS,
    Z,
    _decimal,
    _poly,
    absolute,
    check_json,
    motions,
    robot_text,
)

ALL = ((1, 1), (1, -1), (-1, 1), (-1, -1))


def pieces_file(
    folder: Path, name: str, pieces: list[tuple[Q, Motion]], modes: tuple[int, int] = MODES
) -> Path:
    """A 5R task whose motion.pieces are (until, E(t) in absolute time)."""
    rows = "".join(
        f"    - until: {_decimal(until)}\n      x: {_poly(m.x)}\n      y: {_poly(m.y)}\n"
        for until, m in pieces
    )
    robot = robot_text().replace("modes: [+1, -1]", f"modes: [{modes[0]:+d}, {modes[1]:+d}]")
    path = folder / f"{name}.rprpr.yaml"
    path.write_text(f"name: {name}\n{robot}motion:\n  pieces:\n{rows}")
    return path


def reference(pieces: list[tuple[Q, Q, Motion]], modes: tuple[int, int] = MODES) -> list[Instant]:
    """The reference's instants of the motion made of ``pieces`` (start, end, E(t)), in
    time order, an instant at a knot once."""
    found: dict[Any, Instant] = {}
    for t0, t1, m in pieces:
        for i in singular_instants(ROBOT, m, modes, t0, t1):
            found.setdefault(i.t, i)
    return sorted(found.values(), key=lambda i: sp.N(i.t, 30))


def same_instants(got: list[dict[str, Any]], ref: list[Instant], modes: tuple[int, int]) -> None:
    assert len(got) == len(ref)
    for s, r in zip(got, ref, strict=True):
        assert abs(s["t"] - float(sp.N(r.t, 30))) <= 1e-15
        assert s["t_exact"] == (str(r.t) if r.t.is_Rational else None)
        assert (s["order"], s["sigma"], s["modes"]) == (r.order, r.sigma, list(modes))


def _rules(rep: dict[str, Any]) -> list[tuple[str, float]]:
    return [(f["rule"], f["t"]) for f in rep["findings"]]


def one_sided_bounded(m: Motion, side: int) -> bool:
    """Newton-Euler at 60 digits on one side of t_s (``m`` in the local time τ = t - t_s):
    |T| at τ = ±10^-11 within twice |T| at ±10^-9 (a pole multiplies it by 100)."""
    T = [torques(ROBOT, m, Q(side, 10**k), MODES) for k in (9, 11)]
    with mpmath.workdps(DPS):
        far, near = (max(abs(t[0]), abs(t[1])) for t in T)
        return bool(near < 2 * far)


# -- motion.pieces ----------------------------------------------------------------------


@pytest.mark.parametrize("modes", ALL, ids=lambda m: f"{m[0]:+d}{m[1]:+d}")
def test_an_instant_inside_a_piece_in_each_working_mode(
    tmp_path: Path, modes: tuple[int, int]
) -> None:
    """The consistent crossing cut into three pieces at t = 1/20 and 3/20 (one polynomial:
    no jump at the knots): the working modes of the task file are carried across the
    knots, and each mode has the reference's instants in that mode (the pose's instant at
    t_s = 1/10 inside piece 2 in the modes (+1, -1) only)."""
    m = absolute(motions()["consistent"])
    cuts = [Z, Q(1, 20), Q(3, 20), TF]
    path = pieces_file(tmp_path, "three", [(b, m) for b in cuts[1:]], modes)
    ref = reference([(a, b, m) for a, b in itertools.pairwise(cuts)], modes)
    assert (TS in [r.t for r in ref]) == (modes == MODES)
    code, rep = check_json(path)
    same_instants(rep["singularities"], ref, modes)
    assert [k["t_exact"] for k in rep["knots"]] == ["1/20", "3/20"]
    assert all(k["velocity_jump"] is None and k["acceleration_jump"] is None for k in rep["knots"])
    if modes == MODES:
        (s,) = [s for s in rep["singularities"] if s["t_exact"] == "1/10"]
        assert s["knot"] is False and s["torque_bounded"] and s["consistent"]
        assert code == 0 and rep["verdict"] == "pass" and rep["findings"] == []


def test_an_instant_at_a_knot_is_judged_from_each_side(tmp_path: Path) -> None:
    """Consistent up to t_s, inconsistent after (ÿ raised by 1/10 at the knot t_s = 1/10):
    Newton-Euler keeps the torques bounded before and not after; the report has one
    instant at the knot, bounded before, unbounded after, RPR201 (and RPR204: the
    acceleration jumps by (0, 1/10), the torques undefined at the singular knot)."""
    before, after = motions()["consistent"], motions()["inconsistent"]
    assert one_sided_bounded(before, -1) and not one_sided_bounded(after, 1)
    a, b = absolute(before), absolute(after)
    path = pieces_file(tmp_path, "knot", [(TS, a), (TF, b)])
    ref = reference([(Z, TS, a), (TS, TF, b)])
    assert [(r.t, r.order) for r in ref] == [(sp.Rational(1, 10), 1)]
    code, rep = check_json(path)
    assert code == 1 and rep["verdict"] == "fail"
    same_instants(rep["singularities"], ref, MODES)
    (s,) = rep["singularities"]
    assert s["knot"] is True and set(s["sides"]) == {"before", "after"}
    assert s["sides"]["before"]["torque_bounded"] and s["sides"]["before"]["consistent"]
    assert not s["sides"]["after"]["torque_bounded"] and not s["sides"]["after"]["consistent"]
    assert not s["torque_bounded"] and s["pole_order"] == 1
    assert s["sides"]["before"]["consistency_residual"] == 0
    assert s["consistency_residual"] == s["sides"]["after"]["consistency_residual"] != 0
    # the limit of the bounded side: Newton-Euler's torques at t_s - 10^-8 tend to it
    T = torques(ROBOT, before, Q(-1, 10**8), MODES)
    limit = s["sides"]["before"]["torque_at_singularity"]
    for i in (0, 1):
        assert abs(float(T[i]) - limit[i]) <= 1e-5 * (1 + abs(float(T[i])))
    assert _rules(rep) == [("RPR204", 0.1), ("RPR201", 0.1)]
    (k,) = rep["knots"]
    assert k["acceleration_jump"] == [0, 0.1] and k["torque_jump"] is None
    assert "at a knot" in rep["findings"][1]["message"]


def test_a_knot_that_jumps_in_velocity_is_rpr203_as_for_the_rprpr(tmp_path: Path) -> None:
    """Two straight pieces away from the Type II curve (no instant, by the reference),
    meeting at t = 1/2 with velocities (1, 0) and (0, 1): RPR203 at the knot's line."""
    p1 = Motion((Q(58, 5), Q(1)), (Q(9),))
    p2 = Motion((Q(121, 10),), (Q(9) - Q(1, 2), Q(1)))
    path = pieces_file(tmp_path, "corner", [(Q(1, 2), p1), (Q(1), p2)])
    assert reference([(Z, Q(1, 2), p1), (Q(1, 2), Q(1), p2)]) == []
    code, rep = check_json(path)
    assert code == 1 and rep["singularities"] == []
    assert _rules(rep) == [("RPR203", 0.5)]
    assert rep["knots"][0]["velocity_jump"] == [-1, 1]
    line = next(i for i, t in enumerate(path.read_text().splitlines(), 1) if "until: 0.5" in t)
    assert rep["findings"][0]["line"] == line


def test_the_analysis_stops_at_the_first_type_one_instant(tmp_path: Path) -> None:
    """Piece 1: the consistent crossing (the instant at t_s = 1/10, bounded); piece 2,
    from E(1/5), straight along +x at 12 m/s until t = 2: leg 1 is stretched (|E| = 26)
    at the reference's root; piece 3 comes back through the pose, after the Type I
    instant: not analysed. RPR103 fails the task, in piece 2."""
    m = absolute(motions()["consistent"])
    t = sp.Symbol("t")
    x1 = sum(sp.Rational(c.numerator, c.denominator) * TF**i for i, c in enumerate(m.x))
    y1 = sum(sp.Rational(c.numerator, c.denominator) * TF**i for i, c in enumerate(m.y))
    x1, y1 = Q(str(x1)), Q(str(y1))
    p2 = Motion((x1 - 12 * TF, Q(12)), (y1,))
    x2 = x1 + 12 * (2 - TF)
    p3 = Motion((x2 + 2 * 12, Q(-12)), (y1,))  # back at 12 m/s from t = 2
    path = pieces_file(tmp_path, "stretch", [(TF, m), (Q(2), p2), (Q(3), p3)])
    x_2 = sp.Rational(x1.numerator, x1.denominator) + 12 * (t - sp.Rational(1, 5))
    y_2 = sp.Rational(y1.numerator, y1.denominator)
    reach = [x_2**2 + y_2**2 - 26**2, x_2**2 + y_2**2, (x_2 - 14) ** 2 + y_2**2 - 26**2,
             (x_2 - 14) ** 2 + y_2**2]  # fmt: skip
    roots = sorted(
        (r for f in reach for r in sp.Poly(f, t).real_roots() if sp.Rational(1, 5) <= r <= 2),
        key=lambda r: sp.N(r, 30),
    )
    stop = roots[0]
    assert sp.Poly(reach[0], t).eval(stop) == 0  # leg 1 stretched first
    ref = [r for r in reference([(Z, TF, m), (TF, Q(2), p2)]) if sp.N(r.t - stop, 30) < 0]
    assert [r.t for r in ref] == [sp.Rational(1, 10)]
    code, rep = check_json(path)
    assert code == 1 and rep["verdict"] == "fail"
    same_instants(rep["singularities"], ref, MODES)
    (k,) = rep["kinematic_singularities"]
    assert (k["leg"], k["kind"], k["t_exact"]) == (1, "stretched", None)
    assert abs(k["t"] - float(sp.N(stop, 30))) <= 1e-15
    assert abs(k["x"] - float(sp.N(x_2.subs(t, stop), 30))) <= 1e-12
    assert _rules(rep) == [("RPR203", 0.2), ("RPR103", k["t"])]  # the corner at t = 1/5
    message = rep["findings"][1]["message"]
    assert "(piece 2): leg 1 is stretched" in message
    assert message.endswith("the analysis stops here (1 Type II instant before it)")
    assert [kn["t_exact"] for kn in rep["knots"]] == ["1/5"]  # the knot at 2: not reached


# -- timing.x pieces under a path, waypoints, a CSV ---------------------------------------


def test_timing_x_pieces_under_a_path(tmp_path: Path) -> None:
    """y = 9.8 + (x - 12.6)/2, x(t) = 11.6 + 4t² then 13.6 - 4(1 - t)²: the path passes
    the pose at the knot t = 1/2 (x = 12.6), each side inconsistent (Newton-Euler)."""
    path = tmp_path / "tx.rprpr.yaml"
    path.write_text(
        f"name: tx\n{robot_text()}path:\n  y: 9.8 + 0.5*(x - 12.6)\ntiming:\n  duration: 1\n"
        "  x:\n    - {until: 0.5, x: 11.6 + 4*t^2}\n    - {until: 1, x: 13.6 - 4*(1 - t)^2}\n"
    )
    xa = (Q(58, 5), Z, Q(4))
    xb = (Q(68, 5) - 4, Q(8), Q(-4))
    ya, yb = ((Q(49, 5) - Q(63, 10) + c / 2 if i == 0 else c / 2 for i, c in enumerate(xs))
              for xs in (xa, xb))  # fmt: skip
    a, b = Motion(xa, tuple(ya)), Motion(xb, tuple(yb))
    ref = reference([(Z, Q(1, 2), a), (Q(1, 2), Q(1), b)])
    assert sp.Rational(1, 2) in [r.t for r in ref]
    for m, side in ((a, -1), (b, 1)):  # Newton-Euler about t = 1/2, each side
        local = _about(m, Q(1, 2))
        assert not one_sided_bounded(local, side)
    code, rep = check_json(path)
    assert code == 1
    same_instants(rep["singularities"], ref, MODES)
    s = next(s for s in rep["singularities"] if s["t_exact"] == "1/2")
    assert s["knot"] and not s["torque_bounded"]
    assert ("RPR201", 0.5) in _rules(rep) and ("RPR204", 0.5) in _rules(rep)


def _about(m: Motion, t0: Q) -> Motion:
    """The motion in the local time τ = t - t0."""
    t = sp.Symbol("t")
    out = []
    for cs in (m.x, m.y):
        p = sp.Poly(sum(sp.Rational(c.numerator, c.denominator) * (t + sp.Rational(t0.numerator,
                    t0.denominator)) ** i for i, c in enumerate(cs)), t)  # fmt: skip
        out.append(tuple(Q(int(c.p), int(c.q)) for c in reversed(p.all_coeffs())))
    return Motion(out[0], out[1])


WAYPOINTS = [  # t, p, v, a: the pose crossed inside segment 2 and on the line throughout
    (Z, (Q(58, 5), Q(93, 10)), (Z, Z), (Z, Z)),
    (Q(2, 5), (Q(61, 5), Q(48, 5)), (Q(3, 2), Q(3, 4)), (Z, Z)),
    (Q(1), (Q(68, 5), Q(103, 10)), (Z, Z), (Z, Z)),
]


def _quintic(w0: Any, w1: Any, i: int) -> tuple[Q, ...]:
    """The coordinate i of the quintic segment from waypoint w0 to w1 (position, velocity
    and acceleration at both ends), solved by sympy, in absolute time."""
    t = sp.Symbol("t")
    c = sp.symbols("c0:6")
    t0, t1 = (sp.Rational(w[0].numerator, w[0].denominator) for w in (w0, w1))
    p = sum(c[k] * (t - t0) ** k for k in range(6))
    eqs = []
    for w, at in ((w0, t0), (w1, t1)):
        for d, v in enumerate((w[1][i], w[2][i], w[3][i])):
            eqs.append(sp.Eq(sp.diff(p, t, d).subs(t, at), sp.Rational(v.numerator, v.denominator)))
    sol = sp.solve(eqs, c)
    poly = sp.Poly(p.subs(sol), t)
    return tuple(Q(int(k.p), int(k.q)) for k in reversed(poly.all_coeffs()))


def _waypoint_reference() -> list[Instant]:
    return list(_waypoint_instants())


@cache  # the reference's instants of WAYPOINTS, once for both forms of the test
def _waypoint_instants() -> tuple[Instant, ...]:
    segments = []
    for w0, w1 in itertools.pairwise(WAYPOINTS):
        segments.append((w0[0], w1[0], Motion(_quintic(w0, w1, 0), _quintic(w0, w1, 1))))
    return tuple(reference(segments))


def _row(w: Any) -> list[str]:
    return [_decimal(v) for v in (w[0], *w[1], *w[2], *w[3])]


@pytest.mark.parametrize("form", ["inline", "csv"])
def test_waypoints_inline_and_from_a_csv_file(tmp_path: Path, form: str) -> None:
    """Three waypoints on the line y = 9.8 + (x - 12.6)/2: segment 2 passes the pose at
    an irrational time (the reference's root of its sympy-solved quintic), inconsistently
    (x'' ≠ the consistent acceleration), and RPR201 fails the task there."""
    ref = _waypoint_reference()
    pose = [r for r in ref if not r.t.is_Rational]
    assert len(pose) == 1 and 2 / 5 < sp.N(pose[0].t) < 1
    if form == "inline":
        rows = "".join(
            f"    - {{t: {r[0]}, p: [{r[1]}, {r[2]}], v: [{r[3]}, {r[4]}], a: [{r[5]}, {r[6]}]}}\n"
            for r in map(_row, WAYPOINTS)
        )
        motion = f"motion:\n  waypoints:\n{rows}"
    else:
        csv = "t,x,y,vx,vy,ax,ay\n" + "".join(",".join(_row(w)) + "\n" for w in WAYPOINTS)
        (tmp_path / "planned.csv").write_text(csv)
        motion = "motion:\n  waypoints: planned.csv\n"
    path = tmp_path / "wp.rprpr.yaml"
    path.write_text(f"name: wp\n{robot_text()}{motion}")
    code, rep = check_json(path)
    assert code == 1
    same_instants(rep["singularities"], ref, MODES)
    s = next(s for s in rep["singularities"] if s["t_exact"] is None)
    assert (s["x"], s["y"]) == (12.6, 9.8)
    assert not s["torque_bounded"] and not s["knot"]
    assert ("RPR201", s["t"]) in _rules(rep)
    assert [k["t_exact"] for k in rep["knots"]] == ["2/5"]


# -- bad input --------------------------------------------------------------------------


def test_a_position_jump_between_5r_pieces_is_one_located_line(tmp_path: Path) -> None:
    path = pieces_file(
        tmp_path, "jump",
        [(Q(1, 10), Motion((Q(63, 5), Q(1)), (Q(49, 5),))),
         (Q(1, 5), Motion((Q(64, 5), Q(1)), (Q(49, 5),)))],
    )  # fmt: skip
    code, out, err = run_cli("check", str(path))
    assert (code, out) == (2, "")
    line = next(i for i, t in enumerate(path.read_text().splitlines(), 1) if "until: 0.1" in t)
    assert err == (
        f"{path}:{line}:14: motion.pieces[0].until: the position jumps at the knot t = 0.1:"
        " (x, y) = (12.7, 9.8) before, (12.9, 9.8) after (line"
        f" {line + 3}); position must be continuous [RPR001]\n"
    )


def test_a_5r_waypoint_csv_starting_out_of_reach_is_one_located_line(tmp_path: Path) -> None:
    """E(0) = (27, 1): |E - A| = 27.02 > l1 + l3 = 26 (leg 2 reaches it: |E - B| = 13.04)."""
    (tmp_path / "far.csv").write_text("t,x,y,vx,vy,ax,ay\n0,27,1,0,0,0,0\n1,13.6,10.3,0,0,0,0\n")
    path = tmp_path / "far.rprpr.yaml"
    path.write_text(f"name: far\n{robot_text()}motion:\n  waypoints: far.csv\n")
    code, out, err = run_cli("check", str(path))
    assert (code, out) == (2, "")
    assert err.count("\n") == 1 and err.endswith(" [RPR001]\n")
    assert err.startswith(f"{path}:")
    assert "motion.waypoints: the start point E(0) = (27, 1) is out of reach of leg 1" in err
    assert "[|l1 - l3|, l1 + l3] = [0, 26] m" in err


def test_a_piece_at_rest_on_the_curve_is_rpr104_with_its_span(tmp_path: Path) -> None:
    """Piece 1 moves along +x at 1 m/s into the singular pose (the reference's instant at
    t = 1/10, its end); piece 2 stays there (S₋(E(t)) ≡ 0: the reference refuses it as a
    path along a line-up curve). RPR104 names piece 2 and its span; the instant at the
    knot is judged from its one analysable side (before)."""
    p1 = Motion((Q(63, 5) - Q(1, 10), Q(1)), (Q(49, 5),))
    p2 = Motion((Q(63, 5),), (Q(49, 5),))
    with pytest.raises(ValueError, match="line-up curve"):
        singular_instants(ROBOT, p2, MODES, Q(1, 10), TF)
    ref = reference([(Z, Q(1, 10), p1)])
    path = pieces_file(tmp_path, "rest", [(Q(1, 10), p1), (TF, p2)])
    code, rep = check_json(path)
    assert code == 1 and not rep["on_singular_line"]
    same_instants(rep["singularities"], ref, MODES)
    (s,) = rep["singularities"]
    assert s["knot"] and list(s["sides"]) == ["before"]
    assert [f["rule"] for f in rep["findings"]] == ["RPR104", "RPR203", "RPR201"]
    assert rep["findings"][0]["message"].startswith(
        "piece 2, t = 0.1 s to 0.2 s, runs along a Type II curve of the robot"
    )


def test_an_acceleration_jump_is_rpr204_with_newton_eulers_torque_jump(tmp_path: Path) -> None:
    """Away from the curve (no instant, by the reference): E moves along +x at 1 m/s, then
    from t = 1/2 curves upward (ÿ = 2): the acceleration jumps by (0, 2) at the knot and
    the torques by T(1/2+) - T(1/2-), each side's by Newton-Euler at 60 digits."""
    p1 = Motion((Q(58, 5), Q(1)), (Q(9),))
    p2 = Motion((Q(58, 5), Q(1)), (Q(9) + Q(1, 4), Q(-1), Q(1)))  # y = 9 + (t - 1/2)²
    assert reference([(Z, Q(1, 2), p1), (Q(1, 2), Q(1), p2)]) == []
    before, after = (torques(ROBOT, m, Q(1, 2), MODES) for m in (p1, p2))
    path = pieces_file(tmp_path, "bend", [(Q(1, 2), p1), (Q(1), p2)])
    code, rep = check_json(path)
    assert code == 0 and rep["singularities"] == []  # RPR204: a warning
    assert [(f["rule"], f["severity"]) for f in rep["findings"]] == [("RPR204", "warning")]
    (k,) = rep["knots"]
    assert k["velocity_jump"] is None and k["acceleration_jump"] == [0, 2]
    for i in (0, 1):
        want = float(after[i] - before[i])
        assert abs(k["torque_jump"][i] - want) <= 1e-9 * (1 + abs(want))
    message = rep["findings"][0]["message"]
    assert message.startswith("t = 0.5 s (knot between pieces 1 and 2): the end-point")
    assert f"T1 jumps by {k['torque_jump'][0]:.6g} N m" in message


@pytest.mark.parametrize("form", ["text", "concise", "github", "gitlab", "sarif", "junit", "html"])
def test_every_format_reports_a_5r_knot(tmp_path: Path, form: str) -> None:
    """The knot task of ``test_an_instant_at_a_knot_is_judged_from_each_side``."""
    a, b = absolute(motions()["consistent"]), absolute(motions()["inconsistent"])
    path = pieces_file(tmp_path, "knot", [(TS, a), (TF, b)])
    code, out, err = run_cli("check", "--format", form, str(path))
    assert (code, err) == (1, "")
    assert "RPR201" in out and "RPR204" in out and "internal" not in out
    assert "knot between pieces 1 and 2" in out

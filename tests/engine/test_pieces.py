"""Piecewise motions in task files and from arrays: the trapezoidal law, timing.x as
pieces, motion.pieces, motion.waypoints (inline and CSV), ``rprpr check -``, and
``Motion.from_pieces``. Every test asserts the Task's exact contents (pieces, lines) or
the exact message, line and column of a bad file's error; none audits a piecewise task.
"""

from __future__ import annotations

import io
import random
import sys
from pathlib import Path

import pytest
from flint import fmpq, fmpq_poly

from rprpr.cli.tasks import read_task
from rprpr.io import waypoint_csv
from rprpr.io.loader import load_task, parse_task
from rprpr.model.errors import TaskFileError
from rprpr.model.motion import Motion, exact, with_motion
from rprpr.model.task import Piece, Task
from rprpr.model.waypoints import Waypoint, interpolate, segment
from tests.conftest import CONFIGS, LINKS_ALIKE, PATH2_FILE, run_cli

T = fmpq_poly([0, 1])  # t
q = fmpq
PATH2 = fmpq_poly([q(-222, 10), q(218, 10), q(-72, 10), q(8, 10)])  # eq. (51)
ROBOT = f"name: test\nrobot:\n  a1: 6\n{LINKS_ALIKE}"
PATH = "path:\n  y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2\n  from: [2, -1]\n  to: [4, 1]\n"


def _trapezoid(cruise: str, extra: str = "") -> str:
    return ROBOT + PATH + f"timing:\n  duration: 5\n  law: trapezoidal\n{cruise}{extra}"


def _error(text: str, directory: str = ".") -> TaskFileError:
    with pytest.raises(TaskFileError) as info:
        parse_task(text, "t.yaml", directory=directory)
    return info.value


def _errors(text: str, directory: str = ".") -> list[tuple[int, int, str, str]]:
    """Every error of the file as (line, column, key, message)."""
    e = _error(text, directory)
    return [(x.line, x.column, x.key, x.message) for x in e.errors]


def _shape(task: Task) -> list[tuple[fmpq, fmpq, fmpq_poly, fmpq_poly]]:
    return [(p.start, p.end, p.x, p.y) for p in task.pieces]


# -- (1) the trapezoidal law ------------------------------------------------------------
def test_trapezoidal_law_is_the_hand_written_lspb_pieces() -> None:
    # x0 = 2, x1 = 4, t_f = 5, V = 0.6: t_b = (V t_f - D)/V = 5/3, a = V/t_b = 0.36
    task = parse_task(_trapezoid("  cruise_speed: 0.6\n"), "t.yaml")
    rise, cruise, fall = (
        2 + q(18, 100) * T**2,
        q(3, 2) + q(6, 10) * T,
        4 - q(18, 100) * (5 - T) ** 2,
    )
    assert task.law == "trapezoidal" and task.x_of_t is None and task.duration == 5
    assert [(p.start, p.end, p.x) for p in task.pieces] == [
        (0, q(5, 3), rise),
        (q(5, 3), q(10, 3), cruise),
        (q(10, 3), 5, fall),
    ]
    assert all(p.path == PATH2 and p.y == PATH2(p.x) for p in task.pieces)
    assert task.knots == (q(5, 3), q(10, 3))
    line = 15  # timing.law
    assert task.lines["timing.law"] == line and task.lines["timing.cruise_speed"] == line + 1
    assert {p.line for p in task.pieces} == {line}


def test_trapezoidal_law_at_twice_the_mean_speed_is_a_triangle() -> None:
    task = parse_task(
        _trapezoid("  cruise_speed: 0.8\n"), "t.yaml"
    )  # V = 2D/t_f: t_b = 2.5, a = 0.32
    assert [(p.start, p.end, p.x) for p in task.pieces] == [
        (0, q(5, 2), 2 + q(16, 100) * T**2),
        (q(5, 2), 5, 4 - q(16, 100) * (5 - T) ** 2),
    ]


def test_trapezoidal_law_backwards_decelerates_first() -> None:
    text = _trapezoid("  cruise_speed: 0.6\n").replace("from: [2, -1]", "from: [4, 1]")
    text = text.replace("to: [4, 1]", "to: [2, -1]")
    task = parse_task(text, "t.yaml")
    assert task.pieces[0].x == 4 - q(18, 100) * T**2
    assert task.pieces[-1].x == 2 + q(18, 100) * (5 - T) ** 2


@pytest.mark.parametrize(
    ("cruise", "why"),
    [
        ("0.4", "too slow to cover D in t_f"),
        ("0.3", "too slow to cover D in t_f"),
        ("0.81", "too fast to reach and leave again in t_f (at 2D/t_f the profile is a triangle)"),
    ],
)
def test_a_cruise_speed_outside_its_range_is_named_with_the_range(cruise: str, why: str) -> None:
    assert _errors(_trapezoid(f"  cruise_speed: {cruise}\n")) == [
        (
            16,
            17,
            "timing.cruise_speed",
            f"cruise_speed {cruise} is outside (D/t_f, 2D/t_f] = (0.4, 0.8] for D = |x1 - x0|"
            f" = 2 m and t_f = 5 s: {why}",
        )
    ]


def test_the_trapezoidal_law_needs_its_cruise_speed_and_distinct_ends() -> None:
    assert _errors(_trapezoid("")) == [
        (
            15,
            8,
            "timing.law",
            "law trapezoidal needs cruise_speed (|dx/dt| while cruising [m/s], in (D/t_f,"
            " 2D/t_f], D = |x1 - x0|)",
        )
    ]
    same = _trapezoid("  cruise_speed: 0.6\n").replace("to: [4, 1]", "to: [2, -1]")
    [(line, column, key, message)] = _errors(same)
    assert (line, column, key) == (15, 8, "timing.law")
    assert message.startswith("law trapezoidal needs path.from and path.to at different x")


def test_a_cruise_speed_without_the_trapezoidal_law_is_an_error() -> None:
    text = ROBOT + PATH + "timing:\n  duration: 5\n  law: quintic\n  cruise_speed: 0.6\n"
    assert _errors(text) == [
        (16, 17, "timing.cruise_speed", "cruise_speed is only for law: trapezoidal")
    ]


# -- (1) timing.x as pieces -------------------------------------------------------------
def test_piecewise_timing_equals_the_trapezoidal_law_written_out() -> None:
    pieces = load_task(CONFIGS / "piecewise_timing.rprpr.yaml")
    law = load_task(CONFIGS / "trapezoidal.rprpr.yaml")
    assert pieces.law == "pieces" and pieces.x_of_t is None and pieces.path == PATH2
    assert _shape(pieces) == _shape(law)
    # each piece points at the line of its until
    text = (CONFIGS / "piecewise_timing.rprpr.yaml").read_text(encoding="utf-8").splitlines()
    for i, p in enumerate(pieces.pieces):
        assert text[p.line - 1].lstrip().startswith("- {until:")
        assert pieces.lines[f"timing.x[{i}].until"] == p.line


def test_a_single_polynomial_timing_x_is_still_the_paper_form() -> None:
    text = ROBOT + PATH + "timing:\n  duration: 5\n  x: 2 + 2*t/5\n"
    task = parse_task(text, "t.yaml")
    assert task.law == "explicit" and task.pieces == () and task.x_of_t == 2 + q(2, 5) * T
    assert [(p.start, p.end, p.x) for p in task.motion] == [(0, 5, 2 + q(2, 5) * T)]


def _timed(*pieces: str, duration: str = "5") -> str:
    rows = "".join(f"    - {p}\n" for p in pieces)
    return ROBOT + PATH + f"timing:\n  duration: {duration}\n  x:\n{rows}"


def test_timing_pieces_must_increase_from_zero() -> None:
    text = _timed("{until: 0, x: 2}", "{until: 5, x: 2 + 2*t/5}")
    assert _errors(text) == [
        (
            16,
            15,
            "timing.x[0].until",
            "until 0 must come after t = 0: pieces are consecutive from t = 0, in increasing time",
        )
    ]
    text = _timed("{until: 3, x: 2 + 2*t/5}", "{until: 5/2, x: 2 + 2*t/5}", "{until: 5, x: 4}")
    assert _errors(text)[0][:3] == (17, 15, "timing.x[1].until")
    assert _errors(text)[0][3].startswith(
        "until 2.5 must come after the previous piece's until (3)"
    )


def test_timing_pieces_must_end_at_the_duration() -> None:
    text = _timed("{until: 5/2, x: 2 + 2*t/5}", "{until: 4, x: 2 + 2*t/5}")
    assert _errors(text) == [
        (
            17,
            15,
            "timing.x[1].until",
            "the last piece ends at until = 4, but timing.duration is 5: they must be equal",
        )
    ]


def test_a_jump_in_x_names_the_knot_and_both_values() -> None:
    text = _timed("{until: 5/3, x: 2 + 0.18*t^2}", "{until: 5, x: 2.6 + 0.3*(t - 5/3)}")
    assert _errors(text) == [
        (
            16,
            15,
            "timing.x[0].until",
            "the position jumps at the knot t = 5/3: x = 2.5 before, 2.6 after (line 17);"
            " position must be continuous",
        )
    ]


def test_timing_pieces_must_meet_path_from_and_to() -> None:
    text = _timed("{until: 5/2, x: 2.5 + t/5}", "{until: 5, x: 2.5 + t/5}")
    assert _errors(text) == [
        (
            11,
            9,
            "path.from",
            "path.from has x = 2 but timing.x gives x(0) = 2.5: they must agree",
        )
    ]


# -- (2) motion.pieces ------------------------------------------------------------------
def _motion(body: str, timing: str = "") -> str:
    return ROBOT + timing + "motion:\n" + body


def test_motion_pieces_are_taken_as_written() -> None:
    task = load_task(CONFIGS / "motion_pieces.rprpr.yaml")
    assert task.law == "motion" and task.path is None and task.x_of_t is None
    assert task.duration == 5 and task.knots == (q(5, 2),)
    first, second = task.pieces
    assert first == Piece(
        q(0),
        q(5, 2),
        q(72, 3125) * T**5 - q(4, 25) * T**4 + q(8, 25) * T**3 + 2,
        q(168, 3125) * T**5 - q(212, 625) * T**4 + q(72, 125) * T**3 - 1,
        None,
        18,
    )
    assert (second.start, second.end, second.line) == (q(5, 2), q(5), 21)
    assert task.lines["motion.pieces"] == 17 and task.lines["motion.pieces[1].until"] == 21


def test_a_jump_in_the_motion_names_both_positions() -> None:
    text = _motion(
        "  pieces:\n    - {until: 1, x: 2 + t, y: t - 1}\n    - {until: 2, x: 2 + t, y: t - 0.9}\n"
    )
    assert _errors(text) == [
        (
            11,
            15,
            "motion.pieces[0].until",
            "the position jumps at the knot t = 1: (x, y) = (3, 0) before, (3, 0.1) after"
            " (line 12); position must be continuous",
        )
    ]


def test_a_motion_with_timing_duration_must_end_there() -> None:
    body = "  pieces:\n    - {until: 2, x: 2 + t, y: t - 1}\n"
    task = parse_task(_motion(body, "timing:\n  duration: 2\n"), "t.yaml")
    assert task.duration == 2 and task.law == "motion"
    assert _errors(_motion(body, "timing:\n  duration: 3\n")) == [
        (
            13,
            15,
            "motion.pieces[0].until",
            "the last piece ends at until = 2, but timing.duration is 3: they must be equal",
        )
    ]


@pytest.mark.parametrize(
    ("head", "body", "expected"),
    [
        (
            PATH,
            "  pieces:\n    - {until: 2, x: 2 + t, y: t - 1}\n",
            [
                (
                    14,
                    3,
                    "motion",
                    "give either path (with timing) or motion, not both (motion gives the end"
                    " point's x(t) and y(t) directly)",
                )
            ],
        ),
        (
            "timing:\n  duration: 2\n  law: quintic\n",
            "  pieces:\n    - {until: 2, x: 2 + t, y: t - 1}\n",
            [
                (
                    11,
                    8,
                    "timing.law",
                    "with motion, timing gives only duration (the motion's own times say how it"
                    " moves), found law",
                )
            ],
        ),
        (
            "",
            "  pieces: [{until: 2, x: 2 + t, y: t - 1}]\n  waypoints: [{t: 0, p: [0, 0]}]\n",
            [
                (10, 3, "motion", "give either pieces or waypoints, not both"),
                (11, 14, "motion.waypoints", "expected at least two waypoints, found 1"),
            ],
        ),
        (
            "",
            "  {}\n",
            [
                (
                    10,
                    3,
                    "motion",
                    "missing motion: give pieces (a list of {until, x, y}) or waypoints (a list"
                    " of {t, p, v, a}, or a CSV file's name)",
                )
            ],
        ),
        (
            "",
            "  pieces: []\n",
            [
                (
                    10,
                    11,
                    "motion.pieces",
                    "expected a list of {until, x, y}, found a list of 0",
                )
            ],
        ),
    ],
)
def test_bad_motion_blocks(head: str, body: str, expected: list[tuple[int, int, str, str]]) -> None:
    assert _errors(ROBOT + head + "motion:\n" + body) == expected


def test_without_motion_path_and_timing_are_still_required() -> None:
    assert [(k, m) for _, _, k, m in _errors(ROBOT)] == [
        ("path", "missing required key 'path' at the top level (The end-point path y = p(x))"),
        (
            "timing",
            "missing required key 'timing' at the top level (How x_E moves in time: a"
            " rest-to-rest law between path.from and path.to, or x)",
        ),
    ]


# -- (3) waypoints ----------------------------------------------------------------------
def _random_points(rng: random.Random, n: int, fields: int) -> list[Waypoint]:
    def r() -> fmpq:
        return q(rng.randint(-50, 50), rng.randint(1, 9))

    t = fmpq(0)
    out = []
    for i in range(n):
        out.append(
            Waypoint(
                t,
                (r(), r()),
                (r(), r()) if fields >= 2 else None,
                (r(), r()) if fields >= 3 else None,
                line=i + 1,
            )
        )
        t += q(rng.randint(1, 20), rng.randint(1, 7))
    return out


def _local(piece: fmpq_poly, t0: fmpq) -> list[fmpq]:
    """Coefficients of ``piece`` (in absolute t) in u = t - t0, ascending."""
    c = piece(fmpq_poly([t0, 1])).coeffs()
    return c + [fmpq(0)] * (6 - len(c))


def test_cubic_waypoints_are_the_controllers_formulas() -> None:
    rng = random.Random(20240510)
    points = _random_points(rng, 8, 2)
    for (s, e, x, y, _), w0, w1 in zip(interpolate(points), points, points[1:], strict=False):
        T_ = e - s
        for i, poly in enumerate((x, y)):
            p0, p1, v0, v1 = w0.p[i], w1.p[i], w0.v[i], w1.v[i]  # type: ignore[index]
            c2 = (-3 * p0 + 3 * p1 - 2 * v0 * T_ - v1 * T_) / T_**2
            c3 = (2 * p0 - 2 * p1 + v0 * T_ + v1 * T_) / T_**3
            assert _local(poly, s) == [p0, v0, c2, c3, 0, 0]


def test_quintic_waypoints_are_the_controllers_formulas() -> None:
    rng = random.Random(7)
    points = _random_points(rng, 8, 3)
    for (s, e, x, y, _), w0, w1 in zip(interpolate(points), points, points[1:], strict=False):
        T_ = e - s
        for i, poly in enumerate((x, y)):
            p0, p1 = w0.p[i], w1.p[i]
            v0, v1, a0, a1 = w0.v[i], w1.v[i], w0.a[i], w1.a[i]  # type: ignore[index]
            # joint_trajectory_controller, Trajectory::interpolate_between_points
            c3 = (-20 * p0 + 20 * p1 - 3 * a0 * T_**2 + a1 * T_**2 - 12 * v0 * T_ - 8 * v1 * T_) / (
                2 * T_**3
            )
            c4 = (
                30 * p0 - 30 * p1 + 3 * a0 * T_**2 - 2 * a1 * T_**2 + 16 * v0 * T_ + 14 * v1 * T_
            ) / (2 * T_**4)
            c5 = (-12 * p0 + 12 * p1 - a0 * T_**2 + a1 * T_**2 - 6 * v0 * T_ - 6 * v1 * T_) / (
                2 * T_**5
            )
            assert _local(poly, s) == [p0, v0, a0 / 2, c3, c4, c5]


@pytest.mark.parametrize("fields", [1, 2, 3])
def test_waypoints_reproduce_p_v_a_at_every_waypoint_exactly(fields: int) -> None:
    points = _random_points(random.Random(fields), 10, fields)
    pieces = interpolate(points)
    assert len(pieces) == len(points) - 1
    for (s, e, x, y, line), w0, w1 in zip(pieces, points, points[1:], strict=False):
        assert line == w1.line
        for i, poly in enumerate((x, y)):
            assert (poly(s), poly(e)) == (w0.p[i], w1.p[i])
            if fields >= 2:
                d = poly.derivative()
                assert (d(s), d(e)) == (w0.v[i], w1.v[i])  # type: ignore[index]
            if fields >= 3:
                dd = poly.derivative().derivative()
                assert (dd(s), dd(e)) == (w0.a[i], w1.a[i])  # type: ignore[index]
            if fields == 1:
                assert poly.degree() <= 1
    assert segment(q(2), q(1), q(3)) == [1, 1]  # linear: p0 + (p1 - p0) u / T


def test_inline_waypoints_give_the_motion_of_the_pieces_config() -> None:
    task = load_task(CONFIGS / "waypoints.rprpr.yaml")
    pieces = load_task(CONFIGS / "motion_pieces.rprpr.yaml")
    assert task.law == "waypoints" and task.path is None and task.duration == 5
    assert _shape(task) == _shape(pieces)
    assert [p.line for p in task.pieces] == [18, 19]  # the line of each segment's end point
    assert all(p.file == "" for p in task.pieces)


def _csv_rows(points: list[Waypoint]) -> str:
    def num(v: fmpq) -> str:
        return str(v) if v.q == 1 else f"{v.p}/{v.q}"

    lines = ["t,x,y,vx,vy,ax,ay"]
    for w in points:
        assert w.v is not None and w.a is not None
        lines.append(",".join(num(v) for v in (w.t, *w.p, *w.v, *w.a)))
    return "\n".join(lines) + "\n"


def _inline(points: list[Waypoint]) -> str:
    def num(v: fmpq) -> str:
        return str(v) if v.q == 1 else f"{v.p}/{v.q}"

    rows = "".join(
        f"    - {{t: {num(w.t)}, p: [{num(w.p[0])}, {num(w.p[1])}],"
        f" v: [{num(w.v[0])}, {num(w.v[1])}], a: [{num(w.a[0])}, {num(w.a[1])}]}}\n"  # type: ignore[index]
        for w in points
    )
    return _motion(f"  waypoints:\n{rows}")


def test_csv_and_inline_waypoints_give_the_same_task(tmp_path: Path) -> None:
    points = _random_points(random.Random(3), 12, 3)
    (tmp_path / "plan.csv").write_text(_csv_rows(points), encoding="utf-8")
    (tmp_path / "csv.yaml").write_text(_motion("  waypoints: plan.csv\n"), encoding="utf-8")
    from_csv = load_task(tmp_path / "csv.yaml")
    inline = parse_task(_inline(points), "inline.yaml")
    assert _shape(from_csv) == _shape(inline) and from_csv.law == inline.law == "waypoints"
    assert [p.line for p in from_csv.pieces] == list(range(3, 14))  # the CSV's rows
    assert {p.file for p in from_csv.pieces} == {str(tmp_path / "plan.csv")}
    assert [p.line for p in inline.pieces] == list(range(12, 23))


def test_the_shipped_csv_config_samples_example_2_exactly() -> None:
    task = load_task(CONFIGS / "waypoints_csv.rprpr.yaml")
    x = 2 + 2 * (10 * (T / 5) ** 3 - 15 * (T / 5) ** 4 + 6 * (T / 5) ** 5)  # eq. (49)
    y = PATH2(x)
    assert len(task.pieces) == 10 and task.duration == 5
    for p in task.pieces:  # the quintic segments meet x, y, their speeds and accelerations
        for f, g in ((p.x, x), (p.y, y)):
            for _k in range(3):
                assert f(p.start) == g(p.start) and f(p.end) == g(p.end)
                f, g = f.derivative(), g.derivative()
        assert p.file == str(CONFIGS / "paper_path2_planned.csv")


def _waypoints(*rows: str, timing: str = "") -> str:
    return _motion("  waypoints:\n" + "".join(f"    - {r}\n" for r in rows), timing)


@pytest.mark.parametrize(
    ("rows", "expected"),
    [
        (
            ["{t: 0, p: [0, 0]}"],
            [(11, 5, "motion.waypoints", "expected at least two waypoints, found 1")],
        ),
        (
            ["{t: 1, p: [0, 0]}", "{t: 2, p: [1, 0]}"],
            [
                (
                    11,
                    11,
                    "motion.waypoints[0].t",
                    "the first waypoint is at t = 1; waypoints start at t = 0",
                )
            ],
        ),
        (
            ["{t: 0, p: [0, 0]}", "{t: 2, p: [1, 0]}", "{t: 2, p: [2, 0]}"],
            [
                (
                    13,
                    11,
                    "motion.waypoints[2].t",
                    "t = 2 does not come after the previous waypoint's t = 2: times must increase",
                )
            ],
        ),
        (
            ["{t: 0, p: [0, 0], v: [0, 0]}", "{t: 5/3, p: [1, 0]}"],
            [
                (
                    12,
                    11,
                    "motion.waypoints[1].t",
                    "this waypoint gives p but the first gives p, v: every waypoint must give"
                    " the same fields (p; p, v; or p, v, a)",
                )
            ],
        ),
        (
            ["{t: 0, p: [0, 0], a: [0, 0]}", "{t: 1, p: [1, 0], a: [0, 0]}"],
            [
                (
                    11,
                    28,
                    "motion.waypoints[0].a",
                    "a waypoint giving a must give v too (p; p, v; or p, v, a)",
                )
            ],
        ),
        (
            ["{t: 0, p: [0, 0]}", "{t: -1, p: [1, 0]}"],
            [(12, 11, "motion.waypoints[1].t", "expected a time >= 0 [s], found -1")],
        ),
        (
            ["{t: 0, p: [0, 0]}", "{t: 1, p: [1]}"],
            [
                (
                    12,
                    17,
                    "motion.waypoints[1].p",
                    "expected a list of two numbers [position x [m], position y [m]], found a"
                    " list of 1",
                )
            ],
        ),
    ],
)
def test_bad_waypoints(rows: list[str], expected: list[tuple[int, int, str, str]]) -> None:
    assert _errors(_waypoints(*rows)) == expected


def test_waypoints_with_a_duration_end_there() -> None:
    text = _waypoints("{t: 0, p: [0, 0]}", "{t: 1.5, p: [1, 0]}", timing="timing:\n  duration: 2\n")
    assert _errors(text) == [
        (
            14,
            11,
            "motion.waypoints[1].t",
            "the last waypoint is at t = 1.5, but timing.duration is 2: they must be equal",
        )
    ]


def test_linear_waypoints_fractions_and_decimals_are_exact() -> None:
    task = parse_task(_waypoints("{t: 0, p: [0, 0.1]}", "{t: 1/3, p: [1, 0.1]}"), "t.yaml")
    [piece] = task.pieces
    assert (piece.end, piece.x, piece.y) == (q(1, 3), 3 * T, fmpq_poly([q(1, 10)]))


# -- the CSV file ---------------------------------------------------------------------------
def _csv_task(tmp_path: Path, csv: str | bytes | None, name: str = "plan.csv") -> list[str]:
    """The errors (as the command line prints them) of a task naming ``name``."""
    if csv is not None:
        target = tmp_path / name
        target.write_bytes(csv if isinstance(csv, bytes) else csv.encode("utf-8"))
    task = tmp_path / "t.yaml"
    task.write_text(_motion(f"  waypoints: {name}\n"), encoding="utf-8")
    with pytest.raises(TaskFileError) as info:
        load_task(task)
    return [str(x.naming("t.yaml")) for x in info.value.errors]


@pytest.mark.parametrize(
    ("csv", "message"),
    [
        ("t,x,y\n0,0,0\n1,abc,0\n", "plan.csv:3: column x: expected a number, found 'abc'"),
        ("t,x,y\n0,0,0\n1,0\n", "plan.csv:3: expected 3 values (t,x,y), found 2"),
        ("t,x,y\n0,0,0\n1,, 0\n", "plan.csv:3: column x: empty, expected a number"),
        ("t,x,y\n0,0,0\n1,nan,0\n", "plan.csv:3: column x: expected a number, found 'nan'"),
        ("t,x,y\n0,0,0\n1,0x10,0\n", "plan.csv:3: column x: expected a number, found '0x10'"),
        (
            "t,x,y\n0,0,0\n1,0,1/0\n",
            "plan.csv:3: column y: division by zero in '1/0'",
        ),
        (
            "time,x,y\n0,0,0\n",
            "plan.csv:1: expected the header t,x,y or t,x,y,vx,vy or t,x,y,vx,vy,ax,ay, found"
            " 'time,x,y'",
        ),
        (
            "t,x,y,vx\n0,0,0,0\n",
            "plan.csv:1: expected the header t,x,y or t,x,y,vx,vy or t,x,y,vx,vy,ax,ay, found"
            " 't,x,y,vx'",
        ),
        (
            "# only a comment\n\n",
            "plan.csv: empty file, expected a header t,x,y[,vx,vy[,ax,ay]] and waypoints",
        ),
        (b"t,x,y\n0,0,\xff\n", "plan.csv:2: not UTF-8 text (byte 0xff)"),
        (
            "t,x,y\n1,0,0\n2,1,0\n",
            "plan.csv:2: the first waypoint is at t = 1; waypoints start at t = 0",
        ),
        (
            "t,x,y\n0,0,0\n2,1,0\n2,1,0\n",
            "plan.csv:4: t = 2 does not come after the previous waypoint's t = 2: times must"
            " increase",
        ),
        ("t,x,y\n0,0,0\n", "expected at least two waypoints, found 1"),
    ],
)
def test_a_bad_csv_names_the_file_row_and_column(tmp_path: Path, csv: str, message: str) -> None:
    assert _csv_task(tmp_path, csv) == [f"t.yaml:10:14: motion.waypoints: {message}"]


def test_every_bad_csv_row_is_listed_up_to_a_cap(tmp_path: Path) -> None:
    rows = "".join(f"{i},x,0\n" for i in range(30))
    errors = _csv_task(tmp_path, "t,x,y\n" + rows)
    assert len(errors) == waypoint_csv.MAX_CSV_ERRORS + 1
    assert (
        errors[0]
        == "t.yaml:10:14: motion.waypoints: plan.csv:2: column x: expected a number, found 'x'"
    )
    assert errors[-1] == "t.yaml:10:14: motion.waypoints: plan.csv:22: 10 more"


@pytest.mark.parametrize(
    ("name", "make", "message"),
    [
        ("missing.csv", None, "missing.csv: no such file"),
        ("folder.csv", "dir", "folder.csv: is a directory, expected a CSV file"),
        (
            "../plan.csv",
            None,
            "expected a CSV file's name relative to the task file (no '..', ending in .csv),"
            " found '../plan.csv'",
        ),
        (
            "/etc/passwd.csv",
            None,
            "expected a CSV file's name relative to the task file (no '..', ending in .csv),"
            " found '/etc/passwd.csv'",
        ),
        (
            "plan.txt",
            None,
            "expected a CSV file's name relative to the task file (no '..', ending in .csv),"
            " found 'plan.txt'",
        ),
    ],
)
def test_a_csv_name_that_is_no_usable_file_is_one_clear_error(
    tmp_path: Path, name: str, make: str | None, message: str
) -> None:
    if make == "dir":
        (tmp_path / name).mkdir()
    assert _csv_task(tmp_path, None, name) == [f"t.yaml:10:14: motion.waypoints: {message}"]


def test_the_csv_size_and_row_caps(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(waypoint_csv, "MAX_CSV_ROWS", 3)
    rows = "t,x,y\n" + "".join(f"{i},0,0\n" for i in range(4))
    assert _csv_task(tmp_path, rows) == [
        "t.yaml:10:14: motion.waypoints: plan.csv: 4 waypoints, the cap is 3"
    ]
    monkeypatch.setattr(waypoint_csv, "MAX_CSV_BYTES", 10)
    assert _csv_task(tmp_path, rows) == [
        "t.yaml:10:14: motion.waypoints: plan.csv: file too large: 30 bytes, the cap is 10 bytes"
    ]


def test_a_5000_row_quintic_csv_loads_exactly(tmp_path: Path) -> None:
    # a 1 kHz planner over 5 s: the quintic rest-to-rest motion of Example 2, sampled
    x = 2 + 2 * (10 * (T / 5) ** 3 - 15 * (T / 5) ** 4 + 6 * (T / 5) ** 5)
    dx, ddx = x.derivative(), x.derivative().derivative()
    rows = ["t,x,y,vx,vy,ax,ay"]
    for k in range(5001):
        t = q(k, 1000)
        rows.append(f"{k / 1000},{x(t)},0,{dx(t)},0,{ddx(t)},0".replace(" ", ""))
    (tmp_path / "plan.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")
    (tmp_path / "t.yaml").write_text(_motion("  waypoints: plan.csv\n"), encoding="utf-8")
    task = load_task(tmp_path / "t.yaml")
    assert len(task.pieces) == 5000 and task.duration == 5
    # the quintic Hermite segment through samples of a quintic is that quintic, exactly
    assert all(p.x == x and p.y == 0 for p in task.pieces[::97])


# -- standard input -------------------------------------------------------------------
def test_a_task_on_standard_input_reads_its_csv_from_the_working_directory(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "plan.csv").write_text("t,x,y\n0,2,-1\n5,4,1\n", encoding="utf-8")
    task = read_task("-", _motion("  waypoints: plan.csv\n").encode("utf-8"), "-")
    assert task.law == "waypoints" and task.pieces[0].file == "plan.csv"
    assert task.pieces[0].x == 2 + q(2, 5) * T and task.pieces[0].y == -1 + q(2, 5) * T


def test_rprpr_check_names_standard_input_and_the_csv(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    data = _motion("  waypoints: plan.csv\n").encode("utf-8")
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data)))
    code, _out, err = run_cli("check", "-")
    assert code == 2
    assert err == "-:10:14: motion.waypoints: plan.csv: no such file [RPR001]\n"


def test_rprpr_check_reads_a_paper_task_from_standard_input(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    data = Path(PATH2_FILE).read_bytes()
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data)))
    code, out, _ = run_cli("check", "--format", "github", "-")
    assert code == 0 and out == ""  # passes, nothing to annotate


# -- the Python API ---------------------------------------------------------------------
def test_from_pieces_in_ppoly_layout_equals_the_yaml_motion() -> None:
    yaml_task = load_task(CONFIGS / "motion_pieces.rprpr.yaml")
    breaks = [0, fmpq(5, 2), 5]
    # local coefficients, highest power first: c[j][i]
    cx, cy = [], []
    for p in yaml_task.pieces:
        for c, poly in ((cx, p.x), (cy, p.y)):
            local = poly(fmpq_poly([p.start, 1])).coeffs()
            c.append(list(reversed(local + [fmpq(0)] * (6 - len(local)))))
    motion = Motion.from_pieces(
        breaks, list(map(list, zip(*cx, strict=True))), list(map(list, zip(*cy, strict=True)))
    )
    assert [(p.start, p.end, p.x, p.y) for p in motion.pieces] == _shape(yaml_task)
    task = with_motion(load_task(PATH2_FILE), motion)
    assert _shape(task) == _shape(yaml_task) and task.law == "motion"
    assert task.path is None and task.x_of_t is None and task.duration == 5
    assert task.robot == yaml_task.robot and task.checks == yaml_task.checks
    assert "path.y" not in task.lines and "robot.a1" in task.lines
    # absolute-time coefficients give the same motion
    absolute_x = [
        list(reversed(p.x.coeffs() + [fmpq(0)] * (6 - len(p.x.coeffs())))) for p in yaml_task.pieces
    ]
    absolute_y = [
        list(reversed(p.y.coeffs() + [fmpq(0)] * (6 - len(p.y.coeffs())))) for p in yaml_task.pieces
    ]
    motion2 = Motion.from_pieces(
        breaks,
        list(map(list, zip(*absolute_x, strict=True))),
        list(map(list, zip(*absolute_y, strict=True))),
        local=False,
    )
    assert motion2.pieces == motion.pieces


def test_floats_are_taken_as_their_exact_binary_value() -> None:
    assert exact(0.1) == fmpq(3602879701896397, 36028797018963968)
    assert exact(0.5) == fmpq(1, 2) and exact(3) == 3
    np = pytest.importorskip("numpy")
    assert exact(np.float64(0.1)) == exact(0.1) and exact(np.int64(-7)) == -7
    assert exact(np.float32(0.1)) == fmpq(13421773, 134217728)
    # a cubic spline's layout: c of shape (k, m, 2), numpy floats, one line
    breaks = np.array([0.0, 0.5, 1.25])
    coeffs = np.array(
        [
            [[0.1, -0.2], [0.3, 0.7]],  # t^1 coefficients of piece 0 (x, y), piece 1 (x, y)
            [[1.0, 2.0], [1.05, 1.9]],  # t^0
        ]
    )

    class PPoly:  # the two attributes of scipy's PPoly the conversion reads
        x = breaks
        c = coeffs

    # a float spline is continuous only to rounding: 1 + 0.1/2 != 1.05 in binary
    with pytest.raises(ValueError, match=r"jumps at the knot t = 1/2 .* \(4.16e-17, -8.33e-17\)"):
        Motion.from_ppoly(PPoly())
    motion = Motion.from_ppoly(PPoly(), tolerance=1e-12)
    first, second = motion.pieces
    assert first.x == fmpq_poly([1, exact(0.1)]) and first.y == fmpq_poly([2, exact(-0.2)])
    assert second.start == fmpq(1, 2) and second.end == fmpq(5, 4)
    # the knot's rounding is closed: piece 1 gains the constant that continues piece 0
    assert second.x == fmpq_poly([1 + exact(0.1) / 2 - exact(0.3) / 2, exact(0.3)])
    jumps = (exact(1.05) - (1 + exact(0.1) / 2), exact(1.9) - (2 + exact(-0.2) / 2))
    assert motion.snapped == max(abs(j) for j in jumps) > 0  # value only: slopes differ by 0.2
    assert first.x(fmpq(1, 2)) == second.x(fmpq(1, 2)) and first.y(fmpq(1, 2)) == second.y(
        fmpq(1, 2)
    )


def test_from_pieces_rejects_a_position_jump_beyond_its_tolerance() -> None:
    x = [[1.0, 1.0], [0.0, 1.1]]  # piece 0: t; piece 1: 1.1 + (t - 1) -> jump of 0.1 at t = 1
    y = [[0.0, 0.0], [0.0, 0.0]]
    with pytest.raises(ValueError, match=r"the position jumps at the knot t = 1 \(breaks\[1\]\)"):
        Motion.from_pieces([0, 1, 2], x, y)
    closed = Motion.from_pieces([0, 1, 2], x, y, tolerance=0.2)
    assert closed.pieces[1].x == fmpq_poly([0, 1])  # 1.1 + (t - 1) - 0.1 exactly: x = t
    assert closed.snapped == exact(1.1) - 1
    with pytest.raises(ValueError, match="a motion starts at t = 0"):
        Motion.from_pieces([1, 2], [[1.0]], [[0.0]])
    with pytest.raises(ValueError, match=r"expected a finite number"):
        Motion.from_pieces([0, float("nan")], [[1.0]], [[0.0]])
    with pytest.raises(ValueError, match=r"x_coeffs: expected shape \(k, 2\)"):
        Motion.from_pieces([0, 1, 2], [[1.0]], y)


def test_from_waypoints_equals_the_yaml_waypoints() -> None:
    motion = Motion.from_waypoints(
        [0, 2.5, 5], [(2, -1), (3, 0), (4, 1)], [(0, 0), (0.5, fmpq(1, 10)), (0, 0)], [(0, 0)] * 3
    )
    assert [(p.start, p.end, p.x, p.y) for p in motion.pieces] == _shape(
        load_task(CONFIGS / "waypoints.rprpr.yaml")
    )


def test_a_float_cubic_spline_audits_as_c2_once_its_rounding_is_closed() -> None:
    """A C2 cubic spline in floats: its knots agree in slope and curvature only to
    rounding; with a tolerance the later pieces are corrected (by an amount ``snapped``
    bounds) and every knot is exactly C2, so the audit finds no jump."""
    from rprpr.engine.exact.knots import knots as knot_list

    # x = t^3/3 on [0, 1], then 1/3 + u + u^2 - u^3/3 (u = t - 1): C2 in exact arithmetic
    # (value 1/3, slope 1, curvature 2 at t = 1); in floats 1/3 rounds, 3 fl(1/3) != 1
    third = 1 / 3
    xc = [[third, -third], [0.0, 1.0], [0.0, 1.0], [0.0, third]]
    yc = [[0.0, 0.0], [0.0, 0.0], [0.0, 0.0], [1.0, 1.0]]
    given = fmpq_poly([exact(third), 1, 1, -exact(third)])(fmpq_poly([-1, 1]))
    exact_after = fmpq_poly([fmpq(1, 3), 1, 1, fmpq(-1, 3)])(fmpq_poly([-1, 1]))
    raw = Motion.from_pieces([0, 1, 2], xc, yc)  # position is continuous: accepted as given
    assert raw.pieces[1].x == given and raw.snapped == 0
    assert raw.pieces[0].x.derivative()(1) != given.derivative()(1)  # the slope jumps
    motion = Motion.from_pieces([0, 1, 2], xc, yc, tolerance=1e-12)
    first, second = motion.pieces
    a, b = first.x, second.x
    for _ in range(3):
        assert a(1) == b(1)  # value, slope and curvature closed exactly
        a, b = a.derivative(), b.derivative()
    assert 0 < motion.snapped < fmpq(1, 10**15)
    for t in (fmpq(1), fmpq(3, 2), fmpq(2)):
        assert abs(second.x(t) - given(t)) <= motion.snapped  # within the stated bound
        assert abs(second.x(t) - exact_after(t)) < fmpq(1, 10**15)  # and near the exact one
    task = with_motion(load_task(PATH2_FILE), motion)
    assert [(k.velocity_jump, k.acceleration_jump) for k in knot_list(task.motion, task.robot)] == [
        (None, None)
    ]
    before = with_motion(load_task(PATH2_FILE), raw)
    assert knot_list(before.motion, before.robot)[0].velocity_jump is not None

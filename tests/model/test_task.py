"""``Task`` and ``Piece`` as one readable line: x(t) is written in t, y(x) in x."""

from __future__ import annotations

from rprpr.io.loader import load_task, parse_task
from rprpr.model.numbers import polynomial
from tests.conftest import CONFIGS


def test_a_task_is_one_line_with_x_of_t_in_t() -> None:
    task = load_task(CONFIGS / "paper_path1.rprpr.yaml")
    text = repr(task)
    assert "\n" not in text
    assert text == (
        "<Task 'Example 1 of the paper, path 1': y(x) = x^3 - 9*x^2 + 27*x - 27,"
        " x(t) = 12/3125*t^5 - 6/125*t^4 + 4/25*t^3 + 2, 0 <= t <= 5 s (quintic),"
        f" from {CONFIGS / 'paper_path1.rprpr.yaml'}>"
    )


def test_a_piecewise_task_counts_its_pieces_and_each_piece_is_in_t() -> None:
    task = load_task(CONFIGS / "motion_pieces.rprpr.yaml")
    assert repr(task).startswith(
        "<Task 'Planned motion, two quintic pieces': (x(t), y(t)) in 2 pieces, 0 <= t <= 5 s"
    )
    first = repr(task.motion[0])
    assert first.startswith("<Piece 0 <= t <= 5/2: x(t) = 72/3125*t^5 - 4/25*t^4")
    assert "*x" not in first
    trapezoidal = repr(load_task(CONFIGS / "trapezoidal.rprpr.yaml"))
    assert "x(t) in 3 pieces, 0 <= t <= 5 s (trapezoidal)" in trapezoidal


def test_the_polynomials_written_read_back_exactly() -> None:
    task = load_task(CONFIGS / "paper_path1.rprpr.yaml")
    assert task.x_of_t is not None and task.path is not None
    text = (
        "name: t\nrobot:\n  a1: 6\n  links:\n"
        + "".join(f"    {i}: {{mass: 1, inertia: 0.1, r: 0.5}}\n" for i in (2, 3, 4, 5))
        + f"path:\n  y: {polynomial(task.path, 'x')}\n  from: 2\n  to: 4\n"
        + f"timing:\n  duration: 5\n  x: {polynomial(task.x_of_t, 't')}\n"
    )
    back = parse_task(text)
    assert (back.path, back.x_of_t) == (task.path, task.x_of_t)

"""The robust regressor through the compiled kernel (``regressor_{ball,jet}_<scheme>``,
traced by ``kernel_gen`` from ``regressor.regressor_columns``): on random balls and jets
(both actuation schemes, vectors, scalars and broadcast radii, balls holding 0 under a
division, unbounded and NaN inputs), ``regressor_balls`` gives the same arrays, bit for
bit and of the same shapes, as its numpy path; a spy counts the kernel's calls, so the
equality is never numpy's path against itself. Its enclosures of the reference's efforts
are ``test_regressor.py``'s (which runs whichever path is built)."""

from __future__ import annotations

import numpy as np
import pytest

from rprpr.engine.certified.balls import Ball, quiet
from rprpr.engine.certified.jets import Jet
from rprpr.engine.certified.kernel import KERNEL
from rprpr.engine.robust import regressor
from rprpr.engine.robust.regressor import BASIS, regressor_balls
from tests.engine.certified.test_kernel import Spy, _ball, _robot, _same, _vector

needs_kernel = pytest.mark.skipif(KERNEL is None, reason="the compiled kernel is not built")


@needs_kernel
@pytest.mark.parametrize("prismatic", [False, True])
def test_the_regressor_through_the_kernel_is_numpy_bit_for_bit(
    prismatic: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    rng = np.random.default_rng(61 + prismatic)
    spy = Spy(KERNEL)
    trials = 60
    for trial in range(trials):
        robot = _robot(rng, prismatic, bool(rng.integers(0, 2)))
        n = int(rng.choice([1, 2, 3, 17, 64]))
        kin = [_vector(rng, n)] + [_ball(rng, n) for _ in range(5)]
        jets = [Jet(_vector(rng, n), _ball(rng, n))] + [
            Jet(_ball(rng, n), _ball(rng, n)) for _ in range(5)
        ]
        with quiet():
            monkeypatch.setattr(regressor, "KERNEL", spy)
            got, (got_v, got_d) = regressor_balls(robot, kin), regressor_balls(robot, jets, True)
            monkeypatch.setattr(regressor, "KERNEL", None)
            want, (want_v, want_d) = regressor_balls(robot, kin), regressor_balls(robot, jets, True)
        assert np.shape(want.mid) == (2, len(BASIS), 3, n)
        _same(got, want, (trial, "balls"))
        _same(got_v, want_v, (trial, "jets' values"))
        _same(got_d, want_d, (trial, "jets' derivatives"))
    assert (spy.took, spy.declined) == (2 * trials, 0)


@needs_kernel
def test_the_kernel_declines_what_it_does_not_take(monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(3)
    spy = Spy(KERNEL)
    monkeypatch.setattr(regressor, "KERNEL", spy)
    robot = _robot(rng, False, False)
    mixed = [Jet(_vector(rng, 4), _ball(rng, 4))] + [_vector(rng, 4) for _ in range(5)]
    grid = [Ball(np.ones((2, 3)), 0.0)] * 6  # not a vector of times
    with quiet():
        with pytest.raises(AttributeError):  # numpy's path: a ball has no jet's parts
            regressor_balls(robot, mixed, True)
        got = regressor_balls(robot, grid)  # numpy's path: a grid of times
    assert np.shape(got.mid) == (2, len(BASIS), 3, 2, 3)
    assert spy.took == 0 and spy.declined == 0  # both stopped in Python before a call


@needs_kernel
@pytest.mark.parametrize("prismatic", [False, True])
def test_the_windows_guide_is_the_same_with_and_without_the_kernel(
    prismatic: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    # The doubles that steer the window ends' search must not depend on whether the
    # kernel was built: its mids (√(u·u + v·v)) and numpy's fallback, bit for bit.
    rng = np.random.default_rng(17 + prismatic)
    spy = Spy(KERNEL)
    trials = 40
    for trial in range(trials):
        robot = _robot(rng, prismatic, bool(rng.integers(0, 2)))
        n = int(rng.choice([1, 3, 64]))
        kin = [rng.uniform(-3.0, 5.0, n) for _ in range(6)]
        kin[3] = rng.uniform(-1.0, 1.0, n) * 10.0 ** -float(rng.integers(0, 12))  # y near 0
        with quiet():
            monkeypatch.setattr(regressor, "KERNEL", spy)
            got = regressor.regressor_doubles(robot, kin)
            monkeypatch.setattr(regressor, "KERNEL", None)
            want = regressor.regressor_doubles(robot, kin)
        assert got.shape == want.shape == (2, len(BASIS), 3, n)
        assert np.array_equal(got, want, equal_nan=True), trial
    assert (spy.took, spy.declined) == (trials, 0)


@needs_kernel
@pytest.mark.parametrize("prismatic", [False, True])
def test_the_guides_call_made_once_per_instant_is_regressor_doubles(
    prismatic: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    # ``doubles_call`` packs the kernel's call once per instant (its constants looked up
    # once): the same doubles as ``regressor_doubles`` (numpy's path), through the kernel
    # (a spy counts it), and still the kernel it was made with when the module's name
    # changes later
    rng = np.random.default_rng(41 + prismatic)
    spy = Spy(KERNEL)
    trials = 20
    for trial in range(trials):
        robot = _robot(rng, prismatic, bool(rng.integers(0, 2)))
        n = int(rng.choice([1, 3, 64]))
        kin = [rng.uniform(-3.0, 5.0, n) for _ in range(6)]
        kin[3] = rng.uniform(-1.0, 1.0, n) * 10.0 ** -float(rng.integers(0, 12))
        with quiet():
            monkeypatch.setattr(regressor, "KERNEL", spy)
            call = regressor.doubles_call(robot)
            monkeypatch.setattr(regressor, "KERNEL", None)
            assert call is not None
            got = call(kin)
            want = regressor.regressor_doubles(robot, kin)
        assert got is not None and got.shape == want.shape == (2, len(BASIS), 3, n)
        assert np.array_equal(got, want, equal_nan=True), trial
    assert (spy.took, spy.declined) == (trials, 0)

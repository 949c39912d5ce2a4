"""The compiled ball kernel (``rprpr._kernel``): generated, the same doubles as numpy's
path, enclosures of an independent reference.

- ``rprpr/_kernel.c`` is what ``kernel_gen`` writes today (regenerated like a golden).
- On random balls (both actuation schemes, legs alike and asymmetric, vectors, scalars
  and broadcast radii, balls holding 0 under a division, unbounded and NaN inputs,
  overflow), ``Stacked.legs``/``torques``/``efforts``/``efforts_at`` (λ given: vectors,
  one column, scalars), ``horner`` and y's derivatives over boxes
  (``jets.y_values``/``y_jets``) through the kernel give the same
  arrays, bit for bit and of the same shapes, as their numpy path.
- On random boxes, every output ball holds the value of the mpmath reference
  (``tests.reference``, written apart from the engine) at 256 bits at points of the
  boxes, and each jet's derivative ball holds the reference's derivative; T at λ given
  holds the reference's T where the λ balls hold the reference's λ.
- ``RPRPR_NO_KERNEL=1`` turns the kernel off (the numpy path alone), in a fresh process.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import sysconfig
from fractions import Fraction
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import mpmath
import numpy as np
import pytest
from flint import fmpq

from rprpr.engine.bounds import boxes
from rprpr.engine.certified import balls, kernel, kernel_gen, motion, stacked
from rprpr.engine.certified.balls import Ball, _horner, horner, quiet
from rprpr.engine.certified.jets import Jet, y_jets, y_values
from rprpr.engine.certified.kernel import KERNEL
from rprpr.engine.certified.motion import COMPUTED, CertifiedMotion
from rprpr.engine.certified.stacked import Stacked
from rprpr.engine.exact import equations as dyn
from rprpr.model.link import Link
from rprpr.model.task import Robot
from tests.engine.certified.test_motion import _config
from tests.reference import _evaluate

FIELDS = ("s", "cos", "sin", "s_d", "th_d", "s_dd", "th_dd")
needs_kernel = pytest.mark.skipif(KERNEL is None, reason="the compiled kernel is not built")


def test_the_committed_source_is_what_the_generator_writes() -> None:
    assert kernel_gen.OUT.read_text(encoding="utf-8") == kernel_gen.source(), (
        "rprpr/_kernel.c is stale: python -m rprpr.engine.certified.kernel_gen"
    )


def _compiler() -> bool:
    cc = (sysconfig.get_config_var("CC") or "cc").split()[0]
    return shutil.which(cc) is not None and os.path.exists(sysconfig.get_paths()["include"])


def test_the_kernel_is_built_where_it_can_be_and_is_off_when_asked() -> None:
    off = os.environ.get("RPRPR_NO_KERNEL", "") not in ("", "0")
    if off:
        assert KERNEL is None
    elif _compiler():
        assert KERNEL is not None, "a C compiler is here but rprpr._kernel was not built"
    code = "from rprpr.engine.certified.kernel import KERNEL; print(KERNEL is None)"
    env = {**os.environ, "RPRPR_NO_KERNEL": "1"}
    done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                          text=True, check=True)  # fmt: skip
    assert done.stdout.strip() == "True"


def test_a_kernel_built_from_another_source_is_stale(tmp_path: Path) -> None:
    """A checkout whose _kernel.c was regenerated and not rebuilt must not run the old
    formulas: the digest the kernel was built with names its source."""
    text = kernel_gen.OUT.read_text(encoding="utf-8")
    line = next(t for t in text.splitlines() if t.startswith("#define KERNEL_DIGEST"))
    emptied = text.replace(line, kernel_gen.DIGEST_LINE, 1)
    assert kernel_gen.digest_line(emptied) == line  # the digest of the file, that line left empty
    assert kernel_gen.digest_line(emptied + " ") != line
    built = SimpleNamespace(DIGEST=line.split('"')[1])
    source = tmp_path / "_kernel.c"
    source.write_text(text, encoding="utf-8")
    assert not kernel.stale(built, source)
    source.write_text(text.replace(line, kernel_gen.digest_line(emptied + " "), 1), "utf-8")
    assert kernel.stale(built, source)
    assert not kernel.stale(built, tmp_path / "absent.c")  # a wheel: no source beside it
    if KERNEL is not None:
        assert KERNEL.DIGEST == built.DIGEST, "rprpr._kernel is stale: pip install -e ."


# -- bit for bit against numpy's path -------------------------------------------------------
class Spy:
    """The kernel, counting the calls of its functions (``COUNTED``) it took (True) and
    declined (False): a test of equality with numpy's path means nothing where numpy's
    path ran on both sides. Everything else of the kernel is passed through."""

    COUNTED = ("run", "horner", "bounds", "box_max", "form_bounds")

    def __init__(self, kernel: Any) -> None:
        self.kernel = kernel
        self.took = self.declined = 0

    def __getattr__(self, name: str) -> Any:
        attr = getattr(self.kernel, name)
        if name not in self.COUNTED:
            return attr

        def counted(*args: Any) -> bool:
            done = bool(attr(*args))
            self.took += done
            self.declined += not done
            return done

        return counted


@pytest.fixture
def spy(monkeypatch: pytest.MonkeyPatch) -> Spy:
    s = Spy(KERNEL)
    monkeypatch.setattr(stacked, "KERNEL", s)
    monkeypatch.setattr(balls, "KERNEL", s)
    monkeypatch.setattr(motion, "KERNEL", s)
    monkeypatch.setattr(boxes, "KERNEL", s)
    return s


def _robot(rng: np.random.Generator, prismatic: bool, alike: bool) -> Robot:
    def q() -> fmpq:
        return fmpq(int(rng.integers(1, 400)), int(rng.integers(1, 97)))

    leg_a = (Link(q(), q(), q()), Link(q(), q(), q()))
    leg_b = leg_a if alike else (Link(q(), q(), q()), Link(q(), q(), q()))
    links = {2: leg_a[0], 3: leg_a[1], 4: leg_b[0], 5: leg_b[1]}
    return Robot(q(), links, fmpq(981, 100), "prismatic" if prismatic else "revolute")


_SPECIAL = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 1e308, -1e308, 5e-324, 1e-300])


def _mids(rng: np.random.Generator, n: int, shape: tuple[int, ...]) -> np.ndarray:
    m = rng.uniform(-4.0, 4.0, shape) * 10.0 ** rng.integers(-3, 3, shape)
    hit = rng.random(shape) < 0.08
    m[hit] = rng.choice(_SPECIAL, int(hit.sum()))
    small = rng.random(shape) < 0.08  # near A, B and y = 0: balls of s and δ holding 0
    m[small] = rng.uniform(-1e-9, 1e-9, int(small.sum()))
    return m


def _ball(rng: np.random.Generator, n: int) -> Ball:
    """A ball of n columns: a vector, a scalar, one column (numpy broadcasts both), a
    vector of a scalar radius (``Ball.exact``), or exact small integers (0 among them:
    products and sums of exact zeros, where only the pads η and 2^-1064 are left)."""
    kind = rng.integers(0, 7)
    if kind == 6:
        return Ball(rng.integers(-2, 3, n).astype(float), np.zeros(n) if n % 2 else 0.0)
    shape = () if kind == 0 else (1,) if kind == 1 else (n,)
    mid = _mids(rng, n, shape) if shape else np.array(float(_mids(rng, 1, (1,))[0]))
    if kind == 2:
        return Ball(mid, 0.0)
    with quiet():
        rad = np.abs(mid) * 10.0 ** rng.uniform(-17, 1, np.shape(mid))
    rad = np.where(rng.random(np.shape(mid)) < 0.05, np.inf, rad)
    rad = np.where(np.isfinite(rad), rad, np.inf)
    return Ball(mid, rad)


def _vector(rng: np.random.Generator, n: int) -> Ball:
    b = _ball(rng, n)
    return b if np.shape(b.mid) == (n,) else Ball(_mids(rng, n, (n,)), b.rad)


def _same(a: Ball, b: Ball, what: Any) -> None:
    for x, y in ((a.mid, b.mid), (a.rad, b.rad)):
        assert x.shape == y.shape, what
        # the same doubles (NaN for NaN: its payload is not part of the contract)
        same = (x.view(np.int64) == y.view(np.int64)) | (np.isnan(x) & np.isnan(y))
        assert same.all(), (what, x[~same], y[~same])


@needs_kernel
@pytest.mark.parametrize("prismatic", [False, True])
@pytest.mark.parametrize("alike", [False, True])
def test_stacked_through_the_kernel_is_numpy_bit_for_bit(
    prismatic: bool, alike: bool, spy: Spy
) -> None:
    rng = np.random.default_rng(23 + 2 * prismatic + alike)
    for trial in range(60):
        st = Stacked(_robot(rng, prismatic, alike))
        n = int(rng.choice([1, 2, 3, 17, 64]))
        with quiet():
            args = [_vector(rng, n)] + [_ball(rng, n) for _ in range(5)]
            got, want = st.legs(*args), st._legs(*args)
            for f in FIELDS:
                _same(getattr(got, f), getattr(want, f), (trial, f))
            T, d = st.torques(want, args[3])
            T0, d0 = st._torques(want, args[3])
            _same(T, T0, (trial, "T"))
            _same(d, d0, (trial, "delta"))
            numpy_balls = T0  # numpy's legs, then its torques, of these balls
            given = _ball(rng, n)  # δ given (the factored form near A or B)
            (T, d), (T0, _) = (
                st.torques(want, args[3], delta=given),
                st._torques(want, args[3], delta=given),
            )
            _same(T, T0, (trial, "T at δ"))
            assert d is given
            jets = [Jet(_vector(rng, n), _ball(rng, n))] + [
                Jet(_ball(rng, n), _ball(rng, n)) for _ in range(5)
            ]
            got, want = st.legs(*jets), st._legs(*jets)
            for f in FIELDS:
                _same(getattr(got, f).v, getattr(want, f).v, (trial, f, "v"))
                _same(getattr(got, f).d, getattr(want, f).d, (trial, f, "d"))
            T, d = st.torques(want, jets[3])
            T0, d0 = st._torques(want, jets[3])
            numpy_jets = T0  # numpy's legs, then its torques, of these jets
            for a, b, w in ((T.v, T0.v, "T"), (T.d, T0.d, "T'"), (d.v, d0.v, "δ"),
                            (d.d, d0.d, "δ'")):  # fmt: skip
                _same(a, b, (trial, w))
            given = Jet(_ball(rng, n), _ball(rng, n))
            T = st.torques(want, jets[3], delta=given)[0]
            T0 = st._torques(want, jets[3], delta=given)[0]
            _same(T.v, T0.v, (trial, "T at δ"))
            _same(T.d, T0.d, (trial, "T' at δ"))
            # the legs and the torques in one call (``efforts``) against numpy's two (made
            # above, of the same balls and jets)
            _same(st.efforts(*args), numpy_balls, (trial, "E"))
            E, E0 = st.efforts(*jets), numpy_jets
            _same(E.v, E0.v, (trial, "E"))
            _same(E.d, E0.d, (trial, "E'"))
    assert spy.took >= 8 * 60 * 0.9  # eight calls a trial, and few shapes declined


def _lam(rng: np.random.Generator, n: int) -> Ball:
    """λ as the forms near an instant give it: a vector (a zone's, of ε), one column (a
    box's Lagrange form times a power of ε), or a scalar (the form's ratio alone)."""
    kind = rng.integers(0, 3)
    if kind == 0:
        return _vector(rng, n)
    mid = _mids(rng, 1, (1,))
    with quiet():
        rad = np.abs(mid) * 10.0 ** rng.uniform(-17, 1)
    return Ball(mid, rad) if kind == 1 else Ball(mid[0], rad[0])


@needs_kernel
@pytest.mark.parametrize("prismatic", [False, True])
def test_efforts_at_lambda_given_through_the_kernel_are_numpy_bit_for_bit(
    prismatic: bool, spy: Spy
) -> None:
    """``efforts_at`` (the legs and the torques at λ given, in one call) against numpy's
    ``_torques(_legs(...), y, λ)``, on balls and on jets."""
    rng = np.random.default_rng(61 + prismatic)
    for trial in range(80):
        st = Stacked(_robot(rng, prismatic, bool(rng.integers(0, 2))))
        n = int(rng.choice([1, 2, 3, 17, 64]))
        with quiet():
            args = [_vector(rng, n)] + [_ball(rng, n) for _ in range(5)]
            lam = (_lam(rng, n), _lam(rng, n))
            want = st._torques(st._legs(*args), args[3], lam)[0]
            _same(st.efforts_at(*args, lam), want, (trial, "T at λ"))
            jets = [Jet(_vector(rng, n), _ball(rng, n))] + [
                Jet(_ball(rng, n), _ball(rng, n)) for _ in range(5)
            ]
            lj = (Jet(_lam(rng, n), _lam(rng, n)), Jet(_lam(rng, n), _lam(rng, n)))
            got, want = st.efforts_at(*jets, lj), st._torques(st._legs(*jets), jets[3], lj)[0]
            _same(got.v, want.v, (trial, "T at λ"))
            _same(got.d, want.d, (trial, "T' at λ"))
    assert (spy.took, spy.declined) == (2 * 80, 0)


class _Motion(CertifiedMotion):
    """What ``formulas`` reads of a motion: the robot's parameters and its scheme."""

    def __init__(self, robot: Robot) -> None:
        self.robot = robot
        self.mech = dyn.MECHANISMS[robot.actuation]


@needs_kernel
@pytest.mark.parametrize("prismatic", [False, True])
def test_the_motions_formulas_through_the_kernel_are_numpy_bit_for_bit(
    prismatic: bool, spy: Spy
) -> None:
    rng = np.random.default_rng(41 + prismatic)
    for trial in range(80):
        m = _Motion(_robot(rng, prismatic, bool(rng.integers(0, 2))))
        n = int(rng.choice([1, 2, 3, 17, 64]))
        kin = [_vector(rng, n)] + [_ball(rng, n) for _ in range(5)]
        with quiet():
            got, want = m.formulas(*kin), m._formulas(*kin)
        assert list(got) == list(want)  # the same names in the same order
        for name in want:
            _same(got[name], want[name], (trial, name))
    assert spy.took == 80


@needs_kernel
def test_horner_through_the_kernel_is_numpy_bit_for_bit(spy: Spy) -> None:
    rng = np.random.default_rng(7)
    for trial in range(300):
        n = int(rng.choice([1, 2, 5, 40]))
        c = [_ball(rng, n) for _ in range(int(rng.integers(2, 12)))]
        x = _vector(rng, n)
        with quiet():
            _same(horner(c, x), _horner(c, x), trial)
    assert spy.took == 300


@needs_kernel
def test_y_over_boxes_through_the_kernel_is_numpy_bit_for_bit(spy: Spy) -> None:
    rng = np.random.default_rng(11)
    for trial in range(200):
        n = int(rng.choice([1, 2, 5, 40]))
        kinds = (("y_values", y_values, 5, 3), ("y_jets", y_jets, 7, 4))
        for name, form, k, qd in kinds:
            ins = []
            for i in range(k):  # vectors, and scalars (a derivative of a low degree)
                b = _vector(rng, n)
                scalar = rng.random() < 0.3 and i != qd
                ins.append(Ball(b.mid[0], b.rad.flat[0]) if scalar else
                           Ball(b.mid, np.broadcast_to(b.rad, (n,)).copy()))  # fmt: skip
            with quiet():
                got, want = boxes._compiled(tuple(ins), name, qd), form(*ins)
            assert got is not None and len(got) == len(want)
            for i, (g, w) in enumerate(zip(got, want, strict=True)):
                _same(g, w, (trial, name, i))
    assert (spy.took, spy.declined) == (400, 0)
    scalar = Ball(1.0, 0.0)  # x' and q' scalars: numpy's path (scalar outputs)
    assert boxes._compiled((scalar,) * 5, "y_values", 3) is None and spy.took == 400


@needs_kernel
def test_strided_and_reversed_inputs_are_read_as_numpy_reads_them(spy: Spy) -> None:
    rng = np.random.default_rng(5)
    st = Stacked(_robot(rng, False, False))
    big = [Ball(rng.uniform(-3, 3, 40), rng.uniform(0, 1e-6, 40)) for _ in range(6)]
    with quiet():
        args = [Ball(b.mid[::-2], b.rad[::-2]) for b in big]  # negative strides, of 20
        got, want = st.legs(*args), st._legs(*args)
        for f in FIELDS:
            _same(getattr(got, f), getattr(want, f), f)
        lg = dyn.Leg(*(Ball(getattr(want, f).mid[:, ::-1], getattr(want, f).rad[:, ::-1])
                       for f in FIELDS))  # fmt: skip
        y = Ball(args[3].mid[::-1], args[3].rad[::-1])
        (T, d), (T0, d0) = st.torques(lg, y), st._torques(lg, y)
        _same(T, T0, "T")
        _same(d, d0, "δ")
        c = [Ball(rng.uniform(-1, 1, 40)[::2], rng.uniform(0, 1e-9, 40)[1::2]) for _ in range(4)]
        _same(horner(c, args[0]), _horner(c, args[0]), "horner")
    assert (spy.took, spy.declined) == (3, 0)


@needs_kernel
def test_the_kernel_declines_what_it_does_not_take(spy: Spy) -> None:
    """Shapes outside its contract (a leg field of one row, coefficients of two rows,
    more coefficients than it holds) go the numpy way, with numpy's results."""
    st = Stacked(_config("paper_path1.rprpr.yaml").robot)
    rng = np.random.default_rng(3)
    with quiet():
        c = [Ball(rng.uniform(-1, 1, (2, 4)), 1e-9) for _ in range(3)]
        x = Ball(rng.uniform(-1, 1, 4), 0.0)
        _same(horner(c, x), _horner(c, x), "2 rows")
        c = [Ball(float(v), 0.0) for v in rng.uniform(-1, 1, 80)]
        _same(horner(c, x), _horner(c, x), "80 coefficients")
        c = [Ball(rng.uniform(-1, 1, 4), 0.0) for _ in range(3)]
        one = Ball(np.array([0.5]), 0.0)  # x of one column, coefficients of four
        _same(horner(c, one), _horner(c, one), "x broadcast")
        args = [Ball(rng.uniform(1, 2, 4), 1e-9) for _ in range(6)]
        lg = st._legs(*args)
        one = dyn.Leg(*(getattr(lg, f)[0] for f in FIELDS))  # rows 0 only: (4,) each
        T, d = st.torques(one, args[3])
        T0, d0 = st._torques(one, args[3])
        _same(T, T0, "T")
        _same(d, d0, "δ")
    assert spy.took == 0 and spy.declined == 3  # the legs' shapes checked in Python


# -- enclosures of the reference --------------------------------------------------------
def _points(rng: np.random.Generator, balls: list[Ball], j: int) -> list[Fraction]:
    """A point of each ball (column j): exactly inside, corners included."""
    out = []
    for b in balls:
        m = Fraction(float(np.broadcast_to(b.mid, (len(np.atleast_1d(b.mid)),))[j]))
        r = Fraction(float(np.broadcast_to(b.rad, np.shape(b.mid) or (1,)).flat[j]))
        out.append(m + r * Fraction(int(rng.integers(-8, 9)), 8))
    return out


def _holds(b: Ball, index: Any, v: Any, slack: Any = 0) -> bool:
    m, r = float(np.asarray(b.mid)[index]), float(np.asarray(b.rad)[index])
    return bool(abs(mpmath.mpf(m) - v) <= mpmath.mpf(r) + slack)


def _reference(robot: Robot, point: list[Any]) -> dict[str, Any]:
    class Task:  # what _evaluate reads of a task
        pass

    task = Task()
    task.robot = robot  # type: ignore[attr-defined]
    return _evaluate(task, tuple(point))  # type: ignore[arg-type]


def _leg_values(ref: dict[str, Any], leg: int, u: Any, y: Any) -> list[Any]:
    s = ref[f"s{leg}"]
    return [s, u / s, y / s, ref[f"s{leg}_dot"], ref[f"theta{leg}_dot"],
            ref[f"s{leg}_ddot"], ref[f"theta{leg}_ddot"]]  # fmt: skip


def _boxes(rng: np.random.Generator, n: int) -> list[Ball]:
    """Boxes of x, ẋ, ẍ, y, ẏ, ÿ away from A, B and y = 0 (a reference defined there)."""
    mids = [
        rng.uniform(-1.0, 7.0, n), rng.uniform(-2.0, 2.0, n), rng.uniform(-3.0, 3.0, n),
        rng.choice([-1.0, 1.0], n) * rng.uniform(0.05, 1.0, n),
        rng.uniform(-2.0, 2.0, n), rng.uniform(-3.0, 3.0, n),
    ]  # fmt: skip
    return [Ball(m, np.abs(m) * 10.0 ** rng.uniform(-12, -4, n)) for m in mids]


@needs_kernel
@pytest.mark.parametrize("prismatic", [False, True])
def test_kernel_balls_enclose_the_reference(prismatic: bool, spy: Spy) -> None:
    rng = np.random.default_rng(11 + prismatic)
    checked = 0
    for _ in range(4):
        robot = _robot(rng, prismatic, bool(rng.integers(0, 2)))
        st = Stacked(robot)
        n = 12
        boxes = _boxes(rng, n)
        with quiet():
            lg = st.legs(*boxes)
            T, d = st.torques(lg, boxes[3])
            E = st.efforts(*boxes)  # the legs and the torques in one call
            values = _Motion(robot).formulas(*boxes)
        a1 = mpmath.mpf(int(robot.a1.p)) / int(robot.a1.q)
        for j in range(n):
            for _ in range(3):
                p = _points(rng, boxes, j)
                with mpmath.workprec(256):
                    ref = _reference(robot, p)
                    if ref.get("T1") is None:
                        continue
                    x, y = (mpmath.mpf(v.numerator) / v.denominator for v in (p[0], p[3]))
                    for i, u in ((0, x), (1, x - a1)):
                        for f, v in zip(FIELDS, _leg_values(ref, i + 1, u, y), strict=True):
                            assert _holds(getattr(lg, f), (i, j), v), (f, i, j)
                    assert _holds(T, (0, j), ref["T1"]) and _holds(T, (1, j), ref["T2"])
                    assert _holds(E, (0, j), ref["T1"]) and _holds(E, (1, j), ref["T2"])
                    assert _holds(d, j, ref["delta"])
                    for name in COMPUTED:  # the motion's formulas
                        assert _holds(values[name], j, ref[name]), name
                    checked += 1
    assert checked >= 100  # of 144 points (a few fall where T is undefined)
    assert (spy.took, spy.declined) == (4 * 4, 0)  # legs, torques, efforts, formulas: kernel's


@needs_kernel
@pytest.mark.parametrize("prismatic", [False, True])
def test_efforts_at_lambda_given_enclose_the_reference(prismatic: bool, spy: Spy) -> None:
    """T over boxes at λ given, λ1 and λ2 balls holding the reference's λ at the points
    taken in each box: T's balls hold the reference's T1, T2 at those points."""
    rng = np.random.default_rng(71 + prismatic)
    checked = 0
    for _ in range(4):
        robot = _robot(rng, prismatic, bool(rng.integers(0, 2)))
        st = Stacked(robot)
        n = 12
        boxes = _boxes(rng, n)
        refs: list[list[dict[str, Any]]] = []
        for j in range(n):
            with mpmath.workprec(256):
                got = [_reference(robot, _points(rng, boxes, j)) for _ in range(3)]
            refs.append([r for r in got if r.get("T1") is not None])
        lam = []
        for key in ("lambda1", "lambda2"):
            lo, hi = np.zeros(n), np.zeros(n)
            for j, rs in enumerate(refs):
                v = [float(r[key]) for r in rs] or [0.0]
                lo[j], hi[j] = min(v), max(v)
            mid, rad = 0.5 * lo + 0.5 * hi, 0.5 * (hi - lo)
            lam.append(Ball(mid, rad * 2 + np.abs(mid) * 1e-12 + 1e-300))  # round-off held
        with quiet():
            T = st.efforts_at(*boxes, (lam[0], lam[1]))
        for j, rs in enumerate(refs):
            for ref in rs:
                for i, key in ((0, "lambda1"), (1, "lambda2")):
                    assert _holds(lam[i], j, ref[key])
                assert _holds(T, (0, j), ref["T1"]) and _holds(T, (1, j), ref["T2"])
                checked += 1
    assert checked >= 100  # of 144 points (a few fall where T is undefined)
    assert (spy.took, spy.declined) == (4, 0)  # the kernel's, one call a robot


@needs_kernel
@pytest.mark.parametrize("prismatic", [False, True])
def test_kernel_jets_enclose_the_reference_and_its_derivative(prismatic: bool, spy: Spy) -> None:
    """Jets (f, f') over boxes: at a point p of the values' boxes and a direction q of the
    derivatives' boxes, T(p + τ q) and its derivative at τ = 0 lie in T.v and T.d."""
    rng = np.random.default_rng(31 + prismatic)
    for _ in range(3):
        robot = _robot(rng, prismatic, bool(rng.integers(0, 2)))
        st = Stacked(robot)
        n = 6
        vals, ders = _boxes(rng, n), _boxes(rng, n)
        jets = [Jet(v, d) for v, d in zip(vals, ders, strict=True)]
        with quiet():
            T, d = st.torques(st.legs(*jets), jets[3])
            E = st.efforts(*jets)  # the legs and the torques in one call
        for j in range(n):
            p, q = _points(rng, vals, j), _points(rng, ders, j)
            with mpmath.workprec(256):
                P = [mpmath.mpf(v.numerator) / v.denominator for v in p]
                Q = [mpmath.mpf(v.numerator) / v.denominator for v in q]

                seen: dict[tuple[Any, int], dict[str, Any]] = {}  # T1, T2, δ: one evaluation

                def along(tau: Any, key: str, P: list[Any] = P, Q: list[Any] = Q,
                          robot: Robot = robot, seen: dict = seen) -> Any:  # fmt: skip
                    at = (tau, mpmath.mp.prec)  # the values at τ, at the working precision
                    if at not in seen:
                        seen[at] = _reference(
                            robot, [a + tau * b for a, b in zip(P, Q, strict=True)]
                        )
                    return seen[at][key]

                slack = mpmath.mpf(2) ** -100
                for row, key in ((0, "T1"), (1, "T2")):
                    derivative = mpmath.diff(lambda t, k=key: along(t, k), 0)
                    for J in (T, E):
                        assert _holds(J.v, (row, j), along(0, key))
                        assert _holds(J.d, (row, j), derivative, slack)
                assert _holds(d.v, j, along(0, "delta"))
                assert _holds(d.d, j, mpmath.diff(lambda t: along(t, "delta"), 0), slack)
    assert (spy.took, spy.declined) == (3 * 3, 0)  # the jets' legs, torques, efforts: kernel's

"""What this build cannot audit of a 5R task is refused in one located line, exit 2.

``rprpr check`` audits a 5R task's exact verdicts (tests/fivebar/test_check.py) and its
certified layers (the torque limit, the peak, the samples that
``export`` writes: tests/fivebar/test_certified.py); ``plot`` draws a 5R
(tests/render/test_sheet_five_bar.py). What is not available for a 5R yet
(``engine.five_bar_audit.refuse``): declared uncertainty and ``repair``. The Python API
raises ``TaskFileError`` at the same key.
"""

from __future__ import annotations

from contextlib import chdir
from fractions import Fraction
from functools import cache
from pathlib import Path

import mpmath
import pytest

from rprpr import audit
from rprpr.io.loader import load_task
from tests.conftest import run_cli
from tests.fivebar.reference import DPS, FiveBar, Motion, torques

DEXTAR = Path(__file__).resolve().parents[1] / "io" / "data" / "five_bar_dextar.rprpr.yaml"
TEXT = DEXTAR.read_text()
LIMIT = "  torque_limit: [5, 5]       # |T1|, |T2| [N m]\n"
YET = "not available for a 5R yet"


def _line(text: str, start: str) -> int:
    return next(i for i, ln in enumerate(text.splitlines(), 1) if ln.startswith(start))


MECHANISM_LINE = _line(TEXT, "  mechanism:")


def _without_limit(folder: Path, extra: str = "") -> Path:
    assert LIMIT in TEXT
    path = folder / "dextar.rprpr.yaml"
    path.write_text(TEXT.replace(LIMIT, "  strict: false\n") + extra)
    return path


def _reference_peaks() -> list[Fraction]:
    """max |T1|, max |T2| of the DexTAR task by the Newton-Euler reference (mpmath): on
    201 times of [0, t_f], then twice on a grid 20 times finer about the largest."""
    rb = FiveBar(
        Fraction(1, 5), (Fraction(1, 5),) * 2 + (Fraction(3, 10),) * 2,
        (Fraction(1, 4),) * 2 + (Fraction(3, 20),) * 2,
        (Fraction(83, 100000),) * 2 + (Fraction(1125, 1000000),) * 2,
        (Fraction(1, 10),) * 2 + (Fraction(3, 20),) * 2, Fraction(981, 100),
    )  # fmt: skip
    tf, d = Fraction(1, 2), Fraction(3, 10)  # quintic rest to rest, x from -0.05 to 0.25
    m = Motion((Fraction(-1, 20), 0, 0, 10 * d / tf**3, -15 * d / tf**4, 6 * d / tf**5),
               (Fraction(3, 10),))  # fmt: skip

    @cache
    def both(t: Fraction) -> tuple[Fraction, Fraction]:
        with mpmath.workdps(DPS):
            T = torques(rb, m, t, (1, -1))
            return Fraction(mpmath.nstr(abs(T[0]), 30)), Fraction(mpmath.nstr(abs(T[1]), 30))

    def size(t: Fraction, i: int) -> Fraction:
        return both(t)[i]

    out = []
    for i in (0, 1):
        h = tf / 200
        ts = [h * j for j in range(201)]
        for _ in range(3):
            best = max(ts, key=lambda t: size(t, i))
            ts = [t for t in (best + h * (j - 20) / 20 for j in range(41)) if 0 <= t <= tf]
            h /= 20
        out.append(max(size(t, i) for t in ts))
    return out


# The reference's peaks (``_reference_peaks``: ~400 Newton-Euler evaluations at 60
# digits, ~1 CPU-s), stored as it gives them: the reference's values never change, and a
# slow test recomputes them.
REFERENCE_PEAKS = [Fraction("0.864747141142113073261125828509")] * 2


@pytest.mark.slow  # the reference's peaks recomputed (Newton-Euler at 60 digits)
def test_the_stored_peaks_are_the_references() -> None:
    assert _reference_peaks() == REFERENCE_PEAKS


def test_the_audit_checks_a_5r_tasks_torque_limit() -> None:
    """The reference's max |T1|, |T2| (0.8647 N m) is below the limit 5 N m: passed; and
    the engine's certified peak holds it."""
    peaks = REFERENCE_PEAKS
    assert all(0.8 < p < 5 for p in peaks)
    result = audit(load_task(DEXTAR), peak=True)
    assert result.torque_limit is not None
    assert [c.passed for c in result.torque_limit] == [True, True]
    assert [c.limit for c in result.torque_limit] == [5.0, 5.0]
    assert result.torque_peak is not None
    for pk, ref in zip(result.torque_peak, peaks, strict=True):
        assert pk.value <= ref * (1 + 1e-9) and pk.upper >= ref * (1 - 1e-9)


@pytest.mark.parametrize("form", ["concise", "text"])
def test_check_audits_a_torque_limit_with_status_0(form: str) -> None:
    code, out, err = run_cli("check", "--format", form, str(DEXTAR))
    assert (code, err) == (0, "")
    assert "RPR001" not in out


def test_check_audits_the_same_task_without_the_limit(tmp_path: Path) -> None:
    code, out, err = run_cli("check", str(_without_limit(tmp_path)))
    assert (code, err) == (0, "")
    assert "no Type II singular instant in [0, t_f]" in out
    last = "  verdict: PASS — 0 singular instants, 0 high-order; peak not computed (--peak)"
    assert out.splitlines()[-1] == last  # as the RPRPR says it


def test_check_gives_the_peak_of_a_5r(tmp_path: Path) -> None:
    code, out, err = run_cli("check", "--peak", str(_without_limit(tmp_path)))
    assert (code, err) == (0, "")
    assert "; peak |T1| " in out.splitlines()[-1]


def test_check_refuses_declared_uncertainty_on_a_5r(tmp_path: Path) -> None:
    path = tmp_path / "dextar.rprpr.yaml"
    path.write_text(TEXT + "uncertainty: {links: 5%, acceleration: 0, period: 0.001}\n")
    code, _, err = run_cli("check", str(path))
    assert code == 2
    line = _line(path.read_text(), "uncertainty:")
    # the task file's reader refuses it already (the robust audit is the RPRPR's)
    assert err.startswith(f"{path}:{line}:14: uncertainty: uncertainty is for mechanism: rprpr")
    assert err.endswith(" [RPR001]\n") and err.count("\n") == 1


def test_the_configurations_uncertainty_on_a_5r_is_refused_at_a_line(tmp_path: Path) -> None:
    """The task file holds no ``uncertainty`` key to point at: the one line names the
    configuration and stands at the task's timing (its motion), file:line:col, exit 2."""
    (tmp_path / "rprpr.toml").write_text(
        'uncertainty = {links = "5%", acceleration = 0.01, period = 0.001}\n'
    )
    path = tmp_path / "dextar.rprpr.yaml"
    path.write_text(TEXT)
    with chdir(tmp_path):
        code, _, err = run_cli("check", path.name)
    assert code == 2
    line = _line(TEXT, "timing:")
    assert err == (
        f"{path.name}:{line}:1: uncertainty: uncertainty is {YET} (declared by the"
        f" configuration {tmp_path / 'rprpr.toml'}:1) (its audit is the RPRPR's) [RPR001]\n"
    )


@pytest.mark.parametrize(
    "command",
    [
        ("repair", "-o", "{tmp}/r.yaml"),
    ],
)
def test_repair_refuses_a_5r_task(command: tuple[str, ...], tmp_path: Path) -> None:
    args = [a.format(tmp=tmp_path) for a in command]
    source = _without_limit(tmp_path)
    code, _, err = run_cli(args[0], str(source), *args[1:])
    assert code == 2
    assert err == (
        f"rprpr: {source}:{MECHANISM_LINE}: robot.mechanism: rprpr {args[0]} is {YET}"
        " (rprpr check audits it)\n"
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dextar.rprpr.yaml"]  # nothing written


def _pieces(folder: Path, checks: str) -> Path:
    """The DexTAR task as a motion of two pieces, with ``checks``."""
    text = TEXT
    start = text.index("path:")
    pieces = (
        "motion:\n  pieces:\n"
        "    - until: 0.25\n      x: -0.05 + 0.6*t\n      y: 0.3\n"
        "    - until: 0.5\n      x: -0.05 + 0.6*t\n      y: 0.3\n"
    )
    path = folder / "pieces.rprpr.yaml"
    path.write_text(text[:start] + pieces + "checks:\n" + checks)
    return path


@pytest.mark.parametrize(
    ("checks", "options"),
    [("  torque_limit: [5, 5]\n", ()), ("  strict: false\n", ("--peak",))],
)
def test_check_audits_the_certified_layers_of_several_pieces(
    tmp_path: Path, checks: str, options: tuple[str, ...]
) -> None:
    """No longer refused: their values are tests/fivebar/test_certified_pieces.py's."""
    path = _pieces(tmp_path, checks)
    code, out, err = run_cli("check", *options, str(path))
    assert (code, err) == (0, "")
    assert "verdict: PASS" in out


def test_export_writes_a_5r_motion_of_several_pieces(tmp_path: Path) -> None:
    path = _pieces(tmp_path, "  strict: false\n")
    code, _, err = run_cli("export", str(path), "-o", str(tmp_path / "x.csv"), "--samples", "3")
    assert (code, err) == (0, f"rprpr: wrote {tmp_path / 'x.csv'} (3 samples)\n")
    rows = (tmp_path / "x.csv").read_text().splitlines()[2:]
    assert [r.split(",")[0] for r in rows] == ["0.0", "0.25", "0.5"]


def test_an_rprpr_task_is_audited_as_before() -> None:
    config = Path(__file__).resolve().parents[2] / "configs" / "paper_path2.rprpr.yaml"
    result = audit(load_task(config))
    assert result.task.robot.mechanism == "rprpr"
    assert result.verdict == "pass"

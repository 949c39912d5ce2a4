"""rprpr export: the columns, the paper's numbers, the engine's numbers, nan/null at a pole."""

from __future__ import annotations

import csv
import io
import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from rprpr import __version__
from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from tests.cli.forked import fresh_probe
from tests.conftest import CONFIGS, PATH1_FILE, PATH2_FILE, run_cli, task_text

# the issue's column list, written out independently of samples.COLUMNS, and the reason
ISSUE_COLUMNS = [
    "t", "x", "y", "x_dot", "y_dot", "theta1", "s1", "theta2", "s2",
    "theta1_dot", "s1_dot", "theta2_dot", "s2_dot",
    "delta", "delta_dot", "lambda1", "lambda2", "T1", "T2",
    "x_ddot", "y_ddot", "theta1_ddot", "s1_ddot", "theta2_ddot", "s2_ddot", "reason",
]  # fmt: skip
WIDTH = len(ISSUE_COLUMNS)


def read_csv(text: str) -> tuple[list[str], list[str], np.ndarray]:
    """(comment lines, column names, values) of an exported CSV."""
    lines = text.splitlines()
    comments = [line for line in lines if line.startswith("#")]
    rows = list(csv.reader(line for line in lines if not line.startswith("#")))
    return comments, rows[0], np.array([[float(v) for v in r] for r in rows[1:]])


def engine_rows(path: str, n: int) -> np.ndarray:
    """The engine's samples and their reason codes, as the export's rows."""
    samples = audit(load_task(path), samples=n).samples
    return np.column_stack([samples.rows(), samples.reason])


# ---------------------------------------------------------------------------------------
# content


def test_columns_are_the_issues_in_order() -> None:
    code, out, _ = run_cli("export", PATH2_FILE, "--samples", "5")
    assert code == 0
    _, names, values = read_csv(out)
    assert names == ISSUE_COLUMNS
    assert values.shape == (5, WIDTH)


@pytest.mark.parametrize("path", [PATH1_FILE, PATH2_FILE])
def test_first_row_is_the_papers_initial_configuration(path: str) -> None:
    """Section 4: θ1 = -26.5651°, s1 = 2.2361 m, θ2 = -165.9638°, s2 = 4.1231 m at rest."""
    _, out, _ = run_cli("export", path, "--samples", "11")
    _, names, v = read_csv(out)
    row = dict(zip(names, v[0], strict=True))
    assert row["t"] == 0.0
    assert (row["x"], row["y"]) == pytest.approx((2.0, -1.0), abs=1e-12)
    assert math.degrees(row["theta1"]) == pytest.approx(-26.5651, abs=5e-5)
    assert row["s1"] == pytest.approx(2.2361, abs=5e-5)
    assert math.degrees(row["theta2"]) == pytest.approx(-165.9638, abs=5e-5)
    assert row["s2"] == pytest.approx(4.1231, abs=5e-5)
    # exactly: θ1 = -atan(1/2), s1 = √5, θ2 = -(π - atan(1/4)), s2 = √17
    assert row["theta1"] == pytest.approx(-math.atan(0.5), abs=1e-14)
    assert row["theta2"] == pytest.approx(-(math.pi - math.atan(0.25)), abs=1e-14)
    assert row["s1"] == pytest.approx(math.sqrt(5), abs=1e-14)
    assert row["s2"] == pytest.approx(math.sqrt(17), abs=1e-14)
    for rate in ("x_dot", "y_dot", "theta1_dot", "s1_dot", "theta2_dot", "s2_dot", "delta_dot"):
        assert row[rate] == 0.0  # rest-to-rest quintic (eq. 49)


def test_samples_11_hit_t_2_5_and_write_the_bounded_limit() -> None:
    """Path 2, alike legs: consistent first-order crossing at t = 2.5 s; the torques there
    are the finite limit (63.225, -5.445) N m, not NaN and not a cancellation artefact."""
    _, out, _ = run_cli("export", PATH2_FILE, "--samples", "11")
    _, names, v = read_csv(out)
    col = {n: v[:, j] for j, n in enumerate(names)}
    assert col["t"][5] == 2.5  # exactly: t_i = i t_f / (N - 1)
    assert np.array_equal(col["t"], np.arange(11) * 0.5)
    assert (col["x"][5], col["y"][5], col["delta"][5]) == (3.0, 0.0, 0.0)
    assert col["T1"][5] == pytest.approx(63.225, abs=1e-9)
    assert col["T2"][5] == pytest.approx(-5.445, abs=1e-9)
    limit = audit(load_task(PATH2_FILE)).singularities[0].torque_at_singularity
    assert (col["T1"][5], col["T2"][5]) == pytest.approx(limit, abs=1e-9)
    assert np.all(np.isfinite(v)) and np.all(col["reason"] == 0)
    # δ' = -0.1 there (the path crosses with slope: a first-order singularity, Fig. 4)
    assert col["delta_dot"][5] == pytest.approx(-0.1, abs=1e-12)


def test_unbounded_instant_is_nan_in_csv_and_null_in_json(tmp_path: Path) -> None:
    """Path 1: third-order singularity at t = 2.5 s, pole of order 2: λ2, T1, T2 have no
    value there. λ1 = (s1 F1 + s2 F2)/a1 stays bounded in case 3 and is written."""
    _, out, _ = run_cli("export", PATH1_FILE, "--samples", "11")
    line = [r for r in out.splitlines() if r.startswith("2.5,")]
    assert len(line) == 1
    fields = dict(zip(ISSUE_COLUMNS, line[0].split(","), strict=True))
    assert fields["lambda2"] == fields["T1"] == fields["T2"] == "nan"
    assert fields["reason"] == "1"  # a pole: an unbounded singular instant
    assert math.isfinite(float(fields["lambda1"]))
    _, _, v = read_csv(out)
    others = np.delete(v, 5, axis=0)
    assert np.all(np.isfinite(others))
    assert np.all(others[:, -1] == 0)  # every value of those rows certified
    assert np.max(np.abs(others[:, -3:-1])) < 200  # no huge finite value beside the pole

    dest = tmp_path / "p1.json"
    code, _, _ = run_cli("export", PATH1_FILE, "--samples", "11", "-o", str(dest))
    assert code == 0
    doc = json.loads(dest.read_text(), parse_constant=lambda c: pytest.fail(f"non-JSON {c}"))
    row = dict(zip(doc["columns"], doc["rows"][5], strict=True))
    assert row["t"] == 2.5
    assert row["lambda2"] is None and row["T1"] is None and row["T2"] is None
    assert row["reason"] == 1 and doc["reasons"]["1"].startswith("a singular instant with")
    assert doc["singularities"][0]["torque_bounded"] is False
    assert doc["singularities"][0]["order"] == 3


@pytest.mark.parametrize("fmt", ["csv", "json"])
@pytest.mark.parametrize(  # a 5R's export needs its certified samples: not in this build
    "path", sorted(str(p) for p in CONFIGS.glob("*.yaml") if not p.name.startswith("five_bar_"))
)
def test_export_equals_the_engines_numbers(path: str, fmt: str, tmp_path: Path) -> None:
    """Every value round-trips exactly (shortest repr); NaN where the engine has NaN."""
    dest = tmp_path / f"out.{fmt}"
    code, out, _ = run_cli("export", path, "--samples", "101", "-o", str(dest))
    assert code == 0 and out == ""
    text = dest.read_text(encoding="utf-8")
    if fmt == "csv":
        got = read_csv(text)[2]
    else:
        doc = json.loads(text)
        got = np.array([[np.nan if v is None else v for v in r] for r in doc["rows"]], dtype=float)
    want = engine_rows(path, 101)
    assert got.shape == want.shape == (101, WIDTH)
    assert np.array_equal(got, want, equal_nan=True)


def test_header_names_the_task_and_the_version() -> None:
    _, out, _ = run_cli("export", PATH2_FILE, "--samples", "3")
    first = out.splitlines()[0]
    assert first.startswith(f"# rprpr {__version__} ")
    assert '"Example 2 of the paper, path 2"' in first
    assert PATH2_FILE in first and "3 samples" in first
    assert sum(line.startswith("#") for line in out.splitlines()) == 1
    assert "every value certified to |err| <= 1e-09 (1 + |value|), or nan; reason codes:" in first
    assert first.endswith(
        "0 = every value certified; 1 = a singular instant with unbounded torques (a pole of"
        " λ2): λ2, T1, T2 undefined; 2 = the end point is at A (s1 = 0): θ1, its rates, δ, λ"
        " and T undefined; 3 = the end point is at B (s2 = 0): θ2, its rates, δ, λ and T"
        " undefined; 4 = the path lies on y = 0 (δ ≡ 0): λ and T undefined; 5 = not"
        " certified to 1e-09 at 4096 bits: no value; 6 = beyond the double range: |value| >"
        " 1.8e308 (certified)"
    )

    _, out, _ = run_cli("export", PATH2_FILE, "--samples", "3", "--format", "json")
    doc = json.loads(out)
    assert doc["rprpr"] == __version__
    assert doc["task"] == "Example 2 of the paper, path 2"
    assert doc["columns"] == ISSUE_COLUMNS
    assert doc["units"]["theta1"] == "rad" and doc["units"]["T1"] == "N m"
    assert doc["units"]["reason"] == "code"
    assert list(doc["reasons"]) == ["0", "1", "2", "3", "4", "5", "6"]
    assert doc["reasons"]["0"] == "every value certified"
    assert doc["samples"] == len(doc["rows"]) == 3
    assert doc["singularities"][0]["torque_at_singularity"] == pytest.approx([63.225, -5.445])


def test_csv_reads_back_with_numpy_as_documented(tmp_path: Path) -> None:
    dest = tmp_path / "m.csv"
    run_cli("export", PATH1_FILE, "--samples", "11", "-o", str(dest))
    data = np.genfromtxt(dest, delimiter=",", names=True, skip_header=1)
    assert data.dtype.names == tuple(ISSUE_COLUMNS)
    assert data["t"][5] == 2.5 and math.isnan(data["T1"][5])


def test_default_is_1001_samples_from_0_to_tf() -> None:
    _, out, _ = run_cli("export", PATH2_FILE)
    _, _, v = read_csv(out)
    assert v.shape == (1001, WIDTH)
    assert v[0, 0] == 0.0 and v[-1, 0] == 5.0 and v[500, 0] == 2.5


def test_stdout_only_without_output_file(tmp_path: Path) -> None:
    code, out, err = run_cli("export", PATH2_FILE, "--samples", "4")
    assert code == 0 and out.startswith("# rprpr") and err == ""
    dest = tmp_path / "m.csv"
    code, out, err = run_cli("export", PATH2_FILE, "--samples", "4", "-o", str(dest))
    assert code == 0 and out == "" and f"wrote {dest}" in err
    assert dest.read_text().startswith("# rprpr")
    assert list(tmp_path.iterdir()) == [dest]  # no temporary left behind


# ---------------------------------------------------------------------------------------
# bad invocations: exit 2, one line


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (["-o", "m.txt"], "'.txt'"),
        (["-o", "m"], "(none)"),
        (["-o", "m.json", "--format", "csv"], "contradicts"),
        (["--samples", "1"], "--samples"),
        (["--format", "xml"], "--format"),
    ],
)
def test_bad_invocation_exits_2_with_one_line(
    args: list[str],
    says: str,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.chdir(tmp_path)
    code, out, err = run_cli("export", PATH2_FILE, *args)
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and says in err
    assert list(tmp_path.iterdir()) == []


def test_bad_task_file_exits_2_naming_file_line_and_key(write_task) -> None:  # type: ignore[no-untyped-def]
    bad = write_task(
        task_text(
            "x - 3\n  from: [2, -1]\n  to: [4, 1]",
            "timing:\n  duration: 5\n  law: quintic\n",
            a1="-6",
        )
    )
    code, out, err = run_cli("export", str(bad))
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1
    assert f"{bad}:3" in err and "robot.a1" in err
    code, _, err = run_cli("export", str(bad.parent / "missing.yaml"))
    assert code == 2 and "no such file" in err


def test_unwritable_output_exits_2(tmp_path: Path) -> None:
    code, _, err = run_cli("export", PATH2_FILE, "-o", str(tmp_path / "no" / "dir" / "m.csv"))
    assert code == 2 and "cannot write" in err and len(err.strip().splitlines()) == 1


# ---------------------------------------------------------------------------------------
# matplotlib stays out of check and export


# start-up probes (``tests.cli.forked.fresh_probe``): fresh processes, each in an empty
# folder of its own, from rprpr's dependencies but matplotlib and Pillow
COMMANDS = [["check", PATH2_FILE], ["export", PATH2_FILE, "--samples", "5"]]
for _command in COMMANDS:
    fresh_probe(
        f"test_export {_command!r}",
        "numpy, flint, yaml, click, rich.console",
        "import sys\n"
        "from rprpr.cli.main import main\n"
        "try:\n"
        f"    main({_command!r})\n"
        "except SystemExit as e:\n"
        "    code = e.code\n"
        "loaded = sorted(m for m in sys.modules if m.split('.')[0] in ('matplotlib', 'PIL'))\n"
        "sys.stderr.write(f'EXIT={code} LOADED={loaded}\\n')\n",
    )


@pytest.mark.parametrize("command", COMMANDS)
def test_check_and_export_do_not_import_matplotlib(
    command: list[str], fresh: dict[str, tuple[int, str, str]]
) -> None:
    done = subprocess.CompletedProcess(command, *fresh[f"test_export {command!r}"])
    tail = done.stderr.strip().splitlines()[-1]
    assert tail.startswith("EXIT=0 "), done.stderr
    assert tail.endswith("LOADED=[]"), tail


fresh_probe(
    "test_export module",
    "numpy, flint",
    "import sys, rprpr.render.export\n"
    "banned = ('click', 'matplotlib', 'yaml')\n"
    "print(sorted(m for m in sys.modules if m.split('.')[0] in banned))\n",
)


def test_export_module_is_free_of_click_and_matplotlib(
    fresh: dict[str, tuple[int, str, str]],
) -> None:
    done = subprocess.CompletedProcess("probe", *fresh["test_export module"])
    assert done.stdout.strip() == "[]", done.stderr


def test_json_is_strict_and_one_row_per_line() -> None:
    _, out, _ = run_cli("export", PATH1_FILE, "--samples", "11", "--format", "json")
    json.loads(out, parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))
    row_lines = [line for line in out.splitlines() if line.lstrip().startswith("[") and "," in line]
    assert len(row_lines) == 11
    assert "NaN" not in out and "Infinity" not in out
    assert io.StringIO(out).read().endswith("}\n")


def test_rows_through_a_and_b_say_why_their_values_are_nan(write_task) -> None:  # type: ignore[no-untyped-def]
    """y = x (x - 6)/10 passes A at t = 1 and B at t = 7 (x = t - 1): there the leg's angle,
    its rates, δ, λ and T are undefined (reasons 2 and 3); every other row is certified."""
    path = write_task(task_text("x*(x - 6)/10", "timing:\n  duration: 8\n  x: t - 1\n"))
    code, out, _ = run_cli("export", str(path), "--samples", "9")
    assert code == 0
    _, names, v = read_csv(out)
    col = {n: v[:, j] for j, n in enumerate(names)}
    assert col["reason"].tolist() == [0, 2, 0, 0, 0, 0, 0, 3, 0]
    for j, leg in ((1, "1"), (7, "2")):
        undefined = [f"theta{leg}", f"theta{leg}_dot", f"s{leg}_dot", "delta", "T1", "T2"]
        assert all(math.isnan(col[n][j]) for n in undefined), j
        assert (col["x"][j], col["y"][j]) == ((0.0, 0.0) if leg == "1" else (6.0, 0.0))
    rest = np.delete(v, [1, 7], axis=0)
    assert np.all(np.isfinite(rest))


def test_every_reason_code_is_documented_in_the_readme_and_the_module() -> None:
    import re

    import rprpr.render.export as export_module
    from rprpr.engine.certified.motion import REASONS
    from tests.conftest import ROOT

    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    said = readme.split("the row's `reason` says why:", 1)[1].split("The value at t", 1)[0]
    documented = [int(c) for c in re.findall(r"(?:^|[:,]\s+)(\d) ", " ".join(said.split()))]
    assert documented == sorted(REASONS)  # 0 .. 6, each once, in order
    doc = " ".join((export_module.__doc__ or "").split())
    assert all(f"{code} " in doc for code in REASONS if code)
    assert "6 a value beyond the double range" in doc

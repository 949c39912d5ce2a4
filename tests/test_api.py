"""The Python API: ``import rprpr``, exact times as ``fractions.Fraction``, a short repr,
an HTML table for notebooks, ``to_dict`` equal to the JSON report, ``py.typed``."""

from __future__ import annotations

import json
import math
from fractions import Fraction
from pathlib import Path

import rprpr

from .conftest import CONFIGS, ROOT, run_cli, task_text

PATH1 = str(CONFIGS / "paper_path1.rprpr.yaml")


def test_path1_instant_is_exactly_five_halves_as_a_fraction() -> None:
    s = rprpr.audit(rprpr.load_task(PATH1)).singularities[0]
    assert isinstance(s.t_exact, Fraction)
    assert s.t_exact == Fraction(5, 2) == 2.5  # the paper's t_s = 2.5 s
    assert Fraction(s.t_exact) == Fraction(5, 2)
    assert json.dumps(str(s.t_exact)) == '"5/2"'


def test_irrational_instant_has_no_exact_fraction() -> None:
    # y = x^2 - 2 with x = t: t_s = sqrt 2, irrational
    text = task_text("x^2 - 2", "timing:\n  duration: 2\n  x: t\n")
    r = rprpr.audit(rprpr.parse_task(text))
    (s,) = r.singularities
    assert s.t_exact is None and s.t == math.sqrt(2)
    assert r.to_dict("t.yaml")["singularities"][0]["t_exact"] is None


def test_to_dict_is_the_json_report_entry() -> None:
    status, out, _ = run_cli("check", "--format", "json", PATH1)
    assert status == 1
    (entry,) = json.loads(out)["reports"]
    result = rprpr.audit(rprpr.load_task(PATH1))
    assert result.to_dict() == entry
    assert entry["singularities"][0]["t_exact"] == "5/2"
    assert json.loads(json.dumps(result.to_dict())) == entry


def test_repr_is_one_short_line() -> None:
    r = rprpr.audit(rprpr.load_task(PATH1))
    text = repr(r)
    assert "\n" not in text and len(text) < 160
    assert text == (
        "<AuditResult 'Example 1 of the paper, path 1': fail, 1 singular instant"
        " (1 high-order), findings RPR101, RPR201>"
    )


def test_notebook_html_holds_the_verdict_and_instant_escaped() -> None:
    text = task_text("(x - 3)^3/27", "timing:\n  duration: 2\n  x: 2 + t\n").replace(
        "name: test", "name: '<i>&x'"
    )
    html = rprpr.audit(rprpr.parse_task(text))._repr_html_()
    assert "&lt;i&gt;&amp;x" in html and "<i>" not in html
    assert "<b>FAIL</b>" in html and "3 crossing" in html


def test_package_is_typed() -> None:
    assert (Path(rprpr.__file__).parent / "py.typed").is_file()
    assert '"rprpr" = ["py.typed"]' in (ROOT / "pyproject.toml").read_text(encoding="utf-8")


def test_former_import_name_still_works() -> None:
    import rprpr_cli

    assert rprpr_cli.audit is rprpr.audit


def test_one_options_value_says_what_changes_a_verdict() -> None:
    """``audit(task, AuditOptions(...))``; its fields also as keywords, over the options
    given; ``warn_unbounded`` as ``rprpr check --warn-unbounded``."""
    task = rprpr.load_task(PATH1)  # path 1 of the paper: RPR101 and RPR201 fail it
    assert rprpr.audit(task).verdict == "fail"
    lenient = rprpr.AuditOptions(warn_unbounded=True, samples=11)
    r = rprpr.audit(task, lenient)
    assert [(f.rule, f.severity) for f in r.findings] == [
        ("RPR101", "error"),
        ("RPR201", "warning"),
    ]
    assert r.grid_size == 11 and r.task is task  # the task itself is not changed
    strict = rprpr.audit(task, lenient, strict=True)  # a keyword over the options
    assert [f.severity for f in strict.findings] == ["error", "error"] and strict.strict
    assert rprpr.audit(task, peak=True).peak_computed
    code, out, _ = run_cli("check", "--warn-unbounded", "--format", "json", PATH1)
    by_cli = [(f["rule"], f["severity"]) for f in json.loads(out)["reports"][0]["findings"]]
    assert by_cli == [(f.rule, f.severity) for f in r.findings] and code == 1

"""The text report at any width: no line but a finding's wider than COLUMNS, nothing cut
(no ellipsis), every cell of the wide table present in the narrow layout, findings
clickable and one line each, never wrapped (not even on a terminal)."""

from __future__ import annotations

import os
import re
from unittest import mock

import pytest

from tests.conftest import CONFIGS, reused_runs, run_cli

TASKS = [str(p.relative_to(CONFIGS.parent)) for p in sorted(CONFIGS.glob("*.yaml"))]


def _text(columns: int) -> str:
    with mock.patch.dict(os.environ, {"COLUMNS": str(columns)}), reused_runs():
        _, out, _ = run_cli("check", "--samples", "101", *TASKS)
    return out


def _table_cells(wide: str) -> list[str]:
    """Every cell of the rows of the wide table(s)."""
    cells = []
    for line in wide.splitlines():
        if line.startswith("│"):
            cells += [c.strip() for c in line.strip("│").split("│") if c.strip()]
    return cells


FINDING = re.compile(r"^configs/\w+\.rprpr\.yaml:\d+:1: RPR\d{3} \[(error|warning)\] [a-z-]+: ")


@pytest.mark.parametrize("columns", [60, 80, 120])
def test_no_line_but_a_finding_exceeds_the_width_and_nothing_is_cut(columns: int) -> None:
    out = _text(columns)
    lines = out.splitlines()
    assert all(len(line) <= columns for line in lines if not FINDING.match(line)), columns
    assert "…" not in out


def _findings(out: str) -> list[str]:
    return [ln for ln in out.splitlines() if FINDING.match(ln)]


@pytest.mark.parametrize("columns", [40, 60, 80, 160])
def test_each_finding_is_one_whole_line_at_any_width(columns: int) -> None:
    wide = _findings(_text(10_000))
    assert len(wide) >= 4 and any(len(f) > 160 for f in wide)  # long ones among them
    assert _findings(_text(columns)) == wide


def test_on_a_terminal_too_a_finding_is_one_line() -> None:
    from rich.console import Console

    from rprpr.render.text import render
    from tests.render.test_formats import make_run

    run = make_run("configs/paper_path1.rprpr.yaml")
    console = Console(width=60, force_terminal=True, no_color=True, record=True)
    render(run, console, console)
    lines = console.export_text().splitlines()
    found = [ln for ln in lines if FINDING.match(ln)]
    assert [ln.split(":")[1] for ln in found] == ["19", "13"]
    assert all(" boundedness conditions hold" in ln for ln in found[1:])
    assert not any(ln.startswith("consistent") for ln in lines)


@pytest.mark.parametrize("columns", [60, 80, 120])
def test_every_cell_of_the_wide_table_is_in_the_narrow_report(columns: int) -> None:
    wide = _text(400)
    cells = _table_cells(wide)
    assert len(cells) >= 6 * 11  # a row of 11 cells per shipped config at least
    narrow = " ".join(_text(columns).split())
    for cell in cells:
        assert " ".join(cell.split()) in narrow, (columns, cell)


def test_wide_terminal_gets_the_table_and_narrow_the_stacked_rows() -> None:
    assert "┃ t [s] ┃" in _text(160)
    narrow = _text(80)
    assert "┃" not in narrow and "  T(t_s) [N m]  unbounded" in narrow


def test_findings_are_file_line_col_rule_severity() -> None:
    out = _text(400)
    lines = [ln for ln in out.splitlines() if re.match(r"^configs/\w+\.rprpr\.yaml:\d", ln)]
    assert lines and all(FINDING.match(ln) for ln in lines)
    assert "configs/paper_path1.rprpr.yaml:19:1: RPR101 [error] slope-principle: t = 2.5 s" in out


def _layout(columns: int, layout: str) -> str:
    with mock.patch.dict(os.environ, {"COLUMNS": str(columns)}), reused_runs():
        _, out, _ = run_cli("check", "--layout", layout, *TASKS)
    return out


def test_the_table_on_request_at_80_columns_is_the_wide_table_whole() -> None:
    forced = _layout(80, "table")
    # the same table rows as on a wide terminal, none of them squeezed or cut
    assert _table_cells(forced) == _table_cells(_text(400))
    assert "…" not in forced


def test_the_rows_on_request_on_a_wide_terminal() -> None:
    rows = _layout(400, "rows")
    assert "┃" not in rows and "  T(t_s) [N m]  unbounded" in rows

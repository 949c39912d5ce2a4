"""The exit policy (``report.exit``) and the options every command shares (``cli.options``):
one home each, and every command follows them."""

from __future__ import annotations

import dataclasses
import errno
import inspect
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import click
import pytest

from rprpr.cli.errors import InputError, InternalError, error_status
from rprpr.cli.main import main_group
from rprpr.cli.options import CheckOptions
from rprpr.model.defaults import DEFAULT_SAMPLES
from rprpr.model.options import AuditOptions
from rprpr.report.exit import ExitCode, exception_status, returned_status, run_status
from rprpr.report.run import Run
from tests.cli.forked import fresh_probe
from tests.conftest import PATH2_FILE, run_cli, run_cli_to, stdout_on

RPRPR = [sys.executable, "-m", "rprpr"]


def _run_of(*kinds: str) -> Run:
    """A run with one outcome per kind: "pass", "fail", "input" or "internal"."""
    run = Run()
    for k in kinds:
        if k in ("pass", "fail"):
            run.add("report", {"verdict": k})
        else:
            run.add(k, {"text": k})
    return run


@pytest.mark.parametrize(
    ("kinds", "exit_zero", "status"),
    [
        ((), False, 0),
        (("pass", "pass"), False, 0),
        (("pass", "fail"), False, 1),
        (("pass", "fail"), True, 0),  # --exit-zero forgives a failed audit ...
        (("fail", "input"), True, 2),  # ... but never hides an error
        (("fail", "input"), False, 2),
        (("input", "internal", "fail"), False, 3),  # the highest wins
        (("internal",), True, 3),
    ],
)
def test_run_status_is_the_highest_that_applies(
    kinds: tuple[str, ...], exit_zero: bool, status: int
) -> None:
    assert run_status(_run_of(*kinds), exit_zero=exit_zero) == status


@pytest.mark.parametrize(
    ("error", "status"),
    [
        (click.UsageError("bad option"), 2),
        (click.BadParameter("bad value"), 2),
        (InputError("bad task file"), 2),
        (click.ClickException("cannot write"), 2),  # never click's own 1
        (click.exceptions.Abort(), 2),
        (InternalError("a bug in a named task"), 3),
        (RuntimeError("a bug anywhere"), 3),
        (OSError("unexpected"), 3),
        (BrokenPipeError(), 0),  # the reader went away: nothing failed
        (KeyboardInterrupt(), 130),
        (click.exceptions.Exit(0), 0),
    ],
)
def test_error_status(error: BaseException, status: int) -> None:
    assert error_status(error) == status


def test_returned_status() -> None:
    assert returned_status(None) is ExitCode.PASSED
    assert returned_status(0) is ExitCode.PASSED  # --help, --version
    assert returned_status(ExitCode.FAILED) is ExitCode.FAILED


@pytest.mark.parametrize(("command", "what"), [("schema", "schema"), ("export", "samples")])
@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_a_full_disk_on_standard_output_is_one_line_and_exit_2(command: str, what: str) -> None:
    args = [command] if command == "schema" else [command, PATH2_FILE, "--samples", "5"]
    # in this process on the stream Python makes for /dev/full (a real process writes there
    # in tests/cli/test_output.py)
    returncode, stderr = run_cli_to(stdout_on(os.open("/dev/full", os.O_WRONLY)), *args)
    assert returncode == 2
    assert stderr.splitlines() == [
        f"rprpr: cannot write the {what} to standard output: No space left on device"
    ]


def test_export_into_a_closed_pipe_exits_0() -> None:
    # in this process on the stream Python makes for the pipe (a real process writes into
    # one in tests/cli/test_output_robustness.py)
    read, write = os.pipe()
    os.close(read)
    returncode, err = run_cli_to(stdout_on(write), "export", PATH2_FILE, "--samples", "5")
    assert returncode == 0, err
    assert err == ""


def test_a_bug_outside_any_task_is_one_line_and_exit_3(monkeypatch: pytest.MonkeyPatch) -> None:
    import rprpr.io.schema

    def broken() -> Any:
        raise RuntimeError("simulated bug")

    monkeypatch.setattr(rprpr.io.schema, "json_schema", broken)
    code, _, err = run_cli("schema")
    assert code == 3
    assert err.splitlines() == [
        "rprpr: internal error (RuntimeError: simulated bug); please report it"
    ]


# -- the options: one home for each default -------------------------------------------------
def _params(command: str) -> dict[str, click.Parameter]:
    cmd = main_group.get_command(click.Context(main_group), command)
    assert cmd is not None
    return {p.name: p for p in cmd.params if p.name}


@pytest.mark.parametrize("command", ["plot", "export"])
def test_every_samples_option_defaults_to_the_one_default(command: str) -> None:
    assert _params(command)["samples"].default == DEFAULT_SAMPLES == 1001


def test_check_samples_default_to_the_one_default_through_the_settings() -> None:
    from rprpr.cli.config import KEYS

    assert _params("check")["samples"].default is None  # not given: the configuration's
    assert KEYS["samples"][1] == DEFAULT_SAMPLES


def test_the_audit_defaults_to_the_same_sample_count() -> None:
    from rprpr.engine.audit import audit

    assert AuditOptions().samples == DEFAULT_SAMPLES
    assert inspect.signature(audit).parameters["options"].default is None  # AuditOptions()


def test_check_options_default_to_the_command_lines_defaults() -> None:
    cmd = main_group.get_command(click.Context(main_group), "check")
    assert cmd is not None
    from rprpr.cli.check import resolve

    given = cmd.make_context("check", ["--isolated", "task.yaml"]).params
    del given["tasks"]
    settings, options = resolve(given)
    assert options == CheckOptions()
    assert settings.file is None
    assert set(settings.sources.values()) == {"default"}


def test_check_options_are_one_frozen_value() -> None:
    options = CheckOptions(AuditOptions(samples=11, strict=True), jobs=2)
    with pytest.raises(AttributeError):
        options.jobs = 3  # type: ignore[misc]
    with pytest.raises(AttributeError):
        options.audit.samples = 12  # type: ignore[misc]
    assert options == CheckOptions(jobs=2, audit=AuditOptions(strict=True, samples=11))


def test_what_changes_a_verdict_is_apart_from_the_plumbing() -> None:
    """``check``'s flags that change a verdict build its ``AuditOptions``; the others
    (formats, jobs, budgets, colours) stay the command line's."""
    from rprpr.cli.check import resolve

    cmd = main_group.get_command(click.Context(main_group), "check")
    assert cmd is not None
    argv = ["--isolated", "--strict", "--peak", "--warn-unbounded", "--samples", "21", "-j", "2"]
    given = cmd.make_context("check", [*argv, "task.yaml"]).params
    del given["tasks"]
    _, options = resolve(given)
    assert options.audit == AuditOptions(samples=21, strict=True, peak=True, warn_unbounded=True)
    assert options.jobs == 2
    verdict_fields = {"samples", "strict", "peak", "warn_unbounded"}
    assert not verdict_fields & {f.name for f in dataclasses.fields(CheckOptions)}
    with pytest.raises(ValueError, match="at least 2 samples"):
        AuditOptions(samples=1)


fresh_probe(  # a start-up probe (``tests.cli.forked.fresh_probe``): a fresh process
    "test_exit report stage",
    "",
    "import sys, rprpr.report.exit, rprpr.report.run, rprpr.report.records\n"
    "print(sorted(m for m in sys.modules if m.split('.')[0] == 'click'))\n",
)


def test_the_report_stage_imports_no_click(fresh: dict[str, tuple[int, str, str]]) -> None:
    """The exit policy, the run and the records are plain Python: click's exceptions and
    their statuses are the command line's (``cli.errors``)."""
    done = subprocess.CompletedProcess("probe", *fresh["test_exit report stage"])
    done.check_returncode()
    assert done.stdout.strip() == "[]"


@pytest.mark.parametrize(
    ("error", "status"),
    [
        (OSError(errno.ENOSPC, "No space left on device"), 2),  # the environment, not a bug
        (KeyboardInterrupt(), 130),
        (RuntimeError("a bug"), 3),
    ],
)
def test_the_plain_exceptions_follow_the_policy_without_click(
    error: BaseException, status: int
) -> None:
    assert exception_status(error) == status == error_status(error)

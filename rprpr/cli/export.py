"""``rprpr export``: write the sampled motion of a task as CSV or JSON (``render.export``).

Exits 0 once written, whatever the audit's verdict (``rprpr check`` is the gate).
"""

from __future__ import annotations

import sys
from pathlib import Path

import click

from ..report.exit import ExitCode
from .options import output_file_option, samples_option, suffix_choice
from .output import refuse_overwriting_inputs, say, write_atomic, writing
from .tasks import load, task_inputs, task_named

EXPORT_FORMATS = ("csv", "json")
IMPLIED = {".csv": "csv", ".json": "json"}  # the format an output file's extension names


@click.command()
@click.argument("task", type=click.Path(readable=False))
@output_file_option(
    "Write here, as .csv or .json (format from the extension); standard output when omitted or -.",
    dash_is_stdout=True,
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(EXPORT_FORMATS),
    help="Output format (default: from the -o extension, else csv).",
)
@samples_option(2, 1_000_000, "Sample points t_i = i t_f/(N-1), i = 0..N-1.")
def export(task: str, output_file: str | None, fmt: str | None, samples: int) -> ExitCode:
    """Write the sampled motion of TASK: t, the end point, the joints, δ, λ and the torques,
    one row per sample (SI units, angles in radians)."""
    fmt = _format(output_file, fmt)
    refuse_overwriting_inputs([output_file], [task])  # before any work
    loaded = load(task)
    refuse_overwriting_inputs([output_file], task_inputs(task, loaded))  # and its CSV

    from ..engine.audit import audit
    from ..model.options import AuditOptions
    from ..render import export as E

    with task_named(task):
        result = audit(loaded, AuditOptions(samples))
    if output_file is None:
        with writing("the samples", None, ExitCode.PASSED):
            E.write(result, sys.stdout, fmt, task)
            sys.stdout.flush()
        return ExitCode.PASSED

    def write(tmp: str) -> None:
        with open(tmp, "w", encoding="utf-8", newline="") as fh:
            E.write(result, fh, fmt, task)

    write_atomic(output_file, write, "the samples")
    say(f"rprpr: wrote {output_file} ({samples} samples)")
    return ExitCode.PASSED


def _format(output_file: str | None, fmt: str | None) -> str:
    """The export format: ``--format``, else the one the extension of ``-o`` implies, else
    csv; a usage error when they contradict or the extension names neither."""
    if output_file is not None:
        implied = IMPLIED.get(Path(output_file).suffix.lower())
        if fmt is None:
            if implied is None:
                suffix_choice(output_file, tuple(IMPLIED), "the samples", "-o")
            fmt = implied
        elif implied is not None and implied != fmt:
            raise click.BadParameter(
                f"--format {fmt} contradicts the extension of {output_file!r}", param_hint="-o"
            )
    return fmt or "csv"

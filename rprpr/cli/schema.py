"""``rprpr schema``: print the JSON Schema of the task file (from ``io.schema``, the one
home of the task's keys)."""

from __future__ import annotations

import json
import sys

import click

from ..report.exit import ExitCode
from .output import writing


@click.command()
def schema() -> ExitCode:
    """Print the JSON Schema (draft 2020-12) of the task file."""
    from ..io.schema import json_schema

    with writing("the schema", None, ExitCode.PASSED):
        click.echo(json.dumps(json_schema(), indent=2))
        sys.stdout.flush()
    return ExitCode.PASSED

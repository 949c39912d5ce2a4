"""``rprpr plot`` and ``rprpr export`` (matplotlib is imported only inside ``plot``)."""

from __future__ import annotations

import click


@click.command()
def plot() -> None:
    """Draw the audit sheet of TASK (not yet available)."""
    raise click.UsageError("rprpr plot is not available in this build")


@click.command()
def export() -> None:
    """Write the sampled motion of TASK (not yet available)."""
    raise click.UsageError("rprpr export is not available in this build")

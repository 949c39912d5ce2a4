"""``python -m rprpr_cli``: the former name of ``python -m rprpr``."""

from rprpr.cli.main import run

run()

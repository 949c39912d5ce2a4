"""Defaults shared by the engine and the command line (plain Python: the command line's
options read them without importing numpy or flint)."""

from __future__ import annotations

DEFAULT_SAMPLES = 1001  # grid points t = 0 .. t_f of an audit, an export and a plot
# the task schema's $id (``rprpr schema``), and the modeline that points an editor at it:
# the first line of what ``rprpr init`` and ``rprpr repair`` write
SCHEMA_URL = "https://rprpr.dev/schema/task.json"
SCHEMA_MODELINE = f"# yaml-language-server: $schema={SCHEMA_URL}"


# -- declared uncertainty (docs/robust.md): read alike from a task file and a configuration --
MOVING_LINKS = (2, 3, 4, 5)  # the links whose mass, inertia and r an uncertainty widens
LINK_QUANTITIES = ("mass", "inertia", "r")  # uncertainty.links.<i>: in Uncertainty's order
# a percentage as written ("5%", " 2.5 % ", "1e1%"): the digits, then the exponent
PERCENT = r"^\s*([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?\s*%\s*$"

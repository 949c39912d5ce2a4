"""Defaults shared by the engine and the command line (plain Python: the command line's
options read them without importing numpy or flint)."""

from __future__ import annotations

DEFAULT_SAMPLES = 1001  # grid points t = 0 .. t_f of an audit, an export and a plot

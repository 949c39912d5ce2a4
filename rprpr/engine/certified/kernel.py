"""The compiled ball kernel (``rprpr._kernel``), when it is built and not turned off.

The kernel is C generated from the Python formulas (``kernel_gen.py``) performing the
same IEEE operations as the numpy path of ``balls.Ball``, in the same order: its results
are the same doubles, one C call per pass instead of one numpy call per ball operation.
It is optional, as PyYAML's libyaml is: where it could not be built (no C compiler at
install time) ``KERNEL`` is None and every caller takes the numpy path, with the same
results. ``RPRPR_NO_KERNEL=1`` in the environment turns it off (the test suite runs that
way too: CONTRIBUTING.md)."""

from __future__ import annotations

import os
from importlib import import_module
from typing import Any

KERNEL: Any = None
if os.environ.get("RPRPR_NO_KERNEL", "") in ("", "0"):
    try:
        KERNEL = import_module("rprpr._kernel")
    except ImportError:  # not built: the numpy path
        KERNEL = None

INDEX: dict[str, tuple[int, int]] = (
    {name: (i, nout) for i, (name, nout) in enumerate(KERNEL.names())} if KERNEL else {}
)  # a kernel's name -> (its index, its output rows)

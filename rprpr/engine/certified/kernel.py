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
import warnings
from importlib import import_module
from pathlib import Path
from typing import Any

SOURCE = Path(__file__).resolve().parents[2] / "_kernel.c"  # in a checkout, not in a wheel


def stale(kernel: Any, source: Path = SOURCE) -> bool:
    """True where ``kernel`` was built from another C source than the ``_kernel.c`` beside
    it: a checkout whose kernel was regenerated (``kernel_gen``) and not rebuilt (``pip
    install -e .``). Its formulas would be the old ones; the numpy path runs instead. An
    install without the source (a wheel) is never stale."""
    try:
        with open(source, encoding="utf-8") as f:
            head = f.read(4096)
    except OSError:
        return False
    at = head.find('#define KERNEL_DIGEST "')
    line = head[at:].split("\n", 1)[0] if at >= 0 else ""
    return bool(line) and line != f'#define KERNEL_DIGEST "{getattr(kernel, "DIGEST", "")}"'


KERNEL: Any = None
if os.environ.get("RPRPR_NO_KERNEL", "") in ("", "0"):
    try:
        KERNEL = import_module("rprpr._kernel")
    except ImportError:  # not built: the numpy path
        KERNEL = None
    if KERNEL is not None and stale(KERNEL):
        warnings.warn(
            f"rprpr's compiled kernel is older than {SOURCE}: rebuild it (pip install -e .);"
            " the numpy path runs meanwhile, with the same results, slower",
            RuntimeWarning,
            stacklevel=2,
        )
        KERNEL = None

INDEX: dict[str, tuple[int, int]] = (
    {name: (i, nout) for i, (name, nout) in enumerate(KERNEL.names())} if KERNEL else {}
)  # a kernel's name -> (its index, its output rows)

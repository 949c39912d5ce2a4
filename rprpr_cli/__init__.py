"""The former import name of rprpr, kept so that ``from rprpr_cli import audit`` still works.

New code imports ``rprpr``; this alias offers the same public API and nothing else.
"""

from __future__ import annotations

from typing import Any

import rprpr
from rprpr import __all__, __version__  # noqa: F401


def __getattr__(name: str) -> Any:
    return getattr(rprpr, name)

"""The cyclic garbage collector held off through the program's start-up.

``rprpr`` starts by importing click, numpy, python-flint, PyYAML and the engine: tens of
thousands of objects that live until the process ends, and among which a collection finds
no garbage. Python's collector runs all the same, every few hundred new objects, and the
full collections it runs among them walk everything made so far: ~10-20 ms of a single
``check``'s CPU. So the program (``main.run``) holds the collector off from its first
line (``hold``) until the command's imports are done (``release``): for ``check`` once
the audit's modules are in, before any worker is forked; for the other commands once
their module is. ``check`` also freezes what the start-up made (``gc.freeze``): no later
collection, in rprpr or in a forked worker, walks it again (nor copies its pages).

``main`` called from Python (tests, a user's script) holds nothing: the collector is
left as the caller set it.
"""

from __future__ import annotations

import gc

_held = False  # whether ``hold`` turned the collector off (and it is still off)


def hold() -> None:
    """Turn the collector off until ``release`` (where it is on)."""
    global _held
    if gc.isenabled():
        gc.disable()
        _held = True


def release(*, freeze: bool = False) -> None:
    """Turn the collector back on if ``hold`` turned it off; with ``freeze``, what exists
    now is left out of every later collection."""
    global _held
    if _held:
        if freeze:
            gc.freeze()
        gc.enable()
        _held = False

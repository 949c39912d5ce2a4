"""The reference values of test_certified_corpus.py, stored: tests/reference.py's mpmath
values at every time the corpus samples, computed once and kept beside the corpus as
certified_reference.json.gz (they depend on the motion and the time alone, never on the
engine).

Regenerate after changing a motion or the times sampled (``_times``)::

    .venv/bin/python -m tests.corpora.certified_reference

An entry is keyed by the motion's definition (``repr`` of its ``Motion``) and the
time's ``repr``: a changed motion, or a time not stored, is computed afresh by the test
(nothing stale is ever read). ``test_certified_corpus`` recomputes a sample of the
entries from scratch and checks that the store covers every time the corpus samples.
A value is kept as the pair [m, e] of the binary number m 2^e rounded to BITS bits (read
back exactly, at once); None where undefined.
"""

from __future__ import annotations

import gzip
import json
from functools import cache
from pathlib import Path
from typing import Any

import mpmath

DATA = Path(__file__).with_name("certified_reference.json.gz")
BITS = 70  # 21 digits: far beyond the 1e-9 the tests allow


def encode(entry: dict[str, Any]) -> dict[str, Any]:
    """An expected entry (mpf values, None, the reason code) as JSON values."""
    out: dict[str, Any] = {}
    for k, v in entry.items():
        if k == "reason":
            out[k] = int(v)
        else:
            out[k] = None if v is None else _pair(v)
    return out


def _pair(v: Any) -> list[int]:
    """[m, e]: v rounded to BITS bits is m 2^e (m signed)."""
    with mpmath.workprec(BITS):
        sign, man, exp, _ = (+v)._mpf_
    assert mpmath.isfinite(v), v
    return [-int(man) if sign else int(man), int(exp)]


def decode(entry: dict[str, Any]) -> dict[str, Any]:
    with mpmath.workprec(BITS):  # mpf() rounds to the working precision
        return {
            k: (v if k == "reason" or v is None else mpmath.mpf(tuple(v))) for k, v in entry.items()
        }


@cache
def stored() -> dict[str, dict[str, dict[str, Any]]]:
    """motion key -> time (repr) -> the stored entry (JSON values); {} without the file."""
    if not DATA.exists():
        return {}
    with gzip.open(DATA, "rt", encoding="utf-8") as f:
        data: dict[str, dict[str, dict[str, Any]]] = json.load(f)
    return data


def lookup(motion: str, t: float) -> dict[str, Any] | None:
    """The stored entry of ``motion`` (its key) at ``t``, decoded; None when not stored."""
    entry = stored().get(motion, {}).get(repr(t))
    return None if entry is None else decode(entry)


def main() -> None:
    from tests.corpora import test_certified_corpus as C

    data = {
        repr(C.CORPUS[name]): {repr(t): encode(C.computed(name, t)) for t in C._times(name)}
        for name in sorted(C.CORPUS)
    }
    text = json.dumps(data, indent=0, sort_keys=True)
    with gzip.GzipFile(DATA, "wb", mtime=0) as f:  # the same bytes for the same values
        f.write(text.encode("utf-8"))
    print(f"{DATA}: {sum(len(v) for v in data.values())} entries of {len(data)} motions")


if __name__ == "__main__":
    main()

"""A file name as text that every report can carry.

The operating system names files with bytes; Python decodes the bytes of a name that
are not UTF-8 as lone surrogates (``surrogateescape``: the byte 0xff is U+DCFF), which
no UTF-8 document can hold: a JSON, SARIF or GitLab report, an XML attribute, an SVG.
``file_name`` is the one place a name becomes such text: each such byte is written as
``\\xNN``, the escape ``render.escape.printable`` shows it with, so that a name reads the
same in every report; every other character is kept.
"""

from __future__ import annotations

import re

_LONE_SURROGATE = re.compile("[\ud800-\udfff]")


def _escaped(match: re.Match[str]) -> str:
    code = ord(match[0])
    if 0xDC80 <= code <= 0xDCFF:  # a byte that is not UTF-8, decoded by surrogateescape
        return f"\\x{code - 0xDC00:02x}"
    return f"\\u{code:04x}"  # any other lone surrogate (a Windows name that is not UTF-16)


def file_name(path: str) -> str:
    """``path`` as valid Unicode text: a byte of the name that is not UTF-8 as ``\\xNN``
    (any other lone surrogate as ``\\uNNNN``); unchanged when it is valid already."""
    return _LONE_SURROGATE.sub(_escaped, path)

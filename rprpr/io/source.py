"""The task file's source: bytes -> text, before any YAML is read.

The size cap (``MAX_BYTES``), a byte order mark dropped, UTF-8 only (UTF-16, UTF-32 and
binary files named as such), and no character YAML does not allow in a stream: each
refusal is a ``TaskFileError`` at the line and column it is found.
"""

from __future__ import annotations

import re

from ..model.errors import TaskFileError
from .messages import line_col, too_large

MAX_BYTES = 1 << 20  # 1 MiB: a task file is a few hundred bytes


# Characters YAML does not allow in a stream, found here first so that the message names
# the line and column whichever YAML parser runs: the very pattern of PyYAML's reader
# (yaml.reader.Reader.NON_PRINTABLE), so that re compiles it once (20 ms) for both.
_NON_PRINTABLE = re.compile(
    "[^\x09\x0a\x0d\x20-\x7e\x85\xa0-\ud7ff\ue000-\ufffd\U00010000-\U0010ffff]"
)


def decode(data: bytes | str) -> str:
    """The task file as text: size cap, binary and encoding checks."""
    if isinstance(data, str):
        try:
            data = data.encode("utf-8")
        except UnicodeEncodeError as e:
            raise TaskFileError(
                f"not valid Unicode text (lone surrogate at character {e.start})"
            ) from None
    if len(data) > MAX_BYTES:
        raise TaskFileError(too_large(MAX_BYTES, len(data)))
    text = _utf8(data).removeprefix("\ufeff")
    bad = _NON_PRINTABLE.search(text)
    if bad:
        line, column = line_col(text, bad.start())
        raise TaskFileError(
            f"control character U+{ord(bad.group(0)):04X} is not allowed in YAML text"
            " (a binary file?)",
            line=line,
            column=column,
        )
    return text


def _utf8(data: bytes) -> str:
    """``data`` decoded as UTF-8; UTF-32, UTF-16 and binary files are named as such."""
    if data.startswith((b"\xff\xfe\x00\x00", b"\x00\x00\xfe\xff")):
        raise TaskFileError("UTF-32 text, expected UTF-8: save the file as UTF-8")
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise TaskFileError("UTF-16 text, expected UTF-8: save the file as UTF-8")
    nul = data.find(b"\x00")
    if nul >= 0:
        line = data.count(b"\n", 0, nul) + 1
        column = nul - (data.rfind(b"\n", 0, nul) + 1) + 1  # in bytes
        raise TaskFileError(
            f"binary file (NUL byte at offset {nul}), expected YAML text",
            line=line,
            column=column,
        )
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        column = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1  # in bytes
        raise TaskFileError(
            f"not UTF-8 text: byte 0x{data[e.start]:02x} at offset {e.start} ({e.reason})",
            line=line,
            column=column,
        ) from None
    return text

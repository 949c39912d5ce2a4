"""Text fit for a terminal, a log or a report: the one home of escaping for people.

Anything that came from outside rprpr (a file name, a task's ``name``, a value quoted in
a message) may hold characters that a terminal acts on instead of showing: a newline
that starts a line of its own (``verdict: PASS`` forged under a failing task), ANSI
escape sequences (``\\e[2J`` clears the screen, whatever ``--color`` says), a carriage
return or a backspace that overwrite what was printed, bidirectional overrides that
reorder it, and bytes of a file name that are not UTF-8. ``printable`` writes each of
them as a visible escape; every human-facing output (the text report, the one-line
errors, the annotations' messages, JUnit's text, the CSV comment) goes through it. The
machine-readable JSON keeps the true strings (JSON escapes what it must).

``inert`` keeps a CI runner from acting on a report: a line that begins with ``::``
(after blanks) is a GitHub Actions workflow command (``::warning::``, an annotation
forged; ``::stop-commands::``, the job's own commands silenced), and ``##[`` anywhere in
a line is the older form of them (``##vso[`` for Azure Pipelines, ``##teamcity[`` for
TeamCity). Every report goes through it whole, written in its own language: the text
formats show the escape (``\\x3a:warning::``), JSON and XML write the same character
as ``\\u003a`` or ``&#58;`` (the data is unchanged, only the line no longer reads as a
command).

``ascii_fallback`` is the other half: on a standard output that cannot encode rprpr's
few non-ASCII characters (``PYTHONIOENCODING=cp1252``, a C locale without UTF-8 mode)
δ, σ, θ, λ, μ, →, — ... are written as delta, sigma, theta, lambda, mu, ->, -- ...
instead of failing (``ascii_errors``, a codec error handler, does it on a stream).
"""

from __future__ import annotations

import re
import unicodedata
from collections.abc import Callable

# C0 and C1 controls and DEL; the bidirectional marks, embeddings, overrides and
# isolates; the line and paragraph separators; lone surrogates (a file name's bytes that
# are not UTF-8, as Python decodes them); the noncharacters XML 1.0 cannot carry
_UNPRINTABLE = re.compile(
    "[\x00-\x1f\x7f-\x9f\u061c\u200e\u200f\u2028-\u202e\u2066-\u2069\ud800-\udfff\ufffe\uffff]"
)
_NAMED = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}


def _escaped(ch: str) -> str:
    code = ord(ch)
    if ch in _NAMED:
        return _NAMED[ch]
    if code < 0x100:
        return f"\\x{code:02x}"
    if 0xDC80 <= code <= 0xDCFF:  # a byte that is not UTF-8, decoded by surrogateescape
        return f"\\x{code - 0xDC00:02x}"
    return f"\\u{code:04x}"


def printable(text: str, keep: str = "") -> str:
    """``text`` with every character a terminal would act on (see the module docstring)
    written as an escape: ``\\n``, ``\\r``, ``\\t``, ``\\xNN`` or ``\\uNNNN`` (a byte of
    a file name that is not UTF-8: ``\\xNN``). ``keep`` names the characters to leave as
    they are (``"\\n"`` in a multi-line text of rprpr's own)."""
    return _UNPRINTABLE.sub(lambda m: m[0] if m[0] in keep else _escaped(m[0]), text)


# a line's first characters that a runner reads as a command: ``::`` after blanks (the
# runner trims Unicode white space; ANSI styles are kept out of the trim, so they are
# skipped too), and ``##[``, ``##vso[``, ``##teamcity[`` anywhere
_COMMAND_START = re.compile(r"^((?:[^\S\n]|\x1b\[[0-9;]*m)*):(?=:)", re.MULTILINE)
_COMMAND_ANYWHERE = re.compile(r"#(?=#(?:\[|vso\[|teamcity\[))", re.IGNORECASE)


def inert(text: str, escape: Callable[[str], str] = _escaped) -> str:
    """``text`` (any number of lines) with nothing a CI runner acts on: the first ``:``
    of a line's leading ``::`` and the first ``#`` of ``##[`` (``##vso[``,
    ``##teamcity[``) written by ``escape`` (by default as ``printable`` does: ``\\x3a``,
    ``\\x23``). Unchanged when there is no such line."""
    if "::" not in text and "##" not in text:
        return text
    text = _COMMAND_START.sub(lambda m: m[1] + escape(":"), text)
    return _COMMAND_ANYWHERE.sub(lambda m: escape("#"), text)


def inert_json(text: str) -> str:
    """A JSON document's text made ``inert``: ``\\u003a``, ``\\u0023`` (``#`` and ``:``
    stand only in strings, where the escape means the same character)."""
    return inert(text, lambda ch: f"\\u{ord(ch):04x}")


def inert_xml(text: str) -> str:
    """An XML document's text made ``inert``: ``&#58;``, ``&#35;`` (the same characters)."""
    return inert(text, lambda ch: f"&#{ord(ch)};")


# the non-ASCII characters rprpr's own texts use, beside the Greek letters
_SYMBOLS = {
    "—": "--", "–": "-", "−": "-", "→": "->", "←": "<-", "…": "...", "±": "+/-",
    "≡": "==", "≈": "~", "≠": "!=", "≤": "<=", "≥": ">=", "×": "x", "·": "*",
    "∞": "inf", "▲": "^", "▼": "v", "‖": "||", "°": "deg", "²": "^2", "³": "^3",
    "⁻": "^-", "¹": "1", "µ": "u", "‘": "'", "’": "'", "“": '"', "”": '"', "\u00a0": " ",
}  # fmt: skip


_GREEK_SPELLING = {"lamda": "lambda"}  # Unicode's name of λ, as people spell it


def ascii_fallback(ch: str) -> str:
    """An ASCII stand-in for one character: a Greek letter by its name (δ -> delta,
    Σ -> Sigma), a symbol of ``_SYMBOLS`` (→ -> ``->``), a letter without its accent
    (é -> e), else the character escaped as in ``printable`` (``\\u2603``)."""
    if ch.isascii():
        return ch
    if ch in _SYMBOLS:
        return _SYMBOLS[ch]
    name = unicodedata.name(ch, "")
    if name.startswith(("GREEK SMALL LETTER ", "GREEK CAPITAL LETTER ")):
        letter = name.split(" LETTER ", 1)[1].replace("FINAL ", "").split()[0].lower()
        letter = _GREEK_SPELLING.get(letter, letter)
        return letter.capitalize() if "CAPITAL" in name else letter  # FINAL SIGMA -> sigma
    plain = unicodedata.normalize("NFKD", ch).encode("ascii", "ignore").decode("ascii")
    if plain and plain.isprintable():
        return plain
    return _escaped(ch) if ord(ch) < 0x10000 else f"\\U{ord(ch):08x}"


def ascii_errors(error: UnicodeError) -> tuple[str, int]:
    """A codec error handler (``codecs.register_error``): what a stream cannot encode,
    written with ``ascii_fallback``."""
    if not isinstance(error, UnicodeEncodeError):
        raise error
    bad = error.object[error.start : error.end]
    return "".join(ascii_fallback(ch) for ch in bad), error.end

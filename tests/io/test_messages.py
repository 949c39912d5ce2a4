"""``io.messages``: the one home of the words of input messages (a value shortened,
"did you mean", locations, a file over its cap, what a key expects)."""

from __future__ import annotations

from rprpr.io.loader import MAX_BYTES
from rprpr.io.messages import line_col, near, one_line, shorten, size_name, too_large
from rprpr.io.waypoint_csv import MAX_CSV_BYTES


def test_sizes_in_words() -> None:
    assert size_name(1 << 20) == "1 MiB" and size_name(16 << 20) == "16 MiB"
    assert size_name(4096) == "4 KiB" and size_name(1000) == ""
    assert too_large(1 << 20, 5) == "file too large: 5 bytes, the cap is 1048576 bytes (1 MiB)"


def test_the_caps_are_named_from_their_constants() -> None:
    assert too_large(MAX_BYTES, 2_000_000).endswith("the cap is 1048576 bytes (1 MiB)")
    assert too_large(MAX_CSV_BYTES).startswith("file too large: more than 16777216 bytes")
    assert too_large(MAX_CSV_BYTES).endswith("(16 MiB)")


def test_a_value_is_shown_whole_up_to_its_width_then_cut_with_dots() -> None:
    assert shorten("a" * 40) == "a" * 40
    assert shorten("a" * 41) == "a" * 37 + "..."  # 40 characters in all
    # the polynomial parser's form: one character fewer once cut
    assert shorten("b" * 24, 24, cut=4) == "b" * 24
    assert shorten("b" * 25, 24, cut=4) == "b" * 20 + "..."


def test_did_you_mean_names_the_closest_word_or_none() -> None:
    assert near("duraton", ["duration", "law", "x"]) == ["duration"]
    assert near("zzz", ["duration", "law", "x"]) == []


def test_one_line_escapes_line_breaks_and_control_characters() -> None:
    assert one_line("plain text") == "plain text"
    assert one_line("a\nb\x1b") == "a\\nb\\x1b"


def test_lines_and_columns_count_every_yaml_line_break() -> None:
    text = "a\r\nb\rc\x85d\u2028e\nf"
    assert line_col(text, 0) == (1, 1)
    assert line_col(text, text.index("b")) == (2, 1)
    assert [line_col(text, text.index(c))[0] for c in "cdef"] == [3, 4, 5, 6]
    assert line_col("abc", 2) == (1, 3)

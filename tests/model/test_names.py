"""``model.names.file_name``: any name the OS gives as text every report can carry."""

from __future__ import annotations

import os

from rprpr.model.names import file_name
from rprpr.render.escape import printable


def test_a_byte_that_is_not_utf8_is_written_as_its_escape() -> None:
    assert file_name(os.fsdecode(b"caf\xe9/\xff.yaml")) == "caf\\xe9/\\xff.yaml"


def test_a_valid_name_is_kept_whole() -> None:
    name = "configs/é δ ::x\n.yaml"
    assert file_name(name) == name


def test_any_other_lone_surrogate_is_a_unicode_escape() -> None:
    assert file_name("a\ud800b") == "a\\ud800b"


def test_the_escape_is_the_one_people_see() -> None:
    for raw in (b"\xff", b"a\x80b", b"\xed\xa0\x80"):
        name = os.fsdecode(raw)
        assert file_name(name) == printable(name)
        file_name(name).encode("utf-8")

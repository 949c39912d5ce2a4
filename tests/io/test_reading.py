"""``io.reading``: the one capped reader of every byte stream (task files, standard input,
waypoint CSVs, the configuration)."""

from __future__ import annotations

import io
import os
import re
from pathlib import Path

import pytest

from rprpr.io.reading import ReadProblem, read_file, read_stream


def test_a_stream_within_the_cap_is_read_whole() -> None:
    assert read_stream(io.BytesIO(b"x" * 100), 100) == b"x" * 100
    assert read_stream(None, 10) == b""


def test_a_stream_past_the_cap_stops_at_cap_plus_one() -> None:
    stream = io.BytesIO(b"x" * 10_000)
    with pytest.raises(ReadProblem, match=r"^file too large: more than 100 bytes, the cap"):
        read_stream(stream, 100)
    assert stream.tell() == 101


def test_a_closed_stream_is_empty() -> None:
    stream = io.BytesIO(b"abc")
    stream.close()
    assert read_stream(stream, 10) == b""


def test_a_file_is_read_within_its_cap(tmp_path: Path) -> None:
    f = tmp_path / "a.yaml"
    f.write_bytes(b"abc")
    assert read_file(str(f), 3, "a task file (YAML)") == b"abc"
    with pytest.raises(ReadProblem, match=r"file too large: 3 bytes, the cap is 2 bytes"):
        read_file(str(f), 2, "a task file (YAML)")


@pytest.mark.parametrize(
    ("kind", "message"),
    [
        ("missing", "no such file"),
        ("directory", "is a directory, expected a CSV file"),
        ("fifo", "not a regular file (a device, pipe or socket), expected a CSV file"),
        ("nul", "not a usable file name"),
    ],
)
def test_what_is_not_a_small_regular_file_is_refused_unopened(
    kind: str, message: str, tmp_path: Path
) -> None:
    path = tmp_path / "x.csv"
    if kind == "directory":
        path.mkdir()
    elif kind == "fifo":
        os.mkfifo(path)  # opening it would wait for a writer
    name = str(path) + ("\0" if kind == "nul" else "")
    with pytest.raises(ReadProblem, match=re.escape(message)):
        read_file(name, 100, "a CSV file")


def test_inside_a_folder_after_links(tmp_path: Path) -> None:
    outside = tmp_path / "outside.csv"
    outside.write_bytes(b"secret")
    folder = tmp_path / "task"
    folder.mkdir()
    (folder / "in.csv").write_bytes(b"t,x,y\n")
    (folder / "link.csv").symlink_to(outside)
    (folder / "sub").mkdir()
    (folder / "sub" / "back.csv").symlink_to(folder / "in.csv")
    assert read_file(str(folder / "in.csv"), 100, "a CSV file", inside=str(folder)) == b"t,x,y\n"
    assert read_file(str(folder / "sub/back.csv"), 100, "", inside=str(folder)) == b"t,x,y\n"
    with pytest.raises(ReadProblem, match="resolves outside the task file's folder") as e:
        read_file(str(folder / "link.csv"), 100, "a CSV file", inside=str(folder))
    assert "secret" not in e.value.message

"""Reading a waypoint CSV (``motion.waypoints: planned.csv``): bytes -> ``Waypoint`` list.

The file is a planner's output: a header ``t,x,y``, ``t,x,y,vx,vy`` or
``t,x,y,vx,vy,ax,ay`` (names in this order; spaces around them allowed), then one
waypoint a row. Every number is taken by its text (``0.1`` is 1/10; a fraction such as
``5/3`` is allowed, as in the task file), so the waypoints are exact. Blank lines and
lines starting with ``#`` are skipped. Problems are collected, each as (row, message),
the row 1-based in the file as an editor counts lines; the caller names the file.
"""

from __future__ import annotations

import re
from typing import Any

from flint import fmpq

from ..model.errors import ExpressionError
from ..model.waypoints import Waypoint
from .expression import MAX_EXP10, parse_fraction
from .messages import shorten
from .reading import ReadProblem, read_file
from .schema import WAYPOINT_COLUMNS

MAX_CSV_BYTES = 16 << 20  # 16 MiB: 100,000 rows of seven 20-digit numbers
MAX_CSV_ROWS = 100_000  # waypoints in one file (a 1 kHz planner over 100 s)
MAX_CSV_ERRORS = 20  # problems listed before the rest are summed up in one line
HEADERS = tuple(WAYPOINT_COLUMNS[:n] for n in (3, 5, 7))
# a planner's plain decimal, read here directly (what parse_fraction does, faster): at
# most MAX_DIGITS digits and an exponent within MAX_EXP10; anything else goes through
# parse_fraction, which reads fractions and names what is wrong
_PLAIN = re.compile(r"(-?)([0-9]{1,20})(?:\.([0-9]{0,20}))?(?:[eE]([-+]?[0-9]{1,2}))?")
_POW10 = [10**k for k in range(21 + 2 * 99)]
# a row of such decimals alone, read by one match: (signed whole, fraction, exponent) a cell
_CELL = r"\s*(-?[0-9]{1,20})(?:\.([0-9]{0,20}))?(?:[eE]([-+]?[0-9]{1,2}))?\s*"
_ROWS = {n: re.compile(",".join([_CELL] * n)) for n in (3, 5, 7)}


class CsvProblem(Exception):
    """The file cannot be read (missing, a directory, too large, no header), or a row
    of it; ``row`` is 1-based, 0 for the whole file."""

    def __init__(self, message: str, row: int = 0) -> None:
        super().__init__(message)
        self.message = message
        self.row = row


def read_bytes(path: str, inside: str | None = None) -> bytes:
    """The bytes of the CSV file at ``path`` (``inside``: a folder it must resolve into,
    after symbolic links); raises ``CsvProblem`` saying why not."""
    try:
        return read_file(path, MAX_CSV_BYTES, "a CSV file", inside=inside)
    except ReadProblem as e:
        raise CsvProblem(e.message) from None


def parse_waypoints(data: bytes) -> tuple[list[Waypoint], list[tuple[int, str]]]:
    """The waypoints of a CSV file's bytes, and its problems as (row, message), at most
    ``MAX_CSV_ERRORS`` and a last one counting the rest. Raises ``CsvProblem`` when the
    file has no usable header (nothing else can be read then)."""
    try:
        text = data.decode("utf-8").removeprefix("\ufeff")
    except UnicodeDecodeError as e:
        row = data.count(b"\n", 0, e.start) + 1
        raise CsvProblem(f"not UTF-8 text (byte 0x{data[e.start]:02x})", row) from None
    rows = [
        (i, line)
        for i, line in enumerate(text.splitlines(), 1)
        if line.strip() and not line.lstrip().startswith("#")
    ]
    if not rows:
        raise CsvProblem("empty file, expected a header t,x,y[,vx,vy[,ax,ay]] and waypoints")
    (header_row, header), *body = rows
    names = tuple(c.strip().lower() for c in header.split(","))
    if names not in HEADERS:
        raise CsvProblem(
            "expected the header t,x,y or t,x,y,vx,vy or t,x,y,vx,vy,ax,ay, found"
            f" {shorten(header.strip())!r}",
            header_row,
        )
    if len(body) > MAX_CSV_ROWS:
        raise CsvProblem(f"{len(body)} waypoints, the cap is {MAX_CSV_ROWS}")
    points: list[Waypoint] = []
    problems: list[tuple[int, str]] = []
    whole = _ROWS[len(names)].fullmatch
    for row, line in body:
        plain = whole(line)
        point = _row(row, plain.groups()) if plain is not None else None
        if point is not None:
            points.append(point)
            continue
        try:
            points.append(_waypoint(row, line, names))
        except CsvProblem as e:
            problems.append((row, e.message))
    if len(problems) > MAX_CSV_ERRORS:
        rest = len(problems) - MAX_CSV_ERRORS
        problems = [*problems[:MAX_CSV_ERRORS], (problems[MAX_CSV_ERRORS][0], f"{rest} more")]
    return points, problems


def _row(row: int, cells: tuple[Any, ...]) -> Waypoint | None:
    """The waypoint of a row of plain decimals (``_ROWS``: each cell's signed whole
    part, fraction and exponent), its numbers on integers (``Waypoint.numbers``: t, and
    the others over one power of ten); None for an exponent beyond MAX_EXP10 (then the
    row is read cell by cell, and the cell's problem named)."""
    wholes, fracs, exps = cells[0::3], cells[1::3], cells[2::3]
    numbers = [int(w + f) if f else int(w) for w, f in zip(wholes, fracs, strict=True)]
    scales = [len(f) if f else 0 for f in fracs]  # the value is n / 10^scale
    if any(exps):
        for k, exp in enumerate(exps):
            if exp:
                e = int(exp)
                if e > MAX_EXP10 or e < -MAX_EXP10:
                    return None
                scales[k] -= e
    tn, ts = numbers[0], scales[0]
    if ts >= 0:
        t, td = fmpq(tn, _POW10[ts]), _POW10[ts]
    else:
        tn, td = tn * _POW10[-ts], 1
        t = fmpq(tn)
    K = max(0, *scales[1:])
    rest = [n * _POW10[K - s] for n, s in zip(numbers[1:], scales[1:], strict=True)]
    return Waypoint.row(t, (tn, td, _POW10[K], *rest), row)


def _waypoint(row: int, line: str, names: tuple[str, ...]) -> Waypoint:
    cells = line.split(",")
    if len(cells) != len(names):
        raise CsvProblem(f"expected {len(names)} values ({','.join(names)}), found {len(cells)}")
    values = [_number(cell, name) for cell, name in zip(cells, names, strict=True)]
    t, x, y = values[:3]
    v = (values[3], values[4]) if len(values) >= 5 else None
    a = (values[5], values[6]) if len(values) == 7 else None
    return Waypoint(t, (x, y), v, a, line=row)


def _number(cell: str, name: str) -> fmpq:
    text = cell.strip()
    plain = _PLAIN.fullmatch(text)
    if plain is not None:  # the signed digits over a power of ten, made once
        sign, whole, frac, exp = plain.groups()
        if exp is None:
            return (
                fmpq(int(sign + whole + frac), _POW10[len(frac)])
                if frac
                else fmpq(int(sign + whole))
            )
        if abs(e := int(exp)) <= MAX_EXP10:
            scale = e - len(frac or "")
            n = int(sign + whole + (frac or ""))
            return fmpq(n * 10**scale) if scale >= 0 else fmpq(n, 10**-scale)
    if not text:
        raise CsvProblem(f"column {name}: empty, expected a number")
    try:
        return parse_fraction(text)
    except ExpressionError as e:
        raise CsvProblem(f"column {name}: {e.message}") from None

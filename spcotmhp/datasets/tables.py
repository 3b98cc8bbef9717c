"""Strict CSV reading for dataset folders: every problem becomes a DatasetError naming the file and the
1-based line number in that file (the line a record starts on), never a traceback.

Bounds: a CSV file is a regular file (a symlink to /dev/zero or a FIFO is named as what it is, never read) of at
most ``MAX_CSV_BYTES`` (checked before reading), a field at most Python's csv field limit (128 KiB), an integer
lies within +-``MAX_INT`` (2**53: exact as a float, no int64 overflow) and a number is finite; messages quote at
most a short excerpt of an offending cell.

Columns are bounded before the file is parsed: the first record's line is read with a bound of
``max_columns * MAX_CELL_CHARS`` characters (at least ``MAX_HEADER_CHARS``) and its fields counted against
``max_columns``, so a header of a million columns is refused after reading its first 64 KiB, not parsed (and
every later row must have the header's width). A table with a header (:func:`read_table`) has at most
``MAX_TABLE_COLUMNS`` = 1,000 columns: its columns are named fields, and the loaders know fewer than twenty. A
matrix (:func:`read_matrix`) has at most the columns its reader gives: the map's width for costmap_ros.csv, the
model's largest place and feature counts (``limits.MODEL_MAX_SIZES``) for adjacency.csv and the image features."""

from __future__ import annotations

import csv
import math
from collections import Counter
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from spcotmhp.errors import DatasetError
from spcotmhp.safe_read import excerpt, require_regular_file

MAX_CSV_BYTES = 64 * 1024 * 1024
MAX_INT = 2**53
MAX_INT_CHARS = 40  # longer integer texts are read as floats (parse_int)
MAX_TABLE_COLUMNS = 1_000
MAX_HEADER_CHARS = 64 * 1024  # a header of 1,000 column names of 64 characters
MAX_CELL_CHARS = 32  # a number of a matrix row, with its comma: "-1.2345678901234567e-308," is 25


@dataclass
class Table:
    """A CSV file with a header: lower-cased column names, string cells and each row's line number."""

    path: Path
    header: list[str]
    rows: list[list[str]]
    lines: list[int]

    @property
    def name(self) -> str:
        return self.path.name

    def where(self, i: int) -> str:
        """'teaching.csv row 12' for data row ``i`` (0-based), 12 being the line number in the file."""
        return f"{self.name} row {self.lines[i]}"

    def column(self, name: str) -> list[str]:
        j = self.header.index(name)
        return [r[j] for r in self.rows]

    def has(self, name: str) -> bool:
        return name in self.header

    def require(self, required: Sequence[str | tuple[str, ...]], optional: Sequence[str] = ()) -> None:
        """DatasetError listing the missing columns, the columns found and the columns accepted.

        A tuple in ``required`` means "at least one of these columns"."""
        missing = [c for c in required if not any(a in self.header for a in ((c,) if isinstance(c, str) else c))]
        if missing:

            def show(c: str | tuple[str, ...], join: str) -> str:
                return c if isinstance(c, str) else join.join(c)

            accepted = ", ".join([show(c, " and/or ") for c in required] + [f"[{c}]" for c in optional])
            raise DatasetError(
                f"{self.name}: missing column(s) {', '.join(show(c, ' or ') for c in missing)}; found "
                f"{_short(', '.join(self.header)) or 'none'};"
                f" accepted: {accepted}"
            )

    def ints(self, name: str, minimum: int | None = None) -> np.ndarray:
        """A column of integers (integral floats such as '3.0' are accepted), at least ``minimum``.

        Fast path: every cell as ``int()`` reads it (what :func:`parse_int` tries first, for cells of at most 40
        characters), bounds checked on the whole column; any other column (a float, a bad or out-of-range
        cell) goes through :func:`_slow_ints`, the row-by-row reading that names the first bad row."""
        column = self.column(name)
        try:
            if column and max(map(len, column)) > MAX_INT_CHARS:
                raise ValueError
            out = np.array([int(text) for text in column], dtype=np.int64)  # overflow -> OverflowError
        except (ValueError, OverflowError):
            return self._slow_ints(name, column, minimum)
        low = -MAX_INT if minimum is None else max(minimum, -MAX_INT)
        if len(out) and (out.min() < low or out.max() > MAX_INT):
            return self._slow_ints(name, column, minimum)
        return out

    def _slow_ints(self, name: str, column: list[str], minimum: int | None) -> np.ndarray:
        """:meth:`ints` a row at a time: DatasetError on the first row that is not an integer in range."""
        out = np.empty(len(column), dtype=np.int64)
        for i, text in enumerate(column):
            out[i] = parse_int(text, f"{self.where(i)}: {name}")
            if minimum is not None and out[i] < minimum:
                raise DatasetError(f"{self.where(i)}: {name} is {out[i]}, must be >= {minimum}")
        return out

    def floats(self, name: str) -> np.ndarray:
        """A column of finite floats: every cell as ``float()`` reads it (:func:`parse_float`), the row's
        message built only for a bad cell (the first, in file order)."""
        column = self.column(name)
        try:
            out = np.array([float(text) for text in column], dtype=float)
        except ValueError:
            out = None
        if out is None or not np.isfinite(out).all():
            return np.array([parse_float(t, f"{self.where(i)}: {name}") for i, t in enumerate(column)], dtype=float)
        return out

    def sequence(self, column: str, what: str) -> np.ndarray:
        """The column must read 0, 1, 2, ... in file order; say where it does not."""
        ids = self.ints(column)
        bad = np.flatnonzero(ids != np.arange(len(ids)))
        if len(bad):
            i = int(bad[0])
            earlier = np.flatnonzero(ids[:i] == ids[i])
            if len(earlier):
                raise DatasetError(
                    f"{self.where(i)}: {column} {ids[i]} appears twice (also on row "
                    f"{self.lines[earlier[0]]}); {what} must be 0, 1, 2, ... in file order"
                )
            after = f"follows {ids[i - 1]}" if i else "is the first"
            raise DatasetError(f"{self.where(i)}: {column} {ids[i]} {after}; {what} must be 0, 1, 2, ... in file order")
        return ids


def _short(text: str, limit: int = 120) -> str:
    """``text`` cut to ``limit`` characters (a header of thousands of columns is not repeated in full)."""
    return text if len(text) <= limit else text[:limit] + f"... ({len(text)} characters)"


def parse_float(text: str, where: str) -> float:
    """A finite float, or DatasetError '<where> is 'abc', not a number' / '... not a finite number'."""
    try:
        value = float(text)
    except ValueError:
        raise DatasetError(f"{where} is {excerpt(text.strip())}, not a number") from None
    if not math.isfinite(value):
        raise DatasetError(f"{where} is {excerpt(text.strip())}, not a finite number")
    return value


def parse_int(text: str, where: str) -> int:
    """An integer (or an integral float such as '3.0') within +-MAX_INT, else DatasetError."""
    try:
        number = int(text) if len(text) <= MAX_INT_CHARS else None
    except ValueError:
        number = None
    if number is None:
        value = parse_float(text, where)
        if value != int(value):
            raise DatasetError(f"{where} is {excerpt(text.strip())}, not an integer")
        number = int(value)
    if abs(number) > MAX_INT:
        raise DatasetError(f"{where} is {excerpt(text.strip())}, out of range (integers must lie within +-2**53)")
    return number


def present(path: Path) -> bool:
    """Whether an optional CSV file is there: False when nothing is, True for a regular file, DatasetError for
    anything else (a symlink to /dev/zero, a FIFO, a folder: named as what it is, not taken as absent)."""
    require_regular_file(path, "dataset file", DatasetError)
    return path.is_file()


def _records(path: Path, max_columns: int = MAX_TABLE_COLUMNS) -> list[tuple[int, list[str]]]:
    """(first line number, fields) of every non-blank record of a UTF-8 CSV file (BOM allowed); the first
    record's line and width bounded before parsing (module docstring)."""
    try:
        size = path.stat().st_size
    except OSError as exc:
        raise DatasetError(f"cannot read {path}: {exc.strerror or exc}") from None
    require_regular_file(path, "dataset file", DatasetError)
    if size > MAX_CSV_BYTES:
        raise DatasetError(f"{path.name} is {size} bytes; at most {MAX_CSV_BYTES} are accepted")
    reader = None
    try:
        with path.open(newline="", encoding="utf-8-sig") as fh:
            first: list[int] = []  # the first record's line, once parsed
            reader = csv.reader(_bounded_first_record(fh, path.name, max_columns, first))
            out: list[tuple[int, list[str]]] = []
            start = 1
            for fields in reader:
                stripped = [f.strip() for f in fields]
                if any(stripped):  # not a blank record
                    if not out:
                        _check_width(path.name, start, len(fields), max_columns)
                        first.append(start)
                    out.append((start, stripped))
                start = reader.line_num + 1
    except UnicodeDecodeError as exc:
        raise DatasetError(f"{path.name} is not UTF-8 text ({exc.reason} at byte {exc.start})") from None
    except csv.Error as exc:
        line = reader.line_num if reader is not None else 1
        raise DatasetError(f"{path.name} line {line}: not valid CSV ({exc})") from None
    except OSError as exc:
        raise DatasetError(f"cannot read {path}: {exc.strerror or exc}") from None
    return out


def _bounded_first_record(fh: Any, name: str, max_columns: int, first: list[int]) -> Iterator[str]:
    """The lines of ``fh``; until the first non-blank record is parsed (``first`` is then non-empty) at most
    ``max_columns * MAX_CELL_CHARS`` characters in all (at least MAX_HEADER_CHARS) are read, each line with that
    bound: DatasetError past it (such a record holds more than ``max_columns`` fields or is not a header)."""
    limit = max(MAX_HEADER_CHARS, max_columns * MAX_CELL_CHARS)
    used, line_number = 0, 0
    while not first:
        line = fh.readline(limit - used + 1)
        if not line:
            return
        used, line_number = used + len(line), line_number + 1
        if used > limit:
            raise DatasetError(
                f"{name}: the header (or first row) runs past {limit} characters (line {line_number}); at most "
                f"{max_columns} columns are accepted"
            )
        yield line
    yield from fh


def _check_width(name: str, line: int, width: int, max_columns: int) -> None:
    if width > max_columns:
        raise DatasetError(f"{name} line {line} has {width} columns; at most {max_columns} are accepted")


def read_table(path: Path, what: str) -> Table:
    """Read a CSV file with a header row; rows must have as many fields as the header.

    ``what`` describes the expected content for the message when the file is empty.
    """
    records = _records(path)
    if not records:
        raise DatasetError(f"{path.name} is empty (expected {what})")
    _, header = records[0]
    header = [h.lower() for h in header]
    dupes = sorted(h for h, n in Counter(header).items() if n > 1)
    if dupes:
        raise DatasetError(f"{path.name} line {records[0][0]}: column(s) {_short(', '.join(dupes))} appear twice")
    table = Table(path, header, [], [])
    for line, fields in records[1:]:
        if len(fields) != len(header):
            raise DatasetError(
                f"{path.name} row {line}: {len(fields)} fields, expected {len(header)} ({_short(','.join(header))})"
            )
        table.rows.append(fields)
        table.lines.append(line)
    return table


def read_matrix(path: Path, max_columns: int, allow_header: bool = False) -> tuple[np.ndarray, list[int]]:
    """A rectangular CSV of finite numbers, at most ``max_columns`` wide, as a float (R, C) array, with the line
    number of each row.

    With ``allow_header`` a first row that does not start with a number (column names) is skipped.
    """
    records = _records(path, max_columns)
    if allow_header and records:
        try:
            float(records[0][1][0])
        except ValueError:
            records = records[1:]
    if not records:
        raise DatasetError(f"{path.name} is empty (expected rows of comma-separated numbers)")
    width = len(records[0][1])
    out = np.empty((len(records), width), dtype=float)
    for i, (line, fields) in enumerate(records):
        if len(fields) != width:
            raise DatasetError(
                f"{path.name} row {line}: {len(fields)} values, expected {width} as on row {records[0][0]}"
            )
        try:
            out[i] = np.asarray(fields, dtype=float)
        except ValueError:
            for j, text in enumerate(fields):  # find the culprit for the message
                parse_float(text, f"{path.name} row {line} column {j + 1}")
        if not np.isfinite(out[i]).all():
            j = int(np.flatnonzero(~np.isfinite(out[i]))[0])
            raise DatasetError(f"{path.name} row {line} column {j + 1} is {excerpt(fields[j])}, not a finite number")
    return out, [line for line, _ in records]

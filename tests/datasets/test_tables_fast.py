"""The column readers' whole-column fast path (``Table.ints``, ``Table.floats``) against the row-by-row reading
it replaces (``parse_int`` / ``parse_float`` on every cell): the same values, or the same one-line error naming
the same first bad row."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.datasets.tables import MAX_INT, Table, parse_float, parse_int
from spcotmhp.errors import DatasetError

CELLS = st.one_of(
    st.integers(-(2**60), 2**60).map(str),
    st.sampled_from(
        [
            "0",
            "-0",
            "+7",
            "3.0",
            "3.5",
            "1e3",
            "1_000",
            " 5",
            "nan",
            "inf",
            "-inf",
            "abc",
            "",
            "0x10",
            str(MAX_INT),
            str(MAX_INT + 1),
            str(-MAX_INT - 1),
            "0" * 41 + "12",
            "9" * 41,
            "1e400",
            "٣",
        ]
    ),  # fmt: skip
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
)


def table(cells: list[str]) -> Table:
    return Table(Path("t.csv"), ["v"], [[c] for c in cells], list(range(2, len(cells) + 2)))


def old_ints(t: Table, minimum: int | None) -> np.ndarray:
    """The reading before the fast path, a row at a time."""
    out = np.empty(len(t.rows), dtype=np.int64)
    for i, text in enumerate(t.column("v")):
        out[i] = parse_int(text, f"{t.where(i)}: v")
        if minimum is not None and out[i] < minimum:
            raise DatasetError(f"{t.where(i)}: v is {out[i]}, must be >= {minimum}")
    return out


def old_floats(t: Table) -> np.ndarray:
    return np.array([parse_float(s, f"{t.where(i)}: v") for i, s in enumerate(t.column("v"))], dtype=float)


def outcome(read, *args):
    try:
        return ("ok", read(*args).tolist())
    except DatasetError as exc:
        return ("error", str(exc))


@settings(max_examples=300, deadline=None)
@given(st.lists(CELLS, max_size=12), st.sampled_from([None, 0, 5, -3]))
def test_ints_as_row_by_row(cells: list[str], minimum: int | None) -> None:
    t = table(cells)
    assert outcome(t.ints, "v", minimum) == outcome(old_ints, t, minimum)


@settings(max_examples=300, deadline=None)
@given(st.lists(CELLS, max_size=12))
def test_floats_as_row_by_row(cells: list[str]) -> None:
    t = table(cells)
    assert outcome(t.floats, "v") == outcome(old_floats, t)


def test_hand_cases() -> None:
    assert table(["1", "2", "3.0"]).ints("v").tolist() == [1, 2, 3]
    assert table(["1", "0000000000000000000000000000000000000000012"]).ints("v").tolist() == [1, 12]
    with pytest.raises(DatasetError, match=r"^t.csv row 3: v is -1, must be >= 0$"):
        table(["4", "-1", "-2"]).ints("v", minimum=0)
    with pytest.raises(DatasetError, match=r"^t.csv row 4: v is 'nan', not a finite number$"):
        table(["4", "1.5", "nan"]).floats("v")
    with pytest.raises(DatasetError, match=r"out of range"):
        table(["0", str(MAX_INT + 1)]).ints("v")

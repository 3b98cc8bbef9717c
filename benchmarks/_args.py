"""Command-line arguments the benchmarks share."""

from __future__ import annotations


def parse_seeds(text: str) -> list[int]:
    """Seeds given as "0-99", "3,7,10-12" or "5": every integer of each range, in the order given.

    >>> parse_seeds("3,7,10-12")
    [3, 7, 10, 11, 12]
    """
    out: list[int] = []
    for part in text.split(","):
        lo, _, hi = part.partition("-")
        out.extend(range(int(lo), int(hi or lo) + 1))
    return out

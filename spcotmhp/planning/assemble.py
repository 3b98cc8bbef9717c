"""Path assembly and smoothing (Algorithm 1, lines 12-13).

The start leg and the partial paths are joined into one 8-connected cell path. Smoothing (optional) is greedy
line-of-sight shortcutting (from each kept cell, jump to the farthest visible cell of the segment) between fixed
anchors (the cells where a waypoint or the goal is reached, so the
smoothed path still passes every waypoint candidate and ends at the goal candidate):

* a shortcut from cell a to cell b is taken only if every cell the straight segment between their centres
  touches (its *supercover*, corner crossings counting both side cells) is allowed: traversable, outside avoided
  regions, and not an inscribed (p(x|m) <= 0.01, footprint in collision) cell unless the path already used it;
* the shortcut is drawn as the Bresenham line, whose cells are a subset of that supercover and whose length is
  the octile distance between a and b, the shortest 8-connected length, so a shortcut never lengthens the path
  and a diagonal step never squeezes between two blocked cells.

The reference implementation's smoothing was a moving-average relaxation with no collision check; this one
never enters an occupied, lethal or avoided cell by construction.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

INSCRIBED_P = 0.015
"""Cells with p(x|m) below this are costmap_2d's inscribed (99) or lethal cells; smoothing avoids new ones."""


def join_legs(legs: list[np.ndarray]) -> tuple[np.ndarray, list[int]]:
    """Concatenate cell paths that share their junction cells; returns the path and the index of each leg's
    last cell in it."""
    parts, ends, n = [], [], 0
    for k, leg in enumerate(legs):
        leg = np.asarray(leg, dtype=np.int64).reshape(-1, 2)
        if k > 0 and len(leg) and n and (leg[0] == parts[-1][-1]).all():
            leg = leg[1:]
        if len(leg):
            parts.append(leg)
            n += len(leg)
        ends.append(n - 1)
    return (np.concatenate(parts) if parts else np.empty((0, 2), np.int64)), ends


def path_length(cells: np.ndarray, resolution: float) -> float:
    """Length in metres of an 8-connected cell path (steps 1 or sqrt 2 cells)."""
    if len(cells) < 2:
        return 0.0
    steps = np.abs(np.diff(cells, axis=0)).sum(axis=1)
    return float(resolution * (np.count_nonzero(steps == 1) + math.sqrt(2.0) * np.count_nonzero(steps == 2)))


def smoothing_mask(traversable: np.ndarray, log_p: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Cells a shortcut may touch: traversable, not inscribed unless already on the path."""
    allowed = traversable & (log_p > math.log(INSCRIBED_P))
    allowed[cells[:, 0], cells[:, 1]] = traversable[cells[:, 0], cells[:, 1]]
    return allowed


def smooth(cells: np.ndarray, allowed: np.ndarray, anchors: list[int]) -> np.ndarray:
    """Line-of-sight shortcutting between consecutive ``anchors`` (indices into ``cells``, kept fixed)."""
    cells = np.ascontiguousarray(cells, dtype=np.int64)
    if len(cells) < 3:
        return cells
    fixed = np.unique(np.clip(np.asarray([0, *anchors, len(cells) - 1], dtype=np.int64), 0, len(cells) - 1))
    return _shortcut(cells, np.ascontiguousarray(allowed), fixed)


@njit(cache=True)
def _clear(allowed, r0, c0, r1, c1):  # pragma: no cover - numba
    """True if every cell of the supercover of the segment between the two cell centres is allowed."""
    nr, nc = abs(r1 - r0), abs(c1 - c0)
    sr = 1 if r1 > r0 else -1
    sc = 1 if c1 > c0 else -1
    r, c = r0, c0
    if not allowed[r, c]:
        return False
    ir = 0
    ic = 0
    while ir < nr or ic < nc:
        decision = (1 + 2 * ic) * nr - (1 + 2 * ir) * nc
        if decision == 0:                       # through a corner: both side cells are touched
            if not allowed[r + sr, c] or not allowed[r, c + sc]:
                return False
            r += sr
            c += sc
            ir += 1
            ic += 1
        elif decision < 0:
            c += sc
            ic += 1
        else:
            r += sr
            ir += 1
        if not allowed[r, c]:
            return False
    return True


@njit(cache=True)
def _line(r0, c0, r1, c1, out, k):  # pragma: no cover - numba
    """Write the Bresenham cells after (r0, c0) up to (r1, c1) into out[k:], return the new k."""
    dr, dc = r1 - r0, c1 - c0
    n = max(abs(dr), abs(dc))
    for t in range(1, n + 1):
        # round half away from zero, exactly, in integers: floor((2 d t + n) / (2 n)) for d >= 0
        out[k, 0] = r0 + (np.sign(dr) * ((2 * abs(dr) * t + n) // (2 * n)))
        out[k, 1] = c0 + (np.sign(dc) * ((2 * abs(dc) * t + n) // (2 * n)))
        k += 1
    return k


@njit(cache=True)
def _shortcut(cells, allowed, fixed):  # pragma: no cover - numba
    n = cells.shape[0]
    out = np.empty((n, 2), np.int64)
    out[0] = cells[0]
    k = 1
    for s in range(fixed.shape[0] - 1):
        i, end = fixed[s], fixed[s + 1]
        while i < end:
            j = end                             # the farthest visible cell of this segment
            while j > i + 1 and not _clear(allowed, cells[i, 0], cells[i, 1], cells[j, 0], cells[j, 1]):
                j -= 1
            if j == i + 1:
                out[k] = cells[j]
                k += 1
            else:
                k = _line(cells[i, 0], cells[i, 1], cells[j, 0], cells[j, 1], out, k)
            i = j
    return out[:k].copy()

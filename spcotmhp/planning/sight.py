"""Line of sight on the grid: the compiled kernels of the shortcuts of Algorithm 1, line 13
(:mod:`spcotmhp.planning.assemble`).

A shortcut from cell a to cell b is allowed when every cell of the *supercover* of the segment between their
centres is allowed: every cell whose closed square the segment touches, so a segment through a corner point
counts the two side cells as well. Along the segment's major axis (the one of the larger extent N, minor extent
n <= N), the cells touched in major row a (0 <= a <= N) are the minor columns

    b_lo(a) = max(0, ceil(((2a - 1) n - N) / 2N)) .. b_hi(a) = min(n, floor(((2a + 1) n + N) / 2N))

(the minor coordinate y = x n / N over the row's closed strip x in [a - 1/2, a + 1/2], widened by half a cell):
exact integer arithmetic, and any row can be read without walking the ones before it.

:func:`clear` tests the rows from both ends of the segment inwards, so a blocked cell near either end is found in
a few steps, and skips the rows a precomputed *clearance* certifies: ``clearance[x]`` is the chessboard distance
from cell x to the nearest cell that is not allowed (:func:`chessboard_clearance`), so every cell within
``clearance[x] - 1`` rows and columns of x is allowed, and the rows whose touched cells all lie that close to an
already tested cell need no test. The answer is exactly the supercover test's (tested against a brute force);
the work is about (segment length) / (clearance along it) instead of the length.
"""

from __future__ import annotations

import numpy as np
from numba import njit


def chessboard_clearance(allowed: np.ndarray) -> np.ndarray:
    """(h, w) uint8: for an allowed cell, the chessboard (8-neighbour) distance to the nearest cell that is not
    allowed or lies outside the grid (1 next to one), capped at 255 (a smaller value is still true: every cell
    that close is allowed); 0 on cells that are not allowed. One byte a cell keeps the tests in cache."""
    return np.minimum(_chessboard(np.ascontiguousarray(allowed, dtype=np.bool_)), 255).astype(np.uint8)


@njit(cache=True)
def _chessboard(allowed):  # pragma: no cover - numba
    """Two raster passes of the 8-neighbour chamfer with unit steps: exact for the chessboard distance."""
    h, w = allowed.shape
    d = np.empty((h, w), np.int32)
    for r in range(h):
        for c in range(w):
            if not allowed[r, c]:
                d[r, c] = 0
                continue
            best = min(r + 1, c + 1, h - r, w - c)  # the outside of the grid counts as blocked
            if r > 0:
                best = min(best, d[r - 1, c] + 1)
                if c > 0:
                    best = min(best, d[r - 1, c - 1] + 1)
                if c + 1 < w:
                    best = min(best, d[r - 1, c + 1] + 1)
            if c > 0:
                best = min(best, d[r, c - 1] + 1)
            d[r, c] = best
    for r in range(h - 1, -1, -1):
        for c in range(w - 1, -1, -1):
            best = d[r, c]
            if best == 0:
                continue
            if r + 1 < h:
                best = min(best, d[r + 1, c] + 1)
                if c > 0:
                    best = min(best, d[r + 1, c - 1] + 1)
                if c + 1 < w:
                    best = min(best, d[r + 1, c + 1] + 1)
            if c + 1 < w:
                best = min(best, d[r, c + 1] + 1)
            d[r, c] = best
    return d


@njit(cache=True)
def _b_lo(a, n, N):  # pragma: no cover - numba
    p = (2 * a - 1) * n - N
    return max(0, -((-p) // (2 * N)))


@njit(cache=True)
def _b_hi(a, n, N):  # pragma: no cover - numba
    return min(n, ((2 * a + 1) * n + N) // (2 * N))


@njit(cache=True)
def _row_free(clearance, r0, c0, sr, sc, swap, a, lo, hi):  # pragma: no cover - numba
    """Whether the cells lo..hi of major row a are all allowed (clearance > 0)."""
    for b in range(lo, hi + 1):
        if swap:
            if clearance[r0 + sr * b, c0 + sc * a] == 0:
                return False
        elif clearance[r0 + sr * a, c0 + sc * b] == 0:
            return False
    return True


@njit(cache=True)
def clear(clearance, r0, c0, r1, c1):  # pragma: no cover - numba
    """True if every cell of the supercover of the segment between the centres of (r0, c0) and (r1, c1) is
    allowed (module docstring); ``clearance`` is :func:`chessboard_clearance` of the allowed cells (0 on the
    others: one byte a cell holds both, which keeps the tests in cache)."""
    return blocked_at(clearance, r0, c0, r1, c1)[0] < 0


@njit(cache=True)
def _point_cell_free(clearance, r0, c0, r1, c1, p, q):  # pragma: no cover - numba
    """Whether the cell holding the point at p / q of the segment (a supercover cell: a point on a cell boundary
    touches the cells on both sides, so any rounding is one) is allowed; exact integer arithmetic."""
    return clearance[(2 * (p * r1 + (q - p) * r0) + q) // (2 * q), (2 * (p * c1 + (q - p) * c0) + q) // (2 * q)] > 0


@njit(cache=True)
def blocked_at(clearance, r0, c0, r1, c1):  # pragma: no cover - numba
    """(p, q): a point at p / q of the segment lies in a cell that is not allowed, or (-1, 1) when the segment is
    clear (:func:`clear`)."""
    for p in (2, 1, 3):  # quick rejection: the points at 1/2, 1/4, 3/4
        if not _point_cell_free(clearance, r0, c0, r1, c1, p, 4):
            return p, 4
    nr, nc = abs(r1 - r0), abs(c1 - c0)
    sr = 1 if r1 >= r0 else -1
    sc = 1 if c1 >= c0 else -1
    swap = nc > nr  # the major axis is the column
    N, n = (nc, nr) if swap else (nr, nc)
    if N == 0:
        return (-1, 1) if clearance[r0, c0] > 0 else (0, 1)
    lo, hi = 0, N  # the major rows lo..hi are still to be tested
    while lo <= hi:
        for forward in (True, False):
            if lo > hi:
                break
            a = lo if forward else hi
            b0, b1 = _b_lo(a, n, N), _b_hi(a, n, N)
            if not _row_free(clearance, r0, c0, sr, sc, swap, a, b0, b1):
                return a, N
            b = b0 if forward else b1  # the tested cell the certified rows lie around
            d = np.int64(clearance[r0 + sr * b, c0 + sc * a] if swap else clearance[r0 + sr * a, c0 + sc * b])
            if forward:
                m = min(d - 1, hi - a)
                while m > 0 and _b_hi(a + m, n, N) - b > d - 1:
                    m -= 1
                lo = a + m + 1
            else:
                m = min(d - 1, a - lo)
                while m > 0 and b - _b_lo(a - m, n, N) > d - 1:
                    m -= 1
                hi = a - m - 1
    return -1, 1


@njit(cache=True)
def _line(r0, c0, r1, c1, out, k):  # pragma: no cover - numba
    """Write the Bresenham cells after (r0, c0) up to (r1, c1) into out[k:], return the new k. Kept: no
    dependency draws lines (scipy has none; skimage.draw.line would be a new dependency), and it runs inside the
    compiled :func:`shortcut`, where a library call cannot."""
    dr, dc = r1 - r0, c1 - c0
    n = max(abs(dr), abs(dc))
    for t in range(1, n + 1):
        # round half away from zero, exactly, in integers: floor((2 d t + n) / (2 n)) for d >= 0
        out[k, 0] = r0 + (np.sign(dr) * ((2 * abs(dr) * t + n) // (2 * n)))
        out[k, 1] = c0 + (np.sign(dc) * ((2 * abs(dc) * t + n) // (2 * n)))
        k += 1
    return k


@njit(cache=True)
def _line4(r0, c0, r1, c1, out, k):  # pragma: no cover - numba
    """Write the 4-connected line after (r0, c0) up to (r1, c1) into out[k:] (a walk through the supercover of
    :func:`clear`, stepping along the row first at a corner), return the new k."""
    nr, nc = abs(r1 - r0), abs(c1 - c0)
    sr = 1 if r1 > r0 else -1
    sc = 1 if c1 > c0 else -1
    r, c = r0, c0
    ir = 0
    ic = 0
    while ir < nr or ic < nc:
        if (1 + 2 * ic) * nr - (1 + 2 * ir) * nc <= 0 and ic < nc:
            c += sc
            ic += 1
        else:
            r += sr
            ir += 1
        out[k, 0] = r
        out[k, 1] = c
        k += 1
    return k


@njit(cache=True)
def shortcut(cells, clearance, fixed, four):  # pragma: no cover - numba
    """Between consecutive indices of ``fixed`` (kept), from each kept cell jump to the farthest cell of the
    piece it sees (:func:`clear`; the next candidate is first probed where the last one was blocked, at the
    same fraction of its segment: nearby segments meet the same wall), drawn as the Bresenham line (``four``:
    the 4-connected line). Returns the cells and the new index of each fixed one."""
    n = cells.shape[0]
    out = np.empty((n, 2), np.int64)
    out[0] = cells[0]
    ends = np.zeros(fixed.shape[0], np.int64)  # the new index of each fixed cell
    k = 1
    for s in range(fixed.shape[0] - 1):
        i, end = fixed[s], fixed[s + 1]
        while i < end:
            j = end  # the farthest visible cell of this segment
            hp, hq = -1, 1  # where the last segment tested from i was blocked: probed first on the next one
            while j > i + 1:
                r0, c0, r1, c1 = cells[i, 0], cells[i, 1], cells[j, 0], cells[j, 1]
                if hp < 0 or _point_cell_free(clearance, r0, c0, r1, c1, hp, hq):
                    hp, hq = blocked_at(clearance, r0, c0, r1, c1)
                    if hp < 0:
                        break
                j -= 1
            if j == i + 1:
                out[k] = cells[j]
                k += 1
            elif four:
                k = _line4(cells[i, 0], cells[i, 1], cells[j, 0], cells[j, 1], out, k)
            else:
                k = _line(cells[i, 0], cells[i, 1], cells[j, 0], cells[j, 1], out, k)
            i = j
        ends[s + 1] = k - 1
    return out[:k].copy(), ends

"""Shortest-path trees stored as one byte a cell: the portal graph's local fields (:mod:`spcotmhp.planning.hierarchy`).

A local field into an abstract node is a shortest-path tree over its territory's window: every reached cell
links to the next cell towards the node. Instead of a float64 cost and an int32 link per cell (12 bytes), a
cell keeps one int8 *direction code*, ``(dr + 1) * 3 + (dc + 1)`` of the step to its next cell (0..8 without 4;
-1 at the node and at unreached cells): 12 times less memory and disk, and a tree is read, not rebuilt.

The cost to go from a cell is not stored but summed along its chain from the node end, with the operands and
the order of the search that made the tree (:func:`spcotmhp.metric._grid_kernels.grid_search`, reverse mode:
``dist[v] = dist[u] + cost[u] * step`` where u is v's next cell, ``step`` 1 or the diagonal factor), so it is
bit-for-bit the search's value. Every kernel checks each step against the window and stops after ``h * w``
steps, so a damaged tree can give no path (``inf``, an empty chain) but never a read out of bounds or a loop.
"""

from __future__ import annotations

import numpy as np
from numba import njit

NO_LINK = -1


@njit(cache=True)
def encode_links(parent: np.ndarray, width: int, out: np.ndarray) -> None:  # pragma: no cover
    """Write the direction code of each window-flat ``parent`` link (-1: none) into ``out`` (int8)."""
    for v in range(parent.shape[0]):
        p = parent[v]
        if p < 0:
            out[v] = NO_LINK
            continue
        dr = p // width - v // width
        dc = p % width - v % width
        out[v] = (dr + 1) * 3 + (dc + 1)


@njit(cache=True)
def _chain_length(codes: np.ndarray, h: int, w: int, r: int, c: int) -> int:  # pragma: no cover
    """Cells of the chain from window cell (r, c) to its root (the first cell without a link), or -1 if the
    chain leaves the window, holds an invalid code or does not end within h * w steps."""
    n = 1
    for _ in range(h * w):
        code = codes[r * w + c]
        if code == NO_LINK:
            return n
        if code < 0 or code > 8 or code == 4:
            return -1
        r += code // 3 - 1
        c += code % 3 - 1
        if r < 0 or r >= h or c < 0 or c >= w:
            return -1
        n += 1
    return -1


@njit(cache=True)
def follow_codes(codes: np.ndarray, h: int, w: int, r: int, c: int) -> np.ndarray:  # pragma: no cover
    """The (n, 2) window cells of the chain from (r, c) to its root, empty if the chain is damaged (module
    docstring) or (r, c) is outside the window."""
    if r < 0 or r >= h or c < 0 or c >= w:
        return np.empty((0, 2), np.int64)
    n = _chain_length(codes, h, w, r, c)
    if n < 0:
        return np.empty((0, 2), np.int64)
    out = np.empty((n, 2), np.int64)
    for i in range(n):
        out[i, 0] = r
        out[i, 1] = c
        if i < n - 1:
            code = codes[r * w + c]
            r += code // 3 - 1
            c += code % 3 - 1
    return out


@njit(cache=True)
def chain_cost(
    codes: np.ndarray,
    h: int,
    w: int,
    r: int,
    c: int,
    node_r: int,
    node_c: int,
    cost: np.ndarray,
    r0: int,
    c0: int,
    diag: float,
) -> float:  # pragma: no cover
    """The cost to go from window cell (r, c) into the tree's node (window cell (node_r, node_c)): the sum of
    ``cost`` (the crop's, window corner at crop cell (r0, c0)) of each cell entered times its step, added from
    the node end as the search added it (module docstring); inf when the chain does not end at the node."""
    cells = follow_codes(codes, h, w, r, c)
    n = cells.shape[0]
    if n == 0 or cells[n - 1, 0] != node_r or cells[n - 1, 1] != node_c:
        return np.inf
    total = 0.0
    for i in range(n - 2, -1, -1):
        pr, pc = cells[i + 1, 0], cells[i + 1, 1]
        step = 1.0 if (pr == cells[i, 0] or pc == cells[i, 1]) else diag
        total = total + cost[r0 + pr, c0 + pc] * step
    return total


@njit(cache=True)
def costs_at(
    codes: np.ndarray,
    off: np.ndarray,
    nodes: np.ndarray,
    win: np.ndarray,
    terr: np.ndarray,
    cells: np.ndarray,
    r: int,
    c: int,
    cost: np.ndarray,
    diag: float,
) -> np.ndarray:  # pragma: no cover
    """For each abstract node of ``nodes``, the cost to go from crop cell (r, c) into it over its local field
    (inf off its window or unreached): :func:`chain_cost` on each node's tree."""
    out = np.full(nodes.shape[0], np.inf)
    for i in range(nodes.shape[0]):
        a = nodes[i]
        t = terr[a]
        r0, c0, r1, c1 = win[t, 0], win[t, 1], win[t, 2], win[t, 3]
        h, w = r1 - r0, c1 - c0
        block = codes[off[a] : off[a] + h * w]
        if block.shape[0] != h * w:
            continue
        out[i] = chain_cost(block, h, w, r - r0, c - c0, cells[a, 0] - r0, cells[a, 1] - c0, cost, r0, c0, diag)
    return out


@njit(cache=True)
def pair_costs(
    codes: np.ndarray,
    off: np.ndarray,
    members: np.ndarray,
    bounds: np.ndarray,
    win: np.ndarray,
    cells: np.ndarray,
    cost: np.ndarray,
    diag: float,
) -> np.ndarray:  # pragma: no cover
    """For every territory t (members ``members[bounds[t]:bounds[t + 1]]``) and every two of its nodes a, b, the
    cost from a into b over b's local field, flat: territory t's block starts at sum of n_s**2 over s < t and
    holds [a, b] row by row."""
    total = 0
    for t in range(bounds.shape[0] - 1):
        n = bounds[t + 1] - bounds[t]
        total += n * n
    out = np.full(total, np.inf)
    at = 0
    for t in range(bounds.shape[0] - 1):
        m = members[bounds[t] : bounds[t + 1]]
        n = m.shape[0]
        r0, c0, r1, c1 = win[t, 0], win[t, 1], win[t, 2], win[t, 3]
        h, w = r1 - r0, c1 - c0
        for j in range(n):
            b = m[j]
            block = codes[off[b] : off[b] + h * w]
            for i in range(n):
                a = m[i]
                if i != j and block.shape[0] == h * w:
                    out[at + i * n + j] = chain_cost(
                        block,
                        h,
                        w,
                        cells[a, 0] - r0,
                        cells[a, 1] - c0,
                        cells[b, 0] - r0,
                        cells[b, 1] - c0,
                        cost,
                        r0,
                        c0,
                        diag,
                    )
        at += n * n
    return out

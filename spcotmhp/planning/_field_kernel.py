"""The portal graph's local fields (:mod:`spcotmhp.planning.hierarchy`), computed territory by territory.

Each field is the tree of :func:`spcotmhp.metric._grid_kernels.grid_search` in reverse field mode (Dijkstra
from one node over its territory's window, every other cell blocked, corners not squeezed), written straight
as the direction codes of :mod:`spcotmhp.planning._tree_codes`. It is the same search step for step: the
same 4-ary heap (its ``_push`` and ``_pop_fix``), the same neighbour order, the same strict comparisons and
the same additions, so the same cells leave the heap in the same order and every tree and cost is bit for bit
``grid_search``'s (tested against it). What it saves: the window's costs are copied once a territory (not once
a node) into a grid with a blocked border, so the search needs no bounds checks; the tree is written as codes
while searching (no int32 links to encode after); and the heap is allocated at its bound (with costs >= 0 each
cell is expanded once and pushes at most 8 entries), so it does not grow.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from spcotmhp.metric._grid_kernels import _DC, _DR, _pop_fix, _push
from spcotmhp.planning._tree_codes import NO_LINK


@njit(cache=True)
def padded_window(cost, territory, t, r0, c0, r1, c1):  # pragma: no cover - numba
    """Territory ``t``'s window (r0, c0, r1, c1) of ``cost`` with a blocked (inf) border of one cell and every
    cell outside ``t`` blocked; and the number of its cells in ``t``."""
    h, w = r1 - r0, c1 - c0
    grid = np.full((h + 2) * (w + 2), np.inf)
    n = 0
    for i in range(h):
        for j in range(w):
            if territory[r0 + i, c0 + j] == t:
                grid[(i + 1) * (w + 2) + j + 1] = cost[r0 + i, c0 + j]
                n += 1
    return grid, n


@njit(cache=True, parallel=True)
def territory_fields(grid, h, w, n_cells, sources, codes, offsets, connectivity, diag):  # pragma: no cover
    """The field of every node of one territory: ``sources[n]`` its window cell, its codes written into
    ``codes[offsets[n] : offsets[n] + h * w]``; ``grid`` from :func:`padded_window`."""
    for n in prange(sources.shape[0]):
        _field(grid, h, w, n_cells, sources[n, 0], sources[n, 1], codes[offsets[n] : offsets[n] + h * w],
               connectivity, diag)  # fmt: skip


@njit(cache=True)
def _field(grid, h, w, n_cells, sr, sc, out, connectivity, diag):  # pragma: no cover - numba
    """One tree (module docstring) into ``out`` (h * w int8): grid_search's loop with ``reverse`` and
    ``MODE_FIELD``, ``corner_rule`` CORNER_NO_SQUEEZE, on the padded grid (width w + 2)."""
    W = w + 2
    n_nb = 8 if connectivity == 8 else 4
    out[:] = NO_LINK
    dist = np.full(grid.shape[0], np.inf)
    heap = np.empty((n_nb * n_cells + 16, 2), np.float64)
    src = (sr + 1) * W + sc + 1
    dist[src] = 0.0
    _push(heap, 0, 0.0, src)
    size = 1
    while size > 0:
        if size + n_nb > heap.shape[0]:  # only if a cost were negative (a cell expanded again): grow
            bigger = np.empty((2 * heap.shape[0], 2), np.float64)
            bigger[:size] = heap[:size]
            heap = bigger
        key_u = heap[0, 0]
        u = np.int64(heap[0, 1])
        size -= 1
        if size > 0:
            _pop_fix(heap, size)
        gu = dist[u]
        if key_u > gu:  # stale (lazy deletion), as grid_search
            continue
        ur = u // W
        uc = u - ur * W
        cu = grid[u]
        for k in range(n_nb):
            vr = ur + _DR[k]
            vc = uc + _DC[k]
            v = vr * W + vc
            if not grid[v] < np.inf:  # blocked, outside the territory or the border
                continue
            step = 1.0
            if k >= 4:
                step = diag
                if not grid[ur * W + vc] < np.inf and not grid[vr * W + uc] < np.inf:  # no squeeze
                    continue
            nd = gu + cu * step
            if nd < dist[v]:
                dist[v] = nd
                out[(vr - 1) * w + vc - 1] = (1 - _DR[k]) * 3 + (1 - _DC[k])  # the step from v back to u
                _push(heap, size, nd, v)
                size += 1

"""Numba kernels behind :mod:`spcotmhp.metric.grid_search`: one heap-based best-first search on a cost grid.

The single kernel :func:`grid_search` is Dijkstra when ``h_scale == 0`` and A* otherwise. It uses *lazy
deletion*: a cell is pushed again whenever its tentative cost strictly improves (its parent is updated at the
same moment), and an entry popped with a cost above the cell's current best is stale and skipped. No cell is
ever "closed" for good, so a better path found later (possible with floating-point heuristics) re-opens the
cell instead of being lost, which is exactly the parent-update bug of the reference implementation avoided.

Costs are per-cell, non-negative, additive (negative log-likelihoods); blocked cells are ``+inf``. A step
from ``u`` into a neighbour ``v`` costs ``cost[v] * step`` (forward) where ``step`` is 1 for orthogonal and
``diagonal_factor`` for diagonal moves. In *reverse* mode (cost-to-go fields) the same edge ``v -> u`` is
relaxed from the settled cell ``u``, so it costs ``cost[u] * step``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

CORNER_FREE = 0  # diagonal moves always allowed (pyastar2d's rule)
CORNER_NO_SQUEEZE = 1  # forbidden when BOTH orthogonal cells beside the move are blocked
CORNER_NO_CUT = 2  # forbidden when EITHER orthogonal cell beside the move is blocked

MODE_FIRST = 0  # stop when the first (cheapest) target is settled
MODE_ALL = 1  # stop when every target is settled
MODE_FIELD = 2  # settle every reachable cell

# Neighbour offsets: the 4 orthogonal moves first, then the 4 diagonal ones.
_DR = np.array([-1, 1, 0, 0, -1, -1, 1, 1], dtype=np.int64)
_DC = np.array([0, 0, -1, 1, -1, 1, -1, 1], dtype=np.int64)


# Children per heap node: a 4-ary heap is shallower than a binary one and as cache friendly. Entries are ordered
# by key alone; equal keys come out in no particular order. (Breaking ties towards the deeper entry, the usual
# A* refinement, saves expansions only on exact cost plateaus and made the bundled homes slower: docs/results.md.)
_ARITY = 4


@njit(cache=True, inline="always")
def _push(heap, size, key, node):
    """Insert (key, node) into the heap rows [0, size) (capacity checked by the caller); sift up."""
    i = size
    while i > 0:
        p = (i - 1) // _ARITY
        if not key < heap[p, 0]:
            break
        heap[i, 0] = heap[p, 0]
        heap[i, 1] = heap[p, 1]
        i = p
    heap[i, 0] = key
    heap[i, 1] = node


@njit(cache=True, inline="always")
def _pop_fix(heap, size):
    """After the top was taken and ``size`` rows remain: move the last row to the top and sift it down."""
    k = heap[size, 0]
    n = heap[size, 1]
    i = 0
    while True:
        c = _ARITY * i + 1
        if c >= size:
            break
        best = c
        for j in range(c + 1, min(c + _ARITY, size)):
            if heap[j, 0] < heap[best, 0]:
                best = j
        if not heap[best, 0] < k:
            break
        heap[i, 0] = heap[best, 0]
        heap[i, 1] = heap[best, 1]
        i = best
    heap[i, 0] = k
    heap[i, 1] = n


@njit(cache=True, inline="always")
def _heuristic(vr, vc, trow, tcol, connectivity, diag_extra, h_scale):
    """h(v) = h_scale * min_t L(v, t), L the obstacle-free lattice distance (octile or Manhattan)."""
    best = np.inf
    for t in range(trow.shape[0]):
        dr = abs(vr - trow[t])
        dc = abs(vc - tcol[t])
        if connectivity == 4:
            d = float(dr + dc)
        else:
            d = float(max(dr, dc)) + diag_extra * min(dr, dc)
        best = min(best, d)
    return h_scale * best


@njit(cache=True)
def grid_search(cost, sources, targets, connectivity, diagonal_factor, corner_rule, reverse, mode, h_scale):
    """Best-first search from ``sources`` ((K, 2) int64 cells, all at cost 0) over a C-contiguous cost grid.

    Returns ``(dist, parent, found)``: ``dist`` (H*W,) float64 best costs (``inf`` where not reached; exact on
    settled cells), ``parent`` (H*W,) int32 the previous cell on the best path (the next cell towards the
    sources in reverse mode; -1 at sources and unreached cells), ``found`` the flat index of the settled target
    in ``MODE_FIRST`` (-1 if none is reachable). ``h_scale`` > 0 enables the A* heuristic towards ``targets``
    in ``MODE_FIRST``. Heap rows are (key, node); node indices are exact in float64 below 2**53.
    """
    height, width = cost.shape
    N = height * width
    dist = np.full(N, np.inf)
    parent = np.full(N, -1, np.int32)  # int32 halves the memory to initialise; the caller checks H*W < 2**31
    is_target = np.zeros(N if mode != MODE_FIELD else 0, np.bool_)
    remaining = 0
    for t in range(targets.shape[0] if mode != MODE_FIELD else 0):
        idx = targets[t, 0] * width + targets[t, 1]
        if not is_target[idx]:
            is_target[idx] = True
            remaining += 1
    trow = targets[:, 0].copy()
    tcol = targets[:, 1].copy()
    diag_extra = min(diagonal_factor, 2.0) - 1.0
    use_h = h_scale > 0.0 and mode == MODE_FIRST and targets.shape[0] > 0
    heap = np.empty((max(4096, 2 * sources.shape[0] + 16), 2), np.float64)
    size = 0
    for s in range(sources.shape[0]):
        idx = sources[s, 0] * width + sources[s, 1]
        if dist[idx] > 0.0:
            dist[idx] = 0.0
            key = 0.0
            if use_h:
                key = _heuristic(sources[s, 0], sources[s, 1], trow, tcol, connectivity, diag_extra, h_scale)
            _push(heap, size, key, idx)
            size += 1
    found = -1
    while True:
        # The search loop never rebinds its heap (which would keep numba from holding it in registers): it
        # returns when the heap might overflow, and resumes here on a heap twice as large.
        size, remaining, found, full = _search_loop(
            heap,
            size,
            cost.ravel(),
            height,
            width,
            dist,
            parent,
            is_target,
            remaining,
            trow,
            tcol,
            connectivity,
            diagonal_factor,
            diag_extra,
            corner_rule,
            reverse,
            mode,
            use_h,
            h_scale,
        )
        if not full:
            return dist, parent, found
        bigger = np.empty((2 * heap.shape[0], 2), np.float64)
        bigger[:size] = heap[:size]
        heap = bigger


@njit(cache=True)
def _search_loop(
    heap,
    size,
    flat,
    height,
    width,
    dist,
    parent,
    is_target,
    remaining,
    trow,
    tcol,
    connectivity,
    diagonal_factor,
    diag_extra,
    corner_rule,
    reverse,
    mode,
    use_h,
    h_scale,
):
    """Pop and expand until done, or until the heap has no room for one more expansion (``full``)."""
    n_nb = 8 if connectivity == 8 else 4
    found = -1
    while size > 0:
        if size + n_nb > heap.shape[0]:
            return size, remaining, found, True
        key_u = heap[0, 0]
        u = np.int64(heap[0, 1])
        size -= 1
        if size > 0:
            _pop_fix(heap, size)
        ur = u // width
        uc = u - ur * width
        gu = dist[u]
        # Stale entry (lazy deletion): a cheaper path to u was pushed after this one. The current entry's key
        # was computed as dist[u] + h(u) with the same operands, so the comparison is exact.
        if use_h:
            if key_u > gu + _heuristic(ur, uc, trow, tcol, connectivity, diag_extra, h_scale):
                continue
        elif key_u > gu:
            continue
        if mode == MODE_FIRST:
            if is_target[u]:
                found = int(u)
                break
        elif mode == MODE_ALL and is_target[u]:
            is_target[u] = False
            remaining -= 1
            if remaining == 0:
                break
        cu = flat[u]
        for k in range(n_nb):
            vr = ur + _DR[k]
            vc = uc + _DC[k]
            if vr < 0 or vr >= height or vc < 0 or vc >= width:
                continue
            v = vr * width + vc
            cv = flat[v]
            if not cv < np.inf:
                continue
            step = 1.0
            if k >= 4:
                step = diagonal_factor
                if corner_rule != CORNER_FREE:
                    b1 = not flat[ur * width + vc] < np.inf
                    b2 = not flat[vr * width + uc] < np.inf
                    if corner_rule == CORNER_NO_SQUEEZE:
                        if b1 and b2:
                            continue
                    elif b1 or b2:
                        continue
            nd = gu + (cu if reverse else cv) * step
            if nd < dist[v]:
                dist[v] = nd
                parent[v] = u
                key = nd
                if use_h:
                    key += _heuristic(vr, vc, trow, tcol, connectivity, diag_extra, h_scale)
                _push(heap, size, key, v)
                size += 1
    return size, remaining, found, False


@njit(cache=True)
def first_invalid(cells, grid, check_blocked):
    """(index, reason) of the first of ``cells`` off ``grid`` (reason 1) or, if asked, blocked there (reason 2:
    the value is not finite); (-1, 0) when all are valid."""
    height, width = grid.shape
    for i in range(cells.shape[0]):
        r = cells[i, 0]
        c = cells[i, 1]
        if r < 0 or r >= height or c < 0 or c >= width:
            return i, 1
        if check_blocked and not np.isfinite(grid[r, c]):
            return i, 2
    return -1, 0


@njit(cache=True)
def follow_links(links, first, width, backwards):
    """The chain ``first, links[first], ...`` up to (and including) the cell whose link is -1.

    Returns ``(cells, n_diagonal)``: (n, 2) int64 (row, col), in chain order or, if ``backwards``, reversed
    (a parent chain read from the target gives the path from the start); and the number of diagonal steps.
    """
    n = 1
    v = first
    while links[v] >= 0 and n <= links.shape[0]:
        v = links[v]
        n += 1
    out = np.empty((n, 2), np.int64)
    v = first
    n_diagonal = 0
    prev_r = -1
    prev_c = -1
    for i in range(n):
        j = n - 1 - i if backwards else i
        out[j, 0] = v // width
        out[j, 1] = v - out[j, 0] * width
        if i > 0 and out[j, 0] != prev_r and out[j, 1] != prev_c:
            n_diagonal += 1
        prev_r = out[j, 0]
        prev_c = out[j, 1]
        v = links[v]
    return out, n_diagonal

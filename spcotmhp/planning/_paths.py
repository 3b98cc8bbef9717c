"""Compiled kernels of the online path (Algorithm 1, lines 12-13): lengths and costs of cell paths, the
comparison that decides whether a smoothed piece replaces the old one, and the exact re-planning of a piece
read from a precomputed cost-to-go field when that field's path stays inside the piece's tube.

Why the field read is exact: every cost-to-go field of the planning graph uses the map-only step cost of Eq. 26,
``log|A| - log p(x|m)`` (:mod:`spcotmhp.planning.graph`), which is also the cost the tube re-planning of
:func:`spcotmhp.planning.assemble.replan_segment` minimises. The field's path from a piece's first cell into the
node at its end is the cheapest one over the whole free space; if every cell of it is allowed in the restricted
search (inside the tube and its window, and every diagonal step has an allowed side cell, so the corner rule
"no squeeze" admits it there too), the restricted search's optimum has the same cost, so the field path is an
answer of that search, read in O(path length) instead of a grid search. Otherwise the caller runs the search.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from spcotmhp.metric._grid_kernels import follow_links
from spcotmhp.planning.sight import shortcut

SQRT2 = math.sqrt(2.0)


@njit(cache=True)
def octile_length(cells):  # pragma: no cover - numba
    """Length in cells of an 8-connected cell path (steps 1 or sqrt 2)."""
    total = 0.0
    for k in range(1, cells.shape[0]):
        d = abs(cells[k, 0] - cells[k - 1, 0]) + abs(cells[k, 1] - cells[k - 1, 1])
        if d == 1:
            total += 1.0
        elif d == 2:
            total += SQRT2
    return total


@njit(cache=True)
def cells_cost(cells, cost):  # pragma: no cover - numba
    """Sum of the step costs of an 8-connected path: entering cell v costs ``cost[v]`` times the step length
    (1 or sqrt 2); the first cell is not counted."""
    total = 0.0
    for k in range(1, cells.shape[0]):
        d = abs(cells[k, 0] - cells[k - 1, 0]) + abs(cells[k, 1] - cells[k - 1, 1])
        c = cost[cells[k, 0], cells[k, 1]]
        total += c * SQRT2 if d == 2 else c
    return total


@njit(cache=True)
def is_better(new, old, cost):  # pragma: no cover - numba
    """Whether ``new`` is strictly shorter than ``old``, or as long and no costlier under ``cost``."""
    a = octile_length(new)
    b = octile_length(old)
    return a < b - 1e-9 or (a <= b + 1e-9 and cells_cost(new, cost) <= cells_cost(old, cost) + 1e-9)


@njit(cache=True, inline="always")
def _allowed(r, c, territory, places, lo0, lo1, hi0, hi1):  # pragma: no cover - numba
    if r < lo0 or r >= hi0 or c < lo1 or c >= hi1:
        return False
    k = territory[r, c]
    return k >= 0 and k < places.shape[0] and places[k]


@njit(cache=True)
def field_path_within(links, first, width, territory, places, lo0, lo1, hi0, hi1, cost):  # pragma: no cover
    """The chain ``first, links[first], ...`` (a cost-to-go field's path; -1 ends it) as (n, 2) cells, and
    whether every cell lies in a territory flagged in ``places`` inside rows lo0..hi0, cols lo1..hi1 (and every
    diagonal step has such a side cell of finite ``cost``): the module docstring's condition for the path to be
    an answer of the tube re-planning."""
    out, _ = follow_links(links, first, width, False)
    for i in range(out.shape[0]):
        r = out[i, 0]
        c = out[i, 1]
        if not _allowed(r, c, territory, places, lo0, lo1, hi0, hi1):
            return out, False
        if i > 0 and out[i - 1, 0] != r and out[i - 1, 1] != c:
            pr = out[i - 1, 0]
            pc = out[i - 1, 1]
            side_a = _allowed(pr, c, territory, places, lo0, lo1, hi0, hi1) and np.isfinite(cost[pr, c])
            side_b = _allowed(r, pc, territory, places, lo0, lo1, hi0, hi1) and np.isfinite(cost[r, pc])
            if not (side_a or side_b):
                return out, False
    return out, True


@njit(cache=True)
def crosses(links, start, blocked):  # pragma: no cover - numba
    """Whether the path that follows ``links`` (flat next-step indices, -1 at the end) from ``start`` enters a
    blocked cell."""
    i = start
    while i >= 0:
        if blocked[i]:
            return True
        i = links[i]
    return False


@njit(cache=True)
def territory_sequence(territory, cells, min_dwell):  # pragma: no cover - numba
    """The places a cell path drives through, in order: the runs of equal ``territory`` along ``cells``, runs
    shorter than ``min_dwell`` cells dropped, cells of no territory (-1) left out, consecutive duplicates
    collapsed (``dwell_filtered_sequence`` of the labels, then of its non-negative entries with a dwell of 1)."""
    n = cells.shape[0]
    out = np.empty(n, np.int64)
    m = 0
    i = 0
    while i < n:
        label = territory[cells[i, 0], cells[i, 1]]
        j = i + 1
        while j < n and territory[cells[j, 0], cells[j, 1]] == label:
            j += 1
        if j - i >= min_dwell and label >= 0 and (m == 0 or out[m - 1] != label):
            out[m] = label
            m += 1
        i = j
    return out[:m].copy()


@njit(cache=True)
def shortcut_if_better(cells, clearance, fixed, four, cost):  # pragma: no cover - numba
    """:func:`~spcotmhp.planning.sight.shortcut` of ``cells`` and whether it :func:`is_better` than ``cells``
    under ``cost``, in one call."""
    out, ends = shortcut(cells, clearance, fixed, four)
    return out, ends, is_better(out, cells, cost)


@njit(cache=True)
def start_legs(dist, r, c, usable, end_term):  # pragma: no cover - numba
    """(M,) end_term[j] - dist[j, r, c] (in float64) for the usable nodes, -inf for the others: the start legs'
    w-hat from crop cell (r, c) on dense fields (``PlanningGraph.start_w_hat``'s np.where, in one pass)."""
    M = end_term.shape[0]
    out = np.empty(M)
    for j in range(M):
        out[j] = end_term[j] - np.float64(dist[j, r, c]) if usable[j] else -np.inf
    return out


@njit(cache=True)
def last_territory(territory, cells):  # pragma: no cover - numba
    """The territory of the last cell of ``cells`` that lies in one (-1: none does)."""
    for i in range(cells.shape[0] - 1, -1, -1):
        label = territory[cells[i, 0], cells[i, 1]]
        if label >= 0:
            return label
    return -1


@njit(cache=True)
def path_territories(territory, cells, min_dwell):  # pragma: no cover - numba
    """:func:`territory_sequence` and :func:`last_territory` of one path, in one call."""
    return territory_sequence(territory, cells, min_dwell), last_territory(territory, cells)


@njit(cache=True)
def piece_places(territory, cells, a, b, ends, node_place, n_places):  # pragma: no cover - numba
    """The sorted distinct places of the tube of the piece ``cells[a:b + 1]``: the territories of its cells (-1:
    none) and the places of the nodes reached in it (``ends[e]``, the index where node e, of place
    ``node_place[e]``, is reached)."""
    seen = np.zeros(n_places + 1, np.bool_)
    for i in range(a, b + 1):
        seen[territory[cells[i, 0], cells[i, 1]] + 1] = True
    for e in range(ends.shape[0]):
        if a <= ends[e] <= b:
            seen[node_place[e] + 1] = True
    return np.flatnonzero(seen) - 1


@njit(cache=True)
def crossing_fields(dist, links, fields, r, c, blocked):  # pragma: no cover - numba
    """Of the nodes ``fields`` (indices into the (M, h, w) cost-to-go fields ``dist`` and their next-step links
    ``links``, flat indices, -1 at the end), those whose field is finite at cell (r, c) and whose path from there
    enters a cell where ``blocked`` (h, w) holds (:func:`crosses` for each, in one call)."""
    width = dist.shape[2]
    out = np.empty(fields.shape[0], np.int64)
    m = 0
    for f in fields:
        if not np.isfinite(dist[f, r, c]):
            continue
        i = r * width + c
        while i >= 0:
            row = i // width
            col = i - row * width
            if blocked[row, col]:
                out[m] = f
                m += 1
                break
            i = links[f, row, col]
    return out[:m].copy()


@njit(cache=True)
def _chain_length(links, node, first, width):  # pragma: no cover - numba
    """The number of cells of the chain ``first, links[node][first], ...`` (-1 ends it)."""
    n = 0
    i = first
    while i >= 0:
        n += 1
        i = links[node, i // width, i % width]
    return n


@njit(cache=True)
def _chain_write(links, node, first, width, out, k, skip_first):  # pragma: no cover - numba
    """Write the cells of that chain (without its first one if ``skip_first``) into out[k:]; returns the new k."""
    i = first
    skip = skip_first
    while i >= 0:
        if not skip:
            out[k, 0] = i // width
            out[k, 1] = i % width
            k += 1
        skip = False
        i = links[node, i // width, i % width]
    return k


@njit(cache=True)
def join_field_legs(dist, links, first, nodes, node_cells):  # pragma: no cover - numba
    """Algorithm 1, line 12 on dense fields (``dist``, ``links``: (M, h, w) cost-to-go fields and their next-step
    links, flat indices): the start leg from flat cell ``first`` into ``nodes[0]``, then the partial path from each
    node's cell (``node_cells``, flat) into the next, joined at their shared junction cells as ``join_legs`` joins
    them. Returns the cells, the index where each node is reached, and the index of the first leg that cannot be
    followed (an infinite field value where it starts), -1 when none."""
    width = dist.shape[2]
    n = nodes.shape[0]
    starts = np.empty(n, np.int64)
    starts[0] = first
    for e in range(1, n):
        starts[e] = node_cells[nodes[e - 1]]
    total = 0
    for e in range(n):
        s = starts[e]
        if not np.isfinite(dist[nodes[e], s // width, s % width]):
            return np.empty((0, 2), np.int64), np.empty(0, np.int64), e
        total += _chain_length(links, nodes[e], s, width)
    out = np.empty((total, 2), np.int64)
    ends = np.empty(n, np.int64)
    k = 0
    for e in range(n):
        s = starts[e]
        junction = e > 0 and k > 0 and out[k - 1, 0] == s // width and out[k - 1, 1] == s % width
        k = _chain_write(links, nodes[e], s, width, out, k, junction)
        ends[e] = k - 1
    return out[:k].copy(), ends, -1

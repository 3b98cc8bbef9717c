"""Path assembly and smoothing (Algorithm 1, lines 12-13).

Line 12 joins the start leg and the partial paths of Eq. 27 into one cell path (:func:`join_legs`). Each partial
path runs to the candidate point (the centre) of its place, so the joined path zig-zags through the centre of
every place it passes on its way to a waypoint or the goal, and line-of-sight shortcuts alone cannot bend round
a door corner that the path does not touch (docs/results.md gives a measured case). Line 13,
Path_Smoothing(x, m), is optional in the paper (a moving average there, with no collision check); here it is
two steps that never lengthen the path and never give up a guarantee of the plan (:func:`smooth_on_graph`):

1. **Re-planning in a tube** (:func:`shorten`). The path is cut at its *anchors*, the cells where a stage of
   the instruction is completed (each waypoint's candidate point, then the goal's), so every waypoint place is
   still passed in order. Each piece between two anchors is planned again, exactly (grid A*,
   :func:`~spcotmhp.metric.grid_search.shortest_paths`), under the map term of Eq. 26 alone,
   ``c(x) = log|A| - log p(x|m)`` (the cost map keeps the path off walls), restricted to a *tube*: the
   territories (:mod:`spcotmhp.learning.territory`) of
   the places the piece runs through and of the places of its nodes, grown by ``tube_margin``, plus the
   piece's own cells and their neighbours (so the original piece, diagonal steps included, is always a
   feasible answer). The tube keeps the path on the route that Eq. 28 chose, not through other rooms. Blocked
   cells (occupied, lethal, unknown, an avoided place's region) cost +inf. The new piece replaces the old one
   only if it is strictly shorter, or as long and no costlier (:func:`better`).
2. **Line-of-sight shortcuts** (:func:`smooth`) between the same anchors: from each kept cell, jump to the
   farthest visible cell of the piece, where

   * a shortcut from cell a to cell b is taken only if every cell the straight segment between their centres
     touches (its *supercover*, corner crossings counting both side cells) is traversable (p(x|m) > 0: not
     occupied, unknown, lethal or inscribed, so the robot's footprint stays clear) and outside avoided regions;
   * the shortcut is drawn as the Bresenham line, whose cells are a subset of that supercover and whose
     length is the octile distance between a and b, the shortest 8-connected length, so a shortcut never
     lengthens the path and a diagonal step never squeezes between two blocked cells; a 4-connected planner
     (``connectivity=4``) draws the 4-connected line instead (the supercover walk taking one side cell at each
     corner), of Manhattan length, the shortest 4-connected one, so its paths keep no diagonal step;
   * the shortcut path is kept if it is :func:`better` than the re-planned one (a same-length shortcut that
     runs closer to the walls is not). Shortcuts of the assembled path itself are tried too, and the better
     of the two results is kept: the re-planned path keeps off the walls, so on long straight corridors (a
     generated 100 m office) shortcuts of the assembled path are occasionally a little shorter.

Optionally the path then stops at its *arrival* in the goal place (:func:`arrival`): the first cell after
the last waypoint anchor that lies in the goal place's region at a given quantile (inside its ellipse and
most probable there), rather than at the goal's candidate point.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence

import numpy as np

from spcotmhp.metric.grid_search import shortest_paths
from spcotmhp.planning._paths import cells_cost, is_better, octile_length, piece_places, shortcut_if_better
from spcotmhp.planning.sight import chessboard_clearance, shortcut

_AROUND = np.array([(dr, dc) for dr in (-1, 0, 1) for dc in (-1, 0, 1)], dtype=np.int64)


def join_legs(legs: list[np.ndarray]) -> tuple[np.ndarray, list[int]]:
    """Concatenate cell paths that share their junction cells; returns the path and the index of each leg's
    last cell in it."""
    parts: list[np.ndarray] = []
    ends: list[int] = []
    n = 0
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
    return float(resolution * octile_length(np.ascontiguousarray(cells, dtype=np.int64).reshape(-1, 2)))


def replan_segment(
    cells: np.ndarray, cost: np.ndarray, origin: np.ndarray, tube: np.ndarray, connectivity: int = 8
) -> np.ndarray:
    """Re-plan the piece ``cells`` (grid cells, both ends kept) by exact A* on ``cost`` (+inf blocked)
    restricted to the cells where ``tube`` (a window of the grid with its corner at ``origin``) is True, the
    piece's own cells and their 8-neighbours added; returns the new piece if it is :func:`better` (the search
    never returns a costlier one, so: no longer), else ``cells`` unchanged.

    The window is cut to the square of half-side length / 2 around the middle of the piece's ends a, b (length:
    the piece's length in cells): a path through a cell x outside it has |x - a| + |x - b| > length, so it is
    longer than the piece (a path is at least as long as the straight lines through its cells) and could never
    be accepted."""
    cells = np.asarray(cells, dtype=np.int64)
    if len(cells) < 3:
        return cells
    origin = np.asarray(origin, dtype=np.int64)
    a, b, length = cells[0], cells[-1], path_length(cells, 1.0)
    reach_lo = np.floor((a + b) / 2 - length / 2).astype(np.int64)  # the ellipse lies in this square
    reach_hi = np.ceil((a + b) / 2 + length / 2).astype(np.int64) + 1
    lo = np.maximum(np.minimum(np.maximum(origin, reach_lo), cells.min(axis=0) - 1), 0)
    hi = np.minimum(np.maximum(np.minimum(origin + tube.shape, reach_hi), cells.max(axis=0) + 2), cost.shape)
    window = cost[lo[0] : hi[0], lo[1] : hi[1]]
    allowed = np.zeros(window.shape, dtype=bool)
    t0, t1 = np.maximum(lo - origin, 0), np.minimum(hi - origin, tube.shape)
    if (t1 > t0).all():
        w0 = origin + t0 - lo
        allowed[w0[0] : w0[0] + t1[0] - t0[0], w0[1] : w0[1] + t1[1] - t0[1]] = tube[t0[0] : t1[0], t0[1] : t1[1]]
    near = (cells[:, None, :] - lo + _AROUND[None]).reshape(-1, 2)
    near = near[(near >= 0).all(axis=1) & (near < window.shape).all(axis=1)]
    allowed[near[:, 0], near[:, 1]] = True
    found = shortest_paths(np.where(allowed, window, np.inf), cells[0] - lo, (cells[-1] - lo)[None], connectivity)
    if found is None:
        return cells
    new = found.cells + lo
    return new if better(new, cells, cost) else cells


def shorten(
    cells: np.ndarray,
    anchors: Sequence[int],
    tube: Callable[[int, int], tuple[np.ndarray, np.ndarray]],
    cost: np.ndarray,
    connectivity: int = 8,
    exact: Callable[[int, int], np.ndarray | None] | None = None,
) -> tuple[np.ndarray, list[int]]:
    """Step 1 of the module docstring: re-plan every piece between consecutive anchors (indices into ``cells``;
    the first and last cells are anchors too) with :func:`replan_segment`; ``tube(a, b)`` gives the
    ``(origin, mask)`` of the piece ``cells[a:b + 1]``. ``exact(a, b)``, when given, may return an answer of
    that re-planning found without a search (:mod:`spcotmhp.planning._paths`), or None. Returns the new path
    and the new index of each anchor."""
    cells = np.asarray(cells, dtype=np.int64)
    bounds = sorted({0, len(cells) - 1, *(int(a) for a in anchors)})
    pieces, where, n = [cells[:1]], {0: 0}, 1
    for a, b in itertools.pairwise(bounds):
        old = cells[a : b + 1]
        found = exact(a, b) if exact is not None and len(old) >= 3 else None
        if found is None:
            piece = replan_segment(old, cost, *tube(a, b), connectivity)
        else:
            piece = found if better(found, old, cost) else old
        pieces.append(piece[1:])
        n += len(piece) - 1
        where[b] = n - 1
    return np.concatenate(pieces), [where[int(a)] for a in anchors]


def arrival(cells: np.ndarray, inside: np.ndarray, first: int = 0) -> int:
    """Index of the first cell at or after ``first`` where ``inside`` (a bool per cell) holds; the last index
    if there is none."""
    hits = np.flatnonzero(np.asarray(inside)[first:])
    return first + int(hits[0]) if len(hits) else len(cells) - 1


def path_cost(cells: np.ndarray, cost: np.ndarray) -> float:
    """Sum of the step costs of an 8-connected cell path under the grid search's move model: entering cell v
    costs ``cost[v]`` times the step length (1 or sqrt 2); the first cell is not counted."""
    return float(cells_cost(np.ascontiguousarray(cells, dtype=np.int64).reshape(-1, 2), cost))


def better(new: np.ndarray, old: np.ndarray, cost: np.ndarray) -> bool:
    """Whether ``new`` is strictly shorter than ``old``, or as long and no costlier under ``cost``."""
    return bool(
        is_better(
            np.ascontiguousarray(new, dtype=np.int64).reshape(-1, 2),
            np.ascontiguousarray(old, dtype=np.int64).reshape(-1, 2),
            cost,
        )
    )


def smooth(cells: np.ndarray, allowed: np.ndarray, anchors: list[int], connectivity: int = 8) -> np.ndarray:
    """Line-of-sight shortcutting between consecutive ``anchors`` (indices into ``cells``, kept fixed); the
    shortcuts are ``connectivity``-connected lines (4 or 8, as the path)."""
    return smooth_anchored(cells, allowed, anchors, connectivity)[0]


def smooth_anchored(
    cells: np.ndarray,
    allowed: np.ndarray,
    anchors: Sequence[int],
    connectivity: int = 8,
    clearance: np.ndarray | None = None,
    cost: np.ndarray | None = None,
) -> tuple[np.ndarray, list[int]]:
    """:func:`smooth`, also returning the new index of each anchor; ``clearance``:
    :func:`~spcotmhp.planning.sight.chessboard_clearance` of ``allowed`` when already at hand (the shortcuts are
    the same with or without it; it is computed when not given). With ``cost``, the shortcuts are kept only if
    :func:`better` under it (checked in the same kernel call), else ``cells`` and ``anchors`` come back."""
    if connectivity not in (4, 8):
        raise ValueError(f"connectivity must be 4 or 8, got {connectivity!r}")
    cells = np.ascontiguousarray(cells, dtype=np.int64)
    if len(cells) < 3:
        return cells, [int(a) for a in anchors]
    last = len(cells) - 1
    kept = [min(max(int(a), 0), last) for a in anchors]
    fixed = sorted({0, last, *kept})
    if clearance is None:
        clearance = chessboard_clearance(allowed)
    fixed_arr = np.array(fixed, dtype=np.int64)
    if cost is None:
        out, ends = shortcut(cells, clearance, fixed_arr, connectivity == 4)
    else:
        out, ends, kept_it = shortcut_if_better(cells, clearance, fixed_arr, connectivity == 4, cost)
        if not kept_it:
            return cells, [int(a) for a in anchors]
    where = dict(zip(fixed, ends.tolist(), strict=True))
    return out, [where[a] for a in kept]


def smooth_on_graph(
    graph, cells: np.ndarray, ends: Sequence[int], nodes: Sequence[int] | np.ndarray, anchors: Sequence[int]
) -> tuple[np.ndarray, list[int]]:
    """Algorithm 1, line 13, on a path assembled from a planning graph's legs (``graph``: a
    :class:`~spcotmhp.planning.graph.PlanningGraph`): ``ends[e]`` is the index where node ``nodes[e]`` is
    reached, ``anchors`` the indices where a stage is completed (kept). Each piece between anchors is re-planned
    inside the territories it runs through (:func:`shorten`; the end node's field is read instead of searching
    wherever it is an optimum there, ``PlanningGraph.field_piece``; a piece that is one leg is already that
    field's path, so a path of such pieces skips this step), then line-of-sight shortcuts
    (:func:`smooth_anchored`) of the re-planned path and of the assembled one, each kept only if :func:`better`.
    Returns the cells and the new anchor indices. The one implementation SpCoTMHP and the smoothed baselines
    use."""
    raw = np.ascontiguousarray(cells, dtype=np.int64)
    connectivity = graph.settings.connectivity

    def shortcut(path: np.ndarray, marks: list[int]) -> tuple[np.ndarray, list[int]]:  # kept only if better
        return smooth_anchored(path, graph.traversable, marks, connectivity, graph.clearance, graph.map_cost)

    marks = [int(a) for a in anchors]
    ends_list = ends.tolist() if isinstance(ends, np.ndarray) else [int(e) for e in ends]
    if {0, len(raw) - 1, *marks}.issuperset(ends_list):
        return shortcut(raw, marks)  # every piece is one leg, already a field's path (shorten keeps it as is)
    ends_arr = np.asarray(ends_list, dtype=np.int64)
    nodes = np.asarray(nodes, dtype=np.int64)
    node_place = graph.node_place[nodes]
    n_places = int(graph.model.K)

    found: dict[tuple[int, int], np.ndarray] = {}

    def places(a: int, b: int) -> np.ndarray:
        if (a, b) not in found:
            found[(a, b)] = piece_places(graph.territory, raw, a, b, ends_arr, node_place, n_places)
        return found[(a, b)]

    def tube(a: int, b: int) -> tuple[np.ndarray, np.ndarray]:
        return graph.tube(places(a, b))

    def exact(a: int, b: int) -> np.ndarray | None:
        return graph.field_piece(raw, a, b, ends_arr, nodes, places(a, b))

    # line-of-sight shortcuts on the re-planned path and on the assembled one: the re-planned path keeps off the
    # walls, so shortcuts of the assembled one are occasionally shorter still
    path, moved = shorten(raw, marks, tube, graph.map_cost, connectivity, exact)
    direct = shortcut(raw, marks)
    if path.shape == raw.shape and np.array_equal(path, raw):  # nothing re-planned: the same shortcuts
        return direct
    replanned = shortcut(path, moved)
    return replanned if better(replanned[0], direct[0], graph.map_cost) else direct

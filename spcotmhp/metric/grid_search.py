"""Exact shortest paths on the metric grid with additive log costs (the paper's metric-level planner, Eq. 26).

Control as inference turns the path likelihood into a sum of per-step negative log-likelihoods: a step into cell
x costs ``c(x) = -log p(x|m) - log N(x | mu, Sigma) + log|A|`` (:func:`step_cost_map`; Taniguchi et al. 2024,
Eq. 26, and the reference implementation's step cost ``log 5 - log(p N)``). Costs are added, never densities
multiplied, so nothing underflows. Searches run in numba (:mod:`spcotmhp.metric._grid_kernels`).

Move model (shared by every function here):

* A step from ``u`` into a neighbour ``v`` costs ``cell_cost[v] * 1`` (orthogonal) or
  ``cell_cost[v] * diagonal_factor`` (diagonal, 8-connectivity only). The start cell is not counted; the
  reached target is. Cells with cost ``+inf`` are blocked.
* Corner rule (``corner_rule``): ``"no_squeeze"`` (default) forbids a diagonal move when *both* orthogonal cells
  beside it are blocked, so a path never slips between two blocked cells touching at a corner;
  ``"no_cut"`` forbids it when *either* is blocked (no wall corner is grazed); ``"free"`` allows every diagonal
  (pyastar2d's model).

A* heuristic (used by :func:`shortest_paths` for the nearest target): ``h(v) = c_min * min_t L(v, t)`` where
``c_min`` is the smallest cell cost on the grid and ``L`` the obstacle-free lattice distance: Manhattan
``|dr| + |dc|`` for 4-connectivity, octile ``max + (min(f, 2) - 1) * min`` of ``|dr|, |dc|`` for 8-connectivity
with ``f = diagonal_factor``. It is *admissible*: every step of length ``l`` (1 or f) costs at least
``c_min * l`` and any path to ``t`` has total length at least ``L(v, t)``. It is *consistent*: ``L`` is the
shortest-path metric of the obstacle-free lattice, so ``L(u, t) <= l(u, v) + L(v, t)`` (triangle inequality),
hence ``h(u) <= c_min * l(u, v) + h(v) <= cost(u -> v) + h(v)``, and a minimum over targets of consistent
heuristics is consistent (Hart, Nilsson and Raphael 1968; Pearl 1984, Sec. 3.2). The kernel also re-opens
cells whose cost improves, so the result stays optimal even under floating-point rounding.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal, overload

import numpy as np

from spcotmhp.errors import PlanningError
from spcotmhp.metric import _grid_kernels as _k

SQRT2 = math.sqrt(2.0)
CORNER_RULES = {"free": _k.CORNER_FREE, "no_squeeze": _k.CORNER_NO_SQUEEZE, "no_cut": _k.CORNER_NO_CUT}
# Above this many targets the O(T) heuristic per push costs more than it saves: plain Dijkstra instead.
_MAX_HEURISTIC_TARGETS = 32


class GridSearchError(PlanningError, ValueError):
    """Bad input to a grid search (cell off the grid or blocked, negative or NaN cost, bad option).

    A :class:`~spcotmhp.errors.PlanningError` (so the CLI reports it cleanly) and a :class:`ValueError`.
    """


@dataclass(frozen=True)
class GridPath:
    """One shortest path on the grid.

    Attributes:
        cells: (n, 2) int64 (row, col) from the start cell to the reached target inclusive.
        cost: sum of the step costs along the path (a negative log-likelihood; the start cell is not counted).
        length_m: Euclidean length in metres, ``resolution * sum`` of step lengths (1 or sqrt 2).
        target_index: index (into the requested targets / sources) of the target this path reaches.
    """

    cells: np.ndarray
    cost: float
    length_m: float
    target_index: int

    def world(self, occ_map: Any) -> np.ndarray:
        """(n, 2) map-frame (x, y) metres of the cell centres, via ``OccupancyMap.cell_to_world``."""
        return occ_map.cell_to_world(self.cells)


def step_cost_map(
    log_p: np.ndarray,
    log_density: np.ndarray | None = None,
    connectivity: int = 4,
    n_actions: int | None = None,
) -> np.ndarray:
    """Per-cell step cost ``c(x) = -log p(x|m) - log N(x|mu,Sigma) + log|A|`` (Eq. 26, control as inference).

    Args:
        log_p: (H, W) log p(x|m) of the probabilistic cost map; ``-inf`` marks blocked cells; must be <= 0.
        log_density: optional (H, W) log N(x | mu, Sigma) of the destination's Gaussian (omitted if None).
        connectivity: 4 or 8; sets the default number of actions ``|A|`` (5 or 9: the moves plus staying).
        n_actions: override ``|A|``.

    Returns:
        float64 (H, W) costs, ``+inf`` on blocked cells (log p = -inf, or log N = -inf).

    Raises:
        GridSearchError: bad shapes or values, or a negative finite cost (the Gaussian is so narrow that
            ``log N > log|A| - log p`` there), which Dijkstra and A* cannot handle.
    """
    connectivity = _check_connectivity(connectivity)
    if n_actions is None:
        n_actions = 5 if connectivity == 4 else 9
    if int(n_actions) != n_actions or n_actions < 1:
        raise GridSearchError(f"n_actions must be a positive integer, got {n_actions!r}")
    lp = _as_grid(log_p, "log_p")
    if np.isnan(lp).any() or (lp > 0).any():
        bad = np.argwhere(np.isnan(lp) | (lp > 0))[0]
        raise GridSearchError(
            f"log_p must be a log-probability (<= 0, -inf for blocked cells); cell (row, col) = "
            f"({bad[0]}, {bad[1]}) holds {float(lp[tuple(bad)])!r}"
        )
    cost = -lp + math.log(n_actions)
    if log_density is not None:
        ld = _as_grid(log_density, "log_density")
        if ld.shape != lp.shape:
            raise GridSearchError(f"log_density has shape {ld.shape} but log_p has shape {lp.shape}")
        if np.isnan(ld).any() or (ld == np.inf).any():
            bad = np.argwhere(np.isnan(ld) | (ld == np.inf))[0]
            raise GridSearchError(
                f"log_density must be finite or -inf; cell (row, col) = ({bad[0]}, {bad[1]}) holds "
                f"{float(ld[tuple(bad)])!r}"
            )
        cost = cost - ld
    cost[~np.isfinite(lp)] = np.inf
    negative = cost < 0
    if negative.any():
        cells = np.argwhere(negative)
        r, c = cells[0]
        why = f"-log p = {-lp[r, c]:.4g}" + (f", -log N = {-ld[r, c]:.4g}" if log_density is not None else "")
        raise GridSearchError(
            f"step cost is negative at {len(cells)} cell(s), first (row, col) = ({r}, {c}) with cost "
            f"{cost[r, c]:.4g} ({why}, log|A| = log {n_actions} = {math.log(n_actions):.4g}): the density "
            f"exceeds |A| there (a very narrow Gaussian); shortest-path search needs non-negative step costs, "
            f"so widen Sigma or raise n_actions"
        )
    return cost


Cell = tuple[int, int] | Sequence[int] | np.ndarray  # one (row, col)
Cells = np.ndarray | Sequence[Sequence[int]]  # (T, 2) cells


# the return type follows all_targets (one path or None; a list with one entry per target)
@overload
def shortest_paths(
    cell_cost: np.ndarray,
    start: Cell,
    targets: Cells | Cell,
    connectivity: int = ...,
    diagonal_factor: float = ...,
    resolution: float = ...,
    all_targets: Literal[False] = ...,
    *,
    corner_rule: str = ...,
    strict: bool = ...,
) -> GridPath | None: ...
@overload
def shortest_paths(
    cell_cost: np.ndarray,
    start: Cell,
    targets: Cells | Cell,
    connectivity: int = ...,
    diagonal_factor: float = ...,
    resolution: float = ...,
    *,
    all_targets: Literal[True],
    corner_rule: str = ...,
    strict: bool = ...,
) -> list[GridPath | None]: ...
def shortest_paths(
    cell_cost: np.ndarray,
    start: Cell,
    targets: Cells | Cell,
    connectivity: int = 8,
    diagonal_factor: float = SQRT2,
    resolution: float = 1.0,
    all_targets: bool = False,
    *,
    corner_rule: str = "no_squeeze",
    strict: bool = False,
) -> GridPath | list[GridPath | None] | None:
    """Cheapest path(s) from ``start`` to ``targets`` ((T, 2) cells, or one (row, col)).

    ``all_targets=False``: A* (heuristic in the module docstring) to the cheapest target; returns one
    :class:`GridPath` or None when no target is reachable. ``all_targets=True``: one Dijkstra run until every
    target is settled; returns a list with one path per target (None where unreachable). With ``strict=True``
    an unreachable target raises :class:`~spcotmhp.errors.PlanningError` instead. A start or target off the grid
    or in a blocked cell raises :class:`GridSearchError` naming the cell.

    >>> cost = np.ones((3, 4))
    >>> cost[1, 1:3] = np.inf                                    # a wall of two cells
    >>> path = shortest_paths(cost, (0, 0), [(2, 3)])
    >>> path.cells.tolist(), round(path.cost, 4)
    ([[0, 0], [0, 1], [0, 2], [1, 3], [2, 3]], 4.4142)
    """
    cost = _check_cost(cell_cost)
    connectivity, diagonal_factor, rule = _check_moves(connectivity, diagonal_factor, corner_rule)
    src = _check_cells(start, cost, "start")
    if len(src) != 1:
        raise GridSearchError(f"start must be one (row, col) cell, got {len(src)} cells")
    tgt = _check_cells(targets, cost, "target")
    if all_targets:
        dist, parent, _ = _k.grid_search(cost, src, tgt, connectivity, diagonal_factor, rule, False, _k.MODE_ALL, 0.0)
        paths: list[GridPath | None] = []
        for i, (r, c) in enumerate(tgt):
            end = r * cost.shape[1] + c
            paths.append(_forward_path(dist, parent, end, cost.shape[1], resolution, i))
        missing = [i for i, p in enumerate(paths) if p is None]
        if strict and missing:
            raise PlanningError(
                f"no path from start {_fmt(src[0])} to target(s) " + ", ".join(f"#{i} {_fmt(tgt[i])}" for i in missing)
            )
        return paths
    h_scale = float(cost.min()) if len(tgt) <= _MAX_HEURISTIC_TARGETS else 0.0
    dist, parent, found = _k.grid_search(
        cost, src, tgt, connectivity, diagonal_factor, rule, False, _k.MODE_FIRST, h_scale
    )
    if found < 0:
        if strict:
            raise PlanningError(f"no path from start {_fmt(src[0])} to any of {len(tgt)} target(s)")
        return None
    width = cost.shape[1]
    index = int(np.flatnonzero(tgt[:, 0] * width + tgt[:, 1] == found)[0])
    return _forward_path(dist, parent, found, width, resolution, index)


def cost_to_go(
    cell_cost: np.ndarray,
    sources: np.ndarray | Sequence[Sequence[int]],
    connectivity: int = 8,
    diagonal_factor: float = SQRT2,
    *,
    corner_rule: str = "no_squeeze",
) -> tuple[np.ndarray, np.ndarray]:
    """Cost from every cell to the cheapest of ``sources`` (same move model as :func:`shortest_paths`).

    Returns ``(field, next_step)``: ``field`` float64 (H, W) equals the cost of the best path *from* that cell
    into the sources (``inf`` where unreachable or blocked, 0 at sources); ``next_step`` int32 (H, W) the flat
    index of the next cell on that path (-1 at sources and unreachable cells). Read a path with
    :func:`path_from_field`.
    """
    cost = _check_cost(cell_cost)
    connectivity, diagonal_factor, rule = _check_moves(connectivity, diagonal_factor, corner_rule)
    src = _check_cells(sources, cost, "source")
    dist, nxt, _ = _k.grid_search(
        cost, src, np.empty((0, 2), np.int64), connectivity, diagonal_factor, rule, True, _k.MODE_FIELD, 0.0
    )
    return dist.reshape(cost.shape), nxt.reshape(cost.shape)


@overload
def path_from_field(
    field: np.ndarray,
    next_step: np.ndarray,
    start: Cell,
    sources: Cells | None = ...,
    resolution: float = ...,
    *,
    strict: Literal[True],
) -> GridPath: ...
@overload
def path_from_field(
    field: np.ndarray,
    next_step: np.ndarray,
    start: Cell,
    sources: Cells | None = ...,
    resolution: float = ...,
    *,
    strict: bool = ...,
) -> GridPath | None: ...
def path_from_field(
    field: np.ndarray,
    next_step: np.ndarray,
    start: tuple[int, int] | Sequence[int] | np.ndarray,
    sources: np.ndarray | Sequence[Sequence[int]] | None = None,
    resolution: float = 1.0,
    *,
    strict: bool = False,
) -> GridPath | None:
    """The best path from ``start`` to the sources of a :func:`cost_to_go` field, read in O(path length).

    ``target_index`` is the index of the reached cell in ``sources`` (-1 when ``sources`` is not given).
    Returns None (or raises PlanningError if ``strict``) when ``start`` cannot reach any source.
    """
    field = np.asarray(field)
    next_step = np.asarray(next_step)
    if field.shape != next_step.shape or field.ndim != 2:
        raise GridSearchError(f"field {field.shape} and next_step {next_step.shape} must be the same 2-D shape")
    s = _check_cells(start, field, "start", check_blocked=False)[0]
    if not np.isfinite(field[s[0], s[1]]):
        if strict:
            raise PlanningError(f"start cell {_fmt(s)} cannot reach any source (blocked or disconnected)")
        return None
    width = field.shape[1]
    if next_step.dtype not in (np.int32, np.int64):
        raise GridSearchError(f"next_step must hold int32 or int64 flat cell indices, got dtype {next_step.dtype}")
    links = np.ascontiguousarray(next_step).reshape(-1)
    cells, n_diagonal = _k.follow_links(links, int(s[0] * width + s[1]), width, False)
    index = -1
    if sources is not None:
        src = _check_cells(sources, field, "source", check_blocked=False)
        hit = np.flatnonzero((src == cells[-1]).all(axis=1))
        index = int(hit[0]) if len(hit) else -1
    return GridPath(cells, float(field[s[0], s[1]]), _length_m(len(cells), n_diagonal, resolution), index)


def geodesic_distance(
    free_mask: np.ndarray,
    sources: np.ndarray | Sequence[Sequence[int]],
    connectivity: int = 8,
    resolution: float = 1.0,
    *,
    corner_rule: str = "no_squeeze",
) -> np.ndarray:
    """Shortest free-space path length from every cell to the nearest source (steps 1 and sqrt 2, times
    ``resolution``); ``inf`` on blocked or unreachable cells."""
    free = np.asarray(free_mask, dtype=bool)
    unit = np.where(free, 1.0, np.inf)
    field, _ = cost_to_go(unit, sources, connectivity, SQRT2, corner_rule=corner_rule)
    return field * resolution


def warmup() -> None:
    """Compile (or load from numba's cache) every kernel variant, so later calls pay no JIT cost."""
    grid = np.ones((3, 3))
    for cost in (grid, grid.astype(np.float32)):
        shortest_paths(cost, (0, 0), [(2, 2)])
        shortest_paths(cost, (0, 0), [(2, 2)], all_targets=True)
        path_from_field(*cost_to_go(cost, [(2, 2)]), (0, 0))


def _forward_path(dist, parent, end, width, resolution, index) -> GridPath | None:
    if not np.isfinite(dist[end]):
        return None
    cells, n_diagonal = _k.follow_links(parent, int(end), width, True)
    return GridPath(cells, float(dist[end]), _length_m(len(cells), n_diagonal, resolution), index)


def _length_m(n_cells: int, n_diagonal: int, resolution: float) -> float:
    return float(resolution * ((n_cells - 1 - n_diagonal) + SQRT2 * n_diagonal))


def _fmt(cell: np.ndarray) -> str:
    return f"({int(cell[0])}, {int(cell[1])})"


def _as_grid(a: Any, name: str) -> np.ndarray:
    arr = np.asarray(a)
    if arr.ndim != 2 or arr.size == 0:
        raise GridSearchError(f"{name} must be a non-empty 2-D array (rows, cols), got shape {arr.shape}")
    if not (np.issubdtype(arr.dtype, np.floating) or np.issubdtype(arr.dtype, np.integer)):
        raise GridSearchError(f"{name} must hold numbers, got dtype {arr.dtype}")
    return arr.astype(np.float64)


def _check_cost(cell_cost: Any) -> np.ndarray:
    """float32/float64 C-contiguous cost grid with no NaN and no negative value."""
    arr = np.asarray(cell_cost)
    if arr.dtype not in (np.float32, np.float64):
        arr = _as_grid(arr, "cell_cost")
    elif arr.ndim != 2 or arr.size == 0:
        raise GridSearchError(f"cell_cost must be a non-empty 2-D array (rows, cols), got shape {arr.shape}")
    arr = np.ascontiguousarray(arr)
    if arr.size >= 2**31:
        raise GridSearchError(f"cell_cost has {arr.size} cells; at most 2**31 - 1 are supported")
    low = arr.min()  # NaN propagates through min, so one pass checks both
    if np.isnan(low) or low < 0:
        bad = np.argwhere(np.isnan(arr) | (arr < 0))[0]
        raise GridSearchError(
            f"cell_cost must be >= 0 (inf for blocked cells); cell (row, col) = ({bad[0]}, {bad[1]}) holds "
            f"{float(arr[bad[0], bad[1]])!r}"
        )
    return arr


def _check_connectivity(connectivity: Any) -> int:
    if connectivity not in (4, 8):
        raise GridSearchError(f"connectivity must be 4 or 8, got {connectivity!r}")
    return int(connectivity)


def _check_moves(connectivity: Any, diagonal_factor: Any, corner_rule: str) -> tuple[int, float, int]:
    connectivity = _check_connectivity(connectivity)
    f = float(diagonal_factor)
    if not (math.isfinite(f) and f >= 1.0):
        raise GridSearchError(f"diagonal_factor must be a finite number >= 1, got {diagonal_factor!r}")
    if corner_rule not in CORNER_RULES:
        raise GridSearchError(f"corner_rule must be one of {sorted(CORNER_RULES)}, got {corner_rule!r}")
    return connectivity, f, CORNER_RULES[corner_rule]


def _check_cells(cells: Any, grid: np.ndarray, what: str, check_blocked: bool = True) -> np.ndarray:
    """(K, 2) int64 cells inside ``grid`` (and not blocked there); one (row, col) pair is accepted too."""
    arr = np.asarray(cells)
    if arr.ndim == 1 and arr.shape[0] == 2:
        arr = arr[None, :]
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] == 0:
        raise GridSearchError(f"{what} cells must be (row, col) pairs, shape (n, 2) with n >= 1; got {arr.shape}")
    if arr.dtype.kind == "f" and not np.all(np.isfinite(arr) & (arr == np.round(arr))):
        raise GridSearchError(f"{what} cells must be integer (row, col) indices, got {arr.tolist()}")
    if arr.dtype.kind not in "iuf":
        raise GridSearchError(f"{what} cells must be integer (row, col) indices, got dtype {arr.dtype}")
    arr = np.ascontiguousarray(arr, dtype=np.int64)
    bad, reason = _k.first_invalid(arr, grid, check_blocked)
    if reason == 1:
        raise GridSearchError(
            f"{what} cell (row, col) = {_fmt(arr[bad])} is off the grid of {grid.shape[0]} rows x {grid.shape[1]} cols"
        )
    if reason == 2:
        raise GridSearchError(f"{what} cell (row, col) = {_fmt(arr[bad])} is blocked (cost inf)")
    return arr

"""The start of a plan (Algorithm 1, line 10's x_0): checked, located on the planning graph's grid, and, when it
lies within the robot's radius of an obstacle, the escape from it.

A start outside the map is :class:`~spcotmhp.errors.StartOutsideMap`; in an occupied or unknown cell, or in a
free region that no place reaches (:mod:`spcotmhp.planning.regions`) for a robot of this size,
:class:`~spcotmhp.errors.StartBlocked`. A start in any free region that holds places is planned from within that
region (:meth:`~spcotmhp.planning.graph.PlanningGraph.for_start`). A start that is free on the map but inscribed
in the cost map (the robot's footprint overlaps an obstacle there, so p(x|m) = 0) is allowed: the path first
leaves it along the shortest run of free cells to the nearest cell of a free region with places, and planning
starts there. Messages quote at most a short excerpt of a bad value.
"""

from __future__ import annotations

import math
import reprlib
from collections.abc import Sequence
from typing import Any

import numpy as np

from spcotmhp.errors import StartBlocked, StartOutsideMap
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.costmap import DEFAULT_COSTMAP
from spcotmhp.metric.grid_search import SQRT2, cost_to_go, path_from_field
from spcotmhp.planning.graph import PlanningGraph

__all__ = ["locate_start", "start_cell", "start_point"]
NUMBER = (int, float, np.integer, np.floating)  # a coordinate's accepted types (a bool is not a number here)


def start_point(start: Any) -> np.ndarray:
    """x_0 as two floats: a list, tuple or numpy array of two finite real numbers (Python or numpy ints and
    floats), as the HTTP API takes them (a JSON number, never a string or true/false); else StartOutsideMap.
    ``["1", "2"]`` and ``(True, False)`` are refused, not converted.

    >>> start_point((1, 2.5)).tolist()
    [1.0, 2.5]
    """
    if isinstance(start, np.ndarray) and start.dtype.kind in "iuf" and start.shape == (2,):
        x0 = start.astype(float)  # numbers by their type: only finiteness is left to check
        if math.isfinite(x0[0]) and math.isfinite(x0[1]):
            return x0
    if isinstance(start, np.ndarray):
        values = start.reshape(-1).tolist() if start.dtype.kind in "iuf" else None
    elif isinstance(start, (list, tuple)):
        values = list(start)
    else:
        values = None
    if values is None or not all(isinstance(v, NUMBER) and not isinstance(v, (bool, np.bool_)) for v in values):
        kinds = sorted({type(v).__name__ for v in values or ()} - {"int", "float", "float64", "int64"})
        got = f"{_excerpt(start)}" + (f" ({', '.join(kinds)} is not a number)" if len(kinds) == 1 else "")
        raise StartOutsideMap(f"the start must be two numbers (x, y) in metres, got {got}")
    try:
        x0 = np.array([float(v) for v in values])
    except OverflowError:
        x0 = np.full(len(values), np.inf)
    if x0.shape != (2,) or not np.isfinite(x0).all():
        raise StartOutsideMap(f"the start must be two finite numbers (x, y) in metres, got {_excerpt(start)}")
    return x0


def locate_start(occ: Any, start: Any) -> tuple[np.ndarray, int, int]:
    """(x_0, row, column) of a start on the occupancy map ``occ``: :func:`start_point`, then StartOutsideMap
    for a point outside the map's bounds."""
    x0 = start_point(start)
    x, y = float(x0[0]), float(x0[1])
    res, ox, oy = occ.resolution, float(occ.origin[0]), float(occ.origin[1])
    lo = ox + 0.5 * res - res / 2, oy + 0.5 * res - res / 2  # cell_to_world's arithmetic, in scalars
    hi = ox + (occ.width - 0.5) * res + res / 2, oy + (occ.height - 0.5) * res + res / 2
    # bounds in floats first: a huge start would overflow the integer cell index
    inside = lo[0] <= x < hi[0] and lo[1] <= y < hi[1]
    row, col = (math.floor((y - oy) / res), math.floor((x - ox) / res)) if inside else (-1, -1)
    if not (inside and 0 <= row < occ.height and 0 <= col < occ.width):
        raise StartOutsideMap(
            f"the start ({_metres(x)}, {_metres(y)}) is outside the map "
            f"(x {lo[0]:.2f}..{hi[0]:.2f}, y {lo[1]:.2f}..{hi[1]:.2f})"
        )
    return x0, row, col


def start_cell(
    model: SpatialConceptModel, graph: PlanningGraph, start: Sequence[float] | np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x_0, its crop cell where planning starts, and the escape (map cells) before it: empty unless the start
    is free on the map but within the robot's radius of an obstacle (an inscribed cell), in which case the
    escape is the shortest run of free cells from the start to the nearest cell of a free region with places
    (the planning starts at its end). The cell is in the main graph's crop, in any such region."""
    occ = model.require_map()
    x0, row, col = locate_start(occ, start)
    r, c = row - int(graph.offset[0]), col - int(graph.offset[1])
    cell = np.array([r, c], dtype=np.int64)
    h, w = graph.log_p.shape
    if 0 <= r < h and 0 <= c < w and _plannable(graph)[r, c]:  # graph.in_crop, in Python integers
        return x0, cell, np.empty((0, 2), dtype=np.int64)
    full = np.array([row, col], dtype=np.int64)
    where = f"the start ({x0[0]:.2f}, {x0[1]:.2f})"
    if graph.in_crop(cell) and graph.traversable[cell[0], cell[1]]:
        raise StartBlocked(
            f"{where} is cut off from the places: no place reaches the free space around it for a robot of "
            f"this size{_nearest_start(graph, occ, cell)}"
        )
    value = int(occ.data[full[0], full[1]])
    if value != 0:
        what = {100: "an occupied", -1: "an unknown"}.get(value, "a non-free")
        raise StartBlocked(
            f"{where} is in {what} cell of the map; start from a free cell{_nearest_start(graph, occ, cell)}"
        )
    escape = _escape(occ.free, graph, full, model.costmap.get("inscribed_radius", DEFAULT_COSTMAP.inscribed_radius))
    if escape is None:
        raise StartBlocked(f"{where} is cut off from the places: no free cell the robot fits in is reachable from it")
    return x0, graph.to_crop(escape[-1]), escape[:-1]


def _escape(free: np.ndarray, graph: PlanningGraph, cell: np.ndarray, radius_m: float) -> np.ndarray | None:
    """The shortest run of free map cells (8-connected, diagonal steps sqrt 2) from ``cell`` to a cell of the
    largest free region, else (none in reach) of another free region with places, when one is reachable by a run
    that stays within ``ceil(radius / resolution) + 2`` cells of ``cell`` along each axis; None if none is. The
    largest region first: a start on the edge of a pocket cut off by furniture also touches the free space
    around it, from which every place of that space can be reached. A run found in that window that is longer
    than the window is wide may be beaten by one to a cell just outside it, so the search is then repeated in a
    window as wide as the run is long (which holds every shorter run)."""
    res = graph.model.require_map().resolution
    r = math.ceil(max(radius_m, res) / res) + 2
    targets = [graph.main] + ([graph.plannable] if graph.plannable is not None and graph.regions else [])
    for mask in targets:
        path = _escape_within(free, graph, mask, cell, r)
        if path is not None and (length := _run_length(path)) > r + 1:
            path = _escape_within(free, graph, mask, cell, math.ceil(length))
        if path is not None:
            return path
    return None


def _plannable(graph: PlanningGraph) -> np.ndarray:
    """(h, w) the crop cells a plan can start from: the free regions that hold places
    (:mod:`spcotmhp.planning.regions`; the graph's own region when it has no others)."""
    return graph.plannable if graph.plannable is not None else graph.main


def _run_length(cells: np.ndarray) -> float:
    """Length of a run of 8-connected cells, in cells."""
    steps = np.abs(np.diff(cells, axis=0)).sum(axis=1)
    return float(np.where(steps == 2, SQRT2, steps).sum())


def _escape_within(
    free: np.ndarray, graph: PlanningGraph, goal: np.ndarray, cell: np.ndarray, r: int
) -> np.ndarray | None:
    """The shortest run of free cells from ``cell`` to a cell of ``goal`` (a crop mask) inside the window of
    half-side ``r`` cells around it (map cells), or None."""
    h, w = free.shape
    r0, c0 = max(cell[0] - r, 0), max(cell[1] - r, 0)
    r1, c1 = min(cell[0] + r + 1, h), min(cell[1] + r + 1, w)
    window = free[r0:r1, c0:c1].copy()
    target = np.zeros_like(window)
    o0, o1 = graph.offset
    gr0, gc0 = max(r0 - o0, 0), max(c0 - o1, 0)
    gr1, gc1 = min(r1 - o0, goal.shape[0]), min(c1 - o1, goal.shape[1])
    if gr1 > gr0 and gc1 > gc0:
        target[gr0 + o0 - r0 : gr1 + o0 - r0, gc0 + o1 - c0 : gc1 + o1 - c0] = goal[gr0:gr1, gc0:gc1]
    if not target.any():
        return None
    window |= target
    dist, nxt = cost_to_go(np.where(window, 1.0, np.inf), np.argwhere(target), graph.settings.connectivity, SQRT2)
    path = path_from_field(dist, nxt, np.array([cell[0] - r0, cell[1] - c0]))
    if path is None:
        return None
    return path.cells + np.array([r0, c0])


_SHORT = reprlib.Repr()
_SHORT.maxlist = _SHORT.maxtuple = 4
_SHORT.maxstring = _SHORT.maxother = 40
_SHORT.maxlevel = 2


def _nearest_start(graph: PlanningGraph, occ: Any, cell: np.ndarray) -> str:
    """', e.g. the nearest one the robot can plan from: (x, y)' (a cell of a free region with places closest to
    ``cell``, crop coordinates), or '' when there is none."""
    free = np.argwhere(_plannable(graph))
    if not len(free):
        return ""
    best = free[np.argmin(((free - np.asarray(cell)) ** 2).sum(axis=1))]
    x, y = occ.cell_to_world(graph.to_map(best))
    return f", e.g. the nearest one the robot can plan from, ({_metres(x)}, {_metres(y)})"


def _excerpt(value: Any, limit: int = 60) -> str:
    """A short ``repr`` of ``value`` (error messages never repeat a huge input)."""
    text = _SHORT.repr(value)
    return text if len(text) <= limit else text[:limit] + "…"


def _metres(v: float) -> str:
    """A coordinate for a message: 2 decimals, or 4 significant digits when huge (no 300-digit numbers)."""
    return f"{v:.2f}" if abs(v) < 1e6 else f"{v:.4g}"

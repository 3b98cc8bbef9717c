"""From the stitched search's node sequence to the path a robot drives: one segment per floor, in order, with the
connector ride between consecutive segments (Algorithm 1, lines 12-13, floor by floor).

The sequence is cut where a step rides a connector (stop e on one floor -> stop e' on another). Within a segment
the legs are the floor graph's partial paths (node -> node: ``edge_path``; from the start or a stop into a node:
``leg``) and the cost-to-go fields into stops (into a stop: the field's path), joined as on one floor
(:func:`~spcotmhp.planning.assemble.join_legs`). Smoothing (the planner's ``smooth``) is the single-floor one
(:func:`~spcotmhp.planning.assemble.smooth_on_graph`) on the part of a segment that ends at a place node; the last
leg into a stop is already the field's optimal path and is kept. A stop within the robot's radius of an obstacle
adds its escape run (stop -> planning cell) where the segment leaves or reaches it, so a segment starts and ends
at the connector's stop itself.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from spcotmhp.building.stitch import Endpoint, FloorPart, Stitched, StopFields
from spcotmhp.metric.grid_search import path_from_field
from spcotmhp.planning.assemble import join_legs, path_length, smooth_on_graph
from spcotmhp.planning.plan import PlanPlace
from spcotmhp.planning.search import SearchResult


@dataclass
class Segment:
    """The part of a plan on one floor: map cells and map-frame points (of that floor's map), its length, the
    stitched node items it visits (``items``: (stitched node, completed stages)), and the stops it starts at
    (``arrive``, None for the plan's start) and ends at (``leave``, None for the goal); ``places`` the places it
    reaches, with their roles (the planner names them)."""

    floor: int
    cells: np.ndarray
    path: np.ndarray
    length_m: float
    items: list[tuple[int, tuple[int, ...]]] = field(default_factory=list)
    arrive: Endpoint | None = None
    leave: Endpoint | None = None
    smoothed: bool = False
    places: list[PlanPlace] = field(default_factory=list)


def split_runs(st: Stitched, result: SearchResult) -> list[tuple[int, list[tuple[int, tuple[int, ...]]]]]:
    """The sequence cut at rides: [(floor, [(stitched node, completed stages), ...]), ...]; a run after a ride
    starts with the stop it arrives at."""
    runs: list[tuple[int, list[tuple[int, tuple[int, ...]]]]] = []
    floor = None
    for node, done in zip(result.nodes.tolist(), result.completed, strict=True):
        f = int(st.floor_of[node])
        if floor is None or f != floor:
            runs.append((f, []))
            floor = f
        runs[-1][1].append((node, done))
    return runs


def assemble(
    st: Stitched,
    result: SearchResult,
    parts: dict[int, FloorPart],
    start_cell: np.ndarray,
    escape: np.ndarray,
    fields: StopFields,
    smooth: bool,
) -> list[Segment]:
    """The segments of ``result`` (module docstring). ``start_cell``: the start's crop cell in its floor's graph;
    ``escape``: the map cells of the start's escape run (empty unless it starts within the robot's radius of an
    obstacle)."""
    segments = []
    runs = split_runs(st, result)
    for r, (floor, items) in enumerate(runs):
        part = parts[floor]
        first = r == 0
        arrive = None if first else _stop(st, items[0][0])
        body = items if first else items[1:]  # the arrival stop is where the segment starts
        origin = start_cell if first else np.array(arrive.cell)  # type: ignore[union-attr]
        cells, ends = _legs(st, part, origin, [n for n, _ in body], fields)
        leave = _stop(st, body[-1][0]) if body and st.local[body[-1][0]] < 0 and r < len(runs) - 1 else None
        cells, smoothed = _smooth(part, st, cells, ends, body, smooth)
        map_cells = part.graph.to_map(cells)
        before = escape if first else (arrive.escape if arrive is not None else escape[:0])
        after = leave.escape[::-1] if leave is not None else escape[:0]
        map_cells = np.vstack([before.reshape(-1, 2), map_cells, after.reshape(-1, 2)]).astype(np.int64)
        occ = part.planner.model.require_map()
        seg = Segment(floor, map_cells, occ.cell_to_world(map_cells), path_length(map_cells, occ.resolution),
                      list(body), arrive, leave, smoothed)  # fmt: skip
        segments.append(seg)
    return segments


def _stop(st: Stitched, node: int) -> Endpoint:
    return st.stops[node - st.n_floor_nodes]


def _legs(st: Stitched, part: FloorPart, origin: np.ndarray, nodes: list[int], fields: StopFields):
    """The joined crop cells from ``origin`` through the stitched ``nodes`` (all on ``part``'s floor) and the
    index where each is reached."""
    g = part.graph
    legs = [origin[None, :]]
    here: tuple[str, int] = ("cell", -1)
    for node in nodes:
        local = int(st.local[node])
        source = origin if here[0] == "cell" else (g.node_cell[here[1]] if here[0] == "node" else
                                                   np.array(_stop(st, here[1]).cell))  # fmt: skip
        if local >= 0:
            legs.append(g.edge_path(here[1], local) if here[0] == "node" else g.leg(source, local).cells)
            here = ("node", local)
        else:
            dist, nxt = fields.get(g, _stop(st, node))
            legs.append(path_from_field(dist, nxt, source, strict=True).cells)
            here = ("stop", node)
    cells, ends = join_legs(legs)
    return cells, ends[1:]


def _smooth(part: FloorPart, st: Stitched, cells: np.ndarray, ends: list[int], body: list, smooth: bool):
    """Smoothing of the part of the segment that ends at its last place node (module docstring)."""
    local = [int(st.local[n]) for n, _ in body]
    node_at = [i for i, k in enumerate(local) if k >= 0]
    if not smooth or not node_at:
        return cells, False
    last = node_at[-1]
    cut = ends[last]
    nodes = [local[i] for i in node_at]
    node_ends = [ends[i] for i in node_at]
    anchors = [ends[i] for i in node_at if body[i][1]]
    if ends[last] not in anchors:
        anchors.append(ends[last])  # the prefix ends there
    head, _ = smooth_on_graph(part.graph, cells[: cut + 1], node_ends, nodes, anchors)
    out = np.vstack([head, cells[cut + 1 :]])
    return out, not np.array_equal(out, cells)

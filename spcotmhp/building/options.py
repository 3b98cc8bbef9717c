"""The goal options of a plan in a building: the best plan (Eq. 28) into each instance of the goal's name on every
floor, with the metres of its route (walked, smoothed as the chosen plan, plus the connectors' cost_m), so that
"closest of 6 bedrooms on 3 floors" is a statement about routes the robot would take.

As on one floor (:func:`~spcotmhp.planning.explain.goal_options`), the options are taken in order of a lower bound
of their route: the octile distances between the cells every such route must pass (the start, the cells where a
stage is completed, the connector stops, which smoothing keeps) plus the rides' cost_m; an option whose bound
already exceeds the shortest route found so far cannot be the closest and gets the bound (``exact`` False), so a
building with many bedrooms does not assemble a route into each of them per plan.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.building.plan import FloorOption
from spcotmhp.building.route import Segment, assemble
from spcotmhp.building.stitch import FloorPart, Stitched, StopFields
from spcotmhp.planning import explain
from spcotmhp.planning.search import SearchResult

Rides = dict[tuple[int, int], float]


def route_metres(rides: Rides, segments: list[Segment]) -> float:
    """Walked metres of ``segments`` plus the cost_m of the rides between them (``rides[(e, e')]``: metres)."""
    ridden = sum(rides.get((a.leave.id, b.arrive.id), 0.0) for a, b in zip(segments, segments[1:], strict=False)
                if a.leave is not None and b.arrive is not None)  # fmt: skip
    return float(sum(s.length_m for s in segments) + ridden)


def lower_bound(rides: Rides, st: Stitched, alt: SearchResult, parts: dict[int, FloorPart]) -> float:
    """A lower bound of the route of ``alt`` (module docstring), in metres."""
    here = (int(st.floor_of[alt.nodes[0]]), np.asarray(st.start_cell))
    total, prev = 0.0, -1
    for node, done in zip(alt.nodes.tolist(), alt.completed, strict=True):
        floor, local = int(st.floor_of[node]), int(st.local[node])
        stop = st.stops[node - st.n_floor_nodes] if local < 0 else None
        if floor != here[0] and stop is not None and prev >= st.n_floor_nodes:  # a ride from the stop before
            total += rides.get((st.stops[prev - st.n_floor_nodes].id, stop.id), 0.0)
        prev = node
        if local >= 0 and not done:
            continue  # a place passed through: smoothing may cut its corner
        cell = np.asarray(stop.cell) if stop is not None else parts[floor].graph.node_cell[local]
        if floor == here[0]:
            total += float(parts[floor].planner.model.require_map().resolution) * explain.octile(here[1], cell)
        here = (floor, cell)
    return total


def goal_options(
    st: Stitched, result: SearchResult, parts: dict[int, FloorPart], last: int, chosen: tuple[int, float],
    rides: Rides, fields: StopFields, smooth: bool,
) -> list[FloorOption]:  # fmt: skip
    """The options (module docstring), best Eq. 28 score first; ``chosen``: (goal place, route metres) of the plan
    made; ``rides``, ``fields``, ``smooth``: the building planner's; empty unless the goal's name has two
    instances or more with a route."""
    goal_nodes = np.flatnonzero(st.problem.completes[last] & np.isfinite(result.terminal))
    best: dict[int, int] = {}
    for node in goal_nodes:
        k = int(parts[int(st.floor_of[node])].graph.node_place[st.local[node]])
        if k not in best or result.terminal[node] > result.terminal[best[k]]:
            best[k] = int(node)
    if len(best) < 2:
        return []
    options, pending = [], []
    for k, end in best.items():
        floor = int(st.floor_of[end])
        label = explain.place(parts[floor].planner, k, "goal").label
        if k == chosen[0]:
            options.append(FloorOption(k, floor, label, chosen[1], float(result.log_prob)))
            continue
        alt = result.ending_at(end)
        pending.append((lower_bound(rides, st, alt, parts), k, floor, label, alt))
    shortest = chosen[1]
    empty = np.empty((0, 2), np.int64)
    for bound, k, floor, label, alt in sorted(pending, key=lambda p: p[0]):
        if bound > shortest + 1e-9:
            options.append(FloorOption(k, floor, label, bound, float(alt.log_prob), exact=False))
            continue
        route = route_metres(rides, assemble(st, alt, parts, st.start_cell, empty, fields, smooth))
        shortest = min(shortest, route)
        options.append(FloorOption(k, floor, label, route, float(alt.log_prob)))
    return sorted(options, key=lambda o: -o.log_prob)

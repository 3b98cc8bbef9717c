"""The Eq. 28 search of a building: the floors' candidate graphs and the connectors' stops in one topological level.

The nodes of the stitched search are every floor's candidate nodes (in floor order) and then the connectors'
stops ("endpoints": a stop's cell on its floor's grid). A step's log weight is the per-step factor of Eq. 28
without the word term, as on one floor (:meth:`~spcotmhp.planning.planner.HierarchicalPlanner._problem`):

* node i -> node j on one floor: the floor graph's ``log_transition_all`` (log psi - log UR + w-hat);
* node i -> stop e on its floor: the partial path's likelihood into the stop, -cost(cell_i -> cell_e) under the
  step cost log|A| - log p(x|m) (a stop is not a place: no Gaussian at its end, no transition term), read from a
  cost-to-go field into the stop (:class:`StopFields`);
* stop e -> node j on its floor: the start terms of Eq. 28 with the stop as x_0: log sum_k p(k | x_e) psi[k, i_j]
  - log UR(i_j) + w-hat of the leg from the stop into j (``start_w_hat``), exactly how a plan leaves its start;
* stop e -> stop e' on one floor: -cost(cell_e -> cell_e') (passing through a floor from one connector to
  another);
* stop e -> stop e' of the same connector on another floor (a ride): -cost_m * nats_per_m, the connector's cost
  in the units of the grid's partial paths. A metre of free floor (p(x|m) = 1) costs log|A| / resolution nats
  (a step of one cell costs log|A| = log(connectivity + 1)); a connector of cost_m metres costs what walking
  cost_m metres of free floor costs on the floor it leaves.

The start row is the start's floor's start terms for its nodes and -cost(x_0 -> e) for its stops. Stops have no
word term and complete no stage. With ``metric`` (the fallback of the single-floor planner when no place
sequence satisfies the instruction under psi) the transition terms are dropped (-log UR kept), as on one floor.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from spcotmhp.metric.grid_search import SQRT2, cost_to_go
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.graph_cache import GraphCache
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.search import SearchProblem

FIELD_CACHE_SIZE = 256  # cost-to-go fields into stops (floor graphs and their avoidance views)


@dataclass(frozen=True)
class Endpoint:
    """A connector's stop on one floor: ``region`` is the key of the free region graph holding its planning cell
    ``cell`` (crop cells of that graph; None when no free region with places reaches it: ``why``), ``escape``
    the map cells from the stop to that cell when the stop is within the robot's radius of an obstacle."""

    id: int
    connector: int
    floor: int
    point: tuple[float, float]
    region: str | None
    cell: tuple[int, int] | None
    escape: np.ndarray = field(default_factory=lambda: np.empty((0, 2), np.int64))
    why: str = ""


@dataclass
class FloorPart:
    """One floor in one query: its planner, the graph searched (the start's region on the start's floor, the main
    graph elsewhere; an avoidance view when the instruction avoids places there), its word terms and instances
    (S, K), the first index of its nodes in the stitched problem and its usable stops."""

    floor: int
    planner: HierarchicalPlanner
    graph: PlanningGraph
    semantic: np.ndarray
    inst: np.ndarray
    offset: int = 0
    stops: list[Endpoint] = field(default_factory=list)


class StopFields:
    """Cost-to-go fields into stops, per floor graph (or avoidance view), computed once and kept (a bounded
    cache: the main graphs' fields stay, views' fields go least recently used first)."""

    def __init__(self) -> None:
        self._cache = GraphCache(FIELD_CACHE_SIZE)

    def get(self, graph: PlanningGraph, stop: Endpoint) -> tuple[np.ndarray, np.ndarray]:
        """(dist, next_step) over ``graph``'s crop: the cost of the best path from every cell into the stop."""
        key = (graph.key, tuple(graph.info.get("avoided", ())), stop.id)
        assert stop.cell is not None
        return self._cache.get_or_build(
            key, lambda: cost_to_go(graph.map_cost, np.array([stop.cell]), graph.settings.connectivity, SQRT2)
        )


def nats_per_metre(graph: PlanningGraph) -> float:
    """The log-likelihood of one metre of free floor under the grid's step cost: log|A| / resolution."""
    return math.log(graph.settings.connectivity + 1) / float(graph.model.require_map().resolution)


@dataclass(frozen=True)
class Stitched:
    """The stitched search problem and how its node indices map back: ``floor_of`` / ``local`` per node (a floor
    node's index in its floor graph, or -1 for a stop), ``stops`` the endpoint of each stop node."""

    problem: SearchProblem
    floor_of: np.ndarray
    local: np.ndarray
    stops: tuple[Endpoint, ...]
    n_floor_nodes: int
    start_cell: np.ndarray


@dataclass(frozen=True)
class Skeleton:
    """What a stitched problem holds that no instruction changes, for one choice of floor graphs (views) and
    stops: the (M, M) transition, ``floor_of`` / ``local`` per node, the stops, each floor's first node index
    (``offsets``) and the number of floor nodes. Kept by the building's planner per choice (:func:`skeleton_key`)."""

    transition: np.ndarray
    floor_of: np.ndarray
    local: np.ndarray
    stops: tuple[Endpoint, ...]
    offsets: dict[int, int]
    n_floor_nodes: int


def skeleton_key(parts: list[FloorPart], metric: bool) -> tuple:
    """The key of a skeleton: each floor's graph (its key and avoided places) and its usable stops."""
    return (metric, *((p.floor, p.graph.key, tuple(p.graph.info.get("avoided", ())), tuple(s.id for s in p.stops))
                      for p in parts))  # fmt: skip


def skeleton(parts: list[FloorPart], rides: dict[tuple[int, int], float], fields: StopFields, metric: bool) -> Skeleton:
    """The instruction-free part of the stitched problem (module docstring). ``rides[(e, e')]``: the cost in metres
    of riding from stop e to stop e' (ids of :class:`Endpoint`)."""
    n, offsets = 0, {}
    for part in parts:
        offsets[part.floor], n = n, n + part.graph.n_nodes
    stops = [s for part in parts for s in part.stops]
    M = n + len(stops)
    T = np.full((M, M), -np.inf)
    floor_of, local = np.empty(M, np.int64), np.full(M, -1, np.int64)
    index = {s.id: n + k for k, s in enumerate(stops)}
    for part in parts:
        g, a = part.graph, offsets[part.floor]
        nodes = g.node_place
        sl = slice(a, a + g.n_nodes)
        floor_of[sl], local[sl] = part.floor, np.arange(g.n_nodes)
        ur = part.planner.terms.log_ur[nodes]
        T[sl, sl] = g.w_hat_metric - ur[None, :] if metric else _floor_transition(part)
        rows, cols = g.node_cell[:, 0], g.node_cell[:, 1]
        for s in part.stops:
            e = index[s.id]
            floor_of[e] = part.floor
            dist, _ = fields.get(g, s)
            T[sl, e] = np.where(g.usable, -dist[rows, cols], -np.inf)  # node -> stop
            leave = g.start_w_hat(np.array(s.cell))
            terms = -ur if metric else part.planner.terms.start_terms(_posterior(part, s), nodes)
            T[e, sl] = terms + leave  # stop -> node, as a plan leaves its start
            for t in part.stops:
                if t.id != s.id:
                    T[e, index[t.id]] = -fields.get(g, t)[0][s.cell]
    for (a_id, b_id), cost_m in rides.items():
        if a_id in index and b_id in index:
            T[index[a_id], index[b_id]] = -cost_m * _nats(parts, floor_of[index[a_id]])
    T.setflags(write=False)
    return Skeleton(T, floor_of, local, tuple(stops), offsets, n)


def stitch(
    sk: Skeleton, parts: list[FloorPart], start: FloorPart, cell: np.ndarray, fields: StopFields, max_steps: int,
    metric: bool = False,
) -> Stitched:  # fmt: skip
    """The stitched problem of one instruction (module docstring) on the skeleton ``sk`` of ``parts``: the start
    row, the word terms and the instances. ``cell``: the start's crop cell in ``start.graph``."""
    M = sk.transition.shape[0]
    start_row = np.full(M, -np.inf)
    S = parts[0].semantic.shape[0]
    word, completes = np.zeros((S, M)), np.zeros((S, M), dtype=bool)
    for part in parts:
        part.offset = sk.offsets[part.floor]
        nodes = part.graph.node_place
        sl = slice(part.offset, part.offset + part.graph.n_nodes)
        word[:, sl], completes[:, sl] = part.semantic[:, nodes], part.inst[:, nodes]
    g, a = start.graph, start.offset
    terms = start.planner.terms
    posterior = terms.place_posterior(start.planner.model.require_map().cell_to_world(g.to_map(cell)))
    row = -terms.log_ur[g.node_place] if metric else terms.start_terms(posterior, g.node_place)
    start_row[a : a + g.n_nodes] = row + g.start_w_hat(cell)
    index = {s.id: sk.n_floor_nodes + k for k, s in enumerate(sk.stops)}
    for s in start.stops:
        start_row[index[s.id]] = -fields.get(g, s)[0][int(cell[0]), int(cell[1])]
    problem = SearchProblem(sk.transition, start_row, word, completes, int(max_steps))
    return Stitched(problem, sk.floor_of, sk.local, sk.stops, sk.n_floor_nodes, np.asarray(cell, np.int64))


def _floor_transition(part: FloorPart) -> np.ndarray:
    """The floor graph's per-step factor without the word term (the single-floor planner's choice of graph)."""
    g = part.graph
    return g.log_transition if part.planner.settings.adjacent_only else g.log_transition_all


def _posterior(part: FloorPart, stop: Endpoint) -> np.ndarray:
    """p(k | x_e) at the stop's planning cell (Eq. 3), the marginalised i_0 of a leg leaving the stop."""
    occ = part.planner.model.require_map()
    return part.planner.terms.place_posterior(occ.cell_to_world(part.graph.to_map(np.array(stop.cell))))


def _nats(parts: list[FloorPart], floor: int) -> float:
    return next(nats_per_metre(p.graph) for p in parts if p.floor == floor)

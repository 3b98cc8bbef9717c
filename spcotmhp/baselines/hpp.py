"""Baseline (D) of Experiment I: hierarchical path planning without control as inference, similar to Niijima et
al. (2020) (paper Section 4.2 (D)).

The topological level is a shortest-path search over the SpCoTMHP planning graph's candidate nodes with a
heuristic edge cost, to target nodes drawn from the spatial concepts:

* HPP-I:  edge cost = the partial path's cost, the negative log-likelihood -w_hat[i, j] of Eq. 27;
* HPP-II: edge cost = the partial path's length in metres.

One implementation, the edge cost passed in (:data:`EDGE_COSTS`). The start place is the most probable place of
the start pose (argmax N(x_0 | mu_k, Sigma_k)); each target place is one draw from p(i | S) (the waypoint's from
its own words); the legs start -> waypoint -> goal are planned one after another (no joint choice, unlike
Eq. 28); the metric path is the start leg followed by the partial paths, all REUSED from the
:class:`~spcotmhp.planning.graph.PlanningGraph` (nothing is recomputed).

Moves: the partial paths and start legs are the planning graph's, so HPP moves with the graph's connectivity
(8-connected in the evaluation, as SpCoTMHP), and its edges are the graph's (Figure 3's connected places).

The reference code's HPP-I took its edge costs from the cost of the last cell an exhaustive search visited, not
from the path (0 -> 9: 21,634 instead of 1,235); here it is the partial path's own cost.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping, Sequence
from itertools import pairwise
from typing import Any

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from spcotmhp.errors import PlanningError
from spcotmhp.logspace import logsumexp
from spcotmhp.planning.assemble import join_legs, path_length
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.plan import Plan
from spcotmhp.planning.protocol import PlanVocabulary, StartPose, bag_words, path_plan
from spcotmhp.planning.start import start_point

EdgeCost = Callable[[PlanningGraph], np.ndarray]


def path_cost_edges(graph: PlanningGraph) -> np.ndarray:
    """HPP-I: (M, M) edge costs -w_hat (the partial path's negative log-likelihood); inf where no edge."""
    return np.where(np.isfinite(graph.w_hat), -graph.w_hat, np.inf)


def path_length_edges(graph: PlanningGraph) -> np.ndarray:
    """HPP-II: (M, M) edge costs = the partial path's length in metres; inf where no edge."""
    out = np.full(graph.w_hat.shape, np.inf)
    res = graph.model.require_map().resolution
    for i, j in zip(*np.nonzero(np.isfinite(graph.w_hat)), strict=False):
        out[i, j] = path_length(graph.edge_path(int(i), int(j)), res)
    return out


EDGE_COSTS: dict[str, EdgeCost] = {"hpp1": path_cost_edges, "hpp2": path_length_edges}


Words = Sequence[str] | Mapping[str, float]  # a token list or a weighted bag of words S


def draw_place(graph: PlanningGraph, words: Words, rng: np.random.Generator) -> int:
    """One place drawn from p(i | S) over the active places (:meth:`SpatialConceptModel.log_place_given_words`)."""
    lp = graph.model.log_place_given_words(words if isinstance(words, Mapping) else list(words))
    p = np.exp(lp - logsumexp(lp))
    return int(rng.choice(len(p), p=p / p.sum()))


class HPP:
    """HPP-I / HPP-II on a planning graph. ``edge_cost`` is one of :data:`EDGE_COSTS` (or any callable returning
    (M, M) non-negative costs, inf for no edge); the edge costs and all-pairs shortest paths are computed once
    here (offline), so a plan is a few table look-ups."""

    def __init__(self, graph: PlanningGraph, edge_cost: EdgeCost) -> None:
        self.graph = graph
        cost = np.asarray(edge_cost(graph), dtype=float)
        if cost.shape != graph.w_hat.shape or np.isnan(cost).any() or (cost < 0).any():
            raise ValueError("edge costs must be a non-negative (M, M) array (inf: no edge)")
        finite = np.isfinite(cost)
        # csgraph treats explicit zeros as missing edges: keep zero-cost edges with the smallest positive float
        weights = csr_matrix(np.where(finite, np.maximum(cost, np.finfo(float).tiny), 0.0))
        self.dist, self.pred = dijkstra(weights, directed=True, return_predecessors=True)

    def start_node(self, cell: np.ndarray) -> int:
        """The candidate of the most probable place of the start (argmax N(x_0 | mu_k, Sigma_k)), the one with the
        cheapest start leg if the place has several."""
        g = self.graph
        x0 = g.centres[cell[0], cell[1]]
        ld = np.where(g.model.active_places, g.model.log_place_density(x0), -np.inf)
        nodes = np.flatnonzero(g.node_place == int(np.argmax(ld)))
        if not len(nodes):
            raise PlanningError("the start's most probable place has no candidate point")
        return int(nodes[np.argmin(g.cost_to_nodes(cell)[nodes])])

    def route(self, source: int, place: int) -> list[int]:
        """The cheapest node sequence from ``source`` to any candidate of ``place`` (source included)."""
        targets = np.flatnonzero(self.graph.node_place == place)
        if not len(targets) or not np.isfinite(self.dist[source, targets]).any():
            raise PlanningError(f"no topological route from node {source} to place {place}")
        node = int(targets[np.argmin(self.dist[source, targets])])
        seq = [node]
        while node != source:
            node = int(self.pred[source, node])
            seq.append(node)
        return seq[::-1]

    def plan(
        self,
        cell: np.ndarray,
        stages: Sequence[Words],
        rng: np.random.Generator,
        smooth: bool = False,
    ) -> np.ndarray:
        """The crop cells of the path from crop cell ``cell`` through one drawn place per stage (the waypoints,
        then the goal), leg after leg; with ``smooth``, post-processed by SpCoTMHP's smoothing
        (:func:`spcotmhp.baselines.smoothing.spcotmhp_smoothing`, the stage places kept as anchors)."""
        g = self.graph
        node = self.start_node(cell)
        if not np.isfinite(g.cost_to_nodes(cell)[node]):
            raise PlanningError("the start cannot reach the candidate point of its own place")
        nodes, stage_ends = [node], []
        for words in stages:
            nodes += self.route(nodes[-1], draw_place(g, words, rng))[1:]
            stage_ends.append(len(nodes) - 1)
        legs = [g.leg(cell, nodes[0]).cells] + [g.edge_path(a, b) for a, b in pairwise(nodes)]
        cells, ends = join_legs(legs)
        if not smooth:
            return cells
        from spcotmhp.baselines.smoothing import spcotmhp_smoothing

        return spcotmhp_smoothing(g, cells, ends, nodes, [ends[e] for e in stage_ends])


class HPPPlanner:
    """HPP-I / HPP-II as a :class:`~spcotmhp.planning.protocol.Planner`: one place drawn per stage of the
    instruction (its waypoints, then its goal) with ``rng`` (default: this planner's own generator, seeded by
    ``seed``), the legs between them from the planning graph; with ``smooth``, SpCoTMHP's smoothing."""

    def __init__(self, hpp: HPP, smooth: bool = False, seed: int | None = None) -> None:
        self.hpp, self.smooth = hpp, smooth
        self.vocabulary = PlanVocabulary(hpp.graph.model)
        self.rng = np.random.default_rng(seed)

    def plan(self, instruction: Any, start: StartPose, *, rng: np.random.Generator | None = None) -> Plan:
        t0 = time.perf_counter()
        ins = self.vocabulary.instruction(instruction)
        graph, occ = self.hpp.graph, self.hpp.graph.model.require_map()
        cell = graph.to_crop(occ.world_to_cell(start_point(start)))
        stages = [bag_words(q) for q in ins.stages]
        cells = self.hpp.plan(cell, stages, self.rng if rng is None else rng, smooth=self.smooth)
        return path_plan(self.vocabulary, occ, graph.to_map(cells), ins, t0, graph.time_precompute_s)

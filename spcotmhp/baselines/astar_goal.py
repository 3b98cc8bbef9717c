"""Baseline (A) of Experiment I: A* to a goal position drawn from the spatial concepts (SpCoSLAM-style).

The goal is one draw ``x* ~ p(x | S, Theta) = sum_C p(C | S) sum_k phi_C(k) N(x | mu_k, Sigma_k)`` with
``p(C | S) ∝ pi_C Mult(S | W_C)`` (paper Section 4.2 (A)); it is moved to the nearest traversable cell that
the start can reach, and the cheapest path on the cost map (step cost -log p(x|m) + log|A|, the metric level's
grid search) leads there. No topology, no waypoint handling: an advanced instruction is one bag of words.

Moves: 8-connected by default, the move model of SpCoTMHP's metric level (its partial paths and smoothing) and
of the reference length l of SPL (an 8-connected geodesic), so that the comparison measures the choice of goal
and route, not the move set. (With 4-connected moves every diagonal stretch costs up to sqrt 2 more, and the
baseline would lose SPL for that alone.)
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from spcotmhp.errors import PlanningError
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.logspace import logsumexp
from spcotmhp.metric.grid_search import shortest_paths, step_cost_map
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.metric.snap import component_at, snap
from spcotmhp.planning.plan import Plan
from spcotmhp.planning.protocol import PlanVocabulary, StartPose, merged_bag, path_plan
from spcotmhp.planning.start import start_point


def sample_goal(
    model: SpatialConceptModel, words: Sequence[str] | Mapping[str, float], rng: np.random.Generator
) -> np.ndarray:
    """One draw x ~ p(x | S, Theta): C ~ p(C | S), then k ~ phi_C, then x ~ N(mu_k, Sigma_k). Returns (2,)."""
    with np.errstate(divide="ignore"):
        lc = model.log_word_likelihood(words if isinstance(words, Mapping) else list(words)) + np.log(model.pi)
    pc = np.exp(lc - logsumexp(lc))
    C = rng.choice(len(pc), p=pc / pc.sum())
    k = rng.choice(model.K, p=model.phi[C] / model.phi[C].sum())
    return rng.multivariate_normal(model.mu[k], model.Sigma[k])


def reachable_cell_nearest(
    log_p: np.ndarray, occ_map: OccupancyMap, start: tuple[int, int], xy: np.ndarray
) -> tuple[int, int]:
    """The traversable cell in the start's (4-connected, :mod:`spcotmhp.metric.snap`) component nearest to the
    point ``xy``: exactly the cells the grid search can reach from the start."""
    mine = component_at(np.isfinite(log_p), start)
    r, c = snap(mine, occ_map.world_to_cell(np.asarray(xy, float)))
    return int(r), int(c)


def astar_to_sampled_goal(
    model: SpatialConceptModel,
    log_p: np.ndarray,
    occ_map: OccupancyMap,
    start: tuple[int, int],
    words: Sequence[str] | Mapping[str, float],
    rng: np.random.Generator,
    connectivity: int = 8,
) -> np.ndarray | None:
    """Baseline (A): the grid cells (n, 2) of the cheapest path from ``start`` to a sampled goal, or None.
    Moves are 8-connected by default, as SpCoTMHP's (module docstring)."""
    goal = reachable_cell_nearest(log_p, occ_map, start, sample_goal(model, words, rng))
    path = shortest_paths(step_cost_map(log_p, connectivity=connectivity), start, goal, connectivity=connectivity)
    return None if path is None else path.cells


class AStarGoalPlanner:
    """Baseline (A) as a :class:`~spcotmhp.planning.protocol.Planner`: the waypoints' and the goal's words as one
    bag, a goal drawn from p(x | S, Theta) with ``rng`` (default: this planner's own generator, seeded by
    ``seed``), then the cheapest path on ``log_p`` (the cost map of ``occ_map``)."""

    def __init__(
        self,
        model: SpatialConceptModel,
        log_p: np.ndarray,
        occ_map: OccupancyMap,
        connectivity: int = 8,
        seed: int | None = None,
    ) -> None:
        self.vocabulary = PlanVocabulary(model)
        self.model, self.log_p, self.occ_map, self.connectivity = model, log_p, occ_map, connectivity
        self.rng = np.random.default_rng(seed)

    def plan(self, instruction: Any, start: StartPose, *, rng: np.random.Generator | None = None) -> Plan:
        t0 = time.perf_counter()
        ins = self.vocabulary.instruction(instruction)
        cell = self.occ_map.world_to_cell(start_point(start))
        cells = astar_to_sampled_goal(
            self.model,
            self.log_p,
            self.occ_map,
            (int(cell[0]), int(cell[1])),
            merged_bag(ins),
            self.rng if rng is None else rng,
            connectivity=self.connectivity,
        )
        if cells is None:
            raise PlanningError("A*: no path from the start to the sampled goal")
        return path_plan(self.vocabulary, self.occ_map, cells, ins, t0)

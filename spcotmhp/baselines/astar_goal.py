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

from collections.abc import Sequence

import numpy as np
from scipy.special import logsumexp

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.grid_search import shortest_paths, step_cost_map
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.metric.snap import component_at, snap


def sample_goal(model: SpatialConceptModel, words: Sequence[str], rng: np.random.Generator) -> np.ndarray:
    """One draw x ~ p(x | S, Theta): C ~ p(C | S), then k ~ phi_C, then x ~ N(mu_k, Sigma_k). Returns (2,)."""
    with np.errstate(divide="ignore"):
        lc = model.log_word_likelihood(list(words)) + np.log(model.pi)
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
    words: Sequence[str],
    rng: np.random.Generator,
    connectivity: int = 8,
) -> np.ndarray | None:
    """Baseline (A): the grid cells (n, 2) of the cheapest path from ``start`` to a sampled goal, or None.
    Moves are 8-connected by default, as SpCoTMHP's (module docstring)."""
    goal = reachable_cell_nearest(log_p, occ_map, start, sample_goal(model, words, rng))
    path = shortest_paths(step_cost_map(log_p, connectivity=connectivity), start, goal, connectivity=connectivity)
    return None if path is None else path.cells

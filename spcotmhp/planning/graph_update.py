"""What an update of a planning graph keeps (online learning, a teach): the dense fields of nodes that did not move,
the cost map of an unchanged map, and a model with one place's Gaussian replaced (checked)."""

from __future__ import annotations

import copy
from typing import Any, Protocol

import numpy as np

from spcotmhp.errors import ModelError
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.planning.graph_settings import GraphSettings


class PlanningGraph(Protocol):
    """What an update reads of a :class:`~spcotmhp.planning.graph.PlanningGraph` (a protocol, so that this module
    does not import the graph that imports it)."""

    model: SpatialConceptModel
    settings: GraphSettings
    offset: tuple[int, int]
    log_p: np.ndarray
    node_cell: np.ndarray
    usable: np.ndarray
    dist: Any
    next_step: Any
    blocked: np.ndarray | None
    info: dict

    @property
    def map_cost(self) -> np.ndarray: ...


def with_place(model: SpatialConceptModel, k: int, mu: np.ndarray, Sigma: np.ndarray) -> SpatialConceptModel:
    """A shallow copy of ``model`` with place k's Gaussian replaced by N(mu, Sigma), after checking k, mu and
    Sigma (symmetric positive definite)."""
    K = model.K
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 0 <= k < K:
        raise ModelError(f"place index must be an integer in 0..{K - 1}, got {k!r}")
    mu, Sigma = np.asarray(mu, dtype=float), np.asarray(Sigma, dtype=float)
    if mu.shape != (2,) or Sigma.shape != (2, 2) or not (np.isfinite(mu).all() and np.isfinite(Sigma).all()):
        raise ModelError(
            f"place {k}: mu must be 2 finite numbers and Sigma 2 x 2 finite numbers, got shapes "
            f"{mu.shape} and {Sigma.shape}"
        )
    if not (np.allclose(Sigma, Sigma.T) and np.linalg.eigvalsh(Sigma)[0] > 0):
        raise ModelError(f"place {k}: Sigma must be symmetric positive definite")
    out = copy.copy(model)
    out.mu, out.Sigma = model.mu.copy(), model.Sigma.copy()
    out.mu[k], out.Sigma[k] = mu, Sigma
    return out


def reusable_fields(
    reuse: PlanningGraph | None, graph: PlanningGraph
) -> dict[tuple[int, int], tuple[np.ndarray, np.ndarray]]:
    """{node cell: (field, next step)} of ``reuse``'s dense fields, when its window and step costs are
    ``graph``'s: a field depends on nothing but the step cost and its node's cell (Eq. 26; with ``optimality =
    "every_step"`` also on its place's Gaussian, so nothing is kept), so the fields into nodes that did not move
    are kept and only those of new or moved nodes are computed (a teach changes one or two places)."""
    if (
        reuse is None
        or not isinstance(reuse.dist, np.ndarray)
        or reuse.offset != graph.offset
        or reuse.log_p.shape != graph.log_p.shape
        or reuse.settings.connectivity != graph.settings.connectivity
        or graph.settings.optimality == "every_step"  # its fields hold the node's place, which a teach moves
        or not np.array_equal(reuse.map_cost, graph.map_cost)
    ):
        return {}
    return {
        (int(r), int(c)): (reuse.dist[j], reuse.next_step[j])
        for j, (r, c) in enumerate(reuse.node_cell)
        if reuse.usable[j]
    }


def same_cost_map(graph: PlanningGraph, model: SpatialConceptModel) -> np.ndarray | None:
    """The full-map cost map log p(x|m) ``graph`` was built on, when ``model`` has the same map and cost map
    settings (a teach changes neither), so that an update does not inflate the map again; else None."""
    old = graph.model
    if old.map is None or model.map is None or old.costmap != model.costmap or graph.blocked is not None:
        return None
    if old.map is not model.map and not np.array_equal(old.map.data, model.map.data):
        return None
    r0, r1, c0, c1 = graph.info.get("crop", (0, 0, 0, 0))
    if (r1 - r0, c1 - c0) != graph.log_p.shape:
        return None
    full = np.full(model.map.shape, -np.inf)
    full[r0:r1, c0:c1] = graph.log_p
    return full

"""Settings of the planner and their range checks: the planning graph's precomputation (Algorithm 1, lines 1-7;
:class:`GraphSettings`, part of the graph's cache key) and the online planning (:class:`PlannerSettings`)."""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict, dataclass, fields

import numpy as np

from spcotmhp.errors import InvalidSettings
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.limits import MAX_CANDIDATES, MAX_STEPS, check_count, is_count
from spcotmhp.planning.stops import STOP_COST
from spcotmhp.planning.vocabulary import INSTANCE_RATIO

OPTIMALITY = ("end", "every_step")
"""Where a partial path observes optimality (:class:`GraphSettings`)."""


@dataclass(frozen=True)
class GraphSettings:
    """Settings of the precomputation (part of the cache key).

    n_candidates: candidate points per place (N of Section 3.4; 1 = the means, as in the paper's experiments).
    seed: seed of the candidate sampling (N > 1).  connectivity: 4 or 8 grid moves.
    edge_threshold: connected places have (psi_ab + psi_ba) / 2 at least this (None: 1 / K, Figure 3).
    candidate_quantile: samples are kept inside this chi-square ellipse of their place.
    tube_margin: metres by which each place's territory is grown for smoothing's tubes.
    max_dense_bytes: the cost-to-go fields cover the whole crop, one per node (exact), when they take at most
        this many bytes (12 per cell and node); beyond, territory-local fields and a portal graph
        (:mod:`spcotmhp.planning.hierarchy`).
    portal_spacing: metres between the crossings of one entrance of the portal graph up to two spacings long;
        a longer one of length L gets ceil(sqrt(L / spacing)) (:func:`~spcotmhp.planning._portals.crossings_on`).
    optimality: where a partial path observes optimality o_t = 1 (Eq. 24): "end" (ours: once, at the leg's end)
        or "every_step" (the paper as written: at every cell of the leg, with the destination's Gaussian; dense
        fields only); :mod:`spcotmhp.planning.graph` gives both.
    stop_cost: candidate points (goals, waypoints, Nav2 route nodes) go on their place's cells of published cost
        below this (0..100; default 50, :mod:`spcotmhp.planning.stops` states the rule); None: the nearest
        traversable cell, as the paper.
    """

    n_candidates: int = 1
    seed: int = 0
    connectivity: int = 8
    edge_threshold: float | None = None
    candidate_quantile: float = 0.95
    tube_margin: float = 0.2
    max_dense_bytes: int = 2**28
    portal_spacing: float = 1.0
    optimality: str = "end"
    stop_cost: float | None = STOP_COST

    def dense(self, n_nodes: int, n_cells: int) -> bool:
        """Whether ``n_nodes`` fields over a crop of ``n_cells`` cells are dense (``max_dense_bytes``: 12 bytes a
        cell and node), else the portal graph's (whose fields kernel runs on numba's threads)."""
        return 12 * n_nodes * n_cells <= self.max_dense_bytes

    def __post_init__(self) -> None:
        """Range checks: a bad setting is a :class:`PlanningError` naming it, its value and what is accepted."""
        if self.optimality not in OPTIMALITY:
            raise InvalidSettings(f"optimality must be one of {', '.join(OPTIMALITY)}, got {self.optimality!r}")
        require_int(self.n_candidates, "n_candidates", 1, MAX_CANDIDATES)
        require_int(self.seed, "seed", 0)
        if self.connectivity not in (4, 8) or isinstance(self.connectivity, bool):
            raise InvalidSettings(f"connectivity must be 4 or 8, got {self.connectivity!r}")
        if self.edge_threshold is not None:
            require_range(self.edge_threshold, "edge_threshold", 0.0, 1.0, "in [0, 1] (or None: 1/K)")
        require_range(self.candidate_quantile, "candidate_quantile", 0.0, 1.0, "in (0, 1)", open_=True)
        require_range(self.tube_margin, "tube_margin", 0.0, math.inf, ">= 0")
        require_int(self.max_dense_bytes, "max_dense_bytes", 0)
        require_range(self.portal_spacing, "portal_spacing", 0.0, math.inf, "> 0 (metres)", open_=True)
        if self.stop_cost is not None:
            require_range(
                self.stop_cost, "stop_cost", 0.0, 100.0, "in (0, 100) (a published cost; or None)", open_=True
            )


def require_int(value: object, name: str, low: int, high: int | None = None) -> None:
    """``value`` must be an integer >= ``low`` (and <= ``high`` when given: spcotmhp/limits.py)."""
    if high is not None:
        check_count(value, name, low, high, InvalidSettings)
    elif not is_count(value) or value < low:  # type: ignore[operator]
        raise InvalidSettings(f"{name} must be an integer >= {low}, got {value!r}")


def require_range(value: object, name: str, low: float, high: float, accepted: str, open_: bool = False) -> None:
    """``value`` must be a real number in [low, high] ((low, high) with ``open_``, but always finite)."""
    ok = False
    if isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool):
        v = float(value)
        ok = math.isfinite(v) and (low < v < high if open_ else low <= v <= high)
    if not ok:
        raise InvalidSettings(f"{name} must be {accepted}, got {value!r}")


def fingerprint(model: SpatialConceptModel, settings: GraphSettings, log_p: np.ndarray | None = None) -> str:
    """A hash of everything the graph depends on: the model's parameters, its map and cost map settings, the
    graph settings and an explicit cost map."""
    h = hashlib.sha256()
    for a in (
        model.mu,
        model.Sigma,
        model.psi,
        model.pi,
        model.phi,
        model.W,
        model.active_places,
        model.active_concepts,
    ):
        arr = np.ascontiguousarray(a)
        h.update(str((arr.dtype.str, arr.shape)).encode())
        h.update(arr.tobytes())
    occ = model.require_map()
    h.update(np.ascontiguousarray(occ.data).tobytes())
    h.update(
        json.dumps(
            [
                list(model.vocabulary),
                occ.shape,
                occ.resolution,
                list(occ.origin),
                model.costmap,
                asdict(settings),
            ],
            sort_keys=True,
            default=str,
        ).encode()
    )
    if log_p is not None:
        h.update(np.ascontiguousarray(log_p, dtype=np.float64).tobytes())
    return h.hexdigest()


ARRIVAL_QUANTILE: float | None = None
"""Default ``arrival_quantile`` of :class:`PlannerSettings`: None, the path ends at the goal's candidate point
as in Algorithm 1. Stopping at the first cell inside the goal's region is an option: a place's Gaussian is not
its room, so a large quantile can end the path outside the room (docs/results.md)."""


@dataclass(frozen=True)
class PlannerSettings(GraphSettings):
    """Every knob of the planner: the precomputation's :class:`GraphSettings` (inherited, with their defaults),
    then the online ones.

    steps_per_stage / max_steps: the topological horizon E (max_steps overrides steps_per_stage x stages).
    instance_ratio: instances of a name have p(i | S) >= best / ratio.  start_min_posterior: places with
    p(i_0 | x_0) at least this are plausible start places (used with adjacent_only).  adjacent_only: steps go
    only between connected places and the first from a plausible start place or its neighbours
    (:mod:`~spcotmhp.planning.planner`; default: between any two candidates).  stage_constraint: every stage
    ends at a place its words name (:mod:`~spcotmhp.planning.planner`; False: Eq. 28 as written, for measuring
    the departure).  smooth: Algorithm 1, line 13 (tube re-planning, then line-of-sight shortcuts;
    :mod:`~spcotmhp.planning.assemble`).  arrival_quantile: the path ends at its first
    cell inside the goal place's region at this chi-square quantile (None: at the goal's candidate point).

    Out-of-range values raise :class:`~spcotmhp.errors.InvalidSettings` on construction.
    """

    steps_per_stage: int = 10
    max_steps: int | None = None
    instance_ratio: float = INSTANCE_RATIO
    start_min_posterior: float = 0.01
    smooth: bool = True
    arrival_quantile: float | None = ARRIVAL_QUANTILE
    adjacent_only: bool = False
    stage_constraint: bool = True

    def __post_init__(self) -> None:
        super().__post_init__()
        require_int(self.steps_per_stage, "steps_per_stage", 1, MAX_STEPS)
        if self.max_steps is not None:
            require_int(self.max_steps, "max_steps", 1, MAX_STEPS)
        require_range(self.instance_ratio, "instance_ratio", 1.0, math.inf, ">= 1")
        require_range(self.start_min_posterior, "start_min_posterior", 0.0, 1.0, "in [0, 1]")
        if self.arrival_quantile is not None:
            require_range(self.arrival_quantile, "arrival_quantile", 0.0, 1.0, "in (0, 1) (or None)", open_=True)

    def graph_settings(self) -> GraphSettings:
        return GraphSettings(**{f.name: getattr(self, f.name) for f in fields(GraphSettings)})

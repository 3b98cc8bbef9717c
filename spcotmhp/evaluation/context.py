"""Everything the methods need for one home, built once before the tasks run (the offline part, not timed as
online planning): the parameters (supervised "ideal" ones as in the paper's Experiment I, or learned without
labels), the cost map, the SpCoTMHP planning graph (shared with HPP-I/II), and the ground-truth places.

Beside the planner as shipped, the context holds the planner variants the tables compare (:data:`VARIANTS`):
without smoothing (Algorithm 1, line 13 off), without the stage constraint (every active place may complete
every stage, Eq. 28 alone decides: the planner's ``stage_constraint=False``), and the paper's method ("paper"):
Eq. 24 as written, optimality observed at every step of a leg with the destination's Gaussian
(``optimality="every_step"``, :mod:`spcotmhp.planning.graph`), steps of Eq. 28 only between Figure 3's connected
places (``adjacent_only=True``, the reference code's graph), no smoothing (Algorithm 1's line 13 is optional). It
keeps the stage constraint: Eq. 28 gives no rule for where a stage ends, and its maximum over 1..E steps ends at
the nearest place whatever its name (method spcotmhp-nostage); the reference code fixed each stage's place by
drawing it from p(i | S), our stage constraint lets Eq. 28 choose among the places the words name. So "ours
against the paper" differs in w-hat, the graph and smoothing, nothing else.

Homes without adjacency.csv get their place adjacency from the map (the learning package's connectivity rule);
the context says so in its notes, and the evaluation output carries them.
"""

from __future__ import annotations

import time
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import DatasetError
from spcotmhp.evaluation.methods import Offline, make_planners
from spcotmhp.evaluation.tasks import Place, build_places
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.costmap import CostMap, inflate
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.protocol import Planner

PARAMS = ("supervised", "learned")
CONNECTIVITY = ("auto", "hmm", "walk", "map")
VARIANTS: dict[str, dict[str, Any]] = {  # name: the planner's settings that differ from ours (PlannerSettings)
    "ours": {},
    "unsmoothed": {"smooth": False},
    "nostage": {"stage_constraint": False},
    "nostage-unsmoothed": {"stage_constraint": False, "smooth": False},
    "paper": {"optimality": "every_step", "adjacent_only": True, "smooth": False},
}


@dataclass
class HomeContext:
    """One home, ready to plan in.

    Attributes:
        name: the home's name.  dataset: the loaded dataset.  model: the parameters used by every method.
        params: "supervised" or "learned".  costmap: the cost map (log p(x|m)).
        planner: the SpCoTMHP :class:`~spcotmhp.planning.planner.HierarchicalPlanner` (its graph is reused by HPP).
        planners: every method's :class:`~spcotmhp.planning.protocol.Planner` by name
            (:data:`~spcotmhp.evaluation.methods.METHODS`; "spcotmhp" is ``planner``).
        places: the ground-truth places (regions, names).
        adjacency: the place adjacency the tasks use; adjacency_source: where it came from.
        cell_xy: (H, W, 2) world coordinates of the map's cell centres.
        timings: offline times in seconds (fit, costmap, graph precompute, HPP tables).
    """

    name: str
    dataset: Dataset
    model: SpatialConceptModel
    params: str
    costmap: CostMap
    planner: HierarchicalPlanner
    planners: dict[str, Planner]
    places: list[Place]
    adjacency: np.ndarray
    adjacency_source: str
    cell_xy: np.ndarray
    timings: dict = field(default_factory=dict)

    def notes(self) -> dict:
        """What the output reports about this home (``vs_truth``: learned parameters' NMI / ARI of the kept run's
        places and concepts against the truth, :func:`fit_params`; empty otherwise)."""
        return {
            "params": self.params,
            "adjacency": self.adjacency_source,
            "vs_truth": dict(self.model.info.get("vs_truth") or {}),
            "psi": str(self.model.info.get("psi_from", "given adjacency")),
            "places": [p.name for p in self.places],
            "precompute_s": round(float(self.timings.get("graph_s", 0.0)), 4),
            "fit_s": round(float(self.timings.get("fit_s", 0.0)), 4),
        }


def place_adjacency(dataset: Dataset) -> tuple[np.ndarray, str]:
    """The true places' adjacency: adjacency.csv, or else the learning package's connectivity rule applied to
    the supervised place Gaussians (:func:`spcotmhp.learning.connectivity.map_adjacency`)."""
    if dataset.adjacency is not None:
        return np.asarray(dataset.adjacency), "adjacency.csv"
    from spcotmhp.learning.connectivity import map_adjacency
    from spcotmhp.learning.supervised import fit_supervised

    truth_model = fit_supervised(dataset, adjacency="map")
    return np.asarray(map_adjacency(truth_model, dataset.map)), "connectivity from the map (no adjacency.csv)"


def fit_params(
    dataset: Dataset,
    params: str,
    adjacency: np.ndarray,
    seed: int,
    connectivity: str = "auto",
    learner: Mapping[str, Any] | None = None,
) -> SpatialConceptModel:
    """Supervised ("ideal", the paper's Experiment I: truth labels and the given adjacency) or learned (fully
    unsupervised Gibbs sampling: the learner's default number of runs and selection criterion; ``connectivity``
    is where its psi comes from, see :class:`~spcotmhp.learning.gibbs.SpCoTMHP`; ``learner``: other settings of
    the learner, e.g. ``hyper`` or a research ``variant``) parameters. Learned parameters say how close the kept run's
    partition is to the truth: ``model.info["vs_truth"]``, NMI and ARI of its places and concepts
    (:func:`~spcotmhp.evaluation.table6.score_run`)."""
    if params == "supervised":
        from spcotmhp.learning.supervised import fit_supervised

        return fit_supervised(dataset, adjacency=np.asarray(adjacency))
    if params == "learned":
        from spcotmhp.learning.selection import fit_runs

        if connectivity not in CONNECTIVITY:
            raise DatasetError(f"connectivity must be one of {', '.join(CONNECTIVITY)}, got {connectivity!r}")
        from spcotmhp.evaluation.table6 import score_run

        runs = fit_runs(dataset, seed=seed, connectivity=connectivity, **dict(learner or {}))
        model = runs.model_
        if dataset.truth_place is not None:
            model.info["vs_truth"] = score_run(dataset, runs.best_.places_, runs.best_.concepts_)
        return model
    raise DatasetError(f"params must be one of {', '.join(PARAMS)}, got {params!r}")


def check_model_map(model: SpatialConceptModel, dataset: Dataset) -> None:
    """A model evaluated on a dataset must have been made on its map: same size, resolution, origin and cells (the
    tasks' positions are the dataset's cells, the planner's are the model's).

    Raises:
        DatasetError: the maps differ (which property, both values or how many cells).
    """
    mine, theirs = model.require_map(), dataset.map
    for what, a, b in (
        ("size (rows x cols)", tuple(mine.shape), tuple(theirs.shape)),
        ("resolution (m)", mine.resolution, theirs.resolution),
        ("origin", tuple(mine.origin[:2]), tuple(theirs.origin[:2])),
        ("cells that differ", int(np.count_nonzero(mine.data != theirs.data)) if mine.shape == theirs.shape else 0, 0),
    ):
        if a != b:
            raise DatasetError(
                f"{dataset.name}: the model's map is not the dataset's ({what}: {a} against {b}); evaluate a model "
                "on the dataset it was learned or taught on"
            )


def build_context(
    dataset: Dataset,
    params: str = "supervised",
    seed: int = 0,
    connectivity: str = "auto",
    learner: Mapping[str, Any] | None = None,
    model: SpatialConceptModel | None = None,
) -> HomeContext:
    """Fit (or learn) the parameters and precompute everything offline for one home (``learner``: settings of
    the learner for learned parameters, ``fit_params``; ``model``: parameters already fitted, used as they are,
    ``params`` then only names them, e.g. "model"; a model's map must be the dataset's, :func:`check_model_map`)."""
    from spcotmhp.baselines.hpp import EDGE_COSTS, HPP

    if params not in PARAMS and model is None:
        raise DatasetError(f"params must be one of {', '.join(PARAMS)}, got {params!r}")
    timings = {}
    places = build_places(dataset)
    adjacency, source = place_adjacency(dataset)
    t0 = time.perf_counter()
    if model is None:
        model = fit_params(dataset, params, adjacency, seed, connectivity, learner)
    if model.map is None:
        model.map = dataset.map
    check_model_map(model, dataset)
    timings["fit_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    costmap = inflate(dataset.map, **model.costmap)
    timings["costmap_s"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    planner = HierarchicalPlanner(model, log_p=costmap.log_p)
    timings["graph_s"] = time.perf_counter() - t0
    variants = {
        name: planner if not overrides else HierarchicalPlanner(model, log_p=costmap.log_p, **overrides)
        for name, overrides in VARIANTS.items()
    }
    t0 = time.perf_counter()
    hpp = {name: HPP(planner.graph, cost) for name, cost in EDGE_COSTS.items()}
    timings["hpp_s"] = time.perf_counter() - t0
    planners = make_planners(Offline(model, costmap.log_p, dataset.map, variants, hpp))
    return HomeContext(
        dataset.name,
        dataset,
        model,
        params,
        costmap,
        planner,
        planners,
        places,
        adjacency,
        source,
        dataset.map.cell_centres(),
        timings,
    )

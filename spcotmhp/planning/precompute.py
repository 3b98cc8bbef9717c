"""What a planning graph is computed from (Algorithm 1, lines 1-3), for :meth:`~spcotmhp.planning.graph.
PlanningGraph.build`.

:func:`graph_inputs` gives, in order: the cost map log p(x|m) cropped to the bounding box of its traversable
cells (:func:`crop_cost_map`); the free regions and every place's territories in them
(:mod:`spcotmhp.planning.regions`, from :mod:`spcotmhp.learning.territory`); then, for the largest free region
and for every other region that holds places, on that region's own window: the candidate nodes, snapped into
their own territory (Alg. 1, line 2; :func:`~spcotmhp.planning.places.candidate_nodes`); Figure 3's connected
places (line 3); and every place's territory grown by ``tube_margin`` for smoothing
(:mod:`spcotmhp.planning.territory`). The graph then computes each region's cost-to-go fields (lines 4-6) and
w-hat (Eq. 27; :mod:`spcotmhp.planning.graph`, which gives the equations)."""

from __future__ import annotations

from typing import Any

import numpy as np

from spcotmhp.errors import InvalidSettings, ModelError
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.logspace import log_gaussian
from spcotmhp.metric.costmap import inflate
from spcotmhp.metric.grid_ops import find_boxes
from spcotmhp.planning.graph_settings import GraphSettings
from spcotmhp.planning.places import candidate_nodes, candidate_points, connected_places
from spcotmhp.planning.regions import FreeRegions, free_regions
from spcotmhp.planning.stops import window_stops
from spcotmhp.planning.territory import grown_territories


def graph_inputs(
    model: SpatialConceptModel, settings: GraphSettings, log_p_full: np.ndarray | None
) -> tuple[dict[str, Any], dict[int, dict[str, Any]]]:
    """The fields of a new :class:`~spcotmhp.planning.graph.PlanningGraph` of ``model`` under ``settings`` on the
    main (largest) free region, all but its ``key`` and what the cost-to-go fields give (module docstring), and the
    same for every other free region that holds places (:mod:`spcotmhp.planning.regions`), by region label;
    ``log_p_full`` overrides the cost map."""
    occ = model.require_map()
    log_p, (r0, r1, c0, c1) = crop_cost_map(
        occ, log_p_full if log_p_full is not None else inflate(occ, **model.costmap).log_p
    )
    traversable = np.isfinite(log_p)
    centres = occ.window_centres(int(r0), int(c0), *log_p.shape)
    offset = (int(r0), int(c0))
    # numba's threads for the most probable place only where the fields will start them (the portal graph, for
    # any two nodes or more), so that a small map's build, before worker processes fork, starts no thread
    regions = free_regions(model, traversable, centres, offset, parallel=not settings.dense(2, log_p.size))
    main = regions.labels == regions.main
    shared = {  # the same for every region: Figure 3's edges, the candidate points (Alg. 1, line 2)
        "connected": connected_places(model, settings.edge_threshold),
        "points": candidate_points(
            model, settings.n_candidates, np.random.default_rng(settings.seed), settings.candidate_quantile
        ),
    }
    inputs = _region_inputs(model, settings, regions, regions.main, offset, (0, 0), log_p, main, centres, shared)
    inputs["traversable"] = traversable  # the main graph keeps every traversable cell (and the map's crop)
    inputs["info"]["crop"] = [int(r0), int(r1), int(c0), int(c1)]
    boxes = find_boxes(regions.labels)
    subs = {}
    for g in regions.with_places():
        box = boxes[g - 1]
        assert box is not None  # a region with places has cells
        rows, cols = box
        sub = _region_inputs(
            model,
            settings,
            regions,
            g,
            offset,
            (rows.start, cols.start),
            np.ascontiguousarray(log_p[rows, cols]),
            regions.labels[rows, cols] == g,
            centres[rows, cols],
            shared,
        )
        if len(sub["node_place"]):
            subs[g] = sub
    act = np.flatnonzero(model.active_places)
    planned = set(inputs["node_place"].tolist()).union(*(s["node_place"].tolist() for s in subs.values()))
    unreachable = sorted(set(act.tolist()) - planned)
    plannable = main | np.isin(regions.labels, list(subs))
    inputs.update(region=regions.labels, plannable=plannable)
    for part in (inputs, *subs.values()):
        part["info"]["unreachable_places"] = unreachable
    return inputs, subs


def _region_inputs(
    model: SpatialConceptModel,
    settings: GraphSettings,
    regions: FreeRegions,
    label: int,
    crop_offset: tuple[int, int],
    corner: tuple[int, int],
    log_p: np.ndarray,
    mask: np.ndarray,
    centres: np.ndarray,
    shared: dict[str, Any],
) -> dict[str, Any]:
    """The graph inputs of free region ``label`` on its window of the crop (corner at crop cell ``corner``; the
    crop's at map cell ``crop_offset``): ``log_p``, ``mask`` (the region's cells) and ``centres`` over the window,
    its places' territories, candidate nodes (from ``shared["points"]``) and grown territories."""
    occ = model.require_map()
    (r0, c0), (h, w) = corner, mask.shape
    offset = (crop_offset[0] + r0, crop_offset[1] + c0)
    territory = np.where(mask, regions.territory[r0 : r0 + h, c0 : c0 + w], -1)
    fallback = [(k, (r - r0, c - c0)) for k, (r, c) in regions.fallback.get(label, [])]
    stops = window_stops(model.costmap, occ.resolution, settings.stop_cost, log_p, centres)
    node_place, cells, end_term, no_stop = candidate_nodes(
        model,
        settings.n_candidates,
        settings.seed,
        settings.candidate_quantile,
        offset,
        mask,
        territory,
        fallback,
        shared["points"],
        stops,
    )
    act = np.flatnonzero(model.active_places)
    crop = [offset[0], offset[0] + h, offset[1], offset[1] + w]
    return {
        "model": model,
        "settings": settings,
        "offset": offset,
        "log_p": log_p if label == regions.main else np.where(mask, log_p, -np.inf),
        "traversable": mask,
        "node_place": node_place,
        "node_cell": cells,
        "end_term": end_term if settings.optimality == "end" else np.zeros_like(end_term),  # every step: in the field
        "dist": [],
        "next_step": [],
        "w_hat": np.empty(0),
        "w_hat_metric": np.empty(0),
        "log_transition": np.empty(0),
        "connected": shared["connected"],
        "time_precompute_s": 0.0,
        "info": {"n_nodes": len(cells), "region": int(label), "crop": crop, "stop_fallback": no_stop},
        "_centres": centres,
        "territory": territory,
        "main": mask,
        "usable": np.ones(len(cells), dtype=bool),
        "_territories": grown_territories(territory, act, settings.tube_margin / occ.resolution),
    }


def crop_cost_map(occ, log_p_full: np.ndarray) -> tuple[np.ndarray, tuple[int, int, int, int]]:
    """The cost map log p(x|m) on the bounding box of its traversable (finite) cells, and the box (r0, r1, c0,
    c1) in map cells."""
    if log_p_full.shape != occ.shape:
        raise ModelError(f"log_p has shape {log_p_full.shape}, the model's map {occ.shape}")
    finite = np.isfinite(log_p_full)
    if not finite.any():
        raise ModelError("the model's map has no free cell")
    rows, cols = np.flatnonzero(finite.any(axis=1)), np.flatnonzero(finite.any(axis=0))
    r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
    return np.ascontiguousarray(log_p_full[r0:r1, c0:c1]), (r0, r1, c0, c1)


def every_step_cost(model: SpatialConceptModel, map_cost: np.ndarray, centres: np.ndarray, place: int) -> np.ndarray:
    """The step cost of Eq. 24 as written into a node of ``place`` b: ``map_cost`` (log|A| - log p(x|m), inf off
    the traversable cells) minus log N(x | mu_b, Sigma_b) at the cells' ``centres`` (h, w, 2). A Gaussian so narrow
    that its density exceeds |A| / p(x|m) somewhere gives a negative cost, which no shortest-path search handles:
    refused (:class:`~spcotmhp.errors.InvalidSettings`) rather than clipped."""
    log_n = log_gaussian(centres.reshape(-1, 2), model.mu[place : place + 1], model.Sigma[place : place + 1])
    cost = map_cost - log_n.reshape(map_cost.shape)
    if (cost < 0).any():
        raise InvalidSettings(
            f"place {place}'s Gaussian is so narrow that the step cost of Eq. 24 at every step, log|A| - log p(x|m) "
            f"- log N(x | mu, Sigma), is negative (min {cost.min():.3g}); plan with optimality 'end'"
        )
    return cost

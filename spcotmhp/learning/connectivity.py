"""Which places are directly connected: from the walk (trajectory or event order) or from the map's free space.

``walk_adjacency``: places visited one right after the other are connected.  With a trajectory, each pose gets
its most probable place (N(x_t | mu_k, Sigma_k) p(k) over the active places), stays shorter than ``min_dwell``
poses are dropped as boundary flicker, and consecutive places of what remains are connected.  Without one, the
places of consecutive teaching events are (the order in which a person taught the rooms, which need not be a
walk: use it only when the teaching was given along a walk).

``map_adjacency`` decides from the free space of the map alone (no trajectory, no adjacency).

Rule "territory" (the default): partition the cells the robot can occupy (free, known, outside the inscribed
radius of the model's cost map) among the places (:mod:`spcotmhp.learning.territory`: most probable place,
made connected by geodesic growth from each place's own piece) and connect the places whose territories touch.
Every robot cell of a free component is labelled, so whenever the robot can drive from one place to another
the place graph connects them, directly or through other places, and a place whose mean or teaching points lie
in unknown or occupied cells still owns the free cell nearest its mean and so gets its edges. (The rules below
decide pair by pair and cannot promise that: on homes of the same public source they left a bedroom with no edge
at all.)

Rule "partition": walk the free-space geodesic between the means of places a and b, and label
every cell of it with its most probable place, argmax_k N(x | mu_k, Sigma_k) p(k) over the active places (the
partition of the map that the place posterior induces, cf. Eq. 3).  a and b are directly connected when that
walk passes through no third place: runs of a third label shorter than ``min_run_m`` are ignored as grazing a
corner of its region.  Rule "density": a and b are connected unless the geodesic enters the high-density
region of a third place, Mahalanobis distance below ``radius`` (in standard deviations).

The geodesic is the shortest 8-connected path over the free cells of the occupancy map (``grid_search``); place
means that fall in a wall or unknown cell start from the nearest free cell.  Places that cannot reach each
other are not connected.
"""

from __future__ import annotations

import dataclasses
from typing import TYPE_CHECKING

import numpy as np

from spcotmhp.errors import ModelError
from spcotmhp.learning.hmm import runs
from spcotmhp.learning.hmm import trajectory_places as hmm_trajectory_places
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.learning.territory import place_territories, territory_adjacency
from spcotmhp.logspace import log_gaussian
from spcotmhp.metric.costmap import inflate
from spcotmhp.metric.grid_search import cost_to_go, path_from_field
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.metric.snap import snap

if TYPE_CHECKING:  # not at run time: loading a model for planning reads this module and needs no dataset
    from spcotmhp.datasets.dataset import Dataset

ADJACENCY_CONCENTRATION = 0.1  # psi[k] = mean of Dir(0.1 + A[k]), the authors' conversion (Experiment I)
RULES = ("territory", "partition", "density")
SOURCES = ("auto", "hmm", "walk", "map")


def trajectory_places(model: SpatialConceptModel, trajectory: np.ndarray, min_dwell: int = 3) -> np.ndarray:
    """The sequence of places visited along ``trajectory`` (most probable active place per pose under the
    model's means and place prior, stays shorter than ``min_dwell`` poses dropped, repeats collapsed;
    ``hmm.trajectory_places``)."""
    return hmm_trajectory_places(trajectory, model.mu, model.Sigma, model.log_place_prior(), min_dwell)


def walk_adjacency(
    model: SpatialConceptModel, dataset: Dataset, event_places: np.ndarray | None = None, min_dwell: int = 3
) -> np.ndarray:
    """(K, K) 0/1 adjacency of places visited consecutively: along the dataset's trajectory when it has one,
    else along the teaching events (``event_places``, default each event's most probable place)."""
    if dataset.trajectory is not None:
        seq = trajectory_places(model, np.asarray(dataset.trajectory, dtype=float), min_dwell)
    elif event_places is not None:
        seq = np.asarray(event_places)
    else:
        seq = np.argmax(model.log_place_density(dataset.positions) + model.log_place_prior(), axis=1)
    A = np.zeros((model.K, model.K), dtype=np.int64)
    A[seq[:-1], seq[1:]] = 1
    A = np.maximum(A, A.T)
    act = np.flatnonzero(model.active_places)
    A[act, act] = 1
    return A


def apply_connectivity(
    model: SpatialConceptModel, dataset: Dataset, how: str = "auto", event_places: np.ndarray | None = None
) -> SpatialConceptModel:
    """Set ``model.psi`` for planning and record the source in ``model.info["psi_from"]``.

    "hmm": keep the posterior mean of the learned HMM transitions (the paper); "walk": psi from
    ``walk_adjacency``; "map": psi from ``map_adjacency``; "auto": the union of both when the dataset has a
    trajectory (the walk's evidence kept, the map's guarantee that free space connects the places added), else
    "map".  Adjacencies become psi[k] = mean of Dir(0.1 + A[k]), the form of the paper's Experiment I.  (The
    HMM's self-transitions, many utterances per room, outweigh the few doorway crossings, so under the planner's
    edge rule (psi_ab + psi_ba) / 2 >= 1 / K its psi would show almost no edges; the order of the utterances
    alone, e.g. fifteen per room taught room after room, says little about which rooms touch.)
    """
    if how not in SOURCES:
        raise ModelError(f"connectivity must be one of {SOURCES}, got {how!r}")
    if how == "auto" and dataset.trajectory is not None:
        A = np.maximum(walk_adjacency(model, dataset, event_places), map_adjacency(model, dataset.map))
        model.psi = psi_from_adjacency(A)
        how = "walk+map"
    elif how == "auto":
        how = "map"
    if how == "walk":
        model.psi = psi_from_adjacency(walk_adjacency(model, dataset, event_places))
    elif how == "map":
        model.psi = psi_from_adjacency(map_adjacency(model, dataset.map))
    model.info["psi_from"] = how
    return model


def psi_from_adjacency(adjacency: np.ndarray, concentration: float = ADJACENCY_CONCENTRATION) -> np.ndarray:
    """psi[k] = E[Dir(concentration + A[k])] = (c + A[k]) / (K c + sum_j A[k, j]); A is 0/1 with diagonal 1."""
    A = np.asarray(adjacency, dtype=float)
    if A.ndim != 2 or A.shape[0] != A.shape[1]:
        raise ModelError(f"adjacency must be a square matrix, got shape {A.shape}")
    if not np.isin(A, (0.0, 1.0)).all():
        raise ModelError("adjacency entries must be 0 or 1")
    a = concentration + A
    return a / a.sum(axis=1, keepdims=True)


def nearest_free_cells(occ_map: OccupancyMap, xy: np.ndarray) -> np.ndarray:
    """(n, 2) (row, col) of the free cell nearest to each point (clipped onto the map first)."""
    free = occ_map.free
    if not free.any():
        raise ModelError("the map has no free cell; connectivity from the map needs free space")
    return snap(free, occ_map.world_to_cell(np.asarray(xy, dtype=float)))


def map_adjacency(
    model: SpatialConceptModel,
    occ_map: OccupancyMap | None = None,
    rule: str = "territory",
    min_run_m: float = 0.3,
    radius: float = 1.0,
) -> np.ndarray:
    """(K, K) 0/1 adjacency of the model's places from the map's free space (module docstring); the diagonal
    is 1 on active places, rows and columns of inactive places are 0."""
    occ_map = occ_map if occ_map is not None else model.map
    if occ_map is None:
        raise ModelError("connectivity from the map needs a map (the model has none)")
    if rule not in RULES:
        raise ModelError(f"rule must be one of {RULES}, got {rule!r}")
    act = np.flatnonzero(model.active_places)
    K = model.K
    A = np.zeros((K, K), dtype=np.int64)
    A[act, act] = 1
    if len(act) < 2:
        return A
    if rule == "territory":
        robot = inflate(occ_map, **model.costmap).free
        if not robot.any():
            raise ModelError("the map has no free cell the robot fits in; connectivity from the map needs one")
        if model.map is None or model.map.shape != occ_map.shape:
            model = dataclasses.replace(model, map=occ_map)
        territory = place_territories(model, robot, occ_map.cell_centres())
        return np.maximum(A, territory_adjacency(territory, K)) * (A.diagonal()[:, None] * A.diagonal()[None, :])
    cells = nearest_free_cells(occ_map, model.mu[act])
    unit = np.where(occ_map.free, 1.0, np.inf)
    mu, Sigma = model.mu[act], model.Sigma[act]
    log_prior = model.log_place_prior()[act]
    for i in range(len(act) - 1):
        field, nxt = cost_to_go(unit, cells[i : i + 1])
        for j in range(i + 1, len(act)):
            path = path_from_field(field, nxt, cells[j])
            if path is None:
                continue
            xy = occ_map.cell_to_world(path.cells)
            if rule == "partition":
                ok = _partition_ok(xy, mu, Sigma, log_prior, i, j, min_run_m / occ_map.resolution)
            else:
                ok = _density_ok(xy, mu, Sigma, i, j, radius)
            if ok:
                A[act[i], act[j]] = A[act[j], act[i]] = 1
    return A


def _partition_ok(xy, mu, Sigma, log_prior, i, j, min_run_cells) -> bool:
    """No run of a third place's label of ``min_run_cells`` cells or more along the path ``xy``."""
    labels = np.argmax(log_gaussian(xy, mu, Sigma) + log_prior, axis=1)
    run_labels, lengths = runs(labels)
    return not np.any((run_labels != i) & (run_labels != j) & (lengths >= min_run_cells))


def _density_ok(xy, mu, Sigma, i, j, radius) -> bool:
    inv = np.linalg.inv(Sigma)
    d = xy[:, None, :] - mu[None, :, :]
    maha2 = np.einsum("nki,kij,nkj->nk", d, inv, d)
    others = np.ones(len(mu), dtype=bool)
    others[[i, j]] = False
    return not np.any(maha2[:, others] < radius * radius)

"""Free regions: the robot's free space cut into pieces (a closed door, a gap in the map, furniture), and the
places the planner can reach in each (Algorithm 1, line 2, for every piece).

A *free region* is a 4-connected component of the traversable cells (free, known, outside the robot's inscribed
radius; :mod:`spcotmhp.metric.snap` says why 4-connected components are exactly what the grid search joins). The
robot cannot drive from one region to another, so the planner plans within the start's region
(:meth:`~spcotmhp.planning.graph.PlanningGraph.for_start`), and each region with places has its own graph.

**Which places a region holds.** Territories (:mod:`spcotmhp.learning.territory`) give each place one piece of
the free space, grown from one seed, so a place lies in one region only, which may be a pocket cut off by
furniture while most of the place's mass lies in the region around it (a living room whose mean falls inside a
ring of sofas). The rule here: a place belongs to every region where its Gaussian puts real mass, i.e. where its
``REACH_SIGMAS`` ellipse (Mahalanobis distance 2: 86% of the place's mass) holds a cell of the region. In a region
other than its own territory's, its seed is chosen by its own posterior p(i | x) of Eq. 3 (the place posterior,
eta N(x | mu_i, Sigma_i) p(i)) over the region's cells inside that ellipse: the cell where p(i | x) is highest
(compared as log-odds, which do not round to 1), with the piece around it where the place is the most probable
one, else that cell alone (:func:`~spcotmhp.learning.territory.partition`). Territories are then grown from every
seed at once, so the region's cells are shared among the places it holds, and the place's candidate point is
snapped into its territory there as in the main rule (:func:`~spcotmhp.planning.places.candidate_nodes`). When a
region is too small to give the place a cell of its own (a single cell already taken by another place's seed), its
candidate point is that cell anyway (``FreeRegions.fallback``). Regions where no place reaches have no graph: a
start there is refused.

The ellipse is the acceptance test's criterion ("no place refused while its 2-sigma ellipse holds a reachable
safe cell"), not a tuned constant: a place that puts less than that on a region is not taught there.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numba import njit

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.learning.territory import most_probable_labels, partition, place_anchors
from spcotmhp.logspace import log_gaussian, logsumexp
from spcotmhp.metric.grid_ops import label4, label_sizes

REACH_SIGMAS = 2.0
"""A place reaches a region whose cells lie within this Mahalanobis distance of its mean (module docstring)."""

CHUNK = 8192  # cells whose place posterior is computed together (memory CHUNK x K)

__all__ = ["REACH_SIGMAS", "FreeRegions", "free_regions", "reach_seeds"]


@dataclass
class FreeRegions:
    """The free regions of a crop and the places' territories in all of them (module docstring).

    ``labels``: (h, w) int32 region of each traversable cell (1..n, 0 elsewhere); ``main``: the largest region's
    label; ``territory``: (h, w) place of each cell, -1 where none; ``home``: (K,) the region of each place's own
    territory (the one :func:`~spcotmhp.learning.territory.place_territories` gives; 0: none); ``fallback``: region
    -> ``(place, (row, col))`` candidate points of places that reach the region but own none of its cells."""

    labels: np.ndarray
    main: int
    territory: np.ndarray
    home: np.ndarray
    fallback: dict[int, list[tuple[int, tuple[int, int]]]] = field(default_factory=dict)

    def with_places(self) -> list[int]:
        """The regions other than the main one where some place has a territory or a candidate point."""
        held = set(np.unique(self.labels[self.territory >= 0]).tolist()) | set(self.fallback)
        return sorted(int(r) for r in held if r != self.main)


def free_regions(
    model: SpatialConceptModel,
    traversable: np.ndarray,
    centres: np.ndarray,
    offset: tuple[int, int] = (0, 0),
    parallel: bool = False,
) -> FreeRegions:
    """The regions of ``traversable`` (crop cells whose centres are ``centres``, its corner at map cell ``offset``)
    and the territories of every place in each (module docstring); ``parallel``: the most probable places on
    numba's threads (:func:`~spcotmhp.learning.territory.posterior_arg_max`).

    >>> from spcotmhp.learning.model import SpatialConceptModel
    >>> from spcotmhp.metric.maps import OccupancyMap

    Two rooms behind a closed door; place 0 (sd 2 m) reaches one cell of the right room, (1, 5), at Mahalanobis
    distance 2, where place 1 is more probable: that cell alone is its seed there.

    >>> free = np.ones((3, 9), dtype=bool); free[:, 4] = False  # the closed door
    >>> occ = OccupancyMap(data=np.where(free, 0, 100).astype(np.int8), resolution=1.0)
    >>> m = SpatialConceptModel(mu=np.array([[1.5, 1.5], [7.5, 1.5]]), Sigma=np.array([4 * np.eye(2), np.eye(2)]),
    ...     psi=np.full((2, 2), 0.5), pi=np.ones(1), phi=np.full((1, 2), 0.5), W=np.ones((1, 1)), vocabulary=["x"],
    ...     map=occ)
    >>> r = free_regions(m, free, occ.cell_centres())
    >>> r.territory
    array([[ 0,  0,  0,  0, -1,  1,  1,  1,  1],
           [ 0,  0,  0,  0, -1,  0,  1,  1,  1],
           [ 0,  0,  0,  0, -1,  1,  1,  1,  1]])
    >>> r.home.tolist(), r.with_places()
    ([1, 2], [2])
    """
    labels, n = label4(traversable)
    sizes = label_sizes(labels, n)
    sizes[0] = 0
    main = int(np.argmax(sizes)) if n else 0
    act = np.flatnonzero(model.active_places)
    best = most_probable_labels(model, traversable, centres, parallel=parallel)
    home = np.zeros(model.K, dtype=np.int64)
    territory = np.full(labels.shape, -1, dtype=np.int64)
    if n == 0 or len(act) == 0:
        return FreeRegions(labels, main, territory, home)
    anchors = place_anchors(model, traversable, offset)
    base = partition(best, anchors)
    _set_homes(home, act, base, labels)  # one region per place: its territory grows from one seed
    place, cell, region = reach_seeds(model, labels, centres, home)
    out = partition(best, anchors, np.searchsorted(act, place), cell) if len(place) else base
    territory = np.where(out >= 0, act[np.maximum(out, 0)], -1)
    fallback: dict[int, list[tuple[int, tuple[int, int]]]] = {}
    if len(place):  # (place, region) pairs that own a cell, as one integer each
        owned = np.unique(territory[out >= 0] * (n + 1) + labels[out >= 0])
        for k, (r, c), g in zip(place.tolist(), cell.tolist(), region.tolist(), strict=True):
            if not np.isin(k * (n + 1) + g, owned):
                fallback.setdefault(int(g), []).append((int(k), (int(r), int(c))))
    return FreeRegions(labels, main, territory, home, fallback)


def reach_seeds(
    model: SpatialConceptModel, labels: np.ndarray, centres: np.ndarray, home: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(place, cell, region)``: for every active place and every region other than ``home[place]`` holding a
    cell within ``REACH_SIGMAS`` of the place's mean, the cell of that region inside the ellipse where the place
    posterior p(i | x) (Eq. 3) is highest (ties: the first in row-major order), in crop cells."""
    act = np.flatnonzero(model.active_places)
    mu, Sigma = model.mu[act], model.Sigma[act]
    prior = model.log_place_prior()[act]
    xs, ys = centres[0, :, 0], centres[:, 0, 1]  # increasing: columns go east, rows go north
    width = labels.shape[1]
    out: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    for i, k in enumerate(act):
        half = REACH_SIGMAS * np.sqrt(np.diag(Sigma[i]))  # the ellipse's bounding box: r sqrt(Sigma_xx), ...
        c0, c1 = np.searchsorted(xs, mu[i, 0] - half[0]), np.searchsorted(xs, mu[i, 0] + half[0], side="right")
        r0, r1 = np.searchsorted(ys, mu[i, 1] - half[1]), np.searchsorted(ys, mu[i, 1] + half[1], side="right")
        box = labels[r0:r1, c0:c1]
        rows, cols = np.nonzero((box > 0) & (box != home[k]))
        if not len(rows):
            continue
        rows, cols = rows + r0, cols + c0
        xy = centres[rows, cols]
        d = xy - mu[i]
        inv = np.linalg.inv(Sigma[i])
        inside = np.einsum("ni,ij,nj->n", d, inv, d) <= REACH_SIGMAS**2
        if not inside.any():
            continue
        rows, cols, xy = rows[inside], cols[inside], xy[inside]
        odds = np.concatenate([_log_odds(xy[s : s + CHUNK], mu, Sigma, prior, i) for s in range(0, len(xy), CHUNK)])
        region = labels[rows, cols]
        order = np.lexsort((rows * width + cols, -odds, region))  # by region, best odds first, then row-major
        first = order[np.r_[True, region[order][1:] != region[order][:-1]]]
        cells = np.stack([rows[first], cols[first]], axis=1)
        out.append((np.full(len(first), k, dtype=np.int64), cells, region[first]))
    if not out:
        return np.empty(0, dtype=np.int64), np.empty((0, 2), dtype=np.int64), np.empty(0, dtype=np.int64)
    place, cell, region = (np.concatenate(parts) for parts in zip(*out, strict=True))
    return place, cell.astype(np.int64), region.astype(np.int64)


def _log_odds(xy: np.ndarray, mu: np.ndarray, Sigma: np.ndarray, prior: np.ndarray, i: int) -> np.ndarray:
    """log p(i | x) - log(1 - p(i | x)) at points ``xy`` over the active places (Eq. 3 with the place prior):
    the score of i minus the log-sum of the others' (+inf when i is the only place)."""
    score = log_gaussian(xy, mu, Sigma) + prior
    others = np.delete(score, i, axis=1)
    rest = logsumexp(others, axis=1) if others.shape[1] else np.full(len(xy), -np.inf)
    return score[:, i] - rest


@njit(cache=True)
def _set_homes(home, act, base, labels):  # pragma: no cover - numba
    """``home[act[base[c]]] = labels[c]`` for every cell c of ``base`` >= 0 in raster order, the last one kept (as
    the fancy assignment it replaces, 0.8 s at 16 megapixels; a place's cells lie in one region)."""
    h, w = base.shape
    for r in range(h):
        for c in range(w):
            if base[r, c] >= 0:
                home[act[base[r, c]]] = labels[r, c]

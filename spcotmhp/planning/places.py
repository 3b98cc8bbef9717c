"""The places of the topological level as the planner uses them: candidate points, connectivity, instance sets
and regions (Algorithm 1, lines 2-3, and the hard constraints of the search).

Definitions (each a documented choice; the property tests check the planner against them):

* **Candidate points** (Alg. 1, line 2; Section 3.4): N_i points per active place i. The first is the mean mu_i
  (the paper's N = 1 setting); the others are seeded samples from N(mu_i, Sigma_i) kept inside the place's
  ``quantile`` ellipse (rejection), so that "the candidate waypoints follow the rough shape of the place".
  Each is snapped to the nearest traversable cell (p(x|m) > 0) of its place's territory in a free region (the
  largest one, and every other region the place reaches: :mod:`spcotmhp.planning.regions`), and duplicates after
  snapping are dropped.
* **Connected places** (Alg. 1, line 3): a and b are connected when (psi_ab + psi_ba) / 2 >= 1 / K, the rule of
  the paper's Figure 3 (which writes >; with >= a fully connected home, whose psi is uniform = 1 / K, keeps its
  edges); partial paths are precomputed only between candidates of connected places.
* **Instances of a named place**: the active places whose p(i | S) is at least 1 / ``ratio`` of the best
  (default ratio 4). Several places share a name (three bedrooms), and their posteriors differ a little, so
  taking only the arg-max would drop real instances, while a place that a concept only leaks onto, or a
  beta-smoothed name, is several times less probable (docs/results.md gives the measured factors). An N-best
  bag {bath: 0.7, bedroom: 0.3} (Eq. 25) keeps the bedrooms out; a near tie (0.6 / 0.4) lets both names in,
  and the path cost then decides.
* **Named places**: with learned parameters a concept can spread over places of other names (a concept that
  says "bath" 70% of the time also covering a bedroom), so that p(i | S) for "bath" keeps a bedroom within the
  ratio. A place is then an instance of S only if its name (its label, what the explanation calls it) carries
  every word of S, or of one of S's N-best alternatives (:func:`named_places`), whenever some place's name
  does: "east corridor" names the east corridor only, "corridor" names both corridors, and an N-best bag
  {bath: 0.6, bedroom: 0.4} names baths and bedrooms (p(i | S) then decides, as on supervised parameters). A
  plan that ends in a place whose name is none of the requested words misreads the instruction. When no label
  carries a known word (a learned model may name no place by it), p(i | S) alone decides.
* **Region of a place**: cells within the ``quantile`` Mahalanobis ellipse of its Gaussian (chi-square with 2
  degrees of freedom, default 0.95) where it is also the most probable place p(i | x). Avoided places block
  their regions; "inside a place" means inside its ellipse. A plan *arrives* in its goal place at the first
  cell of the goal's region at a smaller quantile (the planner's ``arrival_quantile``), which is inside the
  0.95 ellipse too.
* **Territory of a place**: the cells where it is the most probable place, arg max_i p(i | x)
  (:func:`most_probable_place`); every cell of the map belongs to exactly one territory. Path smoothing
  re-plans inside the territories the assembled path runs through (:mod:`spcotmhp.planning.assemble`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from spcotmhp.errors import UnknownPlaceWord
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.learning.territory import posterior_arg_max
from spcotmhp.logspace import log_gaussian
from spcotmhp.metric.grid_ops import find_boxes
from spcotmhp.metric.snap import largest_component as main_component
from spcotmhp.metric.snap import snap
from spcotmhp.planning.stops import most_probable

__all__ = [
    "candidate_points",
    "chi2_2d",
    "connected_places",
    "inside_places",
    "instance_places",
    "LabelIndex",
    "mahalanobis2",
    "main_component",
    "most_probable_place",
    "named_places",
    "place_regions",
]


def chi2_2d(quantile: float) -> float:
    """The ``quantile`` of the chi-square distribution with 2 degrees of freedom: -2 log(1 - q)."""
    if not 0.0 < quantile < 1.0:
        raise ValueError(f"quantile must be in (0, 1), got {quantile!r}")
    return float(-2.0 * np.log1p(-quantile))


def mahalanobis2(x: np.ndarray, mu: np.ndarray, Sigma: np.ndarray) -> np.ndarray:
    """Squared Mahalanobis distances of points x (..., 2) to every Gaussian: (..., K)."""
    inv = np.linalg.inv(Sigma)
    d = np.asarray(x, dtype=float)[..., None, :] - mu
    return np.einsum("...ki,kij,...kj->...k", d, inv, d)


def candidate_points(
    model: SpatialConceptModel, n: int, rng: np.random.Generator, quantile: float = 0.95
) -> tuple[np.ndarray, np.ndarray]:
    """Candidate points (Alg. 1, line 2): ``(place, xy)`` with place (M,) and xy (M, 2), places in index order,
    the mean first, then ``n - 1`` samples inside the ``quantile`` ellipse."""
    if n < 1:
        raise ValueError(f"n_candidates must be >= 1, got {n}")
    limit = chi2_2d(quantile)
    places, points = [], []
    for k in np.flatnonzero(model.active_places):
        pts = [model.mu[k]]
        chol = np.linalg.cholesky(model.Sigma[k])
        while len(pts) < n:
            z = rng.standard_normal((4 * n, 2))
            z = z[(z * z).sum(axis=1) <= limit]  # inside the ellipse: |z|^2 = Mahalanobis^2
            pts.extend(model.mu[k] + z[: n - len(pts)] @ chol.T)
        places.extend([k] * n)
        points.extend(pts[:n])
    return np.asarray(places, dtype=np.int64), np.asarray(points, dtype=float).reshape(-1, 2)


def connected_places(model: SpatialConceptModel, threshold: float | None = None) -> np.ndarray:
    """(K, K) bool: (psi_ab + psi_ba) / 2 >= threshold (default 1 / K, the paper's Figure 3; compared with a
    relative tolerance of 1e-9), active places only; the diagonal is True (moves between candidates of one
    place)."""
    thr = 1.0 / model.K if threshold is None else float(threshold)
    act = np.asarray(model.active_places, dtype=bool)
    conn = ((model.psi + model.psi.T) / 2.0 >= thr * (1.0 - 1e-9)) & act[:, None] & act[None, :]
    conn[np.diag_indices(model.K)] = act
    return conn


def instance_places(log_place_given_words: np.ndarray, ratio: float = 4.0) -> np.ndarray:
    """(K,) bool: the places named by a bag S, from log p(i | S) (-inf on inactive places):
    log p(i | S) >= max - log(ratio)."""
    if ratio < 1.0:
        raise ValueError(f"instance_ratio must be >= 1, got {ratio!r}")
    lp = np.asarray(log_place_given_words)
    return np.isfinite(lp) & (lp >= lp.max() - np.log(ratio))


class LabelIndex:
    """The places whose label holds each word ((K,) bool per word), built once per set of labels so that
    :func:`named_places` is a few mask operations per query."""

    def __init__(self, labels: Sequence[str]) -> None:
        self.labels = list(labels)
        self.size = len(labels)
        self.masks: dict[str, np.ndarray] = {}
        for k, label in enumerate(labels):
            for word in label.split():
                self.masks.setdefault(word, np.zeros(self.size, dtype=bool))[k] = True


def named_places(labels: Sequence[str] | LabelIndex, phrases: Sequence[Mapping[str, float]]) -> np.ndarray:
    """(K,) bool: places whose label (space-separated words; or a :class:`LabelIndex` of the labels) holds every
    word of at least one of ``phrases``."""
    index = labels if isinstance(labels, LabelIndex) else LabelIndex(labels)
    out = np.zeros(index.size, dtype=bool)
    for phrase in phrases:
        bag = [w for w, c in phrase.items() if c > 0]
        if not bag:
            continue
        named = np.ones(index.size, dtype=bool)
        for word in bag:
            named &= index.masks.get(word, False)
        out |= named
    return out


def by_label(index: LabelIndex, query: Any, stage: bool = False) -> np.ndarray:
    """(K,) the places whose label carries all the words of a place query (:class:`~spcotmhp.planning.
    instructions.PlaceQuery`, or one of its N-best alternatives; :func:`named_places`), checked as instructions
    need: two or more words that each belong to some label but name no place together ("the kitchen bedroom") are
    refused. A word that several names share ("the corridor" beside an east and a south corridor) names the places
    of all of them, as a name several places share does ("the bedroom"): the closest is meant, and the plan's
    explanation names the others (issue 34; ``stage`` is kept for callers, the rule is the same for every role).

    Raises:
        UnknownPlaceWord: no place is called so.
    """
    named = named_places(index, query.phrases)
    if named.any():
        return named
    masks = index.masks
    if len(query.phrases) == 1 and len(query.words) > 1 and all(w in masks for w in query.words):
        raise UnknownPlaceWord(
            f"no place is called {query.label!r}: "
            + "; ".join(
                f"'{w}' names {', '.join(sorted({index.labels[k] for k in np.flatnonzero(masks[w])}))}"
                for w in query.words
            )
            + "; name one place"
        )
    return named


def inside_places(
    model: SpatialConceptModel, xy: np.ndarray, places: Sequence[int] | np.ndarray, quantile: float = 0.95
) -> np.ndarray:
    """Bool mask over points ``xy`` (..., 2): inside the ``quantile`` ellipse of one of ``places``."""
    places = np.asarray(places, dtype=np.int64)
    if places.size == 0:
        return np.zeros(np.shape(xy)[:-1], dtype=bool)
    return np.any(mahalanobis2(xy, model.mu[places], model.Sigma[places]) <= chi2_2d(quantile), axis=-1)


def most_probable_place(
    model: SpatialConceptModel, xy: np.ndarray, log_density: np.ndarray | None = None
) -> np.ndarray:
    """arg max_i p(i | x) = arg max_i N(x | mu_i, Sigma_i) p(i) over the active places, for points ``xy``
    (..., 2): (...,) int place indices (the module docstring's territories). ``log_density`` (..., K_active),
    if given, is log N(x | mu_i, Sigma_i) of the active places already computed for ``xy``."""
    act = np.flatnonzero(model.active_places)
    if log_density is None:  # compiled, without a (..., K) table
        return act[posterior_arg_max(xy, model.mu[act], model.Sigma[act], model.log_place_prior()[act])]
    return act[np.argmax(log_density + model.log_place_prior()[act], axis=-1)]


def place_regions(model: SpatialConceptModel, xy: np.ndarray, places: np.ndarray, quantile: float = 0.95) -> np.ndarray:
    """Bool mask over points ``xy`` (..., 2): inside the ``quantile`` ellipse of one of ``places`` *and* that
    place is the arg-max of p(i | x) (the module docstring's region)."""
    places = np.asarray(places, dtype=np.int64)
    inside = inside_places(model, xy, places, quantile)
    if not inside.any():
        return inside
    return inside & np.isin(most_probable_place(model, xy), places)


def snap_into_territories(
    node_place: np.ndarray,
    cells: np.ndarray,
    main: np.ndarray,
    territory: np.ndarray,
    stops: Stops | None = None,
) -> tuple[np.ndarray, np.ndarray, list[int]]:
    """Each candidate moved to the nearest cell of its own place's territory inside ``main`` (searched in the
    bounding box of those cells only); ``ok`` is False for places that own no such cell. With ``stops``, onto the
    place's stop cells instead (:mod:`spcotmhp.planning.stops`: the mean candidates to the most probable one, the
    others to the nearest), where it has any; the places without are returned (they keep the nearest cell)."""
    out = np.zeros_like(cells)
    ok = np.zeros(len(cells), dtype=bool)
    fallback: list[int] = []
    boxes = find_boxes(territory + 1)
    for k in np.unique(node_place):
        if k >= len(boxes) or boxes[k] is None:
            continue
        box = boxes[k]
        own = main[box] & (territory[box] == k)
        if not own.any():
            continue
        good = stops.cells_of(int(k), box, own) if stops is not None else None
        if good is not None and not good.any():
            fallback.append(int(k))
            good = None
        target = own if good is None else good
        rows, cols = np.flatnonzero(target.any(axis=1)), np.flatnonzero(target.any(axis=0))
        corner = np.array([rows[0] + box[0].start, cols[0] + box[1].start])
        window = target[rows[0] : rows[-1] + 1, cols[0] : cols[-1] + 1]
        sel = node_place == k
        out[sel] = snap(window, cells[sel] - corner) + corner
        means = sel & stops.is_mean if good is not None and stops is not None else np.zeros(0, dtype=bool)
        if means.any():  # the mean's candidate: the most probable stop cell
            assert stops is not None and good is not None
            out[means] = stops.best(int(k), box, good, cells[means][0])
        ok[sel] = True
    return out, ok, fallback


class Stops:
    """The stop cells of a region's window (:mod:`spcotmhp.planning.stops`) for :func:`snap_into_territories`:
    ``low`` (H, W) the low-cost cells, ``centres`` (H, W, 2) their world points, ``is_mean`` (M,) which candidates
    are their place's mean."""

    def __init__(
        self, model: SpatialConceptModel, low: np.ndarray, centres: np.ndarray, is_mean: np.ndarray, quantile: float
    ) -> None:
        self.model, self.low, self.centres, self.is_mean = model, low, centres, is_mean
        self.limit = chi2_2d(quantile)

    def cells_of(self, k: int, box: tuple[slice, slice], own: np.ndarray) -> np.ndarray:
        """Place ``k``'s stop cells in ``box``: its own cells (``own``) of low cost inside its ellipse."""
        good = own & self.low[box]
        if good.any():
            inside = mahalanobis2(self.centres[box][good], self.model.mu[k : k + 1], self.model.Sigma[k : k + 1])
            good[good] = inside[:, 0] <= self.limit
        return good

    def best(self, k: int, box: tuple[slice, slice], good: np.ndarray, mean_cell: np.ndarray) -> np.ndarray:
        """The (row, col) of place ``k``'s most probable stop cell among ``good`` in ``box``: the cell holding its
        mean (``mean_cell``) when that is one, else the highest density at a cell's centre."""
        r, c = int(mean_cell[0]) - box[0].start, int(mean_cell[1]) - box[1].start
        if 0 <= r < good.shape[0] and 0 <= c < good.shape[1] and good[r, c]:
            return np.asarray(mean_cell)
        rows, cols = np.nonzero(good)
        i = most_probable(self.centres[box][rows, cols], self.model.mu[k], self.model.Sigma[k])
        return np.array([rows[i] + box[0].start, cols[i] + box[1].start])


def candidate_nodes(
    model: SpatialConceptModel,
    n_candidates: int,
    seed: int,
    quantile: float,
    offset: tuple[int, int],
    main: np.ndarray,
    territory: np.ndarray,
    fallback: Sequence[tuple[int, tuple[int, int]]] = (),
    points: tuple[np.ndarray, np.ndarray] | None = None,
    stops: tuple[np.ndarray, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, list[int]]:
    """The planning graph's nodes (Algorithm 1, line 2): :func:`candidate_points` (``n_candidates`` per place,
    drawn with ``seed``; or ``points``, the same already drawn), snapped into their own territory within the free
    region ``main`` (:func:`snap_into_territories`; crop cells, the crop's corner at map cell ``offset``) and
    without duplicates, then ``fallback``: ``(place, crop cell)`` for places that reach the region but own none of
    its cells (:mod:`spcotmhp.planning.regions`). ``stops``: (low-cost cells, cell centres) of the window, to put
    the candidates on their place's stop cells (:mod:`spcotmhp.planning.stops`). Each node's place, crop cell
    and end term log N(x_j | mu_b, Sigma_b) at its cell's centre, and the places left without a stop cell."""
    occ = model.require_map()
    if points is None:
        points = candidate_points(model, n_candidates, np.random.default_rng(seed), quantile)
    node_place, node_xy = points
    is_mean = np.r_[True, node_place[1:] != node_place[:-1]] if len(node_place) else np.zeros(0, dtype=bool)
    where = None if stops is None else Stops(model, stops[0], stops[1], is_mean, quantile)
    cells, ok, no_stop = snap_into_territories(
        node_place, occ.world_to_cell(node_xy) - np.array(offset), main, territory, where
    )
    node_place, cells = node_place[ok], cells[ok]
    _, keep = np.unique(np.stack([node_place, cells[:, 0], cells[:, 1]], axis=1), axis=0, return_index=True)
    keep = np.sort(keep)
    node_place, cells = node_place[keep], cells[keep]
    extra = [(k, cell) for k, cell in fallback if k not in set(node_place.tolist())]
    if extra:
        node_place = np.concatenate([node_place, np.array([k for k, _ in extra], dtype=np.int64)])
        cells = np.concatenate([cells, np.array([c for _, c in extra], dtype=cells.dtype).reshape(-1, 2)])
    xy = occ.cell_to_world(cells + np.array(offset))
    end_term = np.array(
        [log_gaussian(xy[n], model.mu[k : k + 1], model.Sigma[k : k + 1])[0] for n, k in enumerate(node_place)],
        dtype=float,
    ).reshape(-1)
    return node_place, cells, end_term, no_stop

"""Territories: the partition of the robot's free space among the places (the topological level on the map).

Every cell the robot can occupy (``mask``: free, known, outside the inscribed radius of every obstacle) gets the
place it belongs to, in two steps:

1. **Most probable place.** Each cell starts with arg max_i N(x | mu_i, Sigma_i) p(i) over the active places
   (the posterior of Eq. 3, the partition the place posterior induces). For each place the *seed* is the
   4-connected piece of its cells that holds its anchor (the robot cell nearest its mean), else the anchor cell
   alone: a place whose mean lies in a wall, in unknown space or under a larger Gaussian still owns a cell, and
   it is the cell where its own density N(x | mu_i, Sigma_i) (the end term of Eq. 28) is highest. Not its largest
   piece elsewhere: a place under a stronger neighbour's Gaussian at its mean (a name taught once beside a room:
   one event, a broad prior-sized Gaussian, a small p(i)) is most probable only on the far rim of its own
   Gaussian, metres from the events it was learned from, and a territory there sent "go to" it 1.1-3.7 m from
   where it was taught (10 of 120 teaches on generated homes; docs/teaching.md).
2. **Geodesic growth.** Every other cell (stray fragments of a place's posterior region, cells no seed holds)
   goes to the seed that a breadth-first wave from all seeds at once reaches first through free cells.

Each territory is therefore connected, and every cell of a free component that holds a seed is labelled. Two
places are *adjacent* when their territories touch (two 4-neighbouring cells). Because the labelled cells of a
component cover it, the adjacency graph of the places in one free component is connected: whenever the robot
can drive from one place to another, the place graph connects them, directly or through other places
(:func:`territory_adjacency`). Cells in components without any seed keep -1.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.logspace import LOG_2PI, gaussian_log_density, log_gaussian
from spcotmhp.metric.snap import snap

__all__ = [
    "most_probable_labels",
    "partition",
    "place_anchors",
    "place_territories",
    "posterior_arg_max",
    "territory_adjacency",
]


def place_territories(
    model: SpatialConceptModel,
    mask: np.ndarray,
    centres: np.ndarray,
    log_density: np.ndarray | None = None,
    offset: tuple[int, int] = (0, 0),
) -> np.ndarray:
    """(H, W) int64 place index per cell of ``mask`` (-1 elsewhere and in components no place reaches).

    Args:
        model: the places (active ones only are used).
        mask: (H, W) bool, the cells the robot can occupy.
        centres: (H, W, 2) world coordinates of the cell centres.
        log_density: optional (K_active, H, W) log N(x | mu_i, Sigma_i) already computed for ``centres``.
        offset: the map cell of the grids' corner (a crop of ``model.map``).
    """
    act = np.flatnonzero(model.active_places)
    labels = most_probable_labels(model, mask, centres, log_density)
    if len(act) == 0 or not (labels >= 0).any():
        return labels
    out = partition(labels, place_anchors(model, mask, offset))
    return np.where(out >= 0, act[np.maximum(out, 0)], -1)


def most_probable_labels(
    model: SpatialConceptModel,
    mask: np.ndarray,
    centres: np.ndarray,
    log_density: np.ndarray | None = None,
    parallel: bool = False,
) -> np.ndarray:
    """(H, W) int64: on ``mask`` the index (into the active places) of arg max_i N(x | mu_i, Sigma_i) p(i) (step 1
    of the module docstring), -1 elsewhere; ``log_density`` as in :func:`place_territories`, ``parallel`` as in
    :func:`posterior_arg_max`."""
    mask = np.asarray(mask, dtype=bool)
    act = np.flatnonzero(model.active_places)
    labels = np.full(mask.shape, -1, dtype=np.int64)
    if not mask.any() or len(act) == 0:
        return labels
    prior = model.log_place_prior()[act]
    if log_density is None:  # compiled, chunk-bounded; memory O(H W), not O(H W K)
        best = posterior_arg_max(centres, model.mu[act], model.Sigma[act], prior, parallel)
    else:
        best = np.zeros(mask.shape, dtype=np.int64)
        top = np.full(mask.shape, -np.inf)
        for n in range(len(act)):  # running arg max
            score = log_density[n] + prior[n]
            higher = score > top
            best[higher], top[higher] = n, score[higher]
    labels[mask] = best[mask]  # indices into act
    return labels


def place_anchors(model: SpatialConceptModel, mask: np.ndarray, offset: tuple[int, int] = (0, 0)) -> np.ndarray:
    """(K_active, 2) the anchor of each active place: the cell of ``mask`` nearest its mean (grid cells; the
    grid's corner at map cell ``offset``)."""
    act = np.flatnonzero(model.active_places)
    cells = model.require_map().world_to_cell(model.mu[act]) - np.asarray(offset, dtype=np.int64)
    return snap(np.asarray(mask, dtype=bool), cells).astype(np.int64)


def partition(
    labels: np.ndarray,
    anchors: np.ndarray,
    extra_place: np.ndarray | None = None,
    extra_cell: np.ndarray | None = None,
) -> np.ndarray:
    """Seeds, then geodesic growth (the module docstring's two steps) over ``labels`` (:func:`most_probable_labels`)
    with the ``anchors`` of :func:`place_anchors`: (H, W) index into the active places, -1 where no seed's
    component is.

    ``extra_place`` / ``extra_cell`` (E,) / (E, 2): more seeds, one more piece of territory for a place in another
    free component (:mod:`spcotmhp.planning.regions`): the piece of that place's most probable cells holding the
    cell, else the cell alone unless another seed's single cell took it first. Without them the result is the
    module docstring's partition. Kept: scipy.ndimage (``label`` per place, ``watershed_ift`` from the seeds)
    takes 2.4-3.2 ms against 0.13-0.16 ms here on the bundled homes' free cells (benchmarks/wellkept.py)."""
    n = len(anchors)
    if extra_place is None or extra_cell is None or len(extra_place) == 0:
        extra_place, extra_cell = np.empty(0, dtype=np.int64), np.empty((0, 2), dtype=np.int64)
    return _partition(
        np.ascontiguousarray(labels, dtype=np.int64),
        np.ascontiguousarray(anchors, dtype=np.int64).reshape(-1, 2),
        n,
        np.ascontiguousarray(extra_place, dtype=np.int64),
        np.ascontiguousarray(extra_cell, dtype=np.int64).reshape(-1, 2),
    )


def territory_adjacency(territory: np.ndarray, K: int) -> np.ndarray:
    """(K, K) 0/1: places whose territories touch (4-neighbouring cells), diagonal 1 for places that own cells."""
    A = np.zeros((K, K), dtype=np.int64)
    t = np.asarray(territory)
    for a, b in ((t[:, :-1], t[:, 1:]), (t[:-1, :], t[1:, :])):
        touch = (a >= 0) & (b >= 0) & (a != b)
        A[a[touch], b[touch]] = 1
    A = np.maximum(A, A.T)
    owned = np.unique(t[t >= 0])
    A[owned, owned] = 1
    return A


def posterior_arg_max(
    points: np.ndarray, mu: np.ndarray, Sigma: np.ndarray, log_prior: np.ndarray, parallel: bool = False
) -> np.ndarray:
    """arg max_n log N(x | mu_n, Sigma_n) + log_prior_n for every point x of ``points`` (..., 2), first maximum on
    ties: the posterior of Eq. 3 up to its normaliser. Compiled, one thread (no OpenMP: the Gibbs runs fork
    worker processes after using it), memory O(points) (not O(points K));
    the same numbers as :func:`~spcotmhp.logspace.log_gaussian` plus ``log_prior``, and the same answer as
    trying every place at every point (:func:`_most_probable`). Raises ValueError for a covariance that is not
    positive definite. ``parallel``: the chunks shared between threads (the same answer chunk by chunk), for
    the planning graph's build only, which starts numba's threads for its fields anyway and forks nothing after."""
    points = np.asarray(points, dtype=float)
    log_gaussian(points.reshape(-1, 2)[:1], mu, Sigma)  # checks the covariances
    S = np.asarray(Sigma, dtype=float)
    det = S[:, 0, 0] * S[:, 1, 1] - S[:, 0, 1] * S[:, 1, 0]
    flat = np.ascontiguousarray(points.reshape(-1, 2))
    kernel = _most_probable_threads if parallel else _most_probable
    best = kernel(flat, np.asarray(mu, dtype=float), S, det, np.log(det), np.asarray(log_prior, dtype=float))
    return best.reshape(points.shape[:-1])


CHUNK = 64  # consecutive points bounded together (a row of cells, a stretch of trajectory)


@njit(cache=True)
def _most_probable(points, mu, Sigma, det, log_det, prior):  # pragma: no cover - numba
    """arg max_n log N(x | mu_n, Sigma_n) + prior_n per point (first maximum on ties), with the arithmetic of
    :func:`~spcotmhp.logspace.log_gaussian`, over chunks of :data:`CHUNK` consecutive points.

    Within a chunk, place n can only win if an upper bound of its score over the chunk's bounding box reaches
    the smallest exact score, over the chunk, of the place with the highest bound (every point's best score is
    at least that); the others are left out. The bound: the least Mahalanobis distance over the chunk's box
    (:func:`_box_mahalanobis`), widened by a margin far above the rounding error, so the answer is the
    exhaustive one."""
    out = np.zeros(points.shape[0], dtype=np.int64)
    coef, const = _place_bounds(mu, Sigma, det, log_det, prior)
    for ch in range((points.shape[0] + CHUNK - 1) // CHUNK):
        _chunk(points, ch, mu, Sigma, det, log_det, prior, coef, const, out)
    return out


@njit(cache=True, parallel=True)
def _most_probable_threads(points, mu, Sigma, det, log_det, prior):  # pragma: no cover - numba
    """:func:`_most_probable` with its chunks shared between threads (each chunk's answer its own)."""
    out = np.zeros(points.shape[0], dtype=np.int64)
    coef, const = _place_bounds(mu, Sigma, det, log_det, prior)
    for ch in prange((points.shape[0] + CHUNK - 1) // CHUNK):
        _chunk(points, ch, mu, Sigma, det, log_det, prior, coef, const, out)
    return out


@njit(cache=True)
def _place_bounds(mu, Sigma, det, log_det, prior):  # pragma: no cover - numba
    """Per place: a lower bound of the Mahalanobis distance per squared distance, and the score without it."""
    n = mu.shape[0]
    coef = np.empty(n)
    const = np.empty(n)
    for k in range(n):
        a, h, d = Sigma[k, 0, 0], 0.5 * (Sigma[k, 0, 1] + Sigma[k, 1, 0]), Sigma[k, 1, 1]
        lam = 0.5 * (a + d) - np.sqrt(0.25 * (a - d) ** 2 + h * h)
        coef[k] = max(lam, 0.0) / det[k] * (1.0 - 1e-9)
        const[k] = (-0.5 * log_det[k] - LOG_2PI) + prior[k]
    return coef, const


@njit(cache=True)
def _chunk(points, ch, mu, Sigma, det, log_det, prior, coef, const, out):  # pragma: no cover - numba
    """The most probable place of the points of chunk ``ch`` into ``out`` (:func:`_most_probable`)."""
    n = mu.shape[0]
    lo, hi = ch * CHUNK, min(points.shape[0], ch * CHUNK + CHUNK)
    x0, x1 = points[lo:hi, 0].min(), points[lo:hi, 0].max()
    y0, y1 = points[lo:hi, 1].min(), points[lo:hi, 1].max()
    bound = np.empty(n)
    g = 0
    for k in range(n):
        bound[k] = const[k] - 0.5 * _box_mahalanobis(mu, Sigma, det, coef, k, x0, x1, y0, y1)
        if bound[k] > bound[g]:
            g = k
    floor = np.inf  # the lowest score of place g over the chunk
    for p in range(lo, hi):
        floor = min(floor, _score(points, p, mu, Sigma, det, log_det, prior, g))
    floor -= 1e-6 * (1.0 + abs(floor))
    cand = np.empty(n, dtype=np.int64)
    m = 0
    for k in range(n):
        if not bound[k] + 1e-6 * (1.0 + abs(bound[k])) < floor:
            cand[m] = k
            m += 1
    for p in range(lo, hi):
        top = -np.inf
        for t in range(m):
            score = _score(points, p, mu, Sigma, det, log_det, prior, cand[t])
            if score > top:
                top = score
                out[p] = cand[t]


@njit(cache=True)
def _box_mahalanobis(mu, Sigma, det, coef, k, x0, x1, y0, y1):  # pragma: no cover - numba
    """A lower bound of place k's Mahalanobis distance over the box [x0, x1] x [y0, y1]: the larger of the
    isotropic one (``coef``, :func:`_place_bounds`) and the exact minimum of the quadratic form over the box (0
    with the mean inside, else its least value on the four edges, each a clamped one-dimensional minimum),
    shrunk by far more than the rounding error. The exact one is what prunes an elongated Gaussian (a
    corridor's) that the isotropic one, bounded by its long axis, keeps at every chunk."""
    mx, my = mu[k, 0], mu[k, 1]
    dx = max(x0 - mx, mx - x1, 0.0)
    dy = max(y0 - my, my - y1, 0.0)
    iso = coef[k] * (dx * dx + dy * dy)
    if dx == 0.0 and dy == 0.0:
        return 0.0
    a, h, d = Sigma[k, 0, 0], 0.5 * (Sigma[k, 0, 1] + Sigma[k, 1, 0]), Sigma[k, 1, 1]
    best = np.inf
    for e in range(4):  # edges x = x0, x = x1 (dy free), y = y0, y = y1 (dx free)
        if e < 2:
            u = (x0 if e == 0 else x1) - mx
            v = min(max(h * u / a, y0 - my), y1 - my)
        else:
            v = (y0 if e == 2 else y1) - my
            u = min(max(h * v / d, x0 - mx), x1 - mx)
        best = min(best, (d * u * u - 2.0 * h * u * v + a * v * v) / det[k])
    return max(iso, best * (1.0 - 1e-9) - 1e-12)


@njit(cache=True)
def _score(points, p, mu, Sigma, det, log_det, prior, k):  # pragma: no cover - numba
    a, b, c, d = Sigma[k, 0, 0], Sigma[k, 0, 1], Sigma[k, 1, 0], Sigma[k, 1, 1]
    dx = points[p, 0] - mu[k, 0]
    dy = points[p, 1] - mu[k, 1]
    return gaussian_log_density(dx, dy, a, b + c, d, det[k], log_det[k]) + prior[k]


@njit(cache=True)
def _partition(labels, anchors, n, extra_place, extra_cell):  # pragma: no cover - numba
    """Seeds, then breadth-first growth (module docstring, :func:`partition`); ``labels`` holds 0..n-1 on mask
    cells, -1 off."""
    height, width = labels.shape
    N = height * width
    flat = labels.reshape(-1)
    comp, _sizes, _labels, n_comp = _pieces(flat, height, width)
    seed_comp = np.full(n, -1, dtype=np.int64)
    for k in range(n):  # the anchor's piece; a place most probable elsewhere only keeps its anchor (pinned below)
        a = anchors[k, 0] * width + anchors[k, 1]
        if flat[a] == k:
            seed_comp[k] = comp[a]
    owner = np.full(n_comp, -1, dtype=np.int64)
    for k in range(n):
        if seed_comp[k] >= 0:
            owner[seed_comp[k]] = k
    for e in range(extra_place.shape[0]):  # an extra seed's piece, where its cell is its place's
        a = extra_cell[e, 0] * width + extra_cell[e, 1]
        if flat[a] == extra_place[e] and owner[comp[a]] < 0:
            owner[comp[a]] = extra_place[e]
    out = np.full(N, -1, dtype=np.int64)
    queue = np.empty(N, dtype=np.int64)
    pinned = np.zeros(N, dtype=np.bool_)  # cells held by a single-cell seed
    tail = 0
    for i in range(N):
        if flat[i] >= 0 and owner[comp[i]] >= 0:
            out[i] = owner[comp[i]]
            queue[tail] = i
            tail += 1
    for k in range(n):  # a place with no cell of its own keeps its anchor cell
        if seed_comp[k] < 0:
            a = anchors[k, 0] * width + anchors[k, 1]
            tail = _pin(flat, out, queue, pinned, tail, a, k)
    for e in range(extra_place.shape[0]):  # an extra seed outside its place's cells: the cell alone
        a = extra_cell[e, 0] * width + extra_cell[e, 1]
        if flat[a] != extra_place[e] and not pinned[a]:
            tail = _pin(flat, out, queue, pinned, tail, a, extra_place[e])
    head = 0
    while head < tail:  # breadth-first growth from every seed at once
        i = queue[head]
        head += 1
        for d in range(4):
            j = _neighbour(i, d, height, width)
            if j >= 0 and flat[j] >= 0 and out[j] < 0:
                out[j] = out[i]
                queue[tail] = j
                tail += 1
    return out.reshape(height, width)


@njit(cache=True)
def _pieces(flat, height, width):  # pragma: no cover - numba
    """The 4-connected pieces of equal label of the flat ``labels`` (>= 0): each cell's piece (-1 off), each
    piece's size and label, and the number of pieces."""
    N = height * width
    comp = np.full(N, -1, dtype=np.int64)
    queue = np.empty(N, dtype=np.int64)
    sizes = np.zeros(N, dtype=np.int64)
    comp_label = np.zeros(N, dtype=np.int64)
    n_comp = 0
    for s in range(N):
        if flat[s] < 0 or comp[s] >= 0:
            continue
        head, tail = 0, 1
        queue[0] = s
        comp[s] = n_comp
        while head < tail:
            i = queue[head]
            head += 1
            for d in range(4):
                j = _neighbour(i, d, height, width)
                if j >= 0 and comp[j] < 0 and flat[j] == flat[s]:
                    comp[j] = n_comp
                    queue[tail] = j
                    tail += 1
        sizes[n_comp] = tail
        comp_label[n_comp] = flat[s]
        n_comp += 1
    return comp, sizes, comp_label, n_comp


@njit(cache=True)
def _pin(flat, out, queue, pinned, tail, a, k):  # pragma: no cover - numba
    """Seed place ``k`` at the single mask cell ``a``, over any piece that holds it (queued for growth unless
    already seeded), and mark it pinned; returns the queue's new tail."""
    if flat[a] >= 0 and out[a] != k:
        if out[a] < 0:
            queue[tail] = a
            tail += 1
        out[a] = k
    pinned[a] = True
    return tail


@njit(cache=True, inline="always")
def _neighbour(i, d, height, width):  # pragma: no cover - numba
    """The flat index of the 4-neighbour ``d`` (0..3: down, up, right, left in rows/cols) of flat cell ``i`` on
    an H x W grid, or -1 off the grid."""
    r, c = i // width, i % width
    r += 1 if d == 0 else -1 if d == 1 else 0
    c += 1 if d == 2 else -1 if d == 3 else 0
    if r < 0 or r >= height or c < 0 or c >= width:
        return -1
    return r * width + c

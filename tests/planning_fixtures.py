"""A hand-made four-room home for the planning tests (importable helpers, no pytest fixtures).

Resolution 0.5 m, 13 rows x 31 columns (row 0 at the bottom, OccupancyGrid order):

    rows 1-11, cols 1-9    L  "bedroom"  (bedroom #1)
    rows 1-5,  cols 11-19  M  "corridor"
    rows 7-11, cols 11-19  K  "kitchen"   (reachable only through R)
    rows 1-11, cols 21-29  R  "bedroom"  (bedroom #2)

Doors: L-M at col 10 rows 2-4, M-R at col 20 rows 2-4, K-R at col 20 rows 8-10. The cost map is given
explicitly: p(x|m) = 1 on free cells, 0 on walls, so every cost is hand-computable.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.maps import OccupancyMap

RES = 0.5
ROOMS = {"L": (1, 11, 1, 9), "M": (1, 5, 11, 19), "K": (7, 11, 11, 19), "R": (1, 11, 21, 29)}
ORDER = ["L", "M", "K", "R"]
NAMES = {"L": "bedroom", "M": "corridor", "K": "kitchen", "R": "bedroom"}
EDGES = [("L", "M"), ("M", "R"), ("K", "R")]


def home_map() -> OccupancyMap:
    data = np.full((13, 31), 100, dtype=np.int8)
    for r0, r1, c0, c1 in ROOMS.values():
        data[r0:r1 + 1, c0:c1 + 1] = 0
    data[2:5, 10] = 0
    data[2:5, 20] = 0
    data[8:11, 20] = 0
    return OccupancyMap(data=data, resolution=RES, origin=(0.0, 0.0, 0.0))


def home_log_p(occ: OccupancyMap) -> np.ndarray:
    return np.where(occ.data == 0, 0.0, -np.inf)


def home_model(sigma_scale: float = 0.25) -> SpatialConceptModel:
    occ = home_map()
    K = len(ORDER)
    mu, Sigma = np.zeros((K, 2)), np.zeros((K, 2, 2))
    for k, name in enumerate(ORDER):
        r0, r1, c0, c1 = ROOMS[name]
        lo = occ.cell_to_world(np.array([r0, c0]))
        hi = occ.cell_to_world(np.array([r1, c1]))
        mu[k] = (lo + hi) / 2
        Sigma[k] = np.diag(((hi - lo + RES) * sigma_scale) ** 2)
    adj = np.eye(K)
    for a, b in EDGES:
        adj[ORDER.index(a), ORDER.index(b)] = adj[ORDER.index(b), ORDER.index(a)] = 1
    psi = (adj + 0.1) / (adj + 0.1).sum(axis=1, keepdims=True)
    vocab = ["bedroom", "corridor", "kitchen"]
    counts = np.zeros((K, 3))
    for k, name in enumerate(ORDER):
        counts[k, vocab.index(NAMES[name])] = 15
    W = (counts + 0.1) / (counts + 0.1).sum(axis=1, keepdims=True)
    phi = (np.eye(K) * 15 + 0.1) / (15 + 0.1 * K)
    return SpatialConceptModel(mu=mu, Sigma=Sigma, psi=psi, pi=np.full(K, 1.0 / K), phi=phi, W=W,
                               vocabulary=vocab, map=occ)


def world(occ: OccupancyMap, row: int, col: int) -> np.ndarray:
    return occ.cell_to_world(np.array([row, col]))

"""A hand-made four-room home for the planning tests (importable helpers, no pytest fixtures), and the random
grids the hypothesis tests of path assembly draw.

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
from hypothesis import strategies as st

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.maps import OccupancyMap

RES = 0.5
ROOMS = {"L": (1, 11, 1, 9), "M": (1, 5, 11, 19), "K": (7, 11, 11, 19), "R": (1, 11, 21, 29)}
DOORS = [(slice(2, 5), 10), (slice(2, 5), 20), (slice(8, 11), 20)]
ORDER = ["L", "M", "K", "R"]
NAMES = {"L": "bedroom", "M": "corridor", "K": "kitchen", "R": "bedroom"}
EDGES = [("L", "M"), ("M", "R"), ("K", "R")]
SHAPE = (13, 31)


def rooms_map(rooms: dict, doors: list, shape: tuple[int, int]) -> OccupancyMap:
    """Walls everywhere but the rectangular rooms (rows r0-r1, cols c0-c1 inclusive) and the door cells."""
    data = np.full(shape, 100, dtype=np.int8)
    for r0, r1, c0, c1 in rooms.values():
        data[r0 : r1 + 1, c0 : c1 + 1] = 0
    for rows, cols in doors:
        data[rows, cols] = 0
    return OccupancyMap(data=data, resolution=RES, origin=(0.0, 0.0, 0.0))


def make_home(
    rooms: dict, doors: list, names: dict, edges: list, shape: tuple[int, int], sigma_scale: float = 0.25
) -> SpatialConceptModel:
    """A home of rectangular rooms joined by door cells (see :func:`rooms_map`), one Gaussian per room (its
    centre, sd = ``sigma_scale`` times its extent), psi from the given edges, one word per room."""
    occ = rooms_map(rooms, doors, shape)
    order = list(rooms)
    K = len(order)
    mu, Sigma = np.zeros((K, 2)), np.zeros((K, 2, 2))
    for k, name in enumerate(order):
        r0, r1, c0, c1 = rooms[name]
        lo, hi = occ.cell_to_world(np.array([r0, c0])), occ.cell_to_world(np.array([r1, c1]))
        mu[k] = (lo + hi) / 2
        Sigma[k] = np.diag(((hi - lo + RES) * sigma_scale) ** 2)
    adj = np.eye(K)
    for a, b in edges:
        adj[order.index(a), order.index(b)] = adj[order.index(b), order.index(a)] = 1
    psi = (adj + 0.1) / (adj + 0.1).sum(axis=1, keepdims=True)
    vocab = sorted(set(names.values()))
    counts = np.zeros((K, len(vocab)))
    for k, name in enumerate(order):
        counts[k, vocab.index(names[name])] = 15
    W = (counts + 0.1) / (counts + 0.1).sum(axis=1, keepdims=True)
    phi = (np.eye(K) * 15 + 0.1) / (15 + 0.1 * K)
    return SpatialConceptModel(
        mu=mu, Sigma=Sigma, psi=psi, pi=np.full(K, 1.0 / K), phi=phi, W=W, vocabulary=vocab, map=occ
    )


def home_map() -> OccupancyMap:
    return rooms_map(ROOMS, DOORS, SHAPE)


def home_log_p(occ: OccupancyMap) -> np.ndarray:
    return np.where(occ.data == 0, 0.0, -np.inf)


def home_model(sigma_scale: float = 0.25) -> SpatialConceptModel:
    return make_home(ROOMS, DOORS, NAMES, EDGES, SHAPE, sigma_scale)


def world(occ: OccupancyMap, row: int, col: int) -> np.ndarray:
    return occ.cell_to_world(np.array([row, col]))


def draw_blocked(draw) -> np.ndarray:
    """Inside an ``st.composite`` strategy: a 4-14 x 4-14 boolean grid of blocked cells (only cells whose flat
    index is a multiple of 3 may be blocked, so most of the grid stays free)."""
    h, w = draw(st.integers(4, 14)), draw(st.integers(4, 14))
    bits = draw(st.lists(st.booleans(), min_size=h * w, max_size=h * w))
    return np.array(bits).reshape(h, w) & (np.arange(h * w).reshape(h, w) % 3 == 0)


def draw_ends(draw, blocked: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inside an ``st.composite`` strategy: two free cells a, b of ``blocked`` (cleared in place first when
    fewer than two cells are free)."""
    free = np.argwhere(~blocked)
    if len(free) < 2:
        blocked[:] = False
        free = np.argwhere(~blocked)
    a = free[draw(st.integers(0, len(free) - 1))]
    b = free[draw(st.integers(0, len(free) - 1))]
    return a, b

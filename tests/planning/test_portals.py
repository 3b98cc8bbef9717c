"""The portal graph's crossings (spcotmhp.planning._portals) by hand, and the abstraction against brute force on
random grids: never cheaper than the grid's optimum, never "no path" where the grid has one, its legs
real paths (each step entering a cell pays its cost) whose cost is the table's."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.metric.grid_search import SQRT2, cost_to_go
from spcotmhp.planning import _portals, hierarchy


@pytest.mark.parametrize(
    "length, spacing, expect",
    [(1, 10, 1), (10, 10, 1), (11, 10, 2), (20, 10, 2), (40, 10, 2), (41, 10, 3), (90, 10, 3), (91, 10, 4),
     (1000, 10, 10), (7, 1, 7), (0, 10, 1)],
)  # fmt: skip
def test_crossings_on_an_entrance(length, spacing, expect):
    assert _portals.crossings_on(length, spacing) == expect


def test_crossings_of_a_straight_open_boundary_by_hand():
    """Two territories side by side (rows 0-89, columns 0-3 | 4-7): one entrance of 90 u cells (column 3, the
    lower label's side); sqrt(90 / 10) -> 3 crossings at the middles of three parts of 30: rows 15, 45, 75, each
    with the one v cell it faces. Before, one a spacing: 9."""
    territory = np.zeros((90, 8), dtype=np.int64)
    territory[:, 4:] = 1
    assert _portals.crossings(territory, 10) == [(15, 3, 15, 4), (45, 3, 45, 4), (75, 3, 75, 4)]
    assert len(_portals.crossings(territory, 1)) == 90  # a spacing of one cell keeps every crossing


def test_a_door_keeps_its_crossings():
    """A wall (-1) with a door of 15 cells between two rooms: ceil(sqrt(1.5)) = 2 crossings, as one a spacing."""
    territory = np.full((30, 21), -1, dtype=np.int64)
    territory[:, :10] = 0
    territory[:, 11:] = 1
    territory[5:20, 10] = 0  # the door's cells belong to room 0; its last column faces room 1
    assert [c[:2] for c in _portals.crossings(territory, 10)] == [(8, 10), (16, 10)]


def _random_grid(seed: int):
    """A random cost map (costs 1-3, scattered obstacles) cut into a 2 x 3 grid of rectangular territories
    (every territory's free cells connected: the obstacles are isolated cells)."""
    rng = np.random.default_rng(seed)
    h, w = int(rng.integers(40, 70)), int(rng.integers(60, 90))
    cost = rng.uniform(1.0, 3.0, (h, w))
    blocked = rng.random((h, w)) < 0.08
    blocked[1::2, :] = False  # no two obstacles touch vertically ...
    blocked[:, 1::2] = False  # ... nor horizontally or diagonally: free space stays connected
    cost[blocked] = np.inf
    rows = sorted(rng.choice(np.arange(10, h - 10), 1, replace=False))
    cols = sorted(rng.choice(np.arange(10, w - 10), 2, replace=False))
    territory = (np.searchsorted(rows, np.arange(h), side="right")[:, None] * 3
                 + np.searchsorted(cols, np.arange(w), side="right")[None, :]).astype(np.int64)  # fmt: skip
    territory[blocked] = -1
    free = np.argwhere(~blocked)
    nodes = free[rng.choice(len(free), 6, replace=False)]
    return cost, territory, nodes, rng


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("connectivity", [4, 8])
def test_the_abstraction_against_brute_force_on_random_grids(seed, connectivity):
    cost, territory, nodes, rng = _random_grid(seed)
    spacing = int(rng.integers(3, 12))
    h = hierarchy.build(cost, territory, nodes, 6, spacing, connectivity)
    free = np.argwhere(territory >= 0)
    starts = free[rng.choice(len(free), 25, replace=False)]
    for j in range(len(nodes)):
        exact, _ = cost_to_go(cost, nodes[j][None, :], connectivity, SQRT2)
        for cell in [*nodes, *starts]:
            want = exact[cell[0], cell[1]]
            got = h.cost_to_nodes(cell)[j]
            assert np.isfinite(want) and np.isfinite(got)  # the free space joins them: so does the graph
            assert got >= want - 1e-9  # never cheaper than the grid's optimum
            path = h.path(cell, j)
            assert path is not None and tuple(path[0]) == tuple(cell) and tuple(path[-1]) == tuple(nodes[j])
            assert np.all(np.isfinite(cost[path[:, 0], path[:, 1]]))  # every cell traversable
            steps = np.abs(np.diff(path, axis=0))
            assert np.all(steps.max(axis=1) == 1) and (connectivity == 8 or np.all(steps.sum(axis=1) == 1))
            step = np.where(steps.sum(axis=1) == 2, SQRT2, 1.0)
            assert np.isclose(np.sum(cost[path[1:, 0], path[1:, 1]] * step), got, rtol=0, atol=1e-6)


@pytest.mark.parametrize("seed", range(4))
def test_an_avoided_territory_is_never_entered(seed):
    cost, territory, nodes, rng = _random_grid(seed)
    h = hierarchy.build(cost, territory, nodes, 6, 6, 8)
    middle = 1  # the top middle rectangle: between the top left and top right ones
    view = h.without((middle,))
    for j in np.flatnonzero(h.terr[: len(nodes)] != middle):
        for a in np.flatnonzero(h.terr[: len(nodes)] != middle):
            path = view.path(nodes[a], int(j))
            if path is not None:
                assert not np.any(territory[path[:, 0], path[:, 1]] == middle)

"""The compiled online path: the field read of a tube re-planning equals the search's answer in cost, the
compiled path measures agree with numpy, and the numba cache folder falls back to a user cache."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from spcotmhp.datasets.bundled import load_bundled
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.planning._paths import cells_cost, is_better, octile_length
from spcotmhp.planning.assemble import join_legs, path_cost, replan_segment
from spcotmhp.planning.planner import HierarchicalPlanner
from tests.helpers.graphs import GRAPHS


def test_octile_length_and_cost_by_hand():
    cells = np.array([[0, 0], [1, 1], [1, 2], [2, 3]])
    cost = np.arange(16, dtype=float).reshape(4, 4)
    assert octile_length(cells) == pytest.approx(1 + 2 * math.sqrt(2))
    assert cells_cost(cells, cost) == pytest.approx(5 * math.sqrt(2) + 6 + 11 * math.sqrt(2))
    assert is_better(cells[:2], cells, cost) and not is_better(cells, cells[:2], cost)


@pytest.mark.parametrize("home", ["3LDK_01", "3LDK_06"])
def test_field_read_is_an_optimum_of_the_tube_replanning(home):
    """Two-leg pieces start -> node a -> node b: when the field of b gives a path, it lies in the tube and costs
    no more than the tube search's answer (so it is an optimum there), and its cost is the field's value."""
    with warnings.catch_warnings():  # the bundled data's known warnings (said once per process)
        warnings.simplefilter("ignore")
        data = load_bundled(home, lang="en")
    model = fit_supervised(data)
    graph = HierarchicalPlanner(model, cache=GRAPHS).graph
    rng = np.random.default_rng(0)
    free = np.argwhere(graph.main)
    read = 0
    for _ in range(60):
        start = free[rng.integers(len(free))]
        a, b = rng.choice(graph.n_nodes, size=2, replace=False)
        cells, ends = join_legs([graph.leg(start, int(a)).cells, graph.edge_path(int(a), int(b))])
        ends = np.asarray(ends)
        places = np.union1d(graph.territory[cells[:, 0], cells[:, 1]], graph.node_place[[a, b]])
        found = graph.field_piece(cells, 0, len(cells) - 1, ends, np.array([a, b]), places)
        if found is None:
            continue
        read += 1
        origin, mask = graph.tube(places)
        inside = found - origin
        assert ((inside >= 0) & (inside < mask.shape)).all() and mask[inside[:, 0], inside[:, 1]].all()
        searched = replan_segment(cells, graph.map_cost, origin, mask)
        assert path_cost(found, graph.map_cost) <= path_cost(searched, graph.map_cost) + 1e-9
        assert path_cost(found, graph.map_cost) == pytest.approx(graph.dist[b][start[0], start[1]])
        assert (found[0] == start).all() and (found[-1] == graph.node_cell[b]).all()
    assert read >= 20


@pytest.mark.parametrize("home", ["3LDK_01", "3LDK_06"])
def test_joined_field_legs_equal_the_joined_legs(home):
    """The compiled assembly (start leg and partial paths followed in one kernel) gives the cells and node
    indices of join_legs over graph.leg and graph.edge_path, repeated nodes and a start on a node included; a
    start that cannot reach the first node is reported, not followed."""
    from spcotmhp.planning._paths import join_field_legs

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = load_bundled(home, lang="en")
    graph = HierarchicalPlanner(fit_supervised(data), cache=GRAPHS).graph
    width = graph.log_p.shape[1]
    flat = graph.node_cell[:, 0] * width + graph.node_cell[:, 1]
    rng = np.random.default_rng(1)
    free = np.argwhere(graph.main)
    for trial in range(80):
        start = graph.node_cell[rng.integers(graph.n_nodes)] if trial % 10 == 0 else free[rng.integers(len(free))]
        nodes = rng.integers(graph.n_nodes, size=int(rng.integers(1, 5)))
        legs = [graph.leg(start, int(nodes[0])).cells]
        legs += [graph.edge_path(int(a), int(b)) for a, b in zip(nodes[:-1], nodes[1:], strict=True)]
        cells, ends = join_legs(legs)
        got, got_ends, bad = join_field_legs(graph.dist, graph.next_step, int(start[0] * width + start[1]), nodes, flat)
        assert bad == -1 and np.array_equal(got, cells) and got_ends.tolist() == ends
    blocked = np.argwhere(~np.isfinite(graph.dist[0]) & ~graph.traversable)[0]
    assert (
        join_field_legs(graph.dist, graph.next_step, int(blocked[0] * width + blocked[1]), np.array([0]), flat)[2] == 0
    )


def test_kernels_match_their_numpy_definitions():
    """territory_sequence is dwell_filtered_sequence of the territories along a path, then of its non-negative
    entries with a dwell of 1; last_territory its last non-negative entry (path_territories: both); piece_places
    is the union of the piece's territories and its nodes' places; crossing_fields is crosses() of each finite
    field: checked on random grids, paths and link chains."""
    from spcotmhp.learning.hmm import dwell_filtered_sequence
    from spcotmhp.planning._paths import (
        crosses,
        crossing_fields,
        last_territory,
        path_territories,
        piece_places,
        territory_sequence,
    )

    rng = np.random.default_rng(2)
    for _ in range(200):
        territory = rng.integers(-1, 4, size=(6, 7))
        cells = np.column_stack([rng.integers(0, 6, 30), rng.integers(0, 7, 30)]).astype(np.int64)
        dwell = float(rng.choice([1.0, 2.0, 2.5, 4.0]))
        seq = dwell_filtered_sequence(territory[cells[:, 0], cells[:, 1]], dwell)
        assert (
            territory_sequence(territory, cells, dwell).tolist() == dwell_filtered_sequence(seq[seq >= 0], 1).tolist()
        )
        for n in (0, 1, 30):  # last_territory: the last non-negative territory along the path, -1 without one
            labels = territory[cells[:n, 0], cells[:n, 1]]
            labels = labels[labels >= 0]
            assert last_territory(territory, cells[:n]) == (labels[-1] if len(labels) else -1)
            along, last = path_territories(territory, cells[:n], dwell)
            assert along.tolist() == territory_sequence(territory, cells[:n], dwell).tolist()
            assert last == last_territory(territory, cells[:n])
        a, b = sorted(rng.integers(0, 30, 2))
        ends = np.sort(rng.integers(0, 30, 3)).astype(np.int64)
        node_place = rng.integers(0, 4, 3).astype(np.int64)
        inside = node_place[(ends >= a) & (ends <= b)]
        expected = np.union1d(territory[cells[a : b + 1, 0], cells[a : b + 1, 1]], inside)
        assert piece_places(territory, cells, int(a), int(b), ends, node_place, 4).tolist() == expected.tolist()
        # link chains: each cell points to a lower flat index or ends (-1), so every chain terminates
        links = (
            np.stack(
                [
                    np.where(rng.random(42) < 0.2, -1, rng.integers(-1, 42, 42) % (np.arange(42) + 1) - 1)
                    for _ in range(3)
                ]
            )
            .reshape(3, 6, 7)
            .astype(np.int64)
        )
        dist = np.where(rng.random((3, 6, 7)) < 0.2, np.inf, 1.0)
        blocked = rng.random((6, 7)) < 0.15
        r, c = int(rng.integers(6)), int(rng.integers(7))
        fields = np.array([2, 0, 1], dtype=np.int64)
        want = [
            int(f)
            for f in fields
            if np.isfinite(dist[f, r, c]) and crosses(links[f].reshape(-1), r * 7 + c, blocked.reshape(-1))
        ]
        assert crossing_fields(dist, links, fields, r, c, blocked).tolist() == want

"""HPP-I / HPP-II on the hand-made four-room home of the planning tests (L - M - R - K chain of doors)."""

import numpy as np
import pytest

from spcotmhp.baselines.hpp import EDGE_COSTS, HPP, draw_place, path_cost_edges, path_length_edges
from spcotmhp.errors import PlanningError
from spcotmhp.planning.assemble import path_length
from spcotmhp.planning.graph import GraphSettings, PlanningGraph
from tests.helpers.planning import ORDER, home_log_p, home_model, world

L, M, K, R = (ORDER.index(n) for n in "LMKR")


@pytest.fixture(scope="module")
def graph():
    model = home_model()
    return PlanningGraph.build(model, GraphSettings(), log_p=home_log_p(model.map))


def crop(graph, occ, row, col):
    return graph.to_crop(np.array([row, col]))


def test_edge_costs(graph):
    cost1, cost2 = path_cost_edges(graph), path_length_edges(graph)
    finite = np.isfinite(graph.w_hat)
    # one candidate per place (N = 1), edges exactly between connected places
    assert sorted(zip(*np.nonzero(finite), strict=False)) == sorted([(L, M), (M, L), (M, R), (R, M), (K, R), (R, K)])
    np.testing.assert_array_equal(cost1[finite], -graph.w_hat[finite])
    assert (cost1[finite] > 0).all() and np.isinf(cost1[~finite]).all()
    for i, j in zip(*np.nonzero(finite), strict=False):
        assert cost2[i, j] == pytest.approx(path_length(graph.edge_path(i, j), 0.5))
        a, b = graph.node_cell[i], graph.node_cell[j]
        dr, dc = np.abs(a - b)
        assert cost2[i, j] >= 0.5 * (max(dr, dc) + (np.sqrt(2) - 1) * min(dr, dc)) - 1e-9  # octile bound
    assert set(EDGE_COSTS) == {"hpp1", "hpp2"}


@pytest.mark.parametrize("name", ["hpp1", "hpp2"])
def test_route_follows_the_place_graph(graph, name):
    hpp = HPP(graph, EDGE_COSTS[name])
    assert hpp.route(L, K) == [L, M, R, K]  # the kitchen is reachable only through bedroom #2
    assert hpp.route(K, K) == [K]


def test_custom_edge_cost_changes_the_route(graph):
    def shortcut(g):
        c = np.where(np.isfinite(g.w_hat), 10.0, np.inf)
        c[L, K] = 1.0  # a (fictitious) direct edge, cheaper than three real ones
        return c

    assert HPP(graph, shortcut).route(L, K) == [L, K]
    with pytest.raises(ValueError, match="non-negative"):
        HPP(graph, lambda g: -np.ones(g.w_hat.shape))


def test_draw_place_follows_p_i_given_words(graph):
    rng = np.random.default_rng(0)
    draws = np.array([draw_place(graph, ["bedroom"], rng) for _ in range(3000)])
    p = np.exp(graph.model.log_place_given_words(["bedroom"]))
    for k in range(4):
        assert np.mean(draws == k) == pytest.approx(p[k], abs=0.02)
    assert draw_place(graph, ["kitchen"], np.random.default_rng(1)) == draw_place(
        graph, ["kitchen"], np.random.default_rng(1)
    )


def test_plan_reuses_the_graph_paths(graph):
    occ = graph.model.map
    hpp = HPP(graph, path_length_edges)
    start = crop(graph, occ, 3, 13)  # inside the corridor M
    assert hpp.start_node(start) == M
    cells = hpp.plan(start, [["kitchen"]], np.random.default_rng(0))
    assert tuple(cells[0]) == tuple(start)
    assert tuple(cells[-1]) == tuple(graph.node_cell[K])
    assert np.abs(np.diff(cells, axis=0)).max() <= 1  # 8-connected
    assert graph.traversable[cells[:, 0], cells[:, 1]].all()
    # the metric path is the start leg plus the graph's own partial paths M -> R -> K, not recomputed copies
    leg = graph.leg(start, M).cells
    expected = np.vstack([leg, graph.edge_path(M, R)[1:], graph.edge_path(R, K)[1:]])
    np.testing.assert_array_equal(cells, expected)
    assert graph.edge_path(M, R) is graph.edge_path(M, R)


def test_plan_with_waypoint_draws_each_stage(graph):
    hpp = HPP(graph, path_cost_edges)
    occ = graph.model.map
    start = crop(graph, occ, 6, 3)  # bedroom #1 (L)
    cells = hpp.plan(start, [["corridor"], ["kitchen"]], np.random.default_rng(0))
    xy = occ.cell_to_world(graph.to_map(cells))
    assert np.allclose(xy[-1], world(occ, *graph.to_map(graph.node_cell[K])))
    passes = [tuple(c) == tuple(graph.node_cell[M]) for c in cells]
    assert any(passes)


def test_unreachable_place_is_a_planning_error(graph):
    def no_edges(g):
        return np.full(g.w_hat.shape, np.inf)

    with pytest.raises(PlanningError, match=r"no topological route from node 0 to place 3"):
        HPP(graph, no_edges).route(L, R)

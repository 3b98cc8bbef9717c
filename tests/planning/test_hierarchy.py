"""The portal graph (territory-local fields, :mod:`spcotmhp.planning.hierarchy`) against the dense fields: exact
when every crossing is a portal (4-connected moves), an upper bound on the cost otherwise, the same guarantees
(paths on traversable cells, avoided territories never entered), and the incremental rebuild."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spcotmhp.datasets.synthetic import generate_environment
from spcotmhp.errors import ModelError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.learning.territory import posterior_arg_max
from spcotmhp.logspace import log_gaussian
from spcotmhp.metric.costmap import inflate
from spcotmhp.planning._paths import cells_cost
from spcotmhp.planning.avoid import avoided_view
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.graph_settings import GraphSettings
from spcotmhp.planning.planner import HierarchicalPlanner, PlannerSettings


@pytest.fixture(scope="module")
def office():
    ds = generate_environment("office", seed=1, n_rooms=14, size=240)
    model = fit_supervised(ds, adjacency="given")
    return ds, model, inflate(ds.map, **model.costmap).log_p


def pair(office, connectivity=8, spacing=None):
    _, model, log_p = office
    dense = PlanningGraph.build(model, GraphSettings(connectivity=connectivity), log_p=log_p)
    hier = PlanningGraph.build(
        model,
        GraphSettings(connectivity=connectivity, max_dense_bytes=0, portal_spacing=spacing or 1.0),
        log_p=log_p,
    )
    return dense, hier


def test_every_crossing_a_portal_is_exact_with_four_connected_moves(office):
    # the optimum splits into exact intra-territory pieces joined by orthogonal crossings: all of them are nodes
    dense, hier = pair(office, 4, office[0].map.resolution)
    assert hier.hier is not None and dense.hier is None
    assert np.allclose(hier.w_hat_metric, dense.w_hat_metric, rtol=0, atol=1e-9)
    free = np.argwhere(dense.main)
    for cell in free[np.random.default_rng(0).choice(len(free), 40, replace=False)]:
        assert np.allclose(hier.start_w_hat(cell), dense.start_w_hat(cell), rtol=0, atol=1e-9)


def test_legs_are_real_paths_whose_cost_is_w_hat(office):
    dense, hier = pair(office)
    fin = np.isfinite(dense.w_hat_metric)
    assert (fin == np.isfinite(hier.w_hat_metric)).all()  # never stranded: same reachability
    assert (hier.w_hat_metric[fin] <= dense.w_hat_metric[fin] + 1e-9).all()  # a real path: no cheaper
    cost = hier.map_cost
    for i, j in zip(*np.nonzero(fin), strict=True):
        path = hier.edge_path(int(i), int(j))
        steps = np.abs(np.diff(path, axis=0))
        assert steps.max() == 1 and (steps.sum(axis=1) >= 1).all()  # 8-connected, no repeats
        assert hier.traversable[path[:, 0], path[:, 1]].all()
        assert (path[0] == hier.node_cell[i]).all() and (path[-1] == hier.node_cell[j]).all()
        assert hier.end_term[j] - cells_cost(path, cost) == pytest.approx(hier.w_hat_metric[i, j], rel=1e-9)
    rng = np.random.default_rng(1)
    free = np.argwhere(hier.main)
    for cell in free[rng.choice(len(free), 20, replace=False)]:
        j = int(rng.integers(hier.n_nodes))
        leg = hier.leg(cell, j)
        assert leg.cost == pytest.approx(hier.end_term[j] - hier.start_w_hat(cell)[j], rel=1e-9)
        assert leg.cost >= dense.leg(cell, j).cost - 1e-9


def test_avoided_territories_are_never_entered_and_views_stay_exact(office):
    dense, hier = pair(office, 4, office[0].map.resolution)
    corridor = [int(k) for k in np.unique(hier.node_place) if office[0].place_names[k].startswith("corridor")][:1]
    dv, hv = avoided_view(dense, tuple(corridor)), avoided_view(hier, tuple(corridor))
    assert np.allclose(hv.w_hat_metric, dv.w_hat_metric, rtol=0, atol=1e-9)
    for i, j in zip(*np.nonzero(np.isfinite(hv.w_hat_metric)), strict=True):
        path = hv.edge_path(int(i), int(j))
        assert not hv.blocked[path[:, 0], path[:, 1]].any()
    assert avoided_view(hier, tuple(corridor)) is hv  # memoised


def test_rebuild_reuses_unchanged_territories_and_equals_a_fresh_build(office):
    _, model, log_p = office
    s = GraphSettings(max_dense_bytes=0)
    base = PlanningGraph.build(model, s, log_p=log_p)
    same = base.update(model, log_p=log_p)
    assert same.info["fields_computed"] == 0 and same.info["fields_reused"] == base.info["abstract_nodes"]
    k = int(np.flatnonzero(model.active_places)[-1])
    moved = base.update_place(k, model.mu[k] + np.array([0.3, -0.2]), model.Sigma[k] * 1.5)
    fresh = PlanningGraph.build(moved.model, s, log_p=log_p)
    assert 0 < moved.info["fields_computed"] < fresh.info["fields_computed"]
    assert np.array_equal(moved.territory, fresh.territory)
    assert np.array_equal(moved.w_hat_metric, fresh.w_hat_metric)
    assert np.array_equal(moved.hier.fcode, fresh.hier.fcode)
    assert model.mu[k].tolist() != moved.model.mu[k].tolist()  # the base model is left alone
    with pytest.raises(ModelError, match="place index"):
        base.update_place(len(model.mu), model.mu[0], model.Sigma[0])
    with pytest.raises(ModelError, match="positive definite"):
        base.update_place(k, model.mu[k], -np.eye(2))


def test_planner_on_the_portal_graph(office):
    ds, model, log_p = office
    planner = HierarchicalPlanner(model, PlannerSettings(max_dense_bytes=0), log_p=log_p)
    free = np.argwhere(planner.graph.main)
    start = ds.map.cell_to_world(planner.graph.to_map(free[len(free) // 3]))
    goal = ds.place_names[int(np.flatnonzero(model.active_places)[-1])]
    plan = planner.plan(f"go to the {goal}", start)
    cells = planner.graph.to_crop(plan.cells)
    assert planner.graph.traversable[cells[:, 0], cells[:, 1]].all()
    assert plan.places[-1].name.startswith(goal)


def test_compiled_most_probable_place_matches_log_gaussian():
    rng = np.random.default_rng(3)
    K = 7
    mu = rng.normal(size=(K, 2)) * 3
    A = rng.normal(size=(K, 2, 2))
    Sigma = A @ A.transpose(0, 2, 1) + 0.1 * np.eye(2)
    prior = np.log(rng.dirichlet(np.ones(K)))
    centres = rng.normal(size=(30, 40, 2)) * 4
    ref = np.argmax(log_gaussian(centres, mu, Sigma) + prior, axis=-1)
    det = Sigma[:, 0, 0] * Sigma[:, 1, 1] - Sigma[:, 0, 1] * Sigma[:, 1, 0]
    assert np.array_equal(posterior_arg_max(centres, mu, Sigma, prior), ref)
    assert math.isfinite(float(det.min()))

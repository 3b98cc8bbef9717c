"""The precomputation (Algorithm 1, lines 1-7): candidates, w-hat against independent searches, clipping, cache."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from spcotmhp.errors import ModelError
from spcotmhp.logspace import log_gaussian
from spcotmhp.metric.grid_search import SQRT2, cost_to_go, shortest_paths, step_cost_map
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.planning.avoid import avoided_view
from spcotmhp.planning.graph import GraphSettings, PlanningGraph, fingerprint
from spcotmhp.planning.graph_cache import GraphCache
from spcotmhp.planning.places import chi2_2d, connected_places, inside_places, mahalanobis2
from tests.helpers.planning import ORDER, home_log_p, home_map, home_model


def build(model=None, **kw) -> PlanningGraph:
    model = model or home_model()
    return PlanningGraph.build(model, GraphSettings(**kw), log_p=home_log_p(model.map))


def test_candidates_are_the_snapped_means_and_edges_follow_psi():
    g = build()
    model = g.model
    assert g.node_place.tolist() == [0, 1, 2, 3]
    # each mean lies in a free cell of this map, so the candidate is the mean's own cell
    assert (g.to_map(g.node_cell) == model.map.world_to_cell(model.mu)).all()
    # connected: L-M, M-R, K-R (the Figure 3 rule (psi_ab + psi_ba) / 2 > 1 / K)
    expected = {(0, 1), (1, 0), (1, 3), (3, 1), (2, 3), (3, 2)}
    finite = {(int(i), int(j)) for i, j in zip(*np.nonzero(np.isfinite(g.w_hat)), strict=False)}
    assert finite == expected
    assert connected_places(model).sum() == 4 + 6


def test_w_hat_is_minus_the_map_cost_of_the_leg_plus_the_end_gaussian():
    # Eq. 24 observed at a leg's end: w-hat = sum over the leg of [log p(x|m) - log|A|] + log N(x_j | mu_b)
    g = build()
    model, occ = g.model, g.model.map
    log_p = home_log_p(occ)
    cost = np.where(np.isfinite(log_p), math.log(9) - log_p, np.inf)
    for i, j in zip(*np.nonzero(np.isfinite(g.w_hat)), strict=False):
        b = g.node_place[j]
        ref = shortest_paths(
            cost,
            g.to_map(g.node_cell[i]),
            g.to_map(g.node_cell[j])[None],
            connectivity=8,
            diagonal_factor=SQRT2,
        )
        end = occ.cell_to_world(g.to_map(g.node_cell[j]))
        log_n = log_gaussian(end, model.mu[b : b + 1], model.Sigma[b : b + 1])[0]
        assert g.w_hat[i, j] == pytest.approx(log_n - ref.cost, rel=1e-9)
        # and the stored partial path has exactly that cost
        path = g.to_map(g.edge_path(int(i), int(j)))
        steps = np.where(np.abs(np.diff(path, axis=0)).sum(axis=1) == 2, SQRT2, 1.0)
        assert (steps * cost[path[1:, 0], path[1:, 1]]).sum() == pytest.approx(ref.cost, rel=1e-9)


def test_w_hat_by_hand_on_a_one_row_corridor():
    # a single free row: the path from the left candidate to the right one is forced, so w-hat is a plain sum
    data = np.full((3, 12), 100, dtype=np.int8)
    data[1, 1:11] = 0
    occ = OccupancyMap(data=data, resolution=1.0)
    model = home_model()
    model = dataclasses.replace(
        model,
        mu=np.array([[2.5, 1.5], [5.5, 1.5], [8.5, 1.5], [9.5, 1.5]]),
        Sigma=np.tile(np.diag([4.0, 1.0]), (4, 1, 1)),
        map=occ,
    )
    g = PlanningGraph.build(model, GraphSettings(), log_p=np.where(data == 0, 0.0, -np.inf))
    # place 0 at col 2, place 1 at col 5: three steps into cols 3, 4, 5 cost log 9 each (p(x|m) = 1); the leg
    # ends at the mean of place 1: log N(mu | mu, diag(4, 1)) = -log(2 pi) - log(4) / 2
    end = -math.log(2 * math.pi) - 0.5 * math.log(4.0)
    assert g.w_hat[0, 1] == pytest.approx(end - 3 * math.log(9))
    assert g.start_w_hat(g.to_crop(np.array([1, 2])))[1] == pytest.approx(g.w_hat[0, 1])
    # from col 1 the start leg enters cols 2..5: the same end term, one more step
    assert g.start_w_hat(g.to_crop(np.array([1, 1])))[1] == pytest.approx(end - 4 * math.log(9))
    assert g.leg(g.to_crop(np.array([1, 1])), 1).cells.tolist() == [[0, 0], [0, 1], [0, 2], [0, 3], [0, 4]]


def test_leg_likelihood_grows_with_length_not_with_distance_from_the_mean():
    # the cause of the "wrong bedroom": under the every-step Gaussian a short leg into a narrow Gaussian scored
    # below a long leg into a broad one; end-observed, the shorter leg of two equal Gaussians always wins
    data = np.full((3, 30), 100, dtype=np.int8)
    data[1, 1:29] = 0
    occ = OccupancyMap(data=data, resolution=0.1)
    model = home_model()
    Sigma = np.stack([np.eye(2) * 0.04, np.eye(2) * 0.04, np.diag([1.0, 0.04]), np.eye(2) * 0.04])
    model = dataclasses.replace(
        model, mu=np.array([[0.85, 0.15], [0.55, 0.15], [2.25, 0.15], [2.85, 0.15]]), Sigma=Sigma, map=occ
    )
    g = PlanningGraph.build(model, GraphSettings(), log_p=np.where(data == 0, 0.0, -np.inf))
    start = g.start_w_hat(g.to_crop(occ.world_to_cell(np.array([0.95, 0.15]))))
    # place 1 is 4 cells away, place 2 (broad along the row) 13 cells away: the near one scores higher
    assert start[1] > start[2]


def test_inscribed_cells_are_not_traversable_and_nodes_avoid_them():
    import warnings

    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.metric.costmap import inflate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dataset = load_bundled("3LDK_01")
    model = fit_supervised(dataset)
    cm = inflate(model.map, **model.costmap)
    # the toilet's mean lies within the robot's radius of a wall (costmap_2d 253): its node moved out
    toilet = model.map.world_to_cell(model.mu[dataset.place_names.index("toilet")])
    assert cm.costs[toilet[0], toilet[1]] >= 253
    g = PlanningGraph.build(model, GraphSettings(), log_p=cm.log_p)
    crop = (
        slice(g.offset[0], g.offset[0] + g.log_p.shape[0]),
        slice(g.offset[1], g.offset[1] + g.log_p.shape[1]),
    )
    assert not (g.traversable & (cm.costs[crop] >= 253)).any()
    cells = g.to_map(g.node_cell)
    assert (cm.costs[cells[:, 0], cells[:, 1]] < 253).all()


def test_sampled_candidates_are_seeded_inside_their_ellipse():
    g1 = build(n_candidates=5, seed=3)
    g2 = build(n_candidates=5, seed=3)
    g3 = build(n_candidates=5, seed=4)
    assert (g1.node_cell == g2.node_cell).all()
    assert not np.array_equal(g1.node_cell, g3.node_cell)
    model = g1.model
    xy = model.map.cell_to_world(g1.to_map(g1.node_cell))
    for k in range(len(ORDER)):
        mine = g1.node_place == k
        assert 1 <= mine.sum() <= 5
        assert (g1.to_map(g1.node_cell[mine][0]) == model.map.world_to_cell(model.mu[k])).all()  # mean first
        # the snapped cells (free rooms here: the sample's own cell) stay within the 0.95 ellipse up to the
        # distance from a point to its cell centre (half a cell diagonal)
        d2 = mahalanobis2(xy[mine], model.mu[k : k + 1], model.Sigma[k : k + 1])[:, 0]
        slack = 0.5 * SQRT2 * 0.5 / math.sqrt(np.diag(model.Sigma[k]).min())
        assert (np.sqrt(d2) <= math.sqrt(chi2_2d(0.95)) + slack).all()
    assert inside_places(model, model.mu, np.arange(4)).all()


def test_cache_is_keyed_by_model_map_and_settings():
    cache = GraphCache()
    model = home_model()
    log_p = home_log_p(model.map)
    a = PlanningGraph.build(model, GraphSettings(), log_p=log_p, cache=cache)
    assert PlanningGraph.build(model, GraphSettings(), log_p=log_p, cache=cache) is a
    assert PlanningGraph.build(model, GraphSettings(), log_p=log_p) is not a  # no cache: computed afresh
    moved = dataclasses.replace(model, mu=model.mu + np.array([0.5, 0.0]))
    assert PlanningGraph.build(moved, GraphSettings(), log_p=log_p, cache=cache) is not a
    assert PlanningGraph.build(model, GraphSettings(n_candidates=2), log_p=log_p, cache=cache) is not a
    assert len(cache) == 3 and a.key in cache
    data = model.map.data.copy()
    data[5, 5] = 100
    other_map = dataclasses.replace(model, map=dataclasses.replace(model.map, data=data))
    assert fingerprint(other_map, GraphSettings()) != fingerprint(model, GraphSettings())
    assert fingerprint(model, GraphSettings()) == fingerprint(home_model(), GraphSettings())


def test_model_without_map_or_places_is_refused():
    model = home_model()
    with pytest.raises(ModelError, match="the model has no map"):
        PlanningGraph.build(dataclasses.replace(model, map=None))
    with pytest.raises(ModelError, match="no active place"):
        PlanningGraph.build(dataclasses.replace(model, active_places=np.zeros(4, bool)))
    with pytest.raises(ModelError, match="no free cell"):
        PlanningGraph.build(model, log_p=np.full(home_map().shape, -np.inf))


def test_main_component_does_not_join_through_a_diagonal_squeeze():
    from spcotmhp.planning.places import main_component

    free = np.zeros((4, 4), bool)
    free[:2, :2] = True  # a 2x2 room
    free[2, 2] = free[3, 3] = free[3, 2] = True  # touching the room only at the corner (1,1)-(2,2)
    comp = main_component(free)
    assert comp[:2, :2].all() and not comp[2:, 2:].any()
    assert not main_component(np.zeros((2, 2), bool)).any()


def reference_avoiding(g: PlanningGraph, view: PlanningGraph, cell: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """w-hat and start w-hat with every field recomputed from scratch on the blocked map."""
    M = g.n_nodes
    start = np.full(M, -np.inf)
    w_hat = np.full((M, M), -np.inf)
    for j in np.flatnonzero(view.usable):
        cost = step_cost_map(g.log_p, None, g.settings.connectivity)
        cost[view.blocked] = np.inf
        dist, _ = cost_to_go(cost, g.node_cell[j][None], g.settings.connectivity, SQRT2)
        start[j] = g.end_term[j] - dist[cell[0], cell[1]]
        w_hat[:, j] = g.end_term[j] - dist[g.node_cell[:, 0], g.node_cell[:, 1]]
    return start, np.where(np.isfinite(g.w_hat) & view.usable[:, None], w_hat, -np.inf)


def test_avoidance_views_are_exact():
    import warnings

    from spcotmhp.datasets.bundled import load_bundled
    from spcotmhp.learning.supervised import fit_supervised

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        dataset = load_bundled("3LDK_06")
    model = fit_supervised(dataset)
    g = PlanningGraph.build(model)
    rng = np.random.default_rng(0)
    free = np.argwhere(g.traversable)
    recomputed = 0
    for places in [(10,), (6,), (4, 9), (2,)]:  # corridor, dining, living + washroom, kitchen
        view = avoided_view(g, places)
        assert avoided_view(g, places) is view
        for cell in free[rng.integers(len(free), size=25)]:
            if view.blocked[cell[0], cell[1]]:
                continue
            start, w_hat = reference_avoiding(g, view, cell)
            assert np.allclose(view.start_w_hat(cell), start, equal_nan=False)
            assert np.array_equal(np.isfinite(view.w_hat), np.isfinite(w_hat))
            assert np.allclose(view.w_hat[np.isfinite(w_hat)], w_hat[np.isfinite(w_hat)])
        assert not view.usable[np.isin(g.node_place, places)].any()
        recomputed += len(view.info["recomputed_fields"])
    assert 0 < recomputed < 4 * g.n_nodes  # some fields shared, some recomputed


def test_precomputation_runs_with_the_collector_paused_and_resumes_it(monkeypatch):
    import gc

    import spcotmhp.planning.graph as graph_module

    seen = []
    original = graph_module.graph_inputs

    def spy(*args, **kwargs):
        seen.append(gc.isenabled())
        return original(*args, **kwargs)

    monkeypatch.setattr(graph_module, "graph_inputs", spy)
    assert gc.isenabled()
    build()
    assert seen == [False] and gc.isenabled()


def test_every_step_w_hat_is_minus_the_eq24_cost_of_the_best_leg():
    """Eq. 24 as written (optimality at every step): w-hat[i, j] = max over legs of sum over its cells (the start
    cell excepted) of log p(x|m) + log N(x | mu_b, Sigma_b) - log|A|, checked against an independent search on
    step_cost_map with the destination's Gaussian; the end term is 0."""
    g = build(optimality="every_step")
    model, occ = g.model, g.model.map
    log_p = home_log_p(occ)
    centres = occ.cell_centres()
    assert (g.end_term == 0).all()
    for i, j in zip(*np.nonzero(np.isfinite(g.w_hat)), strict=False):
        b = g.node_place[j]
        log_n = log_gaussian(centres.reshape(-1, 2), model.mu[b : b + 1], model.Sigma[b : b + 1]).reshape(occ.shape)
        cost = step_cost_map(log_p, log_n, connectivity=8)
        ref = shortest_paths(
            cost, g.to_map(g.node_cell[i]), g.to_map(g.node_cell[j])[None], connectivity=8, diagonal_factor=SQRT2
        )
        assert g.w_hat[i, j] == pytest.approx(-ref.cost, rel=1e-9)
    # the leg into a place now pays its Gaussian along the way: every w-hat is lower than the end-observed one by
    # at least the Gaussian's smallest -log N over the cells it passes (here: strictly lower)
    end = build()
    both = np.isfinite(g.w_hat) & np.isfinite(end.w_hat)
    assert both.any() and (g.w_hat[both] != end.w_hat[both]).all()


def test_every_step_on_a_one_row_corridor_by_hand():
    data = np.full((3, 12), 100, dtype=np.int8)
    data[1, 1:11] = 0
    occ = OccupancyMap(data=data, resolution=1.0)
    model = dataclasses.replace(
        home_model(),
        mu=np.array([[2.5, 1.5], [5.5, 1.5], [8.5, 1.5], [9.5, 1.5]]),
        Sigma=np.tile(np.diag([4.0, 1.0]), (4, 1, 1)),
        map=occ,
    )
    g = PlanningGraph.build(model, GraphSettings(optimality="every_step"), log_p=np.where(data == 0, 0.0, -np.inf))
    # from col 2 into place 1's mean at col 5: cells 3, 4, 5 at x-distances 2, 1, 0 from it, each
    # log 9 - log N = log 9 + log(2 pi) + log(4) / 2 + dx^2 / (2 * 4)
    per_cell = math.log(9) + math.log(2 * math.pi) + 0.5 * math.log(4.0)
    assert g.w_hat[0, 1] == pytest.approx(-(3 * per_cell + (4 + 1 + 0) / 8))


def test_every_step_refuses_a_negative_step_cost_and_the_portal_graph():
    from spcotmhp.errors import InvalidSettings

    narrow = dataclasses.replace(home_model(), Sigma=np.tile(np.eye(2) * 1e-4, (4, 1, 1)))
    with pytest.raises(InvalidSettings, match="so narrow that the step cost of Eq. 24 at every step"):
        build(narrow, optimality="every_step")
    with pytest.raises(InvalidSettings, match="optimality 'every_step' needs one dense field per node"):
        build(optimality="every_step", max_dense_bytes=0)
    with pytest.raises(InvalidSettings, match="optimality must be one of end, every_step"):
        GraphSettings(optimality="sometimes")


def test_an_update_after_a_teach_keeps_the_fields_of_nodes_that_did_not_move(tmp_path):
    """Issue 24: a teach rebuilt every dense cost-to-go field (0.1-1.4 s). A field depends only on the step cost
    and its node's cell, so ``update`` keeps those of unmoved nodes and computes the rest; the graph equals a full
    build, and the cost map is not inflated again."""
    import warnings

    from spcotmhp.datasets import load_bundled
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.teaching.teach import teach

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = fit_supervised(load_bundled("3LDK_06"))
    before = PlanningGraph.build(model)
    taught = teach(model, [{"x": 3.0, "y": 3.0, "utterance": "this is the study"}]).model
    updated = before.update(taught)
    fresh = PlanningGraph.build(taught)
    assert updated.info["fields_reused"] >= updated.n_nodes - 2 > 0
    assert "fields_reused" not in fresh.info or fresh.info["fields_reused"] == 0
    assert np.array_equal(updated.node_cell, fresh.node_cell)
    assert np.array_equal(updated.dist, fresh.dist) and np.array_equal(updated.next_step, fresh.next_step)
    assert np.array_equal(updated.w_hat, fresh.w_hat) and np.array_equal(updated.log_p, fresh.log_p)


def test_start_legs_kernel_is_the_fields_formula_exactly():
    """On dense fields start_w_hat is one kernel (start_legs): the same floats as end_term - cost_to_nodes where
    the node is usable, -inf elsewhere, from every crop cell (reached or not)."""
    g = build()
    assert g.hier is None and isinstance(g.dist, np.ndarray)
    usable = g.usable.copy()
    usable[1] = False  # as in an avoidance view
    g = dataclasses.replace(g, usable=usable)
    assert not g.usable[1] and isinstance(g.dist, np.ndarray)
    h, w = g.log_p.shape
    for r in range(h):
        for c in range(w):
            cell = np.array([r, c])
            expected = np.where(g.usable, g.end_term - g.cost_to_nodes(cell), -np.inf)
            assert np.array_equal(g.start_w_hat(cell), expected)

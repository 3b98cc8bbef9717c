"""Mean ± sd over seeds, the paper's moving average and HPP with SpCoTMHP's smoothing (hand-computed cases)."""

import numpy as np
import pytest

from spcotmhp.baselines.smoothing import moving_average
from spcotmhp.evaluation.spread import aggregate, aggregate_methods, bootstrap_ci, pm


def test_aggregate_mean_and_sample_sd():
    out = aggregate(
        [
            {"spl": 0.5, "n_tasks": 10, "name": "x"},
            {"spl": 0.7, "n_tasks": 10, "name": "y"},
            {"spl": 0.9, "n_tasks": 10, "name": "z"},
        ]
    )
    # mean 0.7; sample sd sqrt((0.04 + 0 + 0.04) / 2) = 0.2
    assert out["spl"] == pytest.approx(0.7) and out["spl_sd"] == pytest.approx(0.2)
    assert (out["n_tasks"], out["name"], out["seeds"]) == (10, "x", 3) and "n_tasks_sd" not in out
    assert aggregate([{"spl": 0.5}])["spl_sd"] == 0.0
    assert pm({"spl": 0.7, "spl_sd": 0.2, "seeds": 3}, "spl") == "0.700 ± 0.200"
    assert pm({"spl": 0.7, "spl_sd": 0.0, "seeds": 1}, "spl") == "0.700"
    assert list(aggregate_methods([{"b": {"v": 1.0}, "a": {"v": 2.0}}, {"b": {"v": 3.0}, "a": {"v": 2.0}}])) == [
        "b",
        "a",
    ]
    with pytest.raises(ValueError, match="no seeds"):
        aggregate([])


def test_moving_average_window_5_by_hand():
    path = np.array([[0, 0], [1, 0], [2, 0], [3, 0], [3, 1], [3, 2], [3, 3]], float)
    out = moving_average(path)
    # the ends stay; pose 1 averages poses 0-2 (window shrunk to 3); pose 3 averages poses 1-5
    np.testing.assert_allclose(out[0], [0, 0])
    np.testing.assert_allclose(out[-1], [3, 3])
    np.testing.assert_allclose(out[1], [1, 0])
    np.testing.assert_allclose(out[3], [(1 + 2 + 3 + 3 + 3) / 5, (0 + 0 + 0 + 1 + 2) / 5])
    np.testing.assert_allclose(out[5], [3, 2])  # poses 4-6: (3, 1), (3, 2), (3, 3)
    # the corner is cut: the averaged path is shorter
    assert np.linalg.norm(np.diff(out, axis=0), axis=1).sum() < 6.0
    np.testing.assert_allclose(moving_average(path[:2]), path[:2])
    with pytest.raises(ValueError, match="odd integer"):
        moving_average(path, 4)


def test_hpp_with_our_smoothing_keeps_start_waypoint_and_is_not_longer():
    from spcotmhp.baselines.hpp import EDGE_COSTS, HPP, draw_place
    from spcotmhp.datasets import load_bundled
    from spcotmhp.learning.supervised import fit_supervised
    from spcotmhp.planning.assemble import path_length
    from spcotmhp.planning.planner import HierarchicalPlanner

    planner = HierarchicalPlanner(fit_supervised(load_bundled("3LDK_01")))
    g = planner.graph
    hpp = HPP(g, EDGE_COSTS["hpp2"])
    free = np.argwhere(np.isfinite(g.dist[0]) & g.traversable)  # cells connected to the places
    for k in range(8):
        cell = free[np.random.default_rng(k).integers(len(free))]
        stages = [["kitchen"], ["bedroom"]]
        raw = hpp.plan(cell, stages, np.random.default_rng(k))
        smooth = hpp.plan(cell, stages, np.random.default_rng(k), smooth=True)
        assert (smooth[0] == raw[0]).all() and (smooth[-1] == raw[-1]).all()
        assert path_length(smooth, 1.0) <= path_length(raw, 1.0) + 1e-9
        assert g.traversable[smooth[:, 0], smooth[:, 1]].all()
        # the drawn waypoint (the first draw of the plan) is still passed: its candidate point is an anchor
        wp = draw_place(g, ["kitchen"], np.random.default_rng(k))
        anchor = g.node_cell[np.flatnonzero(g.node_place == wp)[0]]
        assert (raw == anchor).all(axis=1).any() and (smooth == anchor).all(axis=1).any()


def test_bootstrap_interval_by_hand():
    # two tasks scoring 0 and 1: a resample's mean is 0, 1/2 or 1 with probabilities 1/4, 1/2, 1/4, so the 2.5th
    # and 97.5th percentiles of 2000 resamples are 0 and 1
    ci = bootstrap_ci([np.array([[0.0], [1.0]])], seed=0)
    assert ci.tolist() == [[0.0, 1.0]]
    # stratified by home: each home keeps its two tasks, so homes that are uniform inside give a fixed mean
    assert bootstrap_ci([np.array([[0.0], [0.0]]), np.array([[1.0], [1.0]])], seed=1).tolist() == [[0.5, 0.5]]
    # 100 tasks, 30 successes: the interval holds 0.3 and is about 2 standard errors wide each way
    terms = np.array([[1.0]] * 30 + [[0.0]] * 70)
    ((low, high),) = bootstrap_ci([terms], seed=2)
    se = np.sqrt(0.3 * 0.7 / 100)
    assert low < 0.3 < high and abs((high - low) / 2 - 1.96 * se) < 0.02
    assert (bootstrap_ci([terms], seed=2) == bootstrap_ci([terms], seed=2)).all()  # seeded
    with pytest.raises(ValueError, match="no tasks"):
        bootstrap_ci([], seed=0)
    assert pm({"spl": 0.5, "spl_ci": [0.25, 0.75], "spl_sd": 0.0, "seeds": 2}, "spl", interval=True) == (
        "0.500 [0.250, 0.750]"
    )

"""SPL family on hand-computed paths (every number below is worked out in the comment beside it)."""

import math

import numpy as np
import pytest

from spcotmhp.evaluation.metrics import (
    Box,
    Outcome,
    densify,
    efficiency,
    failed,
    off_free_space,
    path_length,
    score_path,
    summarise,
)

# Two "bedrooms" and a "corridor" on a 10 m x 10 m plane.
BED_NEAR = Box(4.0, 0.0, 6.0, 2.0)
BED_FAR = Box(8.0, 8.0, 10.0, 10.0)
CORRIDOR = Box(1.0, 3.0, 2.0, 4.0)


def test_box_around_adds_margin_and_contains_bounds():
    box = Box.around(np.array([[1.0, 2.0], [3.0, 5.0], [2.0, 4.0]]), margin=0.1)
    assert box == Box(0.9, 1.9, 3.1, 5.1)
    inside = box.contains(np.array([[0.9, 1.9], [3.1, 5.1], [2.0, 3.0], [0.89, 3.0], [2.0, 5.11]]))
    assert inside.tolist() == [True, True, True, False, False]


def test_path_length_is_euclidean_polyline_length():
    assert path_length(np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 4.0]])) == pytest.approx(7.0)  # 3 + 4
    assert path_length(np.array([[0.0, 0.0], [3.0, 4.0]])) == pytest.approx(5.0)  # one 3-4-5 segment
    assert path_length(np.array([[1.0, 1.0]])) == 0.0
    assert path_length(np.zeros((0, 2))) == 0.0


def test_densify_keeps_vertices_and_limits_spacing():
    pts = densify(np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.5]]), step=0.25)
    # 1 m segment -> 4 pieces, 0.5 m segment -> 2 pieces, plus the last vertex: 7 points
    assert pts.shape == (7, 2)
    np.testing.assert_allclose(pts[:, 0], [0, 0.25, 0.5, 0.75, 1, 1, 1])
    np.testing.assert_allclose(pts[:, 1], [0, 0, 0, 0, 0, 0.25, 0.5])
    assert np.linalg.norm(np.diff(pts, axis=0), axis=1).max() <= 0.25 + 1e-12


def test_efficiency_is_l_over_max_p_l():
    assert efficiency(8.0, 6.0) == pytest.approx(0.75)
    assert efficiency(5.0, 6.0) == 1.0  # a path shorter than the reference is not rewarded above 1
    assert efficiency(0.0, 0.0) == 1.0
    with pytest.raises(ValueError, match="finite and >= 0"):
        efficiency(1.0, math.inf)
    with pytest.raises(ValueError, match="finite and >= 0"):
        efficiency(-1.0, 1.0)


def test_basic_path_to_far_instance_counts_for_spl_not_n_spl():
    # start (0,0) -> (0,9) -> (9,9) ends in BED_FAR: p = 9 + 9 = 18. Shortest success: to BED_NEAR, l = 4.
    path = np.array([[0.0, 0.0], [0.0, 9.0], [9.0, 9.0]])
    out = score_path(path, [BED_NEAR, BED_FAR], closest_goal=0, l=4.0, time_s=0.01)
    assert (out.success, out.n_success, out.w_success) == (True, False, None)
    assert out.p == pytest.approx(18.0)
    assert out.ratio == pytest.approx(4.0 / 18.0)
    m = summarise([out])
    assert m["spl"] == pytest.approx(4.0 / 18.0)
    assert m["n_spl"] == 0.0
    assert "w_spl" not in m and "wn_spl" not in m


def test_basic_path_to_closest_instance():
    # (0,1) -> (4.5,1): 4.5 m, ends inside BED_NEAR; l = 4 (the box's left edge) -> ratio 4 / 4.5
    out = score_path(np.array([[0.0, 1.0], [4.5, 1.0]]), [BED_NEAR, BED_FAR], 0, 4.0, 0.0)
    assert out.success and out.n_success
    assert out.ratio == pytest.approx(4.0 / 4.5)


def test_path_ending_outside_every_goal_fails_but_keeps_length():
    out = score_path(np.array([[0.0, 1.0], [3.0, 1.0]]), [BED_NEAR, BED_FAR], 0, 4.0, 0.0)
    assert not out.success and not out.n_success
    assert summarise([out])["spl"] == 0.0


def test_waypoint_crossed_between_far_vertices_is_seen():
    # one straight segment (0,3.5) -> (5,3.5) -> (5,1): crosses CORRIDOR (x 1..2 at y 3.5) with no vertex in it
    path = np.array([[0.0, 3.5], [5.0, 3.5], [5.0, 1.0]])
    out = score_path(path, [BED_NEAR, BED_FAR], 0, 6.0, 0.0, waypoint_boxes=[CORRIDOR])
    assert out.w_success and out.success and out.n_success
    assert out.p == pytest.approx(7.5)  # 5 + 2.5
    m = summarise([out])
    assert m["w_spl"] == pytest.approx(6.0 / 7.5)
    assert m["wn_spl"] == pytest.approx(6.0 / 7.5)


def test_missed_waypoint_zeroes_w_and_wn_only():
    path = np.array([[0.0, 1.0], [5.0, 1.0]])  # never near the corridor; 5 m, l = 6 -> ratio 1
    out = score_path(path, [BED_NEAR, BED_FAR], 0, 6.0, 0.0, waypoint_boxes=[CORRIDOR])
    m = summarise([out])
    assert (m["spl"], m["n_spl"], m["w_spl"], m["wn_spl"]) == (1.0, 1.0, 0.0, 0.0)


def test_zero_reference_length_is_refused():
    # l = 0 tasks are not made (tasks.py); a zero l reaching the metric is a bug, not a score
    with pytest.raises(ValueError, match="finite and > 0"):
        score_path(np.array([[4.5, 0.5]]), [BED_NEAR, BED_FAR], 0, 0.0, 0.0)


def test_waypoint_counts_only_after_the_path_leaves_its_start_cell():
    # the start (1.5, 3.5) lies in CORRIDOR, in a coarse 1.2 m start cell covering all of it; a path that leaves
    # eastwards never comes back to it
    start = Box.around(np.array([[1.5, 3.5]]), 0.6)
    path = np.array([[1.5, 3.5], [5.0, 3.5], [5.0, 1.0]])
    assert score_path(path, [BED_NEAR], 0, 6.0, 0.0, waypoint_boxes=[CORRIDOR]).w_success  # old rule
    out = score_path(path, [BED_NEAR], 0, 6.0, 0.0, waypoint_boxes=[CORRIDOR], start_box=start)
    assert not out.w_success and out.success
    # ... but a path that goes out of the start cell and through the corridor again passes it
    back = np.array([[1.5, 3.5], [1.5, 4.5], [0.5, 4.5], [0.5, 3.2], [5.0, 3.2], [5.0, 1.0]])
    assert score_path(back, [BED_NEAR], 0, 6.0, 0.0, waypoint_boxes=[CORRIDOR], start_box=start).w_success
    # a path that never leaves the start cell passes no waypoint
    assert not score_path(
        np.array([[1.5, 3.5], [1.52, 3.5]]),
        [CORRIDOR],
        0,
        1.0,
        0.0,
        waypoint_boxes=[CORRIDOR],
        start_box=start,
    ).w_success


def test_n_from_the_start_and_n_via_the_waypoint_are_separate():
    # ends in BED_FAR: closest from the start is BED_NEAR (index 0), closest via the waypoint BED_FAR (index 1)
    path = np.array([[0.0, 1.0], [0.0, 9.0], [9.0, 9.0]])  # 8 + 9 = 17 m
    out = score_path(
        path, [BED_NEAR, BED_FAR], 0, 17.0, 0.0, waypoint_boxes=[Box(-0.5, 4.0, 0.5, 5.0)], closest_goal_via=1
    )
    assert (out.n_success, out.n_via_success, out.w_success) == (False, True, True)
    m = summarise([out])
    assert (m["n_spl"], m["wn_spl"], m["n_spl_via"], m["wn_spl_via"]) == (0.0, 0.0, 1.0, 1.0)


def test_off_free_space():
    free = np.ones((10, 10), bool)
    free[5, 5] = False

    def cell_of(xy):
        return np.floor(xy[:, ::-1]).astype(int)  # 1 m cells, (x, y) -> (row, col)

    assert not off_free_space(np.array([[0.5, 0.5], [9.5, 0.5]]), free, cell_of, 0.25)
    assert off_free_space(np.array([[0.5, 0.5], [9.5, 9.5]]), free, cell_of, 0.25)  # the diagonal hits (5, 5)
    assert off_free_space(np.array([[0.5, 0.5], [10.5, 0.5]]), free, cell_of, 0.25)  # leaves the map


def test_empty_path_is_a_failure():
    assert score_path(np.zeros((0, 2)), [BED_NEAR], 0, 3.0, 0.5) == failed(3.0, 0.5, advanced=False)
    out = failed(3.0, 0.5, advanced=True)
    assert (out.success, out.n_success, out.w_success, out.ratio) == (False, False, False, 0.0)


def test_summarise_means_and_times():
    outs = [
        Outcome(True, True, True, 5.0, 5.0, 1.0, 0.1),  # all four successes, ratio 1
        Outcome(True, False, True, 10.0, 5.0, 0.5, 0.2),  # far instance: S, W; ratio 0.5
        Outcome(False, False, False, 3.0, 5.0, 1.0, 0.3),  # failure
        Outcome(True, True, False, 8.0, 4.0, 0.5, 0.4),  # missed waypoint: S, N; ratio 0.5
    ]
    m = summarise(outs)
    assert m["spl"] == pytest.approx((1.0 + 0.5 + 0 + 0.5) / 4)
    assert m["n_spl"] == pytest.approx((1.0 + 0 + 0 + 0.5) / 4)
    assert m["w_spl"] == pytest.approx((1.0 + 0.5 + 0 + 0) / 4)
    assert m["wn_spl"] == pytest.approx(1.0 / 4)
    assert m["success"] == pytest.approx(0.75)
    assert m["time_median_s"] == pytest.approx(0.25)
    # numpy's linear percentile: rank 0.95 * 3 = 2.85 -> 0.3 + 0.85 * 0.1
    assert m["time_p95_s"] == pytest.approx(0.385)
    assert m["n_tasks"] == 4


def test_summarise_rejects_empty_and_mixed():
    with pytest.raises(ValueError, match="no task outcomes"):
        summarise([])
    with pytest.raises(ValueError, match="mix basic"):
        summarise([Outcome(True, True, None, 1, 1, 1, 0), Outcome(True, True, True, 1, 1, 1, 0)])

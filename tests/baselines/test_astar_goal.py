"""Baseline (A): goal sampling from p(x | S, Theta) and A* to it."""

import numpy as np
import pytest
from scipy.special import logsumexp

from spcotmhp.baselines.astar_goal import astar_to_sampled_goal, reachable_cell_nearest, sample_goal
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.maps import OccupancyMap


def model() -> SpatialConceptModel:
    return SpatialConceptModel(
        mu=np.array([[1.5, 1.5], [7.5, 1.5]]),
        Sigma=np.array([np.eye(2) * 0.04, np.eye(2) * 0.04]),
        psi=np.full((2, 2), 0.5),
        pi=np.array([0.5, 0.5]),
        phi=np.array([[0.95, 0.05], [0.1, 0.9]]),
        W=np.array([[0.9, 0.1], [0.2, 0.8]]),
        vocabulary=["kitchen", "bed"],
    )


def test_sample_goal_mixture_weights():
    m = model()
    rng = np.random.default_rng(0)
    draws = np.array([sample_goal(m, ["bed"], rng) for _ in range(4000)])
    near_bed = np.mean(np.linalg.norm(draws - m.mu[1], axis=1) < 1.0)
    # p(C | bed) ∝ pi_C W_C(bed): (0.05, 0.4) / 0.45; p(k = 1 | bed) = sum_C p(C | bed) phi_C(1)
    lc = np.log(m.pi * m.W[:, 1])
    pc = np.exp(lc - logsumexp(lc))
    assert near_bed == pytest.approx(pc @ m.phi[:, 1], abs=0.02)
    a = sample_goal(m, ["bed"], np.random.default_rng(3))
    b = sample_goal(m, ["bed"], np.random.default_rng(3))
    np.testing.assert_array_equal(a, b)


def test_goal_snapped_into_the_start_component():
    occ = OccupancyMap(np.zeros((3, 10), np.int8), resolution=1.0)
    log_p = np.zeros((3, 10))
    log_p[:, 5] = -np.inf  # a wall: columns 6..9 are another component
    assert reachable_cell_nearest(log_p, occ, (1, 0), np.array([8.5, 1.5])) == (1, 4)
    assert reachable_cell_nearest(log_p, occ, (1, 0), np.array([2.5, 2.5])) == (2, 2)
    assert reachable_cell_nearest(log_p, occ, (1, 9), np.array([8.5, 1.5])) == (1, 8)


def test_astar_to_sampled_goal_reaches_the_named_place():
    occ = OccupancyMap(np.zeros((3, 10), np.int8), resolution=1.0)
    log_p = np.zeros((3, 10))
    m = model()
    m.phi = np.array([[1.0, 1e-9], [1e-9, 1.0]])
    m.W = np.array([[0.999, 0.001], [0.001, 0.999]])
    cells = astar_to_sampled_goal(m, log_p, occ, (1, 1), ["bed"], np.random.default_rng(1))
    assert tuple(cells[0]) == (1, 1)
    assert abs(cells[-1][1] - 7) <= 1 and np.abs(np.diff(cells, axis=0)).max() <= 1


def test_astar_moves_8_connected_like_spcotmhp():
    # open 9 x 9 grid, goal (7, 7) from (1, 1): 6 diagonal steps, the octile (8-connected geodesic) length
    occ = OccupancyMap(np.zeros((9, 9), np.int8), resolution=1.0)
    m = model()
    m.mu = np.array([[1.5, 1.5], [7.5, 7.5]])
    m.Sigma = np.array([np.eye(2) * 1e-6, np.eye(2) * 1e-6])
    m.phi = np.array([[1.0, 1e-9], [1e-9, 1.0]])
    m.W = np.array([[0.999, 0.001], [0.001, 0.999]])
    cells = astar_to_sampled_goal(m, np.zeros((9, 9)), occ, (1, 1), ["bed"], np.random.default_rng(0))
    assert tuple(cells[-1]) == (7, 7)
    assert len(cells) == 7 and (np.abs(np.diff(cells, axis=0)) == 1).all()
    four = astar_to_sampled_goal(m, np.zeros((9, 9)), occ, (1, 1), ["bed"], np.random.default_rng(0), connectivity=4)
    assert len(four) == 13 and (np.abs(np.diff(four, axis=0)).sum(axis=1) == 1).all()

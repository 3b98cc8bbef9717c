"""SpCoNavi baselines: weight map against a direct sum of densities, Viterbi against brute-force enumeration."""

import itertools

import numpy as np
import pytest
from scipy.stats import multivariate_normal

from spcotmhp.baselines.spconavi import (
    ACTIONS_4,
    astar_approximation,
    horizon_objective,
    log_weight_map,
    sample_cells,
    viterbi,
)
from spcotmhp.errors import PlanningError
from spcotmhp.learning.model import SpatialConceptModel


def two_place_model() -> SpatialConceptModel:
    """Place 0 at (1, 1) named "kitchen", place 1 at (4, 1) named "bed" (concept l = place l)."""
    return SpatialConceptModel(
        mu=np.array([[1.0, 1.0], [4.0, 1.0]]),
        Sigma=np.array([np.eye(2) * 0.5, [[1.0, 0.2], [0.2, 0.6]]]),
        psi=np.full((2, 2), 0.5),
        pi=np.array([0.4, 0.6]),
        phi=np.array([[0.9, 0.1], [0.2, 0.8]]),
        W=np.array([[0.7, 0.3], [0.1, 0.9]]),
        vocabulary=["kitchen", "bed"],
    )


def test_weight_map_matches_direct_sum():
    model = two_place_model()
    xy = np.array([[[0.5, 0.5], [2.0, 1.0]], [[4.0, 1.5], [9.0, 9.0]]])
    log_p = np.log(np.array([[1.0, 0.5], [0.25, 1.0]]))
    log_p[1, 1] = -np.inf
    got = log_weight_map(model, log_p, xy, ["bed", "bed", "unknown-word"])
    for r, c in [(0, 0), (0, 1), (1, 0)]:
        total = 0.0
        for C in range(2):
            mult = model.W[C, 1] ** 2  # Mult(S | W_C) up to the coefficient: two "bed"
            dens = sum(
                model.phi[C, k] * multivariate_normal(model.mu[k], model.Sigma[k]).pdf(xy[r, c]) for k in range(2)
            )
            total += mult * model.pi[C] * dens
        assert got[r, c] == pytest.approx(np.log(np.exp(log_p[r, c]) * total), rel=1e-10)
    assert got[1, 1] == -np.inf


def brute_force(log_w, start, T):
    """max over all 5^T action sequences (moves into -inf cells are forbidden)."""
    H, W = log_w.shape
    best = -np.inf
    for seq in itertools.product(range(5), repeat=T):
        r, c = start
        total = 0.0
        for a in seq:
            r, c = r + ACTIONS_4[a][0], c + ACTIONS_4[a][1]
            if not (0 <= r < H and 0 <= c < W) or not np.isfinite(log_w[r, c]):
                total = -np.inf
                break
            total += log_w[r, c]
        best = max(best, total)
    return best


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_viterbi_equals_brute_force(seed):
    rng = np.random.default_rng(seed)
    log_w = rng.normal(-3.0, 1.0, size=(4, 5))
    log_w[1, 2] = log_w[2, 1] = -np.inf  # walls
    T = 4
    res = viterbi(log_w, (0, 0), T=T)
    assert res.log_prob == pytest.approx(brute_force(log_w, (0, 0), T))
    # the decoded path is legal, starts at the start, and scores what was claimed
    assert res.cells.shape == (T + 1, 2) and tuple(res.cells[0]) == (0, 0)
    steps = np.abs(np.diff(res.cells, axis=0)).sum(axis=1)
    assert set(steps.tolist()) <= {0, 1}
    assert np.isfinite(log_w[res.cells[:, 0], res.cells[:, 1]]).all()
    assert log_w[res.cells[1:, 0], res.cells[1:, 1]].sum() == pytest.approx(res.log_prob)


def test_viterbi_walks_to_the_peak_around_a_wall_and_stays():
    # a U-shaped corridor: the peak (0, 4) is 4 cells away as the crow flies but 12 steps around the wall
    log_w = np.full((5, 5), -5.0)
    log_w[0:4, 2] = -np.inf
    log_w[0, 4] = -0.1
    res = viterbi(log_w, (0, 0), T=20)
    cells = [tuple(c) for c in res.cells]
    assert cells[-1] == (0, 4)
    first = cells.index((0, 4))
    assert first == 12 and all(c == (0, 4) for c in cells[first:])
    assert res.log_prob == pytest.approx(11 * -5.0 + 9 * -0.1)


def test_viterbi_eight_connected_uses_diagonals():
    log_w = np.full((3, 3), -1.0)
    log_w[2, 2] = 0.0
    res = viterbi(log_w, (0, 0), T=2, connectivity=8)
    assert [tuple(c) for c in res.cells] == [(0, 0), (1, 1), (2, 2)]


def test_viterbi_bad_input():
    log_w = np.zeros((3, 3))
    log_w[1, 1] = -np.inf
    with pytest.raises(PlanningError, match=r"start cell \(row, col\) = \(1, 1\) is off the grid or not traversable"):
        viterbi(log_w, (1, 1))
    with pytest.raises(PlanningError, match=r"\(5, 0\) is off the grid"):
        viterbi(log_w, (5, 0))
    with pytest.raises(PlanningError, match="horizon T must be >= 1"):
        viterbi(log_w, (0, 0), T=0)
    with pytest.raises(PlanningError, match="connectivity must be 4 or 8"):
        viterbi(log_w, (0, 0), connectivity=6)


def test_horizon_objective_pads_and_truncates():
    log_w = np.arange(12, dtype=float).reshape(3, 4) * -1.0
    cells = np.array([[0, 0], [0, 1], [0, 2]])  # weights 0, -1, -2
    assert horizon_objective(log_w, cells, T=4) == pytest.approx(-1 - 2 - 2 - 2)  # stays at (0, 2)
    assert horizon_objective(log_w, cells, T=1) == pytest.approx(-1)  # truncated after 1 step


def test_sample_cells_follows_weights():
    log_w = np.log(np.array([[0.0, 1.0], [3.0, 0.0]]))
    draws = sample_cells(log_w, 4000, np.random.default_rng(0))
    frac = np.mean((draws == [1, 0]).all(axis=1))
    assert frac == pytest.approx(0.75, abs=0.03)
    assert not ((draws == [0, 0]).all(axis=1)).any()
    with pytest.raises(PlanningError, match="zero everywhere"):
        sample_cells(np.full((2, 2), -np.inf), 1, np.random.default_rng(0))


def test_astar_approximation_keeps_the_best_sampled_goal():
    # two goals of equal weight; the near one collects its weight sooner, so it wins the T-step objective
    log_w = np.full((1, 9), np.log(1e-6))
    log_w[0, 2] = log_w[0, 8] = 0.0
    rng = np.random.default_rng(5)
    cells = astar_approximation(log_w, (0, 0), rng, J=10, T=20)
    assert tuple(cells[-1]) == (0, 2) and tuple(cells[0]) == (0, 0)
    # seeded: the same generator state gives the same path
    again = astar_approximation(log_w, (0, 0), np.random.default_rng(5), J=10, T=20)
    np.testing.assert_array_equal(cells, again)


def test_astar_approximation_detours_through_likely_cells():
    # a 2 x 5 room: the direct row-0 route crosses a low-weight cell (0, 2), a row-1 detour does not
    log_w = np.full((2, 5), -3.0)
    log_w[0, 2] = -30.0
    log_w[0, 4] = 0.0  # the goal: the sampled candidate with the best T-step objective
    log_w[1, 4] = -60.0
    cells = astar_approximation(log_w, (0, 0), np.random.default_rng(0), J=30, T=10)
    visited = [tuple(c) for c in cells]
    # direct: 3 + 30 + 3 + 0 plus 4 log 5; any 6-step detour through row 1: 5 * 3 + 0 plus 6 log 5 (cheaper)
    assert visited[0] == (0, 0) and visited[-1] == (0, 4) and len(visited) == 7
    assert (0, 2) not in visited and (1, 4) not in visited
    with pytest.raises(PlanningError, match="step cost -log w \\+ log\\|A\\| is negative"):
        astar_approximation(np.full((2, 2), 2.0), (0, 0), np.random.default_rng(0))

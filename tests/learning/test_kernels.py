"""The learning kernels made faster for scale (issue 11) against brute force: the most probable place per point
(chunk bounds) against scoring every place, and FFBS's sparse forward pass against a dense one in numpy."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.learning.hmm import ffbs_kernel, trajectory_places
from spcotmhp.learning.territory import posterior_arg_max
from spcotmhp.logspace import log_gaussian


@st.composite
def places_and_points(draw):
    rng = np.random.default_rng(draw(st.integers(0, 2**31)))
    K = draw(st.integers(1, 40))
    mu = rng.uniform(0, 40, (K, 2))
    A = rng.normal(size=(K, 2, 2)) * rng.uniform(0.05, 4.0, (K, 1, 1))  # any orientation and elongation
    Sigma = A @ A.transpose(0, 2, 1) + np.eye(2) * rng.uniform(1e-3, 0.5)
    if draw(st.booleans()):  # equal Gaussians and priors: exact ties, first index wins
        Sigma[:] = Sigma[0]
        mu[K // 2 :] = mu[0]
    log_prior = np.log(rng.dirichlet(np.ones(K))) if draw(st.booleans()) else np.zeros(K)
    n = draw(st.integers(1, 400))
    walk = np.cumsum(rng.normal(scale=draw(st.sampled_from([0.05, 0.5, 5.0])), size=(n, 2)), axis=0) + 20
    points = np.round(walk) if draw(st.booleans()) else walk  # grid points make ties between symmetric means
    return points, mu, Sigma, log_prior


@settings(max_examples=150, deadline=None, derandomize=True)
@given(places_and_points())
def test_most_probable_place_is_the_exhaustive_arg_max(case):
    points, mu, Sigma, log_prior = case
    expected = np.argmax(log_gaussian(points, mu, Sigma) + log_prior, axis=1)
    assert (posterior_arg_max(points, mu, Sigma, log_prior) == expected).all()


def test_trajectory_places_uses_the_places_with_events_only():
    mu = np.array([[0.0, 0.0], [5.0, 0.0], [10.0, 0.0]])
    Sigma = np.tile(np.eye(2), (3, 1, 1))
    walk = np.stack([np.linspace(0, 10, 101), np.zeros(101)], axis=1)
    assert trajectory_places(walk, mu, Sigma, np.log(np.full(3, 1 / 3))).tolist() == [0, 1, 2]
    assert trajectory_places(walk, mu, Sigma, np.array([np.log(0.5), -np.inf, np.log(0.5)])).tolist() == [0, 2]
    assert trajectory_places(walk, mu, Sigma, np.full(3, -np.inf)).tolist() == []


def dense_ffbs(log_emit, log_trans, log_init, uniforms):
    """FFBS with the full forward recursion in log space (numpy), the same backward draws as the kernel."""
    E, K = log_emit.shape
    alpha = np.empty((E, K))
    alpha[0] = log_init + log_emit[0]
    for e in range(1, E):
        alpha[e] = np.logaddexp.reduce(alpha[e - 1][:, None] + log_trans, axis=0) + log_emit[e]
    states = np.empty(E, dtype=np.int64)
    for e in range(E - 1, -1, -1):
        w = alpha[e] + (log_trans[:, states[e + 1]] if e < E - 1 else 0.0)
        p = np.exp(w - w.max())
        states[e] = min(int(np.searchsorted(np.cumsum(p), uniforms[e] * p.sum(), side="right")), K - 1)
    return states


@settings(max_examples=60, deadline=None, derandomize=True)
@given(st.integers(0, 2**31), st.sampled_from([0.2, 3.0, 40.0]))
def test_sparse_forward_pass_draws_what_the_dense_recursion_draws(seed, sharpness):
    # places along a line, events walking along it: far places are many nats below the best emission
    rng = np.random.default_rng(seed)
    K, E = int(rng.integers(2, 25)), int(rng.integers(1, 80))
    mu = np.sort(rng.uniform(0, 50, K))
    x = np.clip(np.cumsum(rng.normal(scale=2.0, size=E)) + 25, 0, 50)
    log_emit = -0.5 * sharpness * (x[:, None] - mu[None]) ** 2
    log_trans = np.log(rng.dirichlet(np.full(K, 0.3), size=K))
    log_init = np.full(K, -np.log(K))
    uniforms = rng.random(E)
    got = ffbs_kernel(log_emit, log_trans, log_init, uniforms)
    want = dense_ffbs(log_emit, log_trans, log_init, uniforms)
    # the floor drops states below e^-60 of the best (most examples have some): the draws are still the same
    assert (got == want).all()


def _box_bound(mu, Sigma, box):
    from spcotmhp.learning.territory import _box_mahalanobis, _place_bounds

    det = np.linalg.det(Sigma)
    coef, _ = _place_bounds(mu, Sigma, det, np.log(det), np.zeros(len(mu)))
    return _box_mahalanobis(mu, Sigma, det, coef, 0, *box)


def test_box_bound_of_an_elongated_gaussian_by_hand():
    """Mean (0, 0), variance 100 along x and 0.01 across: over x in [1, 2], y in [0.5, 0.6] the least
    Mahalanobis distance is 1/100 + 0.25/0.01 = 25.01 at (1, 0.5); the isotropic bound (smallest eigenvalue
    0.01 of the inverse times the squared distance 1.25) was 0.0125, so the corridor's Gaussian was never cut."""
    mu, Sigma = np.zeros((1, 2)), np.array([[[100.0, 0.0], [0.0, 0.01]]])
    assert np.isclose(_box_bound(mu, Sigma, (1.0, 2.0, 0.5, 0.6)), 25.01, rtol=1e-8)
    assert _box_bound(mu, Sigma, (-1.0, 2.0, -0.5, 0.6)) == 0.0  # the mean inside the box


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.integers(0, 2**31))
def test_box_bound_never_exceeds_the_distance_at_any_point_of_the_box(seed):
    rng = np.random.default_rng(seed)
    mu = rng.uniform(-5, 5, (1, 2))
    A = rng.normal(size=(2, 2)) * rng.uniform(0.05, 4.0)
    Sigma = (A @ A.T + np.eye(2) * rng.uniform(1e-3, 0.5))[None]
    x0, y0 = rng.uniform(-8, 8, 2)
    x1, y1 = x0 + rng.uniform(0, 6) * rng.integers(0, 2), y0 + rng.uniform(0, 6)  # a row (x0 == x1) or a box
    gx, gy = np.meshgrid(np.linspace(x0, x1, 81), np.linspace(y0, y1, 81))
    d = np.stack([gx.ravel() - mu[0, 0], gy.ravel() - mu[0, 1]], axis=1)
    q = np.einsum("ni,ij,nj->n", d, np.linalg.inv(Sigma[0]), d)
    bound = _box_bound(mu, Sigma, (x0, x1, y0, y1))
    assert bound <= q.min() * (1 + 1e-9) + 1e-12
    assert bound >= q.min() - 0.05 * (1 + q.min())  # tight: the grid's least value is near the exact one

"""The package's one log-sum-exp and Gaussian log-density (spcotmhp/logspace.py), numpy and numba, against scipy's."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.special import logsumexp as scipy_logsumexp

from spcotmhp.logspace import gaussian_log_density, log_gaussian, logsumexp, logsumexp_vector

values = st.one_of(st.floats(-700, 700), st.just(-np.inf))


@settings(deadline=None)
@given(
    arrays(np.float64, st.tuples(st.integers(1, 4), st.integers(1, 6)), elements=values), st.sampled_from([0, 1, -1])
)
def test_numpy_logsumexp_is_scipys(a, axis):
    with np.errstate(divide="ignore"):
        want = scipy_logsumexp(a, axis=axis)
    np.testing.assert_allclose(logsumexp(a, axis=axis), want, rtol=1e-12, atol=1e-12)
    assert logsumexp(a, axis=axis, keepdims=True).shape == np.sum(a, axis=axis, keepdims=True).shape


@settings(deadline=None)
@given(arrays(np.float64, st.integers(0, 12), elements=values))
def test_numba_logsumexp_is_scipys(v):
    with np.errstate(divide="ignore"):
        want = float(scipy_logsumexp(v)) if v.size else -np.inf
    got = logsumexp_vector(v)
    assert got == pytest.approx(want, rel=1e-12, abs=1e-12) or (np.isneginf(got) and np.isneginf(want))
    assert float(logsumexp(v)) == pytest.approx(got, rel=1e-12, abs=1e-12) or np.isneginf(got)


def test_an_empty_or_all_minus_infinity_sum_is_minus_infinity():
    assert logsumexp(np.array([])) == -np.inf and logsumexp_vector(np.array([])) == -np.inf
    assert logsumexp(np.full(3, -np.inf)) == -np.inf and logsumexp_vector(np.full(3, -np.inf)) == -np.inf


def _covariances(seed: int, k: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    mu = rng.normal(0, 3, (k, 2))
    A = rng.normal(0, 1, (k, 2, 2))
    Sigma = A @ A.transpose(0, 2, 1) + 0.05 * np.eye(2)
    return mu, Sigma


@pytest.mark.parametrize("seed", range(5))
def test_log_gaussian_is_scipys_multivariate_normal(seed):
    from scipy.stats import multivariate_normal

    mu, Sigma = _covariances(seed, 4)
    x = np.random.default_rng(seed + 10).normal(0, 4, (7, 2))
    want = np.stack([multivariate_normal(mu[k], Sigma[k]).logpdf(x) for k in range(4)], axis=-1)
    np.testing.assert_allclose(log_gaussian(x, mu, Sigma), want, rtol=1e-10)


@pytest.mark.parametrize("seed", range(5))
def test_the_kernels_gaussian_is_log_gaussian_to_the_bit(seed):
    mu, Sigma = _covariances(seed, 3)
    x = np.random.default_rng(seed + 20).normal(0, 4, (5, 2))
    det = Sigma[:, 0, 0] * Sigma[:, 1, 1] - Sigma[:, 0, 1] * Sigma[:, 1, 0]
    got = np.array(
        [
            [
                gaussian_log_density(
                    p[0] - mu[k, 0], p[1] - mu[k, 1], Sigma[k, 0, 0], Sigma[k, 0, 1] + Sigma[k, 1, 0],
                    Sigma[k, 1, 1], det[k], np.log(det[k]),
                )
                for k in range(3)
            ]
            for p in x
        ]
    )  # fmt: skip
    assert np.array_equal(got, log_gaussian(x, mu, Sigma))


def test_a_covariance_that_is_not_positive_definite_is_refused():
    with pytest.raises(ValueError, match="not positive definite"):
        log_gaussian(np.zeros((1, 2)), np.zeros((1, 2)), np.zeros((1, 2, 2)))

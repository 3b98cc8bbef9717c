"""Likelihood terms and conjugate updates of the learner, checked against scipy.stats on hand cases."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats
from scipy.special import digamma, gammaln

from spcotmhp.learning.collapsed_terms import digamma_series, log_rising
from spcotmhp.learning.distributions import (
    DirichletCategoricals,
    GaussianStats,
    NIWGaussians,
    cholesky_2d,
    inv_2d,
    sample_inverse_wishart_2d,
    sample_log_dirichlet,
)
from spcotmhp.logspace import log_gaussian

M0 = np.array([0.0, 0.0])
V0 = 2.0 * np.eye(2)


def _niw(K=1, m0=M0, kappa0=1e-3, V0=V0, nu0=3.0):
    return NIWGaussians(K, m0, kappa0, V0, nu0)


def test_log_gaussian_matches_scipy():
    mu = np.array([[1.0, -2.0], [0.5, 0.3]])
    Sigma = np.array([[[2.0, 0.3], [0.3, 0.5]], [[0.1, -0.02], [-0.02, 0.3]]])
    x = np.array([[0.0, 0.0], [1.2, -1.9], [-3.0, 4.0]])
    got = log_gaussian(x, mu, Sigma)
    for k in range(2):
        want = stats.multivariate_normal(mu[k], Sigma[k]).logpdf(x)
        np.testing.assert_allclose(got[:, k], want, rtol=1e-12)


def test_niw_posterior_hand_case():
    # two points, hand-computed with Murphy (2007) Eqs. 250-254
    X = np.array([[1.0, 2.0], [3.0, 2.0]])
    g = _niw(m0=np.array([1.0, 1.0]), kappa0=2.0, V0=np.eye(2), nu0=4.0)
    m_n, kappa_n, V_n, nu_n = g.posterior(GaussianStats.from_assignments(X, np.array([0, 0]), 1))
    assert kappa_n[0] == 4.0 and nu_n[0] == 6.0
    np.testing.assert_allclose(m_n[0], [(2 * 1 + 4) / 4, (2 * 1 + 4) / 4])  # (kappa0 m0 + sum x) / kappa_n
    xbar = np.array([2.0, 2.0])
    S = np.array([[2.0, 0.0], [0.0, 0.0]])  # scatter about the mean
    want_V = np.eye(2) + S + (2.0 * 2 / 4) * np.outer(xbar - 1.0, xbar - 1.0)
    np.testing.assert_allclose(V_n[0], want_V)
    _mu, Sigma = g.posterior_mean(GaussianStats.from_assignments(X, np.array([0, 0]), 1))
    np.testing.assert_allclose(Sigma[0], want_V / (6.0 - 3.0))  # E[Sigma] = V_n / (nu_n - p - 1)


def test_niw_log_marginal_is_the_student_t_predictive():
    # one point: p(x) is the prior predictive t_{nu0-1}(m0, V0 (kappa0+1) / (kappa0 (nu0-1)))
    g = _niw(kappa0=0.5, nu0=4.0)
    x = np.array([[0.7, -1.2]])
    got = g.log_marginal(GaussianStats.from_assignments(x, np.array([0]), 1))
    df = 4.0 - 2 + 1
    want = stats.multivariate_t(M0, V0 * (0.5 + 1) / (0.5 * df), df=df).logpdf(x[0])
    assert got == pytest.approx(want, rel=1e-10)
    # two points: chain rule p(x1, x2) = p(x1) p(x2 | x1), the second term from the updated NIW
    X = np.array([[0.7, -1.2], [1.5, 0.4]])
    both = g.log_marginal(GaussianStats.from_assignments(X, np.array([0, 0]), 1))
    m1, k1, V1, n1 = g.posterior(GaussianStats.from_assignments(x, np.array([0]), 1))
    df2 = n1[0] - 1
    pred = stats.multivariate_t(m1[0], V1[0] * (k1[0] + 1) / (k1[0] * df2), df=df2).logpdf(X[1])
    assert both == pytest.approx(want + pred, rel=1e-10)


def test_inverse_wishart_draws_match_scipy_moments():
    rng = np.random.default_rng(0)
    V = np.array([[2.0, 0.4], [0.4, 1.0]])
    nu = 7.0
    draws = sample_inverse_wishart_2d(rng, np.tile(V, (40000, 1, 1)), np.full(40000, nu))
    np.testing.assert_allclose(draws.mean(axis=0), stats.invwishart(df=nu, scale=V).mean(), rtol=0.03, atol=0.01)
    assert np.all(np.linalg.eigvalsh(draws) > 0)


def test_niw_resample_concentrates_on_the_data():
    rng = np.random.default_rng(1)
    X = rng.multivariate_normal([3.0, -1.0], [[0.2, 0.05], [0.05, 0.1]], size=2000)
    g = _niw()
    g.resample(GaussianStats.from_assignments(X, np.zeros(2000, dtype=int), 1), rng)
    np.testing.assert_allclose(g.mu[0], X.mean(axis=0), atol=0.05)
    np.testing.assert_allclose(g.Sigma[0], np.cov(X.T), atol=0.03)


def test_closed_form_2x2_helpers():
    S = np.array([[[2.0, 0.3], [0.3, 0.5]], [[1.0, -0.9], [-0.9, 1.0]]])
    np.testing.assert_allclose(cholesky_2d(S), np.linalg.cholesky(S), rtol=1e-12)
    np.testing.assert_allclose(inv_2d(S), np.linalg.inv(S), rtol=1e-12)


def test_dirichlet_log_marginal_matches_scipy_dirichlet_multinomial():
    counts = np.array([[3.0, 0.0, 1.0, 2.0], [0.0, 0.0, 0.0, 5.0]])
    d = DirichletCategoricals(2, 4, 0.5)
    got = d.log_marginal(counts)
    want = 0.0
    for row in counts:  # scipy's pmf counts unordered outcomes: remove the multinomial coefficient
        n = row.sum()
        coef = gammaln(n + 1) - gammaln(row + 1).sum()
        want += stats.dirichlet_multinomial(np.full(4, 0.5), int(n)).logpmf(row) - coef
    assert got == pytest.approx(want, rel=1e-12)
    # and the sequential (Polya urn) form by hand for the first row: outcomes 0, 0, 0, 2, 3, 3
    urn = np.log([0.5 / 2, 1.5 / 3, 2.5 / 4, 0.5 / 5, 0.5 / 6, 1.5 / 7]).sum()
    assert DirichletCategoricals(1, 4, 0.5).log_marginal(counts[:1]) == pytest.approx(urn, rel=1e-12)


def test_dirichlet_posterior_mean_and_draws():
    d = DirichletCategoricals(1, 3, 0.1)
    counts = np.array([[4.0, 0.0, 1.0]])
    np.testing.assert_allclose(d.posterior_mean(counts), [[4.1 / 5.3, 0.1 / 5.3, 1.1 / 5.3]])
    rng = np.random.default_rng(2)
    draws = np.exp(sample_log_dirichlet(rng, np.tile([4.1, 0.1, 1.1], (50000, 1))))
    np.testing.assert_allclose(draws.mean(axis=0), stats.dirichlet([4.1, 0.1, 1.1]).mean(), atol=0.004)


def test_tiny_concentration_draws_are_exact_in_log_space():
    # E[log p_i] = psi(a_i) - psi(sum a) for p ~ Dir(a): about -20 for a = 0.05 over 20 outcomes
    rng = np.random.default_rng(3)
    logp = sample_log_dirichlet(rng, np.full((5000, 20), 0.05))
    assert np.isfinite(logp).all()
    np.testing.assert_allclose(np.exp(logp).sum(axis=1), 1.0)
    assert logp.mean() == pytest.approx(digamma(0.05) - digamma(1.0), abs=0.3)


def test_dirichlet_rejects_bad_input():
    with pytest.raises(ValueError, match="concentration must be > 0"):
        DirichletCategoricals(1, 3, 0.0)
    with pytest.raises(ValueError, match=r"counts must have shape \(1, 3\)"):
        DirichletCategoricals(1, 3, 1.0).posterior_mean(np.zeros((2, 3)))
    with pytest.raises(ValueError, match="positive definite"):
        NIWGaussians(1, M0, 1e-3, -np.eye(2), 3.0)


@pytest.mark.parametrize("a,x", [(1.0, 1.0), (2.5, 3.0), (0.3, 0.7), (10.0, 12.0), (1.7, 0.0), (4.0, 250.0)])
def test_log_rising_factorial(a, x):
    assert log_rising(a, x) == pytest.approx(gammaln(a + x) - gammaln(a), rel=1e-10, abs=1e-12)


@pytest.mark.parametrize("x", [1e-3, 0.5, 1.0, 3.7, 6.0, 40.0, 1234.5])
def test_digamma(x):
    assert digamma_series(x) == pytest.approx(digamma(x), rel=1e-11, abs=1e-12)


def test_lean_logsumexp_matches_scipy():
    from scipy.special import logsumexp as scipy_lse

    from spcotmhp.logspace import logsumexp

    a = np.array([[0.0, -1.0, -np.inf], [-np.inf, -np.inf, -np.inf], [1000.0, 999.0, -5.0]])
    np.testing.assert_allclose(logsumexp(a, axis=1), scipy_lse(a, axis=1))
    np.testing.assert_allclose(logsumexp(a, axis=0, keepdims=True), scipy_lse(a, axis=0, keepdims=True))

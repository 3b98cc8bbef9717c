"""The collapsed concept step: the conditional against hand computation, counts kept consistent, the small-count
shortcut."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import digamma, gammaln, logsumexp, polygamma

from spcotmhp.learning.collapsed_terms import SMALL_COUNT, feature_term
from spcotmhp.learning.concepts import CollapsedConceptSampler
from tests.helpers.learning import concept_conditional_by_inverse_cdf, sweep_kernel


def test_collapsed_concept_conditional_matches_hand_computation():
    # 4 events, V = 3 words, D = 2 integer features, K = 2 places, L = 3 concepts; resample event 0
    words = np.array([[1, 1, 0], [1, 0, 0], [0, 1, 1], [0, 0, 2]], dtype=float)
    feats = np.array([[2, 1], [3, 1], [0, 4], [1, 1]], dtype=float)
    places = np.array([0, 0, 1, 1])
    C = np.array([2, 0, 1, 1])
    alpha, gamma, beta, chi, L, K, V, D = 0.5, 0.05, 0.1, 1.0, 3, 2, 3, 2
    sampler = CollapsedConceptSampler(words, feats, background=False, rng=np.random.default_rng(0))
    got = concept_conditional_by_inverse_cdf(sampler, C, places, 0, L, K, (alpha, gamma, beta, chi))
    # by hand: counts without event 0; concept 2 is then empty
    others = [1, 2, 3]
    lp = np.zeros(L)
    for l in range(L):
        mine = [e for e in others if C[e] == l]
        n_l = len(mine)
        n_lk = sum(places[e] == 0 for e in mine)
        Wc = words[mine].sum(axis=0) if mine else np.zeros(V)
        Fc = feats[mine].sum(axis=0) if mine else np.zeros(D)
        x, f = words[0], feats[0]
        lp[l] = (
            np.log(n_l + alpha)
            + np.log(n_lk + gamma)
            - np.log(n_l + K * gamma)
            + gammaln(V * beta + Wc.sum())
            - gammaln(V * beta + Wc.sum() + x.sum())
            + np.sum(gammaln(beta + Wc + x) - gammaln(beta + Wc))
            + gammaln(D * chi + Fc.sum())
            - gammaln(D * chi + Fc.sum() + f.sum())
            + np.sum(gammaln(chi + Fc + f) - gammaln(chi + Fc))
        )
    want = np.exp(lp - logsumexp(lp))
    np.testing.assert_allclose(got, want, atol=2e-4)


def test_constant_feature_columns_are_handled_exactly():
    # the same hand case with a column that is 1 in every event (the "+1" of the authors' counts)
    words = np.array([[1, 0], [1, 0], [0, 1]], dtype=float)
    feats = np.array([[1, 2, 0], [1, 0, 1], [1, 3, 3]], dtype=float)
    sampler = CollapsedConceptSampler(words, feats, background=False, rng=np.random.default_rng(0))
    assert sampler.const.tolist() == [True, False, False]
    places = np.array([0, 0, 1])
    C = np.array([0, 1, 1])
    got = concept_conditional_by_inverse_cdf(sampler, C, places, 2, 2, 2, (1.0, 0.5, 0.5, 1.0))
    lp = np.zeros(2)
    for l in range(2):
        mine = [e for e in (0, 1) if C[e] == l]
        Wc, Fc = words[mine].sum(axis=0), feats[mine].sum(axis=0)
        x, f = words[2], feats[2]
        lp[l] = (
            np.log(len(mine) + 1.0)
            + np.log(0 + 0.5)
            - np.log(len(mine) + 1.0)
            + gammaln(1.0 + Wc.sum())
            - gammaln(1.0 + Wc.sum() + x.sum())
            + np.sum(gammaln(0.5 + Wc + x) - gammaln(0.5 + Wc))
            + gammaln(3.0 + Fc.sum())
            - gammaln(3.0 + Fc.sum() + f.sum())
            + np.sum(gammaln(1.0 + Fc + f) - gammaln(1.0 + Fc))
        )
    np.testing.assert_allclose(got, np.exp(lp - logsumexp(lp)), atol=2e-4)


@pytest.mark.parametrize("background", [False, True])
def test_concept_sweep_keeps_counts_consistent(background):
    rng = np.random.default_rng(5)
    words = rng.integers(0, 3, size=(30, 6)).astype(float)
    feats = rng.random((30, 4))
    sampler = CollapsedConceptSampler(words, feats, background=background, rng=rng)
    C = rng.integers(4, size=30)
    places = rng.integers(3, size=30)
    for _ in range(5):
        C = sampler.sweep(C, places, 4, 3, 0.5, 0.05, 0.1, 1.0, rng)
    assert C.min() >= 0 and C.max() < 4
    np.testing.assert_array_equal(sampler.concept_words().sum() + sampler.background_words().sum(), words.sum())
    if not background:
        assert sampler.background_words().sum() == 0


def test_tiny_feature_shortcut_and_its_cached_digammas_against_the_exact_formula():
    # features scaled to weight 1 over D = 60 dimensions: many counts x <= SMALL_COUNT take the x psi(a)
    # shortcut of log Gamma(a + x) - log Gamma(a); its error is below x^2 psi'(a) / 2 per count
    rng = np.random.default_rng(3)
    E, V, D, L, K, chi = 40, 5, 60, 4, 3, 1.0
    words = rng.integers(0, 3, size=(E, V)).astype(float)
    feats = rng.dirichlet(np.full(D, 0.2), size=E)
    sampler = CollapsedConceptSampler(words, feats, background=False, rng=rng)
    small = (sampler.f_cnt > 0) & (sampler.f_cnt <= SMALL_COUNT)
    assert small.sum() > 100 and (sampler.f_cnt > SMALL_COUNT).sum() > 100
    C = rng.integers(L, size=E)
    places = rng.integers(K, size=E)
    onehot = np.eye(L)[C]
    F_ld, F_l = onehot.T @ sampler.varying, onehot.T @ sampler.n_feat
    digamma_ld = digamma(chi + F_ld)
    n_l = onehot.sum(axis=0)
    for e in range(E):
        for l in range(L):
            got = feature_term(
                l,
                e,
                n_l[l],
                chi,
                float(D),
                F_ld,
                F_l,
                digamma_ld,
                sampler.f_ptr,
                sampler.f_idx,
                sampler.f_cnt,
                sampler.c_val,
                sampler.c_mult,
                sampler.n_feat[e],
            )
            x, F = feats[e], F_ld[l]
            exact = (
                np.sum(gammaln(chi + F + x) - gammaln(chi + F))
                - gammaln(D * chi + F_l[l] + x.sum())
                + gammaln(D * chi + F_l[l])
            )
            tiny = (x > 0) & (x <= SMALL_COUNT)
            bound = np.sum(x[tiny] ** 2 * polygamma(1, chi + F[tiny]) / 2)
            assert abs(got - exact) <= bound + 1e-12
            assert bound < 1e-3  # the docstring's claim
    # the tiny counts really read the cache: a wrong cache moves the value by far more than the bound
    wrong = feature_term(
        0,
        0,
        n_l[0],
        chi,
        float(D),
        F_ld,
        F_l,
        digamma_ld + 1.0,
        sampler.f_ptr,
        sampler.f_idx,
        sampler.f_cnt,
        sampler.c_val,
        sampler.c_mult,
        sampler.n_feat[0],
    )
    right = feature_term(
        0,
        0,
        n_l[0],
        chi,
        float(D),
        F_ld,
        F_l,
        digamma_ld,
        sampler.f_ptr,
        sampler.f_idx,
        sampler.f_cnt,
        sampler.c_val,
        sampler.c_mult,
        sampler.n_feat[0],
    )
    x0 = feats[0]
    assert wrong - right == pytest.approx(x0[(x0 > 0) & (x0 <= SMALL_COUNT)].sum(), rel=1e-9)
    # the cache: after a sweep over every event, digamma_ld is digamma(chi + F_ld) of the final counts
    W_lv = onehot.T @ sampler.concept_words()
    order = rng.permutation(E).astype(np.int64)
    assert (sampler.V, sampler.D) == (V, D)
    counts = (n_l.copy(), _n_lk(C, places, L, K), W_lv, F_ld, F_l)
    C_new = sweep_kernel(
        sampler, C, places, order, rng.random(E + len(sampler.t_word)), L, K, (0.5, 0.05, 0.1, chi), counts, digamma_ld
    )
    assert not np.array_equal(C_new, C)
    np.testing.assert_allclose(F_ld, np.eye(L)[C_new].T @ sampler.varying, atol=1e-12)
    np.testing.assert_allclose(digamma_ld, digamma(chi + F_ld), rtol=1e-12, atol=1e-12)


def _n_lk(C, places, L, K):
    n = np.zeros((L, K))
    np.add.at(n, (C, places), 1.0)
    return n

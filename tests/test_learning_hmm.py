"""The place-sequence sampler (FFBS), transition counting with reverse replay, and the collapsed concept step."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.special import gammaln, logsumexp

from spcotmhp.learning.concepts import CollapsedConceptSampler, _concept_sweep
from spcotmhp.learning.hmm import dwell_filtered_sequence, ffbs, ffbs_kernel, transition_counts


def test_ffbs_draws_from_the_exact_posterior():
    rng = np.random.default_rng(0)
    E, K = 4, 3
    log_emit = rng.normal(size=(E, K))
    log_trans = np.log(rng.dirichlet(np.ones(K), size=K))
    log_init = np.log([0.2, 0.5, 0.3])
    # exact posterior by enumeration
    seqs = list(itertools.product(range(K), repeat=E))
    lp = np.array([log_init[s[0]] + sum(log_emit[e, s[e]] for e in range(E))
                   + sum(log_trans[s[e - 1], s[e]] for e in range(1, E)) for s in seqs])
    exact = np.exp(lp - logsumexp(lp))
    n = 60000
    draws = [tuple(ffbs(log_emit, log_trans, log_init, rng)) for _ in range(n)]
    index = {s: i for i, s in enumerate(seqs)}
    freq = np.bincount([index[d] for d in draws], minlength=len(seqs)) / n
    np.testing.assert_allclose(freq, exact, atol=4 * np.sqrt(exact.max() / n))


def test_ffbs_inverse_cdf_with_given_uniforms():
    # one event, uniform transitions: the state is the inverse CDF of the emission distribution at u
    log_emit = np.log([[0.2, 0.3, 0.5]])
    log_trans = np.zeros((3, 3))
    for u, want in ((0.1, 0), (0.25, 1), (0.49, 1), (0.51, 2), (0.99, 2)):
        assert ffbs_kernel(log_emit, log_trans, np.zeros(3), np.array([u]))[0] == want


def test_transition_counts_and_reverse_replay():
    seq = np.array([0, 0, 1, 2, 1])
    n = transition_counts(seq, 3)
    want = np.zeros((3, 3))
    want[0, 0] = want[0, 1] = want[1, 2] = want[2, 1] = 1
    np.testing.assert_array_equal(n, want)
    # the reversed sequence 1 2 1 0 0 adds the transposed counts
    np.testing.assert_array_equal(transition_counts(seq, 3, reverse_replay=True),
                                  want + transition_counts(seq[::-1], 3))
    assert transition_counts(np.array([2]), 3).sum() == 0


def test_dwell_filter_drops_boundary_flicker():
    labels = np.array([0, 0, 0, 1, 0, 0, 0, 2, 2, 2, 2, 1, 1, 1])
    np.testing.assert_array_equal(dwell_filtered_sequence(labels, 3), [0, 2, 1])
    np.testing.assert_array_equal(dwell_filtered_sequence(labels, 1), [0, 1, 0, 2, 1])
    assert len(dwell_filtered_sequence(np.array([], dtype=int), 3)) == 0


def _conditional_by_inverse_cdf(sampler, C, places, e, L, K, hyper, grid=20001):
    """Probabilities p(C_e = l | rest) read off the kernel: it draws by inverse CDF of one uniform."""
    counts = np.zeros(L)
    alpha, gamma, beta, chi = hyper
    for u in np.linspace(0.0, 1.0, grid, endpoint=False) + 0.5 / grid:
        n_l = np.bincount(C, minlength=L).astype(float)
        n_lk = np.zeros((L, K))
        np.add.at(n_lk, (C, places), 1.0)
        onehot = np.eye(L)[C]
        W_lv = onehot.T @ sampler.concept_words()
        F_ld = onehot.T @ sampler.varying
        F_l = onehot.T @ sampler.n_feat
        bg = sampler.background_words()
        out = _concept_sweep(C.copy(), places, np.array([e]), np.array([u]), L, K, alpha, gamma, beta, chi,
                             sampler.t_ptr, sampler.t_word, sampler.z.copy(), float(sampler.V), False,
                             bg, np.array([bg.sum()]), np.array([0.0, float(sampler.z.sum())]),
                             sampler.f_ptr, sampler.f_idx, sampler.f_cnt, float(sampler.D), sampler.c_val,
                             sampler.c_mult, sampler.n_feat, n_l, n_lk, W_lv, W_lv.sum(axis=1), F_ld, F_l,
                             np.zeros_like(F_ld), True)
        counts[out[e]] += 1
    return counts / grid


def test_collapsed_concept_conditional_matches_hand_computation():
    # 4 events, V = 3 words, D = 2 integer features, K = 2 places, L = 3 concepts; resample event 0
    words = np.array([[1, 1, 0], [1, 0, 0], [0, 1, 1], [0, 0, 2]], dtype=float)
    feats = np.array([[2, 1], [3, 1], [0, 4], [1, 1]], dtype=float)
    places = np.array([0, 0, 1, 1])
    C = np.array([2, 0, 1, 1])
    alpha, gamma, beta, chi, L, K, V, D = 0.5, 0.05, 0.1, 1.0, 3, 2, 3, 2
    sampler = CollapsedConceptSampler(words, feats, background=False, rng=np.random.default_rng(0))
    got = _conditional_by_inverse_cdf(sampler, C, places, 0, L, K, (alpha, gamma, beta, chi))
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
        lp[l] = (np.log(n_l + alpha) + np.log(n_lk + gamma) - np.log(n_l + K * gamma)
                 + gammaln(V * beta + Wc.sum()) - gammaln(V * beta + Wc.sum() + x.sum())
                 + np.sum(gammaln(beta + Wc + x) - gammaln(beta + Wc))
                 + gammaln(D * chi + Fc.sum()) - gammaln(D * chi + Fc.sum() + f.sum())
                 + np.sum(gammaln(chi + Fc + f) - gammaln(chi + Fc)))
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
    got = _conditional_by_inverse_cdf(sampler, C, places, 2, 2, 2, (1.0, 0.5, 0.5, 1.0))
    lp = np.zeros(2)
    for l in range(2):
        mine = [e for e in (0, 1) if C[e] == l]
        Wc, Fc = words[mine].sum(axis=0), feats[mine].sum(axis=0)
        x, f = words[2], feats[2]
        lp[l] = (np.log(len(mine) + 1.0) + np.log(0 + 0.5) - np.log(len(mine) + 1.0)
                 + gammaln(1.0 + Wc.sum()) - gammaln(1.0 + Wc.sum() + x.sum())
                 + np.sum(gammaln(0.5 + Wc + x) - gammaln(0.5 + Wc))
                 + gammaln(3.0 + Fc.sum()) - gammaln(3.0 + Fc.sum() + f.sum())
                 + np.sum(gammaln(1.0 + Fc + f) - gammaln(1.0 + Fc)))
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


def test_ffbs_log_fallback_agrees_with_the_scaled_pass():
    # emissions that underflow any probability-space pass: the kernel falls back to log space
    rng = np.random.default_rng(1)
    log_emit = rng.normal(size=(6, 3)) * 5
    log_emit[3] = [-2000.0, -1e6, -1e6]          # only state 0 is possible at e = 3 ...
    log_trans = np.log(np.array([[1e-300, 0.5, 0.5], [0.5, 0.5, 1e-300], [0.5, 1e-300, 0.5]]))
    log_trans[1, 0] = log_trans[2, 0] = -1e6     # ... and can only be reached from state 0
    u = rng.random(6)
    states = ffbs_kernel(log_emit, log_trans, np.zeros(3), u)
    assert states[3] == 0 and states[2] == 0

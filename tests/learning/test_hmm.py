"""The place-sequence sampler (FFBS) and transition counting with reverse replay."""

from __future__ import annotations

import itertools

import numpy as np
from scipy.special import logsumexp

from spcotmhp.learning.hmm import (
    _forward_log,
    _forward_scaled,
    dwell_filtered_sequence,
    ffbs,
    ffbs_kernel,
    transition_counts,
)


def test_ffbs_draws_from_the_exact_posterior():
    rng = np.random.default_rng(0)
    E, K = 4, 3
    log_emit = rng.normal(size=(E, K))
    log_trans = np.log(rng.dirichlet(np.ones(K), size=K))
    log_init = np.log([0.2, 0.5, 0.3])
    # exact posterior by enumeration
    seqs = list(itertools.product(range(K), repeat=E))
    lp = np.array(
        [
            log_init[s[0]]
            + sum(log_emit[e, s[e]] for e in range(E))
            + sum(log_trans[s[e - 1], s[e]] for e in range(1, E))
            for s in seqs
        ]
    )
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
    np.testing.assert_array_equal(
        transition_counts(seq, 3, reverse_replay=True), want + transition_counts(seq[::-1], 3)
    )
    assert transition_counts(np.array([2]), 3).sum() == 0


def test_dwell_filter_drops_boundary_flicker():
    labels = np.array([0, 0, 0, 1, 0, 0, 0, 2, 2, 2, 2, 1, 1, 1])
    np.testing.assert_array_equal(dwell_filtered_sequence(labels, 3), [0, 2, 1])
    np.testing.assert_array_equal(dwell_filtered_sequence(labels, 1), [0, 1, 0, 2, 1])
    assert len(dwell_filtered_sequence(np.array([], dtype=int), 3)) == 0


def _exact_sequence_posterior(log_emit, log_trans, log_init):
    E, K = log_emit.shape
    seqs = list(itertools.product(range(K), repeat=E))
    lp = np.array(
        [
            log_init[s[0]]
            + sum(log_emit[e, s[e]] for e in range(E))
            + sum(log_trans[s[e - 1], s[e]] for e in range(1, E))
            for s in seqs
        ]
    )
    return seqs, np.exp(lp - logsumexp(lp))


def test_ffbs_log_fallback_runs_and_draws_from_the_exact_posterior():
    # at e = 3 the best emission (state 1, log 0) is unreachable (log psi[:, 1] = -1e6) and the reachable
    # state 0 has log emission -800: exp(-800) underflows in the scaled pass, which must give up
    rng = np.random.default_rng(1)
    E, K = 6, 3
    log_emit = rng.normal(size=(E, K))
    log_emit[3] = [-800.0, 0.0, -1e6]
    log_trans = np.log(rng.dirichlet(np.full(K, 2.0), size=K))
    log_trans[:, 1] = -1e6
    log_init = np.log([0.3, 0.3, 0.4])
    assert not _forward_scaled(log_emit, log_trans, log_init, np.empty((E, K)))  # the fallback is taken
    seqs, exact = _exact_sequence_posterior(log_emit, log_trans, log_init)
    assert (exact > 1e-3).sum() > 30  # a spread posterior
    n = 40000
    index = {q: i for i, q in enumerate(seqs)}
    uniforms = rng.random((n, E))
    draws = [index[tuple(ffbs_kernel(log_emit, log_trans, log_init, u))] for u in uniforms]
    freq = np.bincount(draws, minlength=len(seqs)) / n
    np.testing.assert_allclose(freq, exact, atol=4 * np.sqrt(exact.max() / n))
    assert all(seqs[d][3] == 0 for d in draws)


def test_ffbs_scaled_pass_is_used_when_nothing_underflows():
    rng = np.random.default_rng(2)
    log_emit, log_trans = rng.normal(size=(5, 3)), np.log(rng.dirichlet(np.ones(3), size=3))
    alpha_scaled, alpha_log = np.empty((5, 3)), np.empty((5, 3))
    assert _forward_scaled(log_emit, log_trans, np.zeros(3), alpha_scaled)
    _forward_log(log_emit, log_trans, np.zeros(3), alpha_log)
    # the two passes agree up to a constant per event (the scaling)
    diff = alpha_log - alpha_scaled
    np.testing.assert_allclose(diff - diff[:, :1], 0.0, atol=1e-12)

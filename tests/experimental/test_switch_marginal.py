"""log p(S | C) with the background-word switches summed out: brute force over every switch setting."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.special import gammaln

from spcotmhp.errors import ModelError
from spcotmhp.experimental.switch_marginal import log_words_given_background, log_words_given_concepts

WORDS = np.array([0, 1, 0, 2, 1, 0, 3, 0, 1, 2, 3, 3])
CONCEPTS = np.array([0, 0, 0, 1, 1, 1, 2, 2, 0, 1, 2, 0])
V, BETA = 4, 0.1


def _dirmult(counts: np.ndarray, beta: float) -> np.ndarray:
    """log of a symmetric Dirichlet-multinomial of ordered tokens, per row (by hand)."""
    counts = np.atleast_2d(counts)
    M = counts.shape[1]
    return gammaln(M * beta) - gammaln(M * beta + counts.sum(axis=1)) + (gammaln(beta + counts) - gammaln(beta)).sum(1)


def _settings():
    for bits in itertools.product((False, True), repeat=len(WORDS)):
        z = np.array(bits)
        W = np.zeros((CONCEPTS.max() + 1, V))
        np.add.at(W, (CONCEPTS[z], WORDS[z]), 1.0)
        yield z, W


def _logsumexp(a: list[float]) -> float:
    x = np.array(a)
    return float(x.max() + np.log(np.exp(x - x.max()).sum()))


def test_given_the_background_the_sum_over_switches_is_exact():
    W0, lam = np.array([0.4, 0.3, 0.2, 0.1]), 0.35
    brute = [
        _dirmult(W, BETA).sum() + np.log(W0[WORDS[~z]]).sum() + z.sum() * np.log(lam) + (~z).sum() * np.log(1 - lam)
        for z, W in _settings()
    ]
    N = np.zeros((3, V))
    np.add.at(N, (CONCEPTS, WORDS), 1.0)
    assert log_words_given_background(N, W0, lam, BETA) == pytest.approx(_logsumexp(brute), abs=1e-10)


def test_chib_estimate_matches_the_sum_over_every_switch_setting():
    T = len(WORDS)
    brute = [
        _dirmult(W, BETA).sum()
        + _dirmult(np.bincount(WORDS[~z], minlength=V), BETA)[0]
        + gammaln(2.0) - gammaln(2.0 + T) + gammaln(1.0 + z.sum()) + gammaln(1.0 + T - z.sum())
        for z, W in _settings()
    ]  # fmt: skip
    exact = _logsumexp(brute)
    assert exact == pytest.approx(-19.808063, abs=1e-6)  # 4,096 settings
    for seed in range(3):
        est = log_words_given_concepts(WORDS, CONCEPTS, V, BETA, np.random.default_rng(seed), sweeps=2000)
        assert est == pytest.approx(exact, abs=0.15)
    start = np.zeros(T, dtype=bool)  # the chain's start does not matter
    est = log_words_given_concepts(WORDS, CONCEPTS, V, BETA, np.random.default_rng(0), start, sweeps=2000)
    assert est == pytest.approx(exact, abs=0.15)


def test_bad_token_arrays():
    rng = np.random.default_rng(0)
    with pytest.raises(ModelError):
        log_words_given_concepts(WORDS, CONCEPTS[:-1], V, BETA, rng)
    with pytest.raises(ModelError):
        log_words_given_concepts(WORDS, CONCEPTS, V, BETA, rng, sweeps=10, burn_in=10)
    assert log_words_given_concepts(WORDS[:0], CONCEPTS[:0], V, BETA, rng) == 0.0

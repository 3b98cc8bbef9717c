"""Scores of a fitted run with the background-word switches handled: brute force over every switch setting."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.special import gammaln

from spcotmhp.errors import ModelError
from spcotmhp.learning import run_scores
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.learner_state import state_of_member
from spcotmhp.learning.online_split_merge import state_stats
from spcotmhp.learning.posterior import Priors, log_joint_terms
from tests.helpers.learning import planted_dataset

WORDS = np.array([0, 1, 0, 2, 1, 0, 3, 0, 1, 2, 3, 3])
CONCEPTS = np.array([0, 0, 0, 1, 1, 1, 2, 2, 0, 1, 2, 0])
V, BETA = 4, 0.1


def _dirmult(counts: np.ndarray, beta: float) -> float:
    """log of a symmetric Dirichlet-multinomial of ordered tokens, summed over rows (by hand)."""
    counts = np.atleast_2d(counts)
    M = counts.shape[1]
    return float(
        np.sum(gammaln(M * beta) - gammaln(M * beta + counts.sum(axis=1)))
        + np.sum(gammaln(beta + counts) - gammaln(beta))
    )


def _brute_force(words: np.ndarray, concepts: np.ndarray) -> float:
    """log sum over all 2^T switch settings of p(S, z | C): concept tokens ~ DirMult(beta) per concept,
    background tokens ~ DirMult(beta), switches ~ Beta(1, 1)-Bernoulli."""
    L, T = concepts.max() + 1, len(words)
    out = []
    for bits in itertools.product((False, True), repeat=T):
        z = np.array(bits)
        W = np.zeros((L, V))
        np.add.at(W, (concepts[z], words[z]), 1.0)
        n1 = int(z.sum())
        switches = gammaln(2.0) - gammaln(2.0 + T) + gammaln(1.0 + n1) + gammaln(1.0 + T - n1)
        out.append(_dirmult(W, BETA) + _dirmult(np.bincount(words[~z], minlength=V), BETA) + switches)
    a = np.array(out)
    return float(a.max() + np.log(np.exp(a - a.max()).sum()))


def test_annealed_estimate_of_the_switch_marginal_matches_brute_force():
    exact = _brute_force(WORDS, CONCEPTS)
    assert exact == pytest.approx(-19.808063, abs=1e-6)  # the sum over 4,096 settings
    est = run_scores.log_words_given_concepts(WORDS, CONCEPTS, V, BETA, np.random.default_rng(0), 16, 500)
    assert est == pytest.approx(exact, abs=0.15)
    # one token: the first predictive is exact, (1/2) (1/V) + (1/2) (1/V)
    one = run_scores.log_words_given_concepts(WORDS[:1], CONCEPTS[:1], V, BETA, np.random.default_rng(0), 1, 1)
    assert one == pytest.approx(np.log(1.0 / V), abs=1e-12)


def test_annealed_estimate_is_unbiased_for_the_probability():
    # E p-hat = p(S | C) for any number of chains and steps: the mean of p-hat / p over many seeds is about 1
    exact = _brute_force(WORDS, CONCEPTS)
    est = np.array(
        [
            run_scores.log_words_given_concepts(WORDS, CONCEPTS, V, BETA, np.random.default_rng(s), 4, 50)
            for s in range(300)
        ]
    )
    assert abs(np.log(np.mean(np.exp(est - exact)))) < 0.06
    assert est.std() > 0.05  # a real estimate, not the exact value by construction


def test_bad_token_arrays():
    with pytest.raises(ModelError):
        run_scores.log_words_given_concepts(WORDS, CONCEPTS[:-1], V, BETA, np.random.default_rng(0))
    with pytest.raises(ModelError):
        run_scores.log_words_given_concepts(WORDS, CONCEPTS, V, BETA, np.random.default_rng(0), chains=0)
    assert run_scores.log_words_given_concepts(WORDS[:0], CONCEPTS[:0], V, BETA, np.random.default_rng(0)) == 0.0


@pytest.fixture(scope="module")
def run():
    return SpCoTMHP(iterations=12, seed=3, connectivity="hmm").fit(planted_dataset(E=60))


def _terms(run) -> dict[str, float]:
    st = state_of_member(run.model_.learner, run.model_)
    return log_joint_terms(Priors.build(st.hyper, st.K, st.L, st.V, st.D), state_stats(st), st.trans)


def test_switch_scores_keep_the_non_word_terms_and_replace_the_word_terms(run):
    terms = _terms(run)
    assert sum(terms.values()) == pytest.approx(run.log_joint_, rel=1e-12)
    non_word = sum(v for k, v in terms.items() if k not in ("W", "background"))
    st = state_of_member(run.model_.learner, run.model_)
    words = np.concatenate(st.tokens)
    concepts = np.repeat(st.concept, [len(t) for t in st.tokens])
    # plug-in: every token's log of the exported mixture lambda W_C(w) + (1 - lambda) W_0(w)
    plugin = sum(np.log(run.model_.W[c, w]) for c, w in zip(concepts, words, strict=True))
    assert run_scores.switch_plugin_log_joint(run) == pytest.approx(non_word + plugin, rel=1e-12)
    marginal = run_scores.switch_marginal_log_joint(run, chains=8, steps=300)
    # the switches summed out weigh at least as much as any one setting of them, up to the estimate's noise
    assert marginal >= run_scores.switch_mode_log_joint(run) - 1.0 >= run.log_joint_ - 1.0
    assert marginal == run_scores.switch_marginal_log_joint(run, chains=8, steps=300)  # seeded


def test_tail_mean_is_the_mean_of_the_last_quarter_of_the_trace(run):
    trace = run.log_joint_trace_
    assert len(trace) == 12 and trace[-1] == run.log_joint_
    assert run_scores.tail_mean_log_joint(run) == pytest.approx(np.mean(trace[-3:]), rel=1e-12)
    assert run_scores.tail_mean_log_joint(run, 1.0) == pytest.approx(np.mean(trace), rel=1e-12)
    assert run_scores.tail_mean_log_joint(run, 0.01) == trace[-1]
    with pytest.raises(ModelError):
        run_scores.tail_mean_log_joint(run, 0.0)

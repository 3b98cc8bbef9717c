"""Scores of a fitted run with the background-word switches handled."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.errors import ModelError
from spcotmhp.experimental import run_scores
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.learner_state import state_of_member
from spcotmhp.learning.online_split_merge import state_stats
from spcotmhp.learning.posterior import Priors, log_joint_terms
from tests.helpers.learning import planted_dataset


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
    marginal = run_scores.switch_marginal_log_joint(run)
    # the switches summed out weigh at least as much as any one setting of them, up to the estimate's noise
    assert marginal >= run_scores.switch_mode_log_joint(run) - 1.0 >= run.log_joint_ - 1.0
    assert marginal == run_scores.switch_marginal_log_joint(run)  # seeded


def test_tail_mean_is_the_mean_of_the_last_quarter_of_the_trace(run):
    trace = run.log_joint_trace_
    assert len(trace) == 12 and trace[-1] == run.log_joint_
    assert run_scores.tail_mean_log_joint(run) == pytest.approx(np.mean(trace[-3:]), rel=1e-12)
    assert run_scores.tail_mean_log_joint(run, 1.0) == pytest.approx(np.mean(trace), rel=1e-12)
    assert run_scores.tail_mean_log_joint(run, 0.01) == trace[-1]
    with pytest.raises(ModelError):
        run_scores.tail_mean_log_joint(run, 0.0)


def test_held_out_predictive_of_one_word_sums_to_one_over_the_vocabulary(run):
    st = state_of_member(run.model_.learner, run.model_)
    e = 7
    st.move(e, -1.0)
    total = 0.0
    for v in range(st.V):  # every one-word event at x_e: a distribution over the vocabulary
        st.tokens[e] = np.array([v])
        total += np.exp(run_scores.held_out_event(st, e))
    assert total == pytest.approx(1.0, abs=1e-9)


def test_held_out_words_takes_each_event_out_and_puts_it_back(run):
    st = state_of_member(run.model_.learner, run.model_)
    score = run_scores.held_out_words(run)
    assert np.isfinite(score) and score < 0.0
    e = 3
    k, l = st.place[e], st.concept[e]
    st.move(e, -1.0)
    one = run_scores.held_out_event(st, e)
    st.place[e], st.concept[e] = k, l
    st.move(e, 1.0)
    after = state_of_member(run.model_.learner, run.model_)
    np.testing.assert_array_equal(after.W_lv, st.W_lv)  # the run's own sample is untouched
    assert one < 0.0 and score == run_scores.held_out_words(run)

"""The model's semantic terms, each defined once in learning/model.py and used by the planner, the vocabulary and
the baselines alike: Eq. 28's word term (:func:`log_word_term`, with :func:`normalise_places`), p(C = l | i = k)
(:func:`log_concept_given_place`) and the label score (:meth:`SpatialConceptModel.label_scores`), each checked
against a hand-computed case, a brute-force sum over the concepts and scipy."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.special import gammaln
from scipy.special import logsumexp as scipy_logsumexp
from scipy.stats import multinomial

from spcotmhp.learning.model import (
    SpatialConceptModel,
    bag_indices,
    log_concept_given_place,
    log_word_term,
    normalise_places,
)
from tests.helpers.learning import brute_word_term


def _model(pi, phi, W, vocabulary=("a", "b", "c"), active=None) -> SpatialConceptModel:
    K = np.shape(phi)[1]
    return SpatialConceptModel(
        mu=np.arange(2.0 * K).reshape(K, 2),
        Sigma=np.repeat(np.eye(2)[None], K, axis=0),
        psi=np.full((K, K), 1.0 / K),
        pi=np.asarray(pi, dtype=float),
        phi=np.asarray(phi, dtype=float),
        W=np.asarray(W, dtype=float),
        vocabulary=list(vocabulary),
        active_places=np.ones(K, dtype=bool) if active is None else np.asarray(active, dtype=bool),
    )


@st.composite
def models_and_bags(draw):
    L, K, V = draw(st.integers(1, 4)), draw(st.integers(1, 5)), draw(st.integers(1, 4))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    pi, phi, W = rng.dirichlet(np.ones(L)), rng.dirichlet(np.ones(K), size=L), rng.dirichlet(np.ones(V), size=L)
    counts = np.array(draw(st.lists(st.integers(0, 3), min_size=V, max_size=V)))
    return pi, phi, W, counts


def test_word_term_by_hand():
    # two concepts, two places, words a b: pi = (0.5, 0.5), phi_0 = (0.9, 0.1), phi_1 = (0.3, 0.7),
    # W_0 = (0.8, 0.2), W_1 = (0.25, 0.75); S = {a, a, b}:
    # place 0: 0.5 * 0.9 * 0.8^2 * 0.2 + 0.5 * 0.3 * 0.25^2 * 0.75 = 0.0576 + 0.00703125 = 0.06463125
    # place 1: 0.5 * 0.1 * 0.8^2 * 0.2 + 0.5 * 0.7 * 0.25^2 * 0.75 = 0.0064 + 0.01640625 = 0.02280625
    model = _model([0.5, 0.5], [[0.9, 0.1], [0.3, 0.7]], [[0.8, 0.2], [0.25, 0.75]], vocabulary=("a", "b"))
    want = np.log([0.06463125, 0.02280625])
    assert model.log_semantic(["a", "a", "b"]) == pytest.approx(want, abs=1e-12)
    assert model.log_semantic({"a": 2.0, "b": 1.0, "unknown": 5.0}) == pytest.approx(want, abs=1e-12)
    assert np.exp(model.log_place_given_words(["a", "a", "b"])) == pytest.approx([0.7391708, 0.2608292], abs=1e-7)


@given(models_and_bags())
def test_word_term_is_the_sum_over_concepts(case):
    pi, phi, W, counts = case
    idx, weight = np.flatnonzero(counts), counts[counts > 0].astype(float)
    with np.errstate(divide="ignore"):
        log_W, log_pi, log_phi = np.log(W), np.log(pi), np.log(phi)
    got = log_word_term(idx, weight, log_W, np.isfinite(log_W), log_pi, log_phi)
    np.testing.assert_allclose(got, brute_word_term(pi, phi, W, counts), rtol=1e-9, atol=1e-9)
    # scipy: Mult(S | W_C) up to its coefficient, mixed over C by scipy's log-sum-exp
    n = int(counts.sum())
    coefficient = gammaln(n + 1) - gammaln(counts + 1).sum()
    log_mult = np.array([multinomial.logpmf(counts, n, W[c]) - coefficient for c in range(len(pi))])
    want = scipy_logsumexp(log_mult[:, None] + log_pi[:, None] + log_phi, axis=0)
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9)


def test_word_term_with_a_zero_in_w():
    # W_0(b) = 0: a "b" in S makes concept 0 impossible; an absent "b" adds nothing (not 0 * log 0 = NaN)
    pi, phi, W = np.array([0.5, 0.5]), np.array([[0.9, 0.1], [0.3, 0.7]]), np.array([[1.0, 0.0], [0.5, 0.5]])
    model = _model(pi, phi, W, vocabulary=("a", "b"))
    assert model.log_semantic(["a"]) == pytest.approx(np.log([0.45 + 0.075, 0.05 + 0.175]))
    assert model.log_semantic(["b"]) == pytest.approx(np.log([0.075, 0.175]))  # concept 1 alone
    assert model.log_semantic([]) == pytest.approx(np.log(pi @ phi))  # no word: the place prior
    assert model.log_semantic(["b"]) == pytest.approx(brute_word_term(pi, phi, W, [0, 1]))


def test_normalise_places_over_the_active_places():
    ls = np.log([0.2, 0.1, 0.3])
    got = normalise_places(ls, np.array([True, False, True]))
    assert got[1] == -np.inf
    assert np.exp(got[[0, 2]]) == pytest.approx([0.4, 0.6])
    assert np.isnan(normalise_places(ls, np.zeros(3, dtype=np.bool_))).all()  # no active place: undefined


def test_bag_indices_drops_unknown_words_and_keeps_repeats():
    idx, weight = bag_indices(["b", "x", "b", "a"], {"a": 0, "b": 1})
    assert idx.tolist() == [1, 1, 0] and weight.tolist() == [1.0, 1.0, 1.0]
    idx, weight = bag_indices({"b": 0.25, "x": 1.0}, {"a": 0, "b": 1})
    assert idx.dtype == np.int64 and idx.tolist() == [1] and weight.tolist() == [0.25]
    assert bag_indices([], {"a": 0})[0].shape == (0,)


@given(models_and_bags())
def test_concept_given_place_is_bayes_rule(case):
    pi, phi, _W, _counts = case
    joint = pi[:, None] * phi  # p(C = l, i = k), brute force
    np.testing.assert_allclose(np.exp(log_concept_given_place(pi, phi)), joint / joint.sum(axis=0), rtol=1e-9)


def test_concept_given_place_with_a_zero():
    # phi_1(0) = 0: place 0 comes from concept 0 alone
    got = np.exp(log_concept_given_place(np.array([0.25, 0.75]), np.array([[0.5, 0.5], [0.0, 1.0]])))
    np.testing.assert_allclose(got, [[1.0, 0.125 / 0.875], [0.0, 0.75 / 0.875]])


def test_label_scores_by_hand_and_the_names():
    # p(l | k) = [[0.75, 0.125], [0.25, 0.875]] (above); W columns sum to (1.05, 0.95):
    # word a at place 0: p(a | 0) = 0.75 * 0.8 + 0.25 * 0.25 = 0.6625; rescaled 0.75 * 0.8 / 1.05 + 0.25 * 0.25 / 1.05
    model = _model([0.5, 0.5], [[0.9, 0.1], [0.3, 0.7]], [[0.8, 0.2], [0.25, 0.75]], vocabulary=("a", "b"))
    said = model.word_given_place()
    assert said[0, 0] == pytest.approx(0.6625) and said.sum(axis=1) == pytest.approx([1.0, 1.0])
    scores = model.label_scores()
    assert scores[0, 0] == pytest.approx(0.6625 / 1.05)
    assert scores[1, 1] == pytest.approx((0.125 * 0.2 + 0.875 * 0.75) / 0.95)
    assert model.place_names() == ["a", "b"]


@given(models_and_bags())
def test_label_scores_brute_force(case):
    pi, phi, W, _counts = case
    model = _model(pi, phi, W, vocabulary=[f"w{v}" for v in range(W.shape[1])])
    L, K = phi.shape
    for k in range(K):
        p_l = [pi[c] * phi[c, k] / sum(pi[d] * phi[d, k] for d in range(L)) for c in range(L)]
        for w in range(W.shape[1]):
            said = sum(p_l[c] * W[c, w] for c in range(L))
            rescaled = sum(p_l[c] * W[c, w] / W[:, w].sum() for c in range(L))
            assert model.word_given_place()[k, w] == pytest.approx(said, rel=1e-9)
            assert model.label_scores()[k, w] == pytest.approx(rescaled, rel=1e-9)


def test_label_score_of_a_word_no_concept_says_is_zero():
    model = _model([0.5, 0.5], [[0.9, 0.1], [0.3, 0.7]], [[1.0, 0.0, 0.0], [0.5, 0.5, 0.0]])
    assert (model.label_scores()[:, 2] == 0.0).all()
    # place 0, p(l | 0) = (0.75, 0.25): a (0.75 + 0.25 * 0.5) / 1.5 = 0.583 beats b 0.25 * 0.5 / 0.5 = 0.25;
    # place 1, p(l | 1) = (0.125, 0.875): b 0.875 beats a (0.125 + 0.4375) / 1.5 = 0.375
    np.testing.assert_allclose(model.label_scores()[:, :2], [[0.875 / 1.5, 0.25], [0.5625 / 1.5, 0.875]])
    assert model.place_names() == ["a", "b"]

"""The opt-in "one place, one name" term (``Hyperparameters.place_concepts``, not the paper's): its
Dirichlet-multinomial by hand, the concept step's conditional against the ratio of collapsed joints, the place
step's emissions, the off path unchanged, the hyper-parameter in model folders and refused by the online learner."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import logsumexp

from spcotmhp.errors import ModelError, TeachingError
from spcotmhp.learning.concepts import CollapsedConceptSampler
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.hmm import ffbs
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.online import OnlineSpCoTMHP
from spcotmhp.learning.place_ffbs import place_emissions, sample_places
from spcotmhp.learning.posterior import Priors, log_joint_terms
from spcotmhp.persistence.io import load_model, save_model
from tests.helpers.learning import (
    assert_same_fit,
    concept_conditional_by_inverse_cdf,
    conditional_by_joints,
    folder_without_hyper_key,
    planted_dataset,
    short_fit,
    stats_of,
)


@pytest.fixture(scope="module")
def tiny_dataset():
    return planted_dataset(E=80)


def test_dirichlet_multinomial_of_each_place_by_hand():
    # K = 2 places, L = 3 concepts, eta = 1.5 (0.5 per concept); place 0 holds concepts 0, 0, 2, place 1 concept 1
    places, concepts = np.array([0, 0, 0, 1]), np.array([0, 0, 2, 1])
    priors = Priors.build(Hyperparameters(L=3, K=2, place_concepts=1.5), 2, 3, 2, None)
    terms = log_joint_terms(priors, stats_of(places, concepts, np.ones((4, 2)), 2, 3), None)
    # the sequence's predictive, event by event: (0.5 / 1.5) (1.5 / 2.5) (0.5 / 3.5) and (0.5 / 1.5)
    want = np.log((0.5 / 1.5) * (1.5 / 2.5) * (0.5 / 3.5) * (0.5 / 1.5))
    assert terms["place_concepts"] == pytest.approx(want, rel=1e-12)
    off = log_joint_terms(
        Priors.build(Hyperparameters(L=3, K=2), 2, 3, 2, None), stats_of(places, concepts, np.ones((4, 2)), 2, 3), None
    )
    assert "place_concepts" not in off
    assert {k: v for k, v in terms.items() if k != "place_concepts"} == off


@pytest.mark.parametrize("eta", [0.3, 1.0, 10.0])
def test_concept_conditional_is_the_ratio_of_collapsed_joints(eta):
    # 6 events, V = 3 words, K = 2 places, L = 3 concepts, no features; resample event 1 (at place 0)
    words = np.array([[1, 1, 0], [1, 0, 0], [0, 1, 1], [0, 0, 2], [1, 0, 1], [0, 2, 0]], dtype=float)
    places = np.array([0, 0, 1, 1, 0, 1])
    C = np.array([2, 0, 1, 1, 2, 0])
    L, K, e = 3, 2, 1
    hyper = Hyperparameters(L=L, K=K, alpha=0.5, gamma=1.0, beta=0.1, place_concepts=eta)
    sampler = CollapsedConceptSampler(words, None, background=False, rng=np.random.default_rng(0))
    got = concept_conditional_by_inverse_cdf(sampler, C, places, e, L, K, (0.5, 1.0, 0.1, 1.0), eta_each=eta / L)
    priors = Priors.build(hyper, K, L, 3, None)
    want = conditional_by_joints(priors, places, C, words, e, K, L)
    np.testing.assert_allclose(got, want, atol=2e-4)
    # the term changes the answer here (place 0 holds concepts 2 and 2 besides event 1)
    paper = concept_conditional_by_inverse_cdf(sampler, C, places, e, L, K, (0.5, 1.0, 0.1, 1.0))
    assert np.abs(paper - got).max() > 0.01


def test_place_emissions_gain_log_eta_of_the_event_concept():
    rng = np.random.default_rng(2)
    E, K, L = 40, 4, 3
    X = rng.normal(size=(E, 2)) * 2.0
    concepts = rng.integers(L, size=E)
    mu, Sigma = rng.normal(size=(K, 2)) * 2.0, np.tile(np.eye(2), (K, 1, 1))
    log_phi = np.log(rng.dirichlet(np.ones(K), size=L))
    log_eta = np.log(rng.dirichlet(np.ones(L) * 0.3, size=K))
    log_trans = np.log(rng.dirichlet(np.ones(K), size=K))
    log_init = np.full(K, -np.log(K))
    emit = place_emissions(X, concepts, mu, Sigma, log_phi, logsumexp(log_phi, axis=0)) + log_eta.T[concepts]
    for seed in range(5):
        want = ffbs(emit, log_trans, log_init, np.random.default_rng(seed))
        got = sample_places(X, concepts, mu, Sigma, log_phi, log_trans, log_init, np.random.default_rng(seed), log_eta)
        np.testing.assert_array_equal(got, want)
    zeros = sample_places(
        X, concepts, mu, Sigma, log_phi, log_trans, log_init, np.random.default_rng(0), np.zeros((K, L))
    )
    none = sample_places(X, concepts, mu, Sigma, log_phi, log_trans, log_init, np.random.default_rng(0))
    np.testing.assert_array_equal(zeros, none)


_fit = short_fit


def test_off_path_is_the_papers_fit_bit_for_bit(tiny_dataset):
    paper = _fit(tiny_dataset)
    off = _fit(tiny_dataset, hyper=Hyperparameters(place_concepts=None), term_from=0.0)
    assert_same_fit(off, paper)


def test_the_term_enters_the_log_joint_and_the_sampler(tiny_dataset):
    on = _fit(tiny_dataset, hyper=Hyperparameters(place_concepts=1.0), term_from=0.0)
    late = _fit(tiny_dataset, hyper=Hyperparameters(place_concepts=1.0), term_from=1.0)
    paper = _fit(tiny_dataset)
    # from the last sweep on (term_from = 1): the paper's draws, the joint with the term
    np.testing.assert_array_equal(late.places_, paper.places_)
    priors = Priors.build(Hyperparameters(place_concepts=1.0).resized(20, 20), 20, 20, 1, None)
    extra = priors.place_concepts.log_marginal(paper.model_.learner["arrays"]["n_lk"].T)
    assert late.log_joint_ == pytest.approx(paper.log_joint_ + extra, rel=1e-12)
    assert extra < 0
    assert not (np.array_equal(on.places_, paper.places_) and np.array_equal(on.concepts_, paper.concepts_))


@pytest.mark.parametrize(
    "kwargs, match",
    [({"place_concepts": 0.0}, "place_concepts"), ({"place_concepts": float("inf")}, "place_concepts"),
     ({"place_concepts": True}, "place_concepts")],
)  # fmt: skip
def test_bad_values_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Hyperparameters(**kwargs)


def test_settings_that_cannot_combine_are_refused(tiny_dataset):
    for start in (1.5, "half", True):
        with pytest.raises(ModelError, match="term_from"):
            _fit(tiny_dataset, term_from=start)
    with pytest.raises(TeachingError, match="batch learner only"):
        OnlineSpCoTMHP(hyper=Hyperparameters(place_concepts=1.0)).partial_fit([])


def test_the_planted_places_and_concepts_are_still_recovered_with_the_term():
    from sklearn.metrics import normalized_mutual_info_score

    data = planted_dataset()
    est = SpCoTMHP(seed=0, connectivity="hmm", hyper=Hyperparameters(place_concepts=1.0)).fit(data)
    assert normalized_mutual_info_score(data.truth_place, est.places_) > 0.97
    assert normalized_mutual_info_score(data.truth_concept, est.concepts_) > 0.97


def test_model_folders_keep_the_term_and_old_folders_load(tiny_dataset, tmp_path):
    model = _fit(tiny_dataset, hyper=Hyperparameters(place_concepts=2.5)).model_
    save_model(model, tmp_path / "on")
    assert load_model(tmp_path / "on").hyper.place_concepts == 2.5
    folder_without_hyper_key(model, tmp_path / "old", "place_concepts")  # written before the term existed
    assert load_model(tmp_path / "old").hyper.place_concepts is None

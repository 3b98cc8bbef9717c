"""The opt-in off-name term (``Hyperparameters.off_name`` = lambda, not the paper's; experimental/off_name.py): log g
by hand, the concept step's conditional against the ratio of collapsed joints, the place step's
Metropolis-Hastings acceptance against brute force (and the target it leaves invariant), the off path unchanged,
model folders with and without the key, and the refusals."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest

from spcotmhp.errors import ModelError, TeachingError
from spcotmhp.experimental import OffName, research_learner
from spcotmhp.experimental.off_name import OffNamePlaces, add_off_name_gain, log_off_name, off_name_events
from spcotmhp.learning.concepts import CollapsedConceptSampler, ConceptTerm
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.online import OnlineSpCoTMHP
from spcotmhp.learning.posterior import Priors, log_joint_terms
from spcotmhp.persistence.io import load_model, save_model
from tests.helpers.learning import (
    assert_same_fit,
    concept_conditional_by_inverse_cdf,
    conditional_by_joints,
    folder_without_hyper_key,
    planted_dataset,
    reseal,
    stats_of,
)


@pytest.fixture(scope="module")
def tiny_dataset():
    return planted_dataset(E=80)


def _by_hand(places, concepts):
    """sum over places of (events - events of the place's most frequent concept), with plain Python counters."""
    total = 0
    for k in set(places.tolist()):
        names = concepts[places == k].tolist()
        total += len(names) - max(names.count(c) for c in set(names))
    return total


def test_log_g_by_hand():
    # K = 4 places, L = 3 concepts; place 0 holds 0, 0, 1 (one off), place 1 holds 2, 1 (a tie: one off), place 2
    # holds 2, 2, 2 (none), place 3 is empty
    places = np.array([0, 0, 0, 1, 1, 2, 2, 2])
    concepts = np.array([0, 0, 1, 2, 1, 2, 2, 2])
    assert off_name_events(places, concepts, 4, 3) == 2 == _by_hand(places, concepts)
    words = np.ones((8, 2))
    priors = Priors.build(Hyperparameters(L=3, K=4, off_name=1.5), 4, 3, 2, None)
    extra = OffNamePlaces(1.5, 4, 3).log_terms
    terms = log_joint_terms(priors, stats_of(places, concepts, words, 4, 3), None, extra)
    assert terms["off_name"] == -3.0
    off = log_joint_terms(
        Priors.build(Hyperparameters(L=3, K=4), 4, 3, 2, None), stats_of(places, concepts, words, 4, 3), None
    )
    assert "off_name" not in off
    assert {k: v for k, v in terms.items() if k != "off_name"} == off
    # splitting a place of one concept is free: place 2 split into places 2 and 3
    assert off_name_events(np.array([0, 0, 0, 1, 1, 2, 3, 3]), concepts, 4, 3) == 2
    assert log_off_name(2.0, np.zeros((3, 4))) == 0.0


@pytest.mark.parametrize("lam", [0.5, 1.0, 3.0])
@pytest.mark.parametrize("e", [1, 3, 5])
def test_concept_conditional_is_the_ratio_of_collapsed_joints(lam, e):
    # 7 events, V = 3 words, K = 3 places, L = 3 concepts, no features.  Without event 1, place 0 holds concepts
    # 2, 2 (one majority); without event 3, place 1 holds 1, 0 (a tie: both gain, 2 does not); event 5 is alone
    words = np.array([[1, 1, 0], [1, 0, 0], [0, 1, 1], [0, 0, 2], [1, 0, 1], [0, 2, 0], [1, 1, 1]], dtype=float)
    places = np.array([0, 0, 1, 1, 0, 2, 1])
    C = np.array([2, 0, 1, 1, 2, 0, 0])
    L, K = 3, 3
    hyper = Hyperparameters(L=L, K=K, alpha=0.5, gamma=1.0, beta=0.1, off_name=lam)
    sampler = CollapsedConceptSampler(words, None, background=False, rng=np.random.default_rng(0))
    term = ConceptTerm(add_off_name_gain, lam)
    got = concept_conditional_by_inverse_cdf(sampler, C, places, e, L, K, (0.5, 1.0, 0.1, 1.0), term=term)
    priors = Priors.build(hyper, K, L, 3, None)
    want = conditional_by_joints(priors, places, C, words, e, K, L, OffNamePlaces(lam, K, L).log_terms)
    np.testing.assert_allclose(got, want, atol=2e-4)
    paper = concept_conditional_by_inverse_cdf(sampler, C, places, e, L, K, (0.5, 1.0, 0.1, 1.0))
    changed = np.abs(paper - got).max() > 0.01
    assert changed == (e != 5)  # alone in its place: every candidate gains the same, nothing changes


def test_acceptance_ratio_against_brute_force():
    rng = np.random.default_rng(5)
    K, L, E, lam = 3, 2, 7, 1.3
    mh = OffNamePlaces(lam, K, L)
    for _ in range(50):
        old, new, C = rng.integers(K, size=E), rng.integers(K, size=E), rng.integers(L, size=E)
        want = -lam * (_by_hand(new, C) - _by_hand(old, C))
        assert mh.log_ratio(old, new, C) == pytest.approx(want, abs=1e-12)
    # the step accepts with probability min(1, g(new) / g(old)): here one more event off its place's name
    old, new, C = np.array([0, 0, 1, 1]), np.array([0, 1, 1, 1]), np.array([0, 0, 1, 1])
    draws = [mh.step(old, new, C, rng) is new for _ in range(20000)]
    assert np.mean(draws) == pytest.approx(np.exp(-lam), abs=0.01)
    assert all(mh.step(new, old, C, rng) is old for _ in range(100))  # uphill: always
    assert mh.proposed == 20100 and mh.acceptance == pytest.approx(mh.accepted / 20100)


def test_the_step_leaves_the_conditional_times_g_invariant():
    # all 2^4 place sequences of E = 4 events (K = 2, L = 2); proposal q (the FFBS's role) drawn at random; the
    # Metropolis-Hastings kernel's matrix must leave pi ~ q g invariant
    K, L, lam = 2, 2, 0.8
    C = np.array([0, 1, 1, 0])
    seqs = [np.array(s) for s in itertools.product(range(K), repeat=4)]
    q = np.random.default_rng(1).dirichlet(np.ones(len(seqs)))
    mh = OffNamePlaces(lam, K, L)
    g = np.array([np.exp(-lam * _by_hand(s, C)) for s in seqs])
    T = np.zeros((len(seqs), len(seqs)))
    for a, b in itertools.product(range(len(seqs)), repeat=2):
        if a != b:
            T[a, b] = q[b] * min(1.0, np.exp(mh.log_ratio(seqs[a], seqs[b], C)))
    T[np.diag_indices_from(T)] = 1.0 - T.sum(axis=1)
    target = q * g / (q * g).sum()
    np.testing.assert_allclose(target @ T, target, atol=1e-12)


def _fit(data, split_merge=False, **kwargs):
    """An 8-sweep batch fit (seed 4) through the research entry point (the variant of ``hyper.off_name``)."""
    return research_learner(split_merge, iterations=8, seed=4, **kwargs).fit(data)


def _acceptance(est):
    return est.model_.info.get("off_name_acceptance")


def test_off_path_is_the_papers_fit_bit_for_bit(tiny_dataset):
    paper = _fit(tiny_dataset)
    off = _fit(tiny_dataset, hyper=Hyperparameters(off_name=None), term_from=0.0)
    assert_same_fit(off, paper)
    assert "off_name_acceptance" not in off.model_.info


def test_the_term_enters_the_log_joint_and_the_sampler(tiny_dataset):
    paper = _fit(tiny_dataset)
    late = _fit(tiny_dataset, hyper=Hyperparameters(off_name=1.0), term_from=1.0)
    # never in the sampler (term_from = 1): the paper's draws, no random number taken, the joint with log g
    np.testing.assert_array_equal(late.places_, paper.places_)
    np.testing.assert_array_equal(late.concepts_, paper.concepts_)
    extra = -1.0 * off_name_events(paper.places_, paper.concepts_, 20, 20)
    assert late.log_joint_ == pytest.approx(paper.log_joint_ + extra, rel=1e-12)
    assert _acceptance(late) is None
    on = _fit(tiny_dataset, hyper=Hyperparameters(off_name=1.0), term_from=0.0)
    default = _fit(tiny_dataset, hyper=Hyperparameters(off_name=1.0))  # term_from None: off_name.OFF_NAME_FROM = 0
    np.testing.assert_array_equal(default.places_, on.places_)
    np.testing.assert_array_equal(default.concepts_, on.concepts_)
    assert 0.0 <= _acceptance(on) <= 1.0
    assert on.model_.info["off_name_acceptance"] == on.variant_run_.acceptance
    assert not (np.array_equal(on.places_, paper.places_) and np.array_equal(on.concepts_, paper.concepts_))


def test_the_planted_places_and_concepts_are_still_recovered_with_the_term_after_half_the_sweeps():
    # from the first sweep (the default start, off_name.OFF_NAME_FROM) the initial fragments keep their own
    # concepts and stay apart here (place NMI 0.73): docs/learning-model-study.md, section 9
    from sklearn.metrics import normalized_mutual_info_score

    data = planted_dataset()
    est = research_learner(seed=0, connectivity="hmm", hyper=Hyperparameters(off_name=1.0), term_from=0.5).fit(data)
    assert normalized_mutual_info_score(data.truth_place, est.places_) > 0.97
    assert normalized_mutual_info_score(data.truth_concept, est.concepts_) > 0.97
    assert _acceptance(est) > 0.5


@pytest.mark.parametrize("value", [0.0, -1.0, float("inf"), float("nan"), True, "1"])
def test_bad_values_are_refused(value):
    with pytest.raises(ValueError, match=r"off_name must be a finite number of nats in \(0, 1e\+06\]"):
        Hyperparameters(off_name=value)


def test_settings_that_cannot_combine_are_refused(tiny_dataset):
    with pytest.raises(ValueError, match="place_concepts and off_name"):
        Hyperparameters(place_concepts=1.0, off_name=1.0)
    with pytest.raises(ModelError, match="split_merge moves do not price off_name"):
        _fit(tiny_dataset, hyper=Hyperparameters(off_name=1.0), split_merge=True)
    with pytest.raises(ModelError, match="hyper.off_name is a research variant's term: fit with variant="):
        SpCoTMHP(iterations=2, hyper=Hyperparameters(off_name=1.0)).fit(tiny_dataset)  # the core alone
    with pytest.raises(ModelError, match="the off-name variant needs hyper.off_name"):
        SpCoTMHP(iterations=2, variant=OffName()).fit(tiny_dataset)
    with pytest.raises(TeachingError, match="off_name is a term of the batch learner only"):
        OnlineSpCoTMHP(hyper=Hyperparameters(off_name=1.0)).partial_fit([])


def test_model_folders_keep_the_term_and_old_folders_load(tiny_dataset, tmp_path):
    model = _fit(tiny_dataset, hyper=Hyperparameters(off_name=0.5)).model_
    save_model(model, tmp_path / "on")
    assert load_model(tmp_path / "on").hyper.off_name == 0.5
    with pytest.raises(TeachingError, match="off_name"):
        OnlineSpCoTMHP(init_model=load_model(tmp_path / "on")).partial_fit([])
    meta_path = folder_without_hyper_key(model, tmp_path / "old", "off_name")  # written before the term existed
    meta = json.loads(meta_path.read_text())
    assert load_model(tmp_path / "old").hyper.off_name is None
    for bad, message in ((-2.0, r"off_name must be a finite number of nats in \(0, 1e\+06\]"), (1.0, "set one or")):
        meta["hyper"].update(off_name=bad, place_concepts=1.0 if bad > 0 else None)
        meta_path.write_text(json.dumps(meta))
        reseal(tmp_path / "old")
        with pytest.raises(ModelError, match=message):
            load_model(tmp_path / "old")

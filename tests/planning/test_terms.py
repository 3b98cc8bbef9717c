"""The per-query model terms of the planner (planning/terms.py): the compiled kernels give the model's
quantities (Eq. 3's place posterior, Eq. 28's word term per stage, checked against its brute-force sum over the
concepts, the first-step transition, the instance sets)."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.planning.places import instance_places
from spcotmhp.planning.terms import ModelTerms
from tests.helpers.learning import brute_word_term
from tests.helpers.planning import home_model


@pytest.fixture(scope="module")
def model():
    return home_model()


BAGS = [{"bedroom": 1.0}, {"kitchen": 0.7, "corridor": 0.3}, {"corridor": 2.0}, {"unknown": 1.0, "bedroom": 1.0}]


@pytest.mark.parametrize("ratio", [1.0, 4.0, 100.0])
def test_stage_terms_are_the_word_terms_and_the_instances(model, ratio):
    terms = ModelTerms(model)
    semantic, inst = terms.stage_terms(BAGS, ratio)
    assert semantic.shape == inst.shape == (len(BAGS), model.K)
    for s, bag in enumerate(BAGS):
        assert semantic[s] == pytest.approx(brute_word_term(model.pi, model.phi, model.W, model.bag_vector(bag)))
        assert (inst[s] == instance_places(model.log_place_given_words(bag), ratio)).all()
    with pytest.raises(ValueError, match="instance_ratio"):
        terms.stage_terms(BAGS, 0.5)


def test_stage_terms_when_w_holds_a_zero(model):
    # a word with W_l(w) = 0 makes concept l impossible for that bag; an absent word adds nothing
    model = home_model()
    W = model.W.copy()
    W[0] = [1.0, 0.0, 0.0]
    model.W = W
    semantic, _ = ModelTerms(model).stage_terms([{"bedroom": 1.0}, {"kitchen": 1.0}], 4.0)
    assert semantic[0] == pytest.approx(brute_word_term(model.pi, model.phi, W, [1, 0, 0]))
    assert semantic[1] == pytest.approx(brute_word_term(model.pi, model.phi, W, [0, 0, 1]))  # words sorted
    assert np.isfinite(semantic).all()


def test_posterior_and_start_terms_match_the_model(model):
    terms = ModelTerms(model)
    rng = np.random.default_rng(0)
    places = np.flatnonzero(model.active_places)
    for x in rng.uniform(-2.0, 8.0, size=(20, 2)):
        post = terms.place_posterior(x)
        assert post == pytest.approx(model.place_posterior(x))
        with np.errstate(divide="ignore"):
            expected = np.log(post @ model.psi)[places] - model.log_unigram_rescaling()[places]
        assert terms.start_terms(post, places) == pytest.approx(expected)

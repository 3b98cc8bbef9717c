"""evaluate-learning --online (``evaluation.online_eval``): the final samples it reports beside the scores (places,
concepts and the collapsed log target of the online and the batch samples, on the same terms)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from spcotmhp.errors import ModelError
from spcotmhp.evaluation.online_eval import (
    batch_sample_summary,
    dataset_events,
    evaluate_online,
    format_report,
    sample_summary,
)
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.learner_state import state_of_member
from spcotmhp.learning.online import OnlineSpCoTMHP, log_new_place_density
from spcotmhp.learning.online_split_merge import log_target
from spcotmhp.metric.maps import OccupancyMap
from tests.helpers.learning import planted_dataset


@pytest.fixture(scope="module")
def planted():
    return planted_dataset(E=40, seed=3)


@pytest.fixture(scope="module")
def result(planted):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return evaluate_online(planted, seeds=2, seed=5, iterations=8)


def test_new_place_density_is_one_over_the_known_area():
    grid = np.zeros((10, 20), np.int8)
    grid[:, :5] = -1  # 150 known cells (free or occupied) of 0.2 m: 6 m^2
    grid[0, 10] = 100
    assert log_new_place_density(OccupancyMap(grid, 0.2)) == pytest.approx(-math.log(6.0))


def test_online_samples_are_the_learners_own(planted, result):
    """The online side's sample figures are the means over seeds of the streamed learners' final states."""
    want = []
    for s in (5, 6):
        learner = OnlineSpCoTMHP(map=planted.map, check_map=False, seed=s)
        for event in dataset_events(planted):
            learner.partial_fit([event])
        st = learner.state_
        want.append((len(set(learner.places_)), len(set(learner.concepts_)), log_target(st)))
    got = result["online"]["sample"]
    assert got["places"] == pytest.approx(np.mean([w[0] for w in want]))
    assert got["concepts"] == pytest.approx(np.mean([w[1] for w in want]))
    assert got["log_target"] == pytest.approx(np.mean([w[2] for w in want]), rel=1e-12)
    assert got["std"]["log_target"] == pytest.approx(np.std([w[2] for w in want]), rel=1e-9, abs=1e-9)


def test_batch_samples_are_scored_on_the_online_learners_terms(planted, result):
    """Each batch run's final sample, as a learner state with the map's new-place density, gives the log target
    reported; the places and concepts are those its final assignment uses."""
    runs = []
    for r in range(2):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            est = SpCoTMHP(iterations=8, seed=5, run=r, connectivity="hmm").fit(planted)
        st = state_of_member(est.model_.learner, est.model_)
        st.log_new_place = log_new_place_density(planted.map)
        runs.append((len(set(est.places_)), len(set(est.concepts_)), log_target(st)))
        assert batch_sample_summary(est.model_, planted) == sample_summary(st)
    got = result["batch"]["sample"]
    assert got["places"] == pytest.approx(np.mean([r[0] for r in runs]))
    assert got["concepts"] == pytest.approx(np.mean([r[1] for r in runs]))
    assert got["log_target"] == pytest.approx(np.mean([r[2] for r in runs]), rel=1e-12)
    assert "log target" in format_report(result)


def test_a_model_without_its_sample_is_refused(planted):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = SpCoTMHP(iterations=2, seed=0).fit(planted).model_
    model.learner = None
    with pytest.raises(ModelError, match="final sample"):
        batch_sample_summary(model, planted)


def test_priors_go_to_both_learners(planted, result):
    """``hyper`` reaches the online and the batch learner: both sides' samples are scored under the sized place
    prior, and each side's log target is that of its own learner under it."""
    from spcotmhp.learning.model import Hyperparameters

    hyper = Hyperparameters(place_size=0.5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sized = evaluate_online(planted, seeds=1, seed=5, iterations=8, hyper=hyper)
        learner = OnlineSpCoTMHP(map=planted.map, check_map=False, seed=5, hyper=hyper)
        for event in dataset_events(planted):
            learner.partial_fit([event])
        batch = SpCoTMHP(iterations=8, seed=5, run=0, connectivity="hmm", hyper=hyper).fit(planted)
    assert sized["online"]["sample"]["log_target"] == pytest.approx(log_target(learner.state_), rel=1e-12)
    want = batch_sample_summary(batch.model_, planted)["log_target"]
    assert batch.model_.hyper.place_size == 0.5
    assert sized["batch"]["sample"]["log_target"] == pytest.approx(want, rel=1e-12)


def test_the_report_counts_its_seeds_in_words(result):
    """The report says "1 seed" and "2 seeds" (the second audit found "1 seeds")."""
    for seeds, words in ((1, "1 seed\n"), (2, "2 seeds\n")):
        assert words in format_report({**result, "seeds": seeds})

"""Several runs and the choice of one."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.errors import ModelError
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.selection import MultiRunSelector, fit_runs
from tests.helpers.learning import planted_dataset


@pytest.fixture(scope="module")
def data():
    return planted_dataset(E=80)


def test_selects_the_best_run_by_each_criterion(data):
    for criterion, key in (("mutual_information", "mutual_information"), ("log_joint", "log_joint")):
        sel = fit_runs(data, runs=4, iterations=15, criterion=criterion, connectivity="hmm")
        scores = [getattr(s, key) for s in sel.summaries_]
        assert sel.best_index_ == int(np.argmax(scores))
        assert sel.model_ is sel.estimators_[sel.best_index_].model_
        assert sel.model_.info["selected_run"] == sel.best_index_ and sel.model_.info["criterion"] == criterion


def test_auto_uses_the_log_joint_without_features_and_the_mutual_information_with_them(data):
    from dataclasses import replace

    rng = np.random.default_rng(0)
    featured = replace(data, features=rng.dirichlet(np.ones(5), size=data.n_events))
    with_features = fit_runs(featured, runs=3, iterations=10, connectivity="hmm")
    words_only = fit_runs(data, runs=3, iterations=10, connectivity="hmm")
    assert data.features is None
    assert with_features.criterion_ == "mutual_information"
    assert with_features.best_index_ == int(np.argmax([s.mutual_information for s in with_features.summaries_]))
    assert words_only.criterion_ == "log_joint" and words_only.model_.info["criterion"] == "log_joint"
    assert words_only.best_index_ == int(np.argmax([s.log_joint for s in words_only.summaries_]))


def test_log_joint_picks_better_runs_than_mutual_information_on_generated_homes():
    # words-only teaching with templates: the mutual information can prefer concepts built from the templates'
    # function words, which merge differently named places; the log joint does not (README: run selection)
    from sklearn.metrics import adjusted_rand_score

    from spcotmhp.datasets.synthetic_battery import battery_home

    better = 0
    for seed in (0, 9):
        d = battery_home(seed)
        sel = fit_runs(d, runs=6, seed=seed)
        ari = [adjusted_rand_score(d.truth_concept, e.concepts_) for e in sel.estimators_]
        mi = int(np.argmax([s.mutual_information for s in sel.summaries_]))
        better += ari[sel.best_index_] >= ari[mi] - 0.01  # as good, up to about one event of 165
        assert sel.criterion_ == "log_joint" and ari[sel.best_index_] >= 0.9
    assert better == 2


def test_runs_are_the_children_of_the_seed(data):
    sel = fit_runs(data, runs=3, iterations=10, seed=5, connectivity="hmm")
    for r, est in enumerate(sel.estimators_):
        alone = SpCoTMHP(iterations=10, seed=5, run=r, connectivity="hmm").fit(data)
        np.testing.assert_array_equal(est.places_, alone.places_)
    assert len({tuple(e.places_) for e in sel.estimators_}) > 1 or len({e.log_joint_ for e in sel.estimators_}) > 1


def test_process_pool_gives_the_same_runs(data):
    one = fit_runs(data, runs=3, iterations=10, seed=2, n_jobs=1, connectivity="hmm")
    two = fit_runs(data, runs=3, iterations=10, seed=2, n_jobs=2, connectivity="hmm")
    for a, b in zip(one.estimators_, two.estimators_, strict=False):
        np.testing.assert_array_equal(a.concepts_, b.concepts_)
        np.testing.assert_array_equal(a.model_.mu, b.model_.mu)


def test_connectivity_is_applied_to_the_chosen_run_only(data):
    sel = fit_runs(data, runs=2, iterations=10, connectivity="map")
    assert sel.model_.info["psi_from"] == "map"
    other = sel.estimators_[1 - sel.best_index_]
    assert other.model_.info["psi_from"] == "hmm"
    np.testing.assert_array_equal(other.model_.psi_learned, other.model_.psi)
    # the chosen run plans with the map's psi and keeps the HMM's as psi_learned
    assert sel.model_.psi_learned is not None and not np.allclose(sel.model_.psi_learned, sel.model_.psi)
    np.testing.assert_allclose(sel.model_.psi_learned.sum(axis=1), 1.0)


def test_progress_counts_every_sweep(data):
    seen = []
    fit_runs(data, runs=2, iterations=7, progress=seen.append, connectivity="hmm")
    assert sum(seen) == 14


def test_bad_settings(data):
    with pytest.raises(ModelError, match="criterion must be one of"):
        MultiRunSelector(runs=2, criterion="coin").fit(data)
    with pytest.raises(ModelError, match=r"runs must be an integer in \[1, 1000\], got 0"):
        MultiRunSelector(runs=0).fit(data)


@pytest.mark.parametrize("kwargs", [{"runs": 10**9}, {"n_jobs": 10**6}, {"runs": 2.5}])
def test_counts_are_bounded_before_any_run_is_set_up(data, monkeypatch, kwargs):
    """Audit item 5: a billion runs used to build a billion job dicts (MemoryError); now a one-line ModelError
    comes first."""
    from spcotmhp.learning import selection

    monkeypatch.setattr(selection.SpCoTMHP, "get_params", lambda self: pytest.fail("runs were set up"))
    with pytest.raises(ModelError, match=r"(runs|n_jobs) must be an integer in \[1, \d+\], got "):
        MultiRunSelector(**kwargs).fit(data)


def _state_joint(st, transitions=True) -> float:
    from spcotmhp.learning.online_split_merge import state_stats
    from spcotmhp.learning.posterior import Priors, log_joint

    priors = Priors.build(st.hyper, st.K, st.L, st.V, st.D)
    return log_joint(priors, state_stats(st), st.trans if transitions else None)


def test_switch_mode_is_a_local_maximum_of_the_joint(data):
    """The run's stored joint is its final state's; iterated conditional modes never lower it and end where no
    single switch flipped raises it (brute force over every token)."""
    from spcotmhp.learning.learner_state import state_of_member

    run = SpCoTMHP(iterations=10, seed=1, connectivity="hmm").fit(data)
    st = state_of_member(run.model_.learner, run.model_)
    assert _state_joint(st) == pytest.approx(run.log_joint_, rel=1e-12)
    before = _state_joint(st)
    st.switch_mode()
    mode = _state_joint(st)
    assert mode >= before
    for e in range(st.E):
        l = st.concept[e]
        for j, v in enumerate(st.tokens[e]):
            on = bool(st.z[e][j])
            (st.W_lv[l] if on else st.bg_v)[v] -= 1.0
            (st.bg_v if on else st.W_lv[l])[v] += 1.0
            st.z_tot += np.array([1.0, -1.0]) if on else np.array([-1.0, 1.0])
            assert _state_joint(st) <= mode + 1e-9
            (st.bg_v if on else st.W_lv[l])[v] -= 1.0
            (st.W_lv[l] if on else st.bg_v)[v] += 1.0
            st.z_tot -= np.array([1.0, -1.0]) if on else np.array([-1.0, 1.0])
    st.switch_mode()
    assert _state_joint(st) == pytest.approx(mode, rel=1e-12)


def test_choose_keeps_another_run_among_the_fitted_ones(data):
    sel = fit_runs(data, runs=3, iterations=10, connectivity="map")
    mi = [s.mutual_information for s in sel.summaries_]
    assert sel.choose("mutual_information").best_index_ == int(np.argmax(mi))
    assert sel.model_ is sel.estimators_[int(np.argmax(mi))].model_ and sel.model_.info["psi_from"] == "map"
    with pytest.raises(ModelError):
        sel.choose("best")
    with pytest.raises(ModelError):
        sel.scores("auto")

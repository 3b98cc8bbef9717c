"""The order of one Gibbs sweep, the exported psi, the one trajectory labelling, the scaled priors and the
warning about a saturated truncation."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.datasets import generate_environment
from spcotmhp.learning.connectivity import trajectory_places as model_trajectory_places
from spcotmhp.learning.distributions import DirichletCategoricals
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.hmm import runs, trajectory_places, transition_counts
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.observations import Observations
from spcotmhp.learning.posterior import (
    Priors,
    SufficientStats,
    TruncationWarning,
    log_place_prior,
    posterior_mean_model,
)
from tests.helpers.learning import planted_dataset


@pytest.fixture(scope="module")
def house():
    return generate_environment("house", seed=0)  # 11 places, 165 events and a trajectory through the doors


def _fit(data, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", TruncationWarning)
        return SpCoTMHP(**kwargs).fit(data)


def test_the_first_psi_draw_already_counts_the_trajectory(house, monkeypatch):
    # the Gaussians are drawn before the trajectory is labelled, so even sweep 0 sees the doorway crossings
    drawn = []
    original = DirichletCategoricals.resample

    def spy(self, counts, rng):
        if self.R == self.M == 20 and self.concentration == 10.0 / 20:  # psi: K x K, omega = 10 / K
            drawn.append(np.array(counts))
        return original(self, counts, rng)

    monkeypatch.setattr(DirichletCategoricals, "resample", spy)
    _fit(house, iterations=1, L=12, seed=0, connectivity="hmm")
    assert len(drawn) == 1
    events_only = 2 * (house.n_events - 1)  # event transitions counted forwards and backwards
    assert drawn[0].sum() > events_only + 2 * 10  # more than ten place changes along the trajectory


def test_exported_psi_is_the_posterior_mean_for_counts_labelled_with_the_exported_means(house):
    est = _fit(house, iterations=15, seed=1, connectivity="hmm")
    m = est.model_
    seq = model_trajectory_places(m, np.asarray(house.trajectory, dtype=float), est.min_dwell)
    assert len(seq) > 10
    counts = transition_counts(est.places_, m.K, True) + transition_counts(seq, m.K, True)
    want = (m.hyper.omega + counts) / (m.K * m.hyper.omega + counts.sum(axis=1, keepdims=True))
    np.testing.assert_allclose(m.psi, want, rtol=1e-12)
    np.testing.assert_array_equal(m.psi_learned, m.psi)


def test_adjacency_psi_keeps_the_learned_psi(house):
    est = _fit(house, iterations=15, seed=1)  # connectivity "auto": "walk" with a trajectory
    hmm = _fit(house, iterations=15, seed=1, connectivity="hmm")
    assert est.model_.info["psi_from"] == "walk+map"
    assert not np.allclose(est.model_.psi, est.model_.psi_learned)
    np.testing.assert_array_equal(est.model_.psi_learned, hmm.model_.psi)


def test_one_trajectory_labelling_by_hand():
    # unit Gaussians at x = 0 and x = 2: with place weights 0.5 / 0.5 the boundary is x = 1, with 0.9 / 0.1 it is
    # x = 1 + log(9) / 2 = 2.099; place 2 holds no events (weight 0) and is never chosen although it is nearest
    mu = np.array([[0.0, 0.0], [2.0, 0.0], [2.2, 0.0]])
    Sigma = np.array([np.eye(2), np.eye(2), 0.01 * np.eye(2)])
    xs = np.round(np.arange(-1.0, 2.25, 0.1), 10)  # poses at -1.0, -0.9, ..., 2.2
    traj = np.stack([xs, np.zeros_like(xs)], axis=1)
    even = np.array([np.log(0.5), np.log(0.5), -np.inf])
    skew = np.array([np.log(0.9), np.log(0.1), -np.inf])
    assert trajectory_places(traj, mu, Sigma, even, 3).tolist() == [0, 1]  # 1.1 .. 2.2 in place 1
    assert trajectory_places(traj[xs <= 2.0], mu, Sigma, skew, 1).tolist() == [0]
    assert trajectory_places(traj, mu, Sigma, skew, 3).tolist() == [0]  # 2.1, 2.2: a stay of 2 poses
    assert trajectory_places(traj, mu, Sigma, skew, 2).tolist() == [0, 1]


def test_sampler_and_model_score_places_the_same_way():
    data = planted_dataset(E=60)
    obs = Observations.from_dataset(data)
    rng = np.random.default_rng(0)
    places, concepts = rng.integers(0, 5, size=60), rng.integers(0, 3, size=60)
    places[places == 4] = 0  # place 4 holds no events
    hyper = Hyperparameters(L=3, K=6)
    priors = Priors.build(hyper, 6, 3, len(obs.vocabulary), None)
    stats = SufficientStats.from_assignments(obs, places, concepts, 6, 3)
    model = posterior_mean_model(priors, stats, None, obs.vocabulary, hyper)
    np.testing.assert_allclose(log_place_prior(priors, stats), model.log_place_prior())
    assert np.isneginf(log_place_prior(priors, stats)[[4, 5]]).all()
    traj = data.positions[:40]
    np.testing.assert_array_equal(
        model_trajectory_places(model, traj, 1),
        trajectory_places(traj, model.mu, model.Sigma, model.log_place_prior(), 1),
    )


def test_run_length_encoding():
    labels, lengths = runs(np.array([3, 3, 1, 1, 1, 3, 2, 2]))
    assert labels.tolist() == [3, 1, 3, 2] and lengths.tolist() == [2, 3, 1, 2]
    labels, lengths = runs(np.array([], dtype=int))
    assert len(labels) == len(lengths) == 0


def test_priors_follow_the_truncation():
    h = Hyperparameters()
    assert (h.alpha, h.gamma, h.omega) == (0.5, 0.05, 0.5)  # the paper's values at L = K = 20
    r = h.resized(10, 40)
    assert (r.L, r.K, r.alpha, r.gamma, r.omega) == (10, 40, 1.0, 0.025, 0.25)
    given = Hyperparameters(alpha=2.0, omega=0.1).resized(10, 40)  # given values are kept
    assert (given.alpha, given.gamma, given.omega) == (2.0, 0.025, 0.1)
    with pytest.raises(ValueError, match=r"L must be an integer in \[1, 10000\], got 0"):
        Hyperparameters(L=0)
    est = _fit(planted_dataset(E=40), L=8, K=25, iterations=2, connectivity="hmm")
    hy = est.model_.hyper
    assert (hy.L, hy.K, hy.alpha, hy.gamma, hy.omega) == (8, 25, 1.25, 0.04, 0.4)


def test_saturated_truncation_warns_and_is_recorded():
    data = planted_dataset(E=80)  # four places, four concepts
    with pytest.warns(TruncationWarning) as caught:
        est = SpCoTMHP(K=2, L=2, iterations=5, seed=0, connectivity="hmm").fit(data)
    messages = [str(w.message) for w in caught]
    assert est.model_.info["truncation_saturated"] == ["places", "concepts"]
    assert messages == [
        (
            "all K = 2 place components hold events (the weak-limit truncation is saturated, so places may have "
            "been merged): learn again with a larger --max-places (SpCoTMHP(K=...))"
        ),
        (
            "all L = 2 concept components hold events (the weak-limit truncation is saturated, so concepts may have "
            "been merged): learn again with a larger --max-concepts (SpCoTMHP(L=...))"
        ),
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("error", TruncationWarning)
        roomy = SpCoTMHP(iterations=5, seed=0, connectivity="hmm").fit(data)
    assert roomy.model_.info["truncation_saturated"] == []

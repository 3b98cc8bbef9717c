"""Hyper-parameters (learning/model.py): the place prior with a stated size (``Hyperparameters.place_size``),
checked by hand against the NIW terms of both learners (batch ``NIWGaussians``, online ``CollapsedState``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from spcotmhp.evaluation.online_eval import dataset_events
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.distributions import GaussianStats
from spcotmhp.learning.gibbs import SpCoTMHP
from spcotmhp.learning.model import Hyperparameters, place_size_prior
from spcotmhp.learning.online import OnlineSpCoTMHP
from spcotmhp.learning.posterior import Priors
from spcotmhp.persistence.io import load_model, save_model
from tests.helpers.learning import planted_dataset


def test_place_size_sets_a_finite_prior_mean():
    h = Hyperparameters(place_size=1.5)
    assert h.nu0 == 5.0 and h.V0 == ((4.5, 0.0), (0.0, 4.5))  # V0 = (nu0 - 3) s^2 I
    # E[Sigma] = V0 / (nu0 - 3) = s^2 I: the posterior mean of a place without events
    _mu, Sigma = Priors.build(h, 1, 1, 1, None).gauss.posterior_mean(
        GaussianStats.from_assignments(np.zeros((0, 2)), np.zeros(0, int), 1)
    )
    np.testing.assert_allclose(Sigma[0], 2.25 * np.eye(2))
    paper = Hyperparameters()
    assert paper.place_size is None and paper.nu0 == 3.0 and paper.V0 == ((2.0, 0.0), (0.0, 2.0))
    assert h.resized(30, 40).V0 == h.V0 and h.resized(30, 40).place_size == 1.5


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"place_size": 0.0}, r"place_size must be a finite number of metres in \[0.001, 100000\], got 0.0"),
        ({"place_size": 1e308}, r"place_size must be a finite number of metres in \[0.001, 100000\], got 1e\+308"),
        ({"place_size": float("inf")}, "place_size must be a finite number"),
        ({"place_size": True}, "place_size must be a finite number"),
        ({"place_size": 1.0, "nu0": 7.0}, r"place_size sets nu0 and V0 \(to 5 and 2 I\): give one or the other"),
        ({"place_size": 1.0, "V0": ((1.0, 0.0), (0.0, 1.0))}, "give one or the other"),
    ],
)
def test_place_size_rejects_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        Hyperparameters(**kwargs)


def test_place_size_prior_keeps_its_own_derived_values():
    assert place_size_prior(2.0, 5.0, ((8.0, 0.0), (0.0, 8.0))) == (5.0, ((8.0, 0.0), (0.0, 8.0)))


def test_one_position_by_hand_in_both_learners():
    # at x = m0 the prior predictive is a 2-D Student t with nu0 - 1 = 4 degrees of freedom and scale
    # S = V0 (kappa0 + 1) / (kappa0 (nu0 - 1)) = 2 * 1.001 / 0.004 I = 500.5 I:
    # log t = log Gamma(3) - log Gamma(2) - log(4 pi) - log 500.5
    want = math.log(2.0) - math.log(4.0 * math.pi) - math.log(500.5)
    assert want == pytest.approx(-8.053485, abs=1e-6)
    h = Hyperparameters(place_size=1.0)
    batch = Priors.build(h, 1, 1, 1, None).gauss.log_marginal(
        GaussianStats(np.ones(1), np.zeros((1, 2)), np.zeros((1, 2, 2)))
    )
    assert batch == pytest.approx(want, abs=1e-9)
    online = CollapsedState(1, 1, 1, None, h)
    assert online.log_predictive(np.zeros(2))[0] == pytest.approx(want, abs=1e-9)


def test_online_predictive_is_the_batch_marginal_ratio():
    # the two homes of the place term agree: log t(x | place) = log p(X + x) - log p(X) under the sized prior
    rng = np.random.default_rng(3)
    X = rng.normal([2.0, -1.0], [0.8, 0.4], size=(6, 2))
    x = np.array([2.5, -0.7])
    h = Hyperparameters(place_size=0.8)
    gauss = Priors.build(h, 1, 1, 1, None).gauss

    def marginal(points):
        return gauss.log_marginal(GaussianStats.from_assignments(points, np.zeros(len(points), int), 1))

    st = CollapsedState(1, 1, 1, None, h)
    st.n_k[0], st.sx[0], st.sxx[0] = len(X), X.sum(axis=0), X.T @ X
    assert st.log_predictive(x)[0] == pytest.approx(marginal(np.vstack([X, x])) - marginal(X), abs=1e-9)


def test_both_learners_carry_the_place_size_and_a_model_folder_keeps_it(tmp_path):
    data = planted_dataset(E=60)
    h = Hyperparameters(place_size=0.7)
    batch = SpCoTMHP(iterations=3, seed=0, hyper=h).fit(data)
    assert batch.model_.hyper.place_size == 0.7 and batch.model_.hyper.nu0 == 5.0
    back = load_model(save_model(batch.model_, tmp_path / "m"))
    assert back.hyper == batch.model_.hyper
    online = OnlineSpCoTMHP(hyper=h, map=data.map, seed=0).partial_fit(dataset_events(data)[:5])
    assert online.state_.hyper.V0 == h.V0 and online.model_.hyper.place_size == 0.7

"""The supervised ("ideal", Experiment I) fit: hand-computed posterior means on the bundled 3LDK_01 home."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from spcotmhp.datasets import generate_environment, load_bundled
from spcotmhp.datasets.bundled import bundled_path
from spcotmhp.errors import DatasetError, ModelError
from spcotmhp.learning.connectivity import map_adjacency, psi_from_adjacency, walk_adjacency
from spcotmhp.learning.supervised import fit_supervised

pytestmark = pytest.mark.filterwarnings("ignore::spcotmhp.datasets.loader.DatasetWarning")


@pytest.fixture(scope="module")
def home():
    return load_bundled("3LDK_01", lang="en")


def _raw_place(place: int):
    """Positions and English words of one place's events, read straight from the CSV files."""
    folder = bundled_path("3LDK_01")
    with open(folder / "truth.csv", newline="") as f:
        truth = {int(r["event"]): int(r["place"]) for r in csv.DictReader(f)}
    X, words = [], []
    with open(folder / "teaching.csv", newline="", encoding="utf-8") as f:
        for r in csv.DictReader(f):
            if truth[int(r["event"])] == place:
                X.append([float(r["x"]), float(r["y"])])
                words += r["words_en"].split()
    return np.array(X), words, len(truth)


def test_place_zero_matches_hand_computed_posterior_means(home):
    model = fit_supervised(home, adjacency="given")
    X, words, E = _raw_place(0)
    n = len(X)
    kappa0, nu0 = 1e-3, 3.0
    xbar = X.mean(axis=0)
    # NIW: m_n = (kappa0 m0 + n xbar) / (kappa0 + n); V_n = V0 + S + kappa0 n / (kappa0 + n) xbar xbar^T (m0 = 0)
    S = (X - xbar).T @ (X - xbar)
    V_n = 2.0 * np.eye(2) + S + (kappa0 * n / (kappa0 + n)) * np.outer(xbar, xbar)
    np.testing.assert_allclose(model.mu[0], n * xbar / (kappa0 + n), rtol=1e-12)
    np.testing.assert_allclose(model.Sigma[0], V_n / (nu0 + n - 3.0), rtol=1e-12)
    # W: Dirichlet(beta = 0.1) mean of the word counts of concept 0 (= place 0: no concept column)
    V = len(model.vocabulary)
    for w in set(words):
        j = model.vocabulary.index(w)
        assert model.W[0, j] == pytest.approx((0.1 + words.count(w)) / (0.1 * V + len(words)))
    # pi: Dirichlet(alpha = 1) mean; phi: Dirichlet(gamma = 0.1) mean over K = 11 places
    assert model.pi[0] == pytest.approx((1.0 + n) / (11 * 1.0 + E))
    assert model.phi[0, 0] == pytest.approx((0.1 + n) / (0.1 * 11 + n))
    assert model.phi[0, 1] == pytest.approx(0.1 / (0.1 * 11 + n))
    # psi: mean of Dir(0.1 + adjacency[0])
    A0 = home.adjacency[0]
    np.testing.assert_allclose(model.psi[0], (0.1 + A0) / (0.1 * 11 + A0.sum()))
    assert model.info["psi_from"] == "adjacency.csv"
    assert model.K == model.L == 11 and model.active_places.all()


def test_auto_uses_the_given_adjacency(home):
    np.testing.assert_allclose(fit_supervised(home).psi, fit_supervised(home, adjacency="given").psi)


def test_transitions_and_map_sources(home):
    trans = fit_supervised(home, adjacency="transitions")
    # events are taught room after room: 0 -> 1 -> ... -> 10, counted in both directions (reverse replay)
    counts = np.diag(np.full(11, 28.0))
    for a in range(10):
        counts[a, a + 1] = counts[a + 1, a] = 1.0
    np.testing.assert_allclose(trans.psi, (0.1 + counts) / (1.1 + counts.sum(axis=1, keepdims=True)))
    mapped = fit_supervised(home, adjacency="map")
    np.testing.assert_allclose(mapped.psi, psi_from_adjacency(map_adjacency(mapped, home.map)))
    assert mapped.info["psi_from"] == "map"


def test_walk_source_on_a_synthetic_home_with_a_trajectory():
    data = generate_environment("house", seed=1)
    model = fit_supervised(data)  # auto: the synthetic home also has adjacency.csv
    assert model.info["psi_from"] == "adjacency.csv"
    walk = fit_supervised(data, adjacency="walk")
    A = walk_adjacency(walk, data).astype(bool)
    np.testing.assert_allclose(walk.psi, psi_from_adjacency(A))
    truth = data.adjacency.astype(bool)
    off = ~np.eye(walk.K, dtype=bool)
    tp = (A & truth & off).sum()  # the doors the teaching walk went through
    assert tp / (A & off).sum() >= 0.9 and tp / (truth & off).sum() >= 0.8


def test_bad_requests(home):
    with pytest.raises(ModelError, match="adjacency must be one of"):
        fit_supervised(home, adjacency="psychic")
    with pytest.raises(ModelError, match=r"adjacency must be 11x11"):
        fit_supervised(home, adjacency=np.eye(3))
    no_truth = load_bundled("3LDK_01", lang="en")
    no_truth.truth_place = None
    with pytest.raises(DatasetError, match="needs truth places"):
        fit_supervised(no_truth)
    no_adj = load_bundled("3LDK_01", lang="en")
    no_adj.adjacency = None
    with pytest.raises(DatasetError, match="has no adjacency.csv"):
        fit_supervised(no_adj, adjacency="given")


def test_the_feature_weight_is_recorded_for_prediction():
    from spcotmhp.learning.observations import scale_features

    data = load_bundled("albert-b", lang="ja")
    authors = fit_supervised(data, adjacency="transitions", feature_weight=None)
    unit = fit_supervised(data, adjacency="transitions")
    assert authors.info["feature_weight"] is None and unit.info["feature_weight"] == 1.0
    assert authors.info["features"] is True
    # theta is the Dir(chi = 1) posterior mean of the counts of the chosen scaling
    counts = scale_features(np.asarray(data.features, dtype=float), None)[data.truth_concept == 0].sum(axis=0)
    np.testing.assert_allclose(authors.theta[0], (1.0 + counts) / (counts.size + counts.sum()))
    assert not np.allclose(authors.theta, unit.theta)

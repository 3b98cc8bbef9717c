"""The Gibbs sampler: recovery of planted parameters, determinism, modes, and bad inputs."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.optimize import linear_sum_assignment
from sklearn.metrics import normalized_mutual_info_score

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import DatasetError, ModelError
from spcotmhp.learning.connectivity import map_adjacency, psi_from_adjacency
from spcotmhp.learning.gibbs import SpCoTMHP, make_rng
from tests.helpers.learning import CONCEPT_OF_PLACE, NAMES, PLANTED_MU, PLANTED_PSI, PLANTED_SIGMA, planted_dataset


@pytest.fixture(scope="module")
def planted_fit():
    data = planted_dataset()
    return data, SpCoTMHP(seed=0, connectivity="hmm").fit(data)


def _match(learned: np.ndarray, truth: np.ndarray, K: int) -> dict[int, int]:
    """Learned place -> planted place by maximum overlap (Hungarian assignment)."""
    overlap = np.zeros((K, 4))
    np.add.at(overlap, (learned, truth), 1)
    rows, cols = linear_sum_assignment(-overlap)
    return {int(r): int(c) for r, c in zip(rows, cols, strict=False) if overlap[r, c] > 0}


def test_recovers_planted_places_and_concepts(planted_fit):
    data, est = planted_fit
    assert normalized_mutual_info_score(data.truth_place, est.places_) > 0.97
    assert normalized_mutual_info_score(data.truth_concept, est.concepts_) > 0.97
    assert est.model_.active_places.sum() == 4


def test_recovers_planted_gaussians(planted_fit):
    data, est = planted_fit
    m = est.model_
    for k, t in _match(est.places_, data.truth_place, m.K).items():
        # the NIW posterior mean given the true members (m0 = 0, kappa0 = 1e-3, V0 = 2 I, nu0 = 3) ...
        X = data.positions[data.truth_place == t]
        n = len(X)
        xbar = X.mean(axis=0)
        V_n = 2 * np.eye(2) + (X - xbar).T @ (X - xbar) + (1e-3 * n / (1e-3 + n)) * np.outer(xbar, xbar)
        np.testing.assert_allclose(m.mu[k], n * xbar / (1e-3 + n), atol=1e-9)
        np.testing.assert_allclose(m.Sigma[k], V_n / (3 + n - 3), atol=1e-9)
        # ... which is near the planted parameters (about three standard errors of ~75 samples)
        np.testing.assert_allclose(m.mu[k], PLANTED_MU[t], atol=0.2)
        np.testing.assert_allclose(m.Sigma[k], PLANTED_SIGMA[t], atol=0.2)


def test_recovers_planted_transitions(planted_fit):
    data, est = planted_fit
    match = _match(est.places_, data.truth_place, est.model_.K)
    order = list(match)
    learned = est.model_.psi[np.ix_(order, order)]
    truth = PLANTED_PSI[np.ix_(list(match.values()), list(match.values()))]
    np.testing.assert_allclose(learned, truth, atol=0.12)
    # exactly the posterior mean of Dir(omega + counts + transposed counts) (reverse replay), omega = 0.5
    seq = np.array([order.index(k) for k in est.places_])
    counts = np.zeros((4, 4))
    np.add.at(counts, (seq[:-1], seq[1:]), 1)
    counts += counts.T
    K = est.model_.K
    np.testing.assert_allclose(learned, (0.5 + counts) / (0.5 * K + counts.sum(axis=1, keepdims=True)))
    assert est.model_.info["psi_from"] == "hmm"


def test_recovers_planted_words(planted_fit):
    data, est = planted_fit
    m = est.model_
    for c in np.flatnonzero(m.active_concepts):
        truth = np.bincount(data.truth_concept[est.concepts_ == c]).argmax()
        assert m.vocabulary[int(np.argmax(m.W[c]))] == NAMES[truth]
    names = m.place_names()
    for k, t in _match(est.places_, data.truth_place, m.K).items():
        assert names[k] == NAMES[CONCEPT_OF_PLACE[t]]


def test_learned_attributes_are_consistent(planted_fit):
    data, est = planted_fit
    m = est.model_
    assert est.places_.shape == est.concepts_.shape == (data.n_events,)
    assert set(np.unique(est.places_)) == set(np.flatnonzero(m.active_places))
    assert set(np.unique(est.concepts_)) == set(np.flatnonzero(m.active_concepts))
    np.testing.assert_allclose(m.psi.sum(axis=1), 1.0)
    np.testing.assert_allclose(m.W.sum(axis=1), 1.0)
    np.testing.assert_allclose(m.phi.sum(axis=1), 1.0)
    assert len(est.log_joint_trace_) == est.iterations and est.log_joint_trace_[-1] == est.log_joint_
    assert est.log_joint_trace_[-1] > est.log_joint_trace_[0]
    assert np.isfinite(est.mutual_information_) and est.mutual_information_ > 0


def test_seeded_runs_are_reproducible_and_independent():
    data = planted_dataset(E=60)
    a = SpCoTMHP(iterations=10, seed=3, run=1, connectivity="hmm").fit(data)
    b = SpCoTMHP(iterations=10, seed=3, run=1, connectivity="hmm").fit(data)
    c = SpCoTMHP(iterations=10, seed=3, run=2, connectivity="hmm").fit(data)
    np.testing.assert_array_equal(a.places_, b.places_)
    np.testing.assert_array_equal(a.model_.mu, b.model_.mu)
    assert not np.array_equal(a.model_.mu, c.model_.mu)
    # run r is the r-th spawned child of the seed
    want = np.random.SeedSequence(3).spawn(3)[2]
    assert make_rng(3, 2).random() == np.random.default_rng(want).random()


def test_gmm_mode_is_the_same_sampler_without_transitions():
    data = planted_dataset(E=120)
    est = SpCoTMHP(transitions="none", seed=0).fit(data)
    np.testing.assert_allclose(est.model_.psi, 1.0 / est.model_.K)
    assert est.model_.info["method"] == "SpCoSLAM (GMM)"
    assert normalized_mutual_info_score(data.truth_place, est.places_) > 0.9


def test_map_connectivity_replaces_psi_with_an_adjacency():
    data = planted_dataset(E=120)  # an empty (all free) map: the ring's sides are direct, the diagonals
    est = SpCoTMHP(seed=0, connectivity="map").fit(data)  # pass through a third place
    m = est.model_
    assert m.info["psi_from"] == "map"
    A = map_adjacency(m, data.map)
    np.testing.assert_allclose(m.psi, psi_from_adjacency(A))
    match = _match(est.places_, data.truth_place, m.K)
    at = {t: k for k, t in match.items()}
    for a, b in ((0, 1), (1, 2), (2, 3), (3, 0)):
        assert A[at[a], at[b]] == 1


def test_features_are_used_and_scaled():
    data = planted_dataset(E=80)
    rng = np.random.default_rng(0)
    data.features = rng.dirichlet(np.ones(5), size=80)
    est = SpCoTMHP(iterations=20, seed=0).fit(data)
    assert est.model_.theta.shape == (20, 5)
    np.testing.assert_allclose(est.model_.theta.sum(axis=1), 1.0)
    assert est.model_.info["features"] is True


def _bad(**changes) -> Dataset:
    data = planted_dataset(E=20)
    for k, v in changes.items():
        setattr(data, k, v)
    return data


@pytest.mark.parametrize(
    "changes,message",
    [
        ({"positions": np.zeros((0, 2)), "tokens": []}, "no teaching events; learning needs at least 2"),
        ({"positions": np.zeros((1, 2)), "tokens": [["kitchen"]]}, "only 1 teaching event"),
        (
            {"positions": np.vstack([np.zeros((19, 2)), [[np.nan, 1.0]]])},
            "teaching event 19 has a non-finite position",
        ),
        ({"positions": np.zeros((20, 3))}, r"positions must be an \(E, 2\) array"),
        ({"tokens": [["a"]] * 19}, "19 token lists for 20 teaching events"),
        ({"tokens": [[] for _ in range(20)]}, "no teaching event has any word"),
        ({"features": np.ones((19, 4))}, r"one row per teaching event \(E = 20\), got shape \(19, 4\)"),
        ({"features": -np.ones((20, 4))}, "image feature row 0 has a negative or non-finite value"),
        ({"trajectory": np.full((5, 2), np.inf)}, "trajectory has non-finite positions"),
    ],
)
def test_bad_datasets_get_clear_errors(changes, message):
    with pytest.raises(DatasetError, match=message):
        SpCoTMHP(iterations=2).fit(_bad(**changes))


@pytest.mark.parametrize(
    "kwargs,message",
    [
        ({"transitions": "hsmm"}, "transitions must be one of"),
        ({"connectivity": "magic"}, "connectivity must be one of"),
        ({"init": "zeros"}, "init must be one of"),
        ({"K": 0}, r"K \(the place truncation\) must be an integer in \[1, 1000\], got 0"),
        ({"K": 10**8}, r"K \(the place truncation\) must be an integer in \[1, 1000\], got 100000000"),
        ({"L": 10**8}, r"L \(the concept truncation\) must be an integer in \[1, 1000\], got 100000000"),
        ({"iterations": 10**9}, r"iterations must be an integer in \[1, 100000\], got 1000000000"),
    ],
)
def test_bad_settings_get_clear_errors(kwargs, message):
    with pytest.raises(ModelError, match=message):
        SpCoTMHP(**kwargs).fit(planted_dataset(E=20))


def test_counts_are_refused_before_the_observations_are_built(monkeypatch):
    """Audit item 5: --max-places 100000000 used to allocate (K, 4) arrays first; the events x K bound too."""
    from spcotmhp import limits
    from spcotmhp.learning import gibbs

    monkeypatch.setattr(gibbs.Observations, "from_dataset", lambda *a, **k: pytest.fail("observations were built"))
    data = planted_dataset(E=20)
    for kwargs in ({"K": 10**8}, {"L": 10**8}, {"iterations": 10**9}):
        with pytest.raises(ModelError, match="must be an integer in"):
            SpCoTMHP(**kwargs).fit(data)
    monkeypatch.setattr(limits, "MAX_EVENT_PLACES", 19_999)  # 20 events x K = 1000 is one number too many
    with pytest.raises(ModelError, match="20 events x K=1000 places is 20000 numbers per .* more than the 19999"):
        SpCoTMHP(K=1000).fit(data)


def test_trajectory_transitions_recover_the_synthetic_house_doors():
    """Trajectory-aware connectivity: the rooms walked through one after the other are the house's doors.

    Doors are compared between named rooms: the house has two adjacent rooms both named "corridor", which the
    learner may give one place (their words cannot tell them apart), so a door is counted between names."""
    from spcotmhp.datasets import generate_environment

    data = generate_environment("house", seed=0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        est = SpCoTMHP(seed=0).fit(data)
    m = est.model_
    assert m.info["psi_from"] == "walk+map"
    names = sorted(set(data.place_names))
    name_of = np.array([names.index(n) for n in data.place_names])
    N = len(names)
    truth = np.zeros((N, N), dtype=bool)
    for a, b in zip(*np.nonzero(data.adjacency > 0), strict=True):
        truth[name_of[a], name_of[b]] |= name_of[a] != name_of[b]
    event_name = name_of[data.truth_place]
    label = {
        k: np.bincount(event_name[est.places_ == k], minlength=N).argmax() for k in np.flatnonzero(m.active_places)
    }
    edges = np.zeros((N, N), dtype=bool)
    conn = (m.psi + m.psi.T) / 2 >= 1.0 / m.K  # the planner's edge rule (paper Fig. 3)
    for a, la in label.items():
        for b, lb in label.items():
            if a != b and conn[a, b] and la != lb:
                edges[la, lb] = True
    tp = (edges & truth).sum()
    assert tp / edges.sum() >= 0.8 and tp / truth.sum() >= 0.8
    # the event order alone (fifteen utterances per room) finds almost none of them as HMM edges
    hmm = SpCoTMHP(seed=0, use_trajectory=False, connectivity="hmm").fit(data).model_
    act = np.flatnonzero(hmm.active_places)
    conn_hmm = ((hmm.psi + hmm.psi.T) / 2 >= 1.0 / hmm.K)[np.ix_(act, act)]
    assert (conn_hmm & ~np.eye(len(act), dtype=bool)).sum() / 2 < tp / 2

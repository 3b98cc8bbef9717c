"""Geweke's joint-distribution test of the Gibbs sampler in GMM mode (``transitions="none"``, the partially
collapsed sampler of :mod:`spcotmhp.learning.gibbs`) on a tiny model: 4 events, K = 3 places, L = 2 concepts, 3
words, 2 tokens per event, no features, no background words.

The marginal-conditional simulator draws (pi, phi, W, mu, Sigma), then C, i, x and S from the generative model
(written here with numpy and scipy, independently of the package). The successive-conditional simulator
alternates one sweep of the package's sampler (steps 1, 4, 5 of the gibbs module docstring) with fresh data
drawn given the current assignments (x | i and S | C, the parameters drawn from their priors: p(x, S | i, C)).
If the sweep leaves p(i, C | x, S) invariant, both simulators draw (i, C, x, S) from the same joint, so every
test function has the same mean; each mean difference is compared with its standard error (batch means for the
autocorrelated chain) at a fixed seed.

The sweep is replayed step by step here (it is not a function of the package), so a first test checks that the
replay gives exactly what ``SpCoTMHP.fit`` gives for one sweep from the same state and seed.
"""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.learning import gibbs
from spcotmhp.learning.concepts import CollapsedConceptSampler
from spcotmhp.learning.gibbs import SpCoTMHP, make_rng
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.observations import Observations
from spcotmhp.learning.posterior import Priors
from spcotmhp.metric.maps import OccupancyMap

E, K, L, V, TOKENS = 4, 3, 2, 3, 4
HYPER = Hyperparameters(
    L=L,
    K=K,
    alpha=1.0,
    gamma=0.7,
    beta=0.2,
    chi=1.0,
    omega=1.0,
    m0=(0.0, 0.0),
    kappa0=0.05,
    V0=((1.0, 0.0), (0.0, 1.0)),
    nu0=5.0,
)
VOCABULARY = ["a", "b", "c"]


def estimator() -> SpCoTMHP:
    return SpCoTMHP(
        L=L,
        K=K,
        iterations=1,
        transitions="none",
        use_features=False,
        use_trajectory=False,
        background_words=False,
        hyper=HYPER,
    )


# ---- the generative model, independently of the package -------------------------------------------------------
def draw_gaussians(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray]:
    """n draws of (mu, Sigma) ~ NIW(m0, kappa0, V0, nu0): Sigma ~ IW(nu0, V0), mu | Sigma ~ N(m0, Sigma / kappa0).
    With an integer nu0, Sigma^-1 ~ Wishart(nu0, V0^-1) is a sum of nu0 outer products of N(0, V0^-1) draws."""
    z = rng.standard_normal((n, int(HYPER.nu0), 2)) @ np.linalg.cholesky(np.linalg.inv(np.asarray(HYPER.V0))).T
    Sigma = np.linalg.inv(np.einsum("nji,njk->nik", z, z))
    chol = np.linalg.cholesky(Sigma / HYPER.kappa0)
    mu = np.asarray(HYPER.m0) + np.einsum("nij,nj->ni", chol, rng.standard_normal((n, 2)))
    return mu, Sigma


def draw_data(rng: np.random.Generator, places: np.ndarray, concepts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(x, S) ~ p(x, S | i, C): fresh Gaussians and word distributions from their priors, then the data."""
    mu, Sigma = draw_gaussians(rng, K)
    W = rng.dirichlet(np.full(V, HYPER.beta), size=L)
    chol = np.linalg.cholesky(Sigma[places])
    X = mu[places] + np.einsum("eij,ej->ei", chol, rng.standard_normal((E, 2)))
    words = np.stack([rng.multinomial(TOKENS, W[c]) for c in concepts]).astype(float)
    return X, words


def draw_joint(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(i, C, x, S) from the generative model (marginal-conditional simulator)."""
    pi = rng.dirichlet(np.full(L, HYPER.alpha))
    phi = rng.dirichlet(np.full(K, HYPER.gamma), size=L)
    concepts = rng.choice(L, size=E, p=pi)
    places = np.array([rng.choice(K, p=phi[c]) for c in concepts])
    X, words = draw_data(rng, places, concepts)
    return places, concepts, X, words


def joint_statistics(places: np.ndarray, concepts: np.ndarray, X: np.ndarray, words: np.ndarray) -> np.ndarray:
    """Bounded functions of the joint state: agreements of the assignments, occupancy, and how the
    assignments relate to the data (near positions share a place, shared words share a concept)."""
    close = np.exp(-0.5 * np.sum((X[0] - X[1]) ** 2))
    similar = words[0] @ words[1] / (np.linalg.norm(words[0]) * np.linalg.norm(words[1]))
    same_place, same_concept = places[0] == places[1], concepts[0] == concepts[1]
    return np.array(
        [
            same_place,
            same_concept,
            len(set(places.tolist())),
            len(set(concepts.tolist())),
            same_place * close,
            same_concept * similar,
            same_place * same_concept,
            np.tanh(X[:, 0]).mean() * (places[0] == places[2]),
        ],
        dtype=float,
    )


# ---- one sweep of the package's sampler, replayed --------------------------------------------------------------
def sweep(
    est: SpCoTMHP,
    obs: Observations,
    priors: Priors,
    sampler: CollapsedConceptSampler,
    places: np.ndarray,
    concepts: np.ndarray,
    rng: np.random.Generator,
) -> tuple[np.ndarray, np.ndarray]:
    """Steps 1, 4 and 5 of a GMM-mode sweep, in ``SpCoTMHP.fit``'s order and with its calls."""
    hyper = HYPER.resized(L, K)
    stats = est._stats(obs, places, concepts, sampler)
    priors.gauss.resample(stats.gauss, rng)  # step 1
    priors.phi.resample(stats.place_given_concept, rng)
    places = est._sample_places(priors, obs, concepts, rng)  # step 4
    concepts = sampler.sweep(concepts, places, L, K, hyper.alpha, hyper.gamma, hyper.beta, hyper.chi, rng)  # step 5
    return places, concepts


def tiny_dataset(X: np.ndarray, words: np.ndarray) -> Dataset:
    tokens = [[w for w, n in zip(VOCABULARY, row, strict=True) for _ in range(int(n))] for row in words]
    grid = OccupancyMap(np.zeros((10, 10), np.int8), resolution=1.0, origin=(-5.0, -5.0, 0.0))
    return Dataset(name="tiny", map=grid, positions=X, tokens=tokens)


def test_the_inverse_wishart_draws_have_the_prior_mean():
    """The test's own NIW draws against E[Sigma^-1] = nu0 V0^-1 (Wishart) and E[mu] = m0 (the reference is right)."""
    mu, Sigma = draw_gaussians(np.random.default_rng(0), 200000)
    np.testing.assert_allclose(np.linalg.inv(Sigma).mean(axis=0), HYPER.nu0 * np.linalg.inv(HYPER.V0), atol=0.05)
    np.testing.assert_allclose(mu.mean(axis=0), HYPER.m0, atol=0.03)  # 4 standard errors (sd 3.2 / sqrt(2e5))


def test_the_replayed_sweep_is_the_sweep_of_fit(monkeypatch):
    rng = np.random.default_rng(7)
    for seed in range(5):
        places, concepts, X, words = draw_joint(rng)
        words[:, 0] += 1  # every word of the vocabulary in the data, so fit's vocabulary is VOCABULARY
        words[0] += 1
        dataset = tiny_dataset(X, words)
        monkeypatch.setattr(gibbs, "initial_assignments", lambda *args, p=places, c=concepts: (p.copy(), c.copy()))
        fitted = estimator()
        fitted.seed = seed
        fitted.fit(dataset)

        est = estimator()
        obs = Observations.from_dataset(dataset, use_features=False, use_trajectory=False)
        assert obs.vocabulary == VOCABULARY
        run = make_rng(seed)
        priors = Priors.build(HYPER.resized(L, K), K, L, V, None)
        sampler = CollapsedConceptSampler(obs.words, None, False, run)
        got = sweep(est, obs, priors, sampler, places.copy(), concepts.copy(), run)
        np.testing.assert_array_equal(got[0], fitted.places_)
        np.testing.assert_array_equal(got[1], fitted.concepts_)


def batch_means_se(values: np.ndarray, batches: int = 50) -> np.ndarray:
    """Standard error of the mean of each column of an autocorrelated series, by batch means."""
    n = len(values) // batches * batches
    means = values[:n].reshape(batches, -1, values.shape[1]).mean(axis=1)
    return means.std(axis=0, ddof=1) / np.sqrt(batches)


@pytest.mark.filterwarnings("ignore")
def test_geweke_gmm_mode():
    rng = np.random.default_rng(2024)
    n_marginal, n_chain = 20000, 10000
    marginal = np.array([joint_statistics(*draw_joint(rng)) for _ in range(n_marginal)])

    est = estimator()
    priors = Priors.build(HYPER.resized(L, K), K, L, V, None)
    places, concepts, X, words = draw_joint(rng)
    chain = np.empty((n_chain, marginal.shape[1]))
    for t in range(n_chain):
        obs = Observations(X=X, words=words, vocabulary=VOCABULARY)
        sampler = CollapsedConceptSampler(words, None, False, rng)
        places, concepts = sweep(est, obs, priors, sampler, places, concepts, rng)
        chain[t] = joint_statistics(places, concepts, X, words)  # new assignments, the data they were drawn for
        X, words = draw_data(rng, places, concepts)

    se = np.sqrt(marginal.var(axis=0, ddof=1) / n_marginal + batch_means_se(chain) ** 2)
    z = (chain.mean(axis=0) - marginal.mean(axis=0)) / se
    # 8 test functions, each |z| < 3.5: a family-wise false alarm rate below 0.4 % for a correct sampler
    assert np.all(np.abs(z) < 3.5), f"z = {np.round(z, 2)}, means {chain.mean(axis=0)} vs {marginal.mean(axis=0)}"

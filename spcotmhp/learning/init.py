"""Initial assignments for the Gibbs sampler."""

from __future__ import annotations

import numpy as np

from spcotmhp.learning.observations import Observations

INITS = ("kmeans", "keyword", "random")


def kmeans_places(X: np.ndarray, K: int, rng: np.random.Generator, iterations: int = 10) -> np.ndarray:
    """k-means++ seeding and a few Lloyd iterations on the positions: an over-segmentation into min(K, E)
    clusters that the sampler then merges."""
    E = len(X)
    k = min(K, E)
    centres = [X[rng.integers(E)]]
    d2 = np.sum((X - centres[0]) ** 2, axis=1)
    for _ in range(1, k):
        p = d2 / d2.sum() if d2.sum() > 0 else np.full(E, 1.0 / E)
        centres.append(X[rng.choice(E, p=p)])
        d2 = np.minimum(d2, np.sum((X - centres[-1]) ** 2, axis=1))
    C = np.array(centres)
    for _ in range(iterations):
        z = np.argmin(((X[:, None, :] - C[None]) ** 2).sum(-1), axis=1)
        for j in range(k):
            if np.any(z == j):
                C[j] = X[z == j].mean(axis=0)
    return np.argmin(((X[:, None, :] - C[None]) ** 2).sum(-1), axis=1)


def keyword_concepts(words: np.ndarray, L: int, rng: np.random.Generator) -> np.ndarray:
    """Each event starts in the concept of its rarest word (fewest events use it): place names are rarer than
    the phrases around them.  Keywords beyond L share concepts at random; events without words are random."""
    df = (words > 0).sum(axis=0).astype(float)
    E = words.shape[0]
    key = np.full(E, -1)
    for e in range(E):
        nz = np.flatnonzero(words[e])
        if nz.size:
            best = nz[df[nz] == df[nz].min()]
            key[e] = rng.choice(best)
    keys = np.unique(key[key >= 0])
    keys = keys[np.argsort(-df[keys], kind="stable")]
    concept_of = {int(w): (j if j < L else int(rng.integers(L))) for j, w in enumerate(keys)}
    return np.array([concept_of[int(w)] if w >= 0 else int(rng.integers(L)) for w in key])


def initial_assignments(
    obs: Observations, K: int, L: int, how: str, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """(places, concepts) to start from: "kmeans" (over-segmented places, random concepts), "keyword" (the
    same places, concepts from each utterance's rarest word) or "random" (both uniform)."""
    if how == "random":
        return rng.integers(K, size=obs.E), rng.integers(L, size=obs.E)
    if how == "kmeans":
        return kmeans_places(obs.X, K, rng), rng.integers(L, size=obs.E)
    if how == "keyword":
        return kmeans_places(obs.X, K, rng), keyword_concepts(obs.words, L, rng)
    raise ValueError(f"init must be one of {INITS}, got {how!r}")

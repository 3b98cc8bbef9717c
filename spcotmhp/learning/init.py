"""How a Gibbs run starts: its random stream (``make_rng``, shared by the batch and online learners), its
initial assignments, and the hooks a research variant starts it with (:class:`SweepVariant`, gibbs.py)."""

from __future__ import annotations

from typing import Protocol

import numpy as np
from numba import njit

from spcotmhp.errors import ModelError
from spcotmhp.learning.concepts import CollapsedConceptSampler, ConceptTerm
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.observations import Observations
from spcotmhp.learning.posterior import SufficientStats
from spcotmhp.limits import is_count

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
    C = np.array(centres, dtype=float)
    X = np.ascontiguousarray(X, dtype=float)
    for _ in range(iterations):
        _lloyd_means(X, _nearest(X, C), C)
    return _nearest(X, C)


@njit(cache=True)
def _nearest(X, C):  # pragma: no cover - numba
    """The nearest centre of every point (squared distance dx^2 + dy^2, first on ties): the numbers of
    ``np.argmin(((X[:, None, :] - C[None]) ** 2).sum(-1), axis=1)`` without the (E, k, 2) table."""
    z = np.empty(X.shape[0], dtype=np.int64)
    for e in range(X.shape[0]):
        best, arg = np.inf, 0
        for j in range(C.shape[0]):
            dx, dy = X[e, 0] - C[j, 0], X[e, 1] - C[j, 1]
            d = dx * dx + dy * dy
            if d < best:
                best, arg = d, j
        z[e] = arg
    return z


@njit(cache=True)
def _lloyd_means(X, z, C):  # pragma: no cover - numba
    """Every centre with points moves to their mean (summed in order, then divided: what ``X[z == j].mean(0)``
    gives); centres without points stay."""
    total = np.zeros(C.shape)
    n = np.zeros(C.shape[0])
    for e in range(X.shape[0]):
        total[z[e], 0] += X[e, 0]
        total[z[e], 1] += X[e, 1]
        n[z[e]] += 1.0
    for j in range(C.shape[0]):
        if n[j] > 0:
            C[j, 0] = total[j, 0] / n[j]
            C[j, 1] = total[j, 1] / n[j]


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


def make_rng(seed: int | np.random.SeedSequence, run: int | None = None) -> np.random.Generator:
    """The generator of one run: run r of seed s uses the r-th child of SeedSequence(s) (what
    ``SeedSequence(s).spawn`` would give), independent of the others; ``run=None`` uses the seed itself.
    Raises ModelError for a seed or run that is not a non-negative integer."""
    if not isinstance(seed, np.random.SeedSequence) and not (is_count(seed) and seed >= 0):
        raise ModelError(f"seed must be a non-negative integer (or a numpy SeedSequence), got {seed!r}")
    if run is not None and not (is_count(run) and run >= 0):
        raise ModelError(f"run must be a non-negative integer or None, got {run!r}")
    ss = seed if isinstance(seed, np.random.SeedSequence) else np.random.SeedSequence(int(seed))
    if run is not None:
        ss = np.random.SeedSequence(ss.entropy, spawn_key=tuple(ss.spawn_key) + (int(run),))
    return np.random.default_rng(ss)


def seed_repr(seed: int | np.random.SeedSequence) -> int | str:
    return int(seed) if not isinstance(seed, np.random.SeedSequence) else str(seed.entropy)


class VariantRun:
    """The hooks of one fit of a research variant (``SweepVariant.start``); these defaults leave every step the
    paper's and draw nothing, a variant overrides the ones it changes.  ``term_from``: the fraction of the sweeps
    before its term enters (``SpCoTMHP(term_from=None)``; None: half); ``concept_term``, ``places``: step 5's
    extra log-term and step 4's places kept given the FFBS draw, while the term is on; ``concepts``: after
    step 5's Gibbs pass, every sweep; ``log_terms``: added to the collapsed log joint; ``info``: to model.info."""

    term_from: float | None = None
    concept_term: ConceptTerm | None = None

    def places(
        self, old: np.ndarray, proposal: np.ndarray, concepts: np.ndarray, rng: np.random.Generator
    ) -> np.ndarray:
        return proposal

    def concepts(self, concepts: np.ndarray, places: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        return concepts

    def log_terms(self, stats: SufficientStats) -> dict[str, float]:
        return {}

    def info(self) -> dict:
        return {}


class SweepVariant(Protocol):
    """A research variant of the sampler (spcotmhp.experimental).  A setting like any other: copied to every run
    of ``MultiRunSelector`` and pickled to its workers, so it keeps no state; ``start`` gives one fit's hooks
    (raising ModelError for settings it cannot price)."""

    def start(
        self, sampler: CollapsedConceptSampler, hyper: Hyperparameters, K: int, L: int, features: bool
    ) -> VariantRun: ...

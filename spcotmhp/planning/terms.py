"""The model terms that online planning evaluates per query, with their logarithms taken once.

The model's own terms (:mod:`spcotmhp.learning.model`: Eq. 28's word term :func:`~spcotmhp.learning.model.
log_word_term` and its normalisation, the place prior and the unigram-rescaling denominator), with log pi,
log phi, log W, the place prior and the Gaussians' closed-form 2 x 2 inverses computed once per model, and the
per-query arithmetic in compiled kernels (the Gaussian of :func:`~spcotmhp.logspace.gaussian_log_density`, the
package's ``logsumexp``), so that a query costs a few microseconds.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numba import njit

from spcotmhp.learning.model import SpatialConceptModel, bag_indices, log_word_term, normalise_places
from spcotmhp.logspace import gaussian_log_density, logsumexp_vector


class ModelTerms:
    """Log terms of Eq. 28 for one model."""

    def __init__(self, model: SpatialConceptModel) -> None:
        self.model = model
        self._log_W0, self._finite_W, self.log_pi, self.log_phi = model.word_arrays()
        with np.errstate(divide="ignore"):
            self.log_psi = np.log(model.psi)
        self.active = np.asarray(model.active_places, dtype=bool)
        self.log_prior = model.log_place_prior()
        self.log_ur = model.log_unigram_rescaling()
        self.word_index = model.word_index
        self._mu = np.ascontiguousarray(model.mu, dtype=np.float64)
        self._Sigma = np.ascontiguousarray(model.Sigma, dtype=np.float64)
        self._psi = np.ascontiguousarray(model.psi, dtype=np.float64)

    def place_posterior(self, x: np.ndarray) -> np.ndarray:
        """p(i_0 = k | x_0) over places (K,) for one point (Eq. 3 with the place prior)."""
        x = np.asarray(x, dtype=float)
        return _posterior(float(x[0]), float(x[1]), self._mu, self._Sigma, self.log_prior)

    def bag_indices(self, bag: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """The bag as (vocabulary indices, weights) of its known words (:func:`~spcotmhp.learning.model.
        bag_indices`; words outside the vocabulary are dropped)."""
        return bag_indices(bag, self.word_index)

    def log_semantic(self, bag: Mapping[str, float]) -> np.ndarray:
        """Eq. 28's word term log sum_C Mult(i | phi_C) Mult(S | W_C) Mult(C | pi) for every place (K,)
        (:func:`~spcotmhp.learning.model.log_word_term`)."""
        idx, weight = self.bag_indices(bag)
        return log_word_term(idx, weight, self._log_W0, self._finite_W, self.log_pi, self.log_phi)

    def normalise(self, log_semantic: np.ndarray) -> np.ndarray:
        """log p(i | S) over active places from :meth:`log_semantic`'s output (K,)."""
        return normalise_places(log_semantic, self.active)

    def log_place_given_words(self, bag: Mapping[str, float]) -> np.ndarray:
        """log p(i | S) over active places, normalised (K,)."""
        return self.normalise(self.log_semantic(bag))

    def start_terms(self, posterior: np.ndarray, places: np.ndarray, plus: np.ndarray | None = None) -> np.ndarray:
        """log sum_k p(i_0 = k | x_0) psi[k, i] - log sum_c phi_c(i) for the place i of each node (``places``):
        the first step's transition term of Eq. 28 with i_0 marginalised; ``plus`` (one value per node, e.g. the
        start legs' w-hat) is added, in the same kernel."""
        plus = np.zeros(len(places)) if plus is None else plus
        return _start_terms(posterior, self._psi, places, self.log_ur, plus)

    def stage_terms(self, bags: Sequence[Mapping[str, float]], ratio: float) -> tuple[np.ndarray, np.ndarray]:
        """For the bags S_1..S_n of an instruction's stages, in one kernel: (n, K) :meth:`log_semantic` of each
        and (n, K) bool, the places whose p(i | S) is within ``ratio`` of the best
        (:func:`~spcotmhp.planning.places.instance_places` of :meth:`log_place_given_words`)."""
        if ratio < 1.0:
            raise ValueError(f"instance_ratio must be >= 1, got {ratio!r}")
        index, idx, weight, offsets = self.word_index, [], [], [0]
        for bag in bags:
            for w, c in bag.items():
                if w in index:
                    idx.append(index[w])
                    weight.append(float(c))
            offsets.append(len(idx))
        return _stage_terms(
            np.array(idx, dtype=np.int64),
            np.array(weight, dtype=np.float64),
            np.array(offsets, dtype=np.int64),
            self._log_W0,
            self._finite_W,
            self.log_pi,
            self.log_phi,
            self.active,
            np.log(ratio),
        )


@njit(cache=True)
def _posterior(x, y, mu, Sigma, log_prior):  # pragma: no cover - numba
    """p(k | x) proportional to N(x | mu_k, Sigma_k) p(k) (log_gaussian's closed form, then normalised)."""
    K = mu.shape[0]
    lp = np.empty(K)
    for k in range(K):
        a, b, c, d = Sigma[k, 0, 0], Sigma[k, 0, 1], Sigma[k, 1, 0], Sigma[k, 1, 1]
        det = a * d - b * c
        if det <= 0:
            raise ValueError("a place covariance is not positive definite")
        dx = x - mu[k, 0]
        dy = y - mu[k, 1]
        lp[k] = gaussian_log_density(dx, dy, a, b + c, d, det, np.log(det)) + log_prior[k]
    return np.exp(lp - logsumexp_vector(lp))


@njit(cache=True)
def _start_terms(posterior, psi, places, log_ur, plus):  # pragma: no cover - numba
    out = np.empty(places.shape[0])
    for j in range(places.shape[0]):
        i = places[j]
        total = 0.0
        for k in range(posterior.shape[0]):
            total += posterior[k] * psi[k, i]
        out[j] = (np.log(total) - log_ur[i]) + plus[j]
    return out


@njit(cache=True)
def _stage_terms(idx, weight, offsets, log_W0, finite_W, log_pi, log_phi, active, log_ratio):  # pragma: no cover
    """:meth:`ModelTerms.stage_terms` for the bags ``idx[offsets[s]:offsets[s + 1]]`` (with their weights)."""
    n = offsets.shape[0] - 1
    K = log_phi.shape[1]
    semantic = np.empty((n, K))
    inst = np.zeros((n, K), np.bool_)
    for s in range(n):
        a, b = offsets[s], offsets[s + 1]
        semantic[s] = log_word_term(idx[a:b], weight[a:b], log_W0, finite_W, log_pi, log_phi)
        lp = normalise_places(semantic[s], active)
        best = lp.max()
        for k in range(K):
            inst[s, k] = np.isfinite(lp[k]) and lp[k] >= best - log_ratio
    return semantic, inst

"""The model terms that online planning evaluates per query, with their logarithms taken once.

The same quantities as :class:`~spcotmhp.learning.model.SpatialConceptModel`'s methods (``place_posterior``,
``log_semantic``, ``log_place_given_words``; tests check they agree), with log pi, log phi, log W, the place
prior and the Gaussians' closed-form 2 x 2 inverses precomputed, and the per-query arithmetic in compiled
kernels (the same formulas as :func:`~spcotmhp.logspace.log_gaussian`,
:func:`~spcotmhp.learning.model.log_multinomial` and the package's ``logsumexp``), so that a query costs a few
microseconds.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
from numba import njit

from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.logspace import gaussian_log_density, logsumexp_vector
from spcotmhp.logspace import logsumexp as _lse


class ModelTerms:
    """Log terms of Eq. 28 for one model."""

    def __init__(self, model: SpatialConceptModel) -> None:
        self.model = model
        with np.errstate(divide="ignore"):
            self.log_pi = np.log(model.pi)
            self.log_phi = np.log(model.phi)
            self.log_W = np.log(model.W)
            self.log_psi = np.log(model.psi)
        self.active = np.asarray(model.active_places, dtype=bool)
        self.log_prior = np.where(self.active, _lse(self.log_pi[:, None] + self.log_phi, axis=0), -np.inf)
        self.log_ur = _lse(self.log_phi, axis=0)
        self.word_index = model.word_index
        self._finite_W = np.isfinite(self.log_W)
        self._log_W0 = np.ascontiguousarray(np.where(self._finite_W, self.log_W, 0.0))
        self._mu = np.ascontiguousarray(model.mu, dtype=np.float64)
        self._Sigma = np.ascontiguousarray(model.Sigma, dtype=np.float64)
        self._psi = np.ascontiguousarray(model.psi, dtype=np.float64)

    def place_posterior(self, x: np.ndarray) -> np.ndarray:
        """p(i_0 = k | x_0) over places (K,) for one point (Eq. 3 with the place prior)."""
        x = np.asarray(x, dtype=float)
        return _posterior(float(x[0]), float(x[1]), self._mu, self._Sigma, self.log_prior)

    def bag_indices(self, bag: Mapping[str, float]) -> tuple[np.ndarray, np.ndarray]:
        """The bag as (vocabulary indices, weights) of its known words (the model's ``bag_vector`` without the
        zeros; words outside the vocabulary are dropped)."""
        index = self.word_index
        known = [(index[w], float(c)) for w, c in bag.items() if w in index]
        return np.array([i for i, _ in known], dtype=np.int64), np.array([c for _, c in known], dtype=np.float64)

    def log_semantic(self, bag: Mapping[str, float]) -> np.ndarray:
        """log sum_C Mult(i | phi_C) Mult(S | W_C) Mult(C | pi) for every place (K,) (Eq. 28, last factor)."""
        idx, weight = self.bag_indices(bag)
        return _semantic(idx, weight, self._log_W0, self._finite_W, self.log_pi, self.log_phi)

    def normalise(self, log_semantic: np.ndarray) -> np.ndarray:
        """log p(i | S) over active places from :meth:`log_semantic`'s output (K,)."""
        return _normalise(log_semantic, self.active)

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
def _semantic(idx, weight, log_W0, finite_W, log_pi, log_phi):  # pragma: no cover - numba
    """log sum_C phi_C(i) W_C(S) pi_C for every place i: log Mult(S | W_C) as sum_w n_w log W_C(w) (-inf when a
    word of S has W_C(w) = 0), plus log pi_C, then log-sum-exp over C with log phi_C(i)."""
    L, K = log_phi.shape
    lw = np.empty(L)
    for c in range(L):
        total = 0.0
        for j in range(idx.shape[0]):
            if weight[j] > 0 and not finite_W[c, idx[j]]:
                total = -np.inf
                break
            total += weight[j] * log_W0[c, idx[j]]
        lw[c] = total + log_pi[c]
    out = np.empty(K)
    col = np.empty(L)
    for i in range(K):
        for c in range(L):
            col[c] = lw[c] + log_phi[c, i]
        out[i] = logsumexp_vector(col)
    return out


@njit(cache=True)
def _normalise(log_semantic, active):  # pragma: no cover - numba
    ls = np.where(active, log_semantic, -np.inf)
    return ls - logsumexp_vector(ls)


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
        semantic[s] = _semantic(idx[a:b], weight[a:b], log_W0, finite_W, log_pi, log_phi)
        lp = _normalise(semantic[s], active)
        best = lp.max()
        for k in range(K):
            inst[s, k] = np.isfinite(lp[k]) and lp[k] >= best - log_ratio
    return semantic, inst

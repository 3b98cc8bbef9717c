"""The model terms that online planning evaluates per query, with their logarithms taken once.

The same quantities as :class:`~spcotmhp.learning.model.SpatialConceptModel`'s methods (``place_posterior``,
``log_semantic``, ``log_place_given_words``; tests check they agree), built from the same functions
(:func:`~spcotmhp.learning.model.log_multinomial`, the package's one ``logsumexp``), with log pi, log phi,
log W and the place prior precomputed so that a query costs microseconds.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from spcotmhp.learning.logspace import logsumexp as _lse
from spcotmhp.learning.model import SpatialConceptModel, bag_counts, log_gaussian, log_multinomial


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

    def place_posterior(self, x: np.ndarray) -> np.ndarray:
        """p(i_0 = k | x_0) over places (K,) for one point (Eq. 3 with the place prior)."""
        lp = log_gaussian(np.asarray(x, dtype=float), self.model.mu, self.model.Sigma) + self.log_prior
        return np.exp(lp - _lse(lp, axis=-1))

    def bag_vector(self, bag: Mapping[str, float]) -> np.ndarray:
        """The bag as a count vector over the vocabulary (the model's ``bag_vector``, with the word index
        built once)."""
        return bag_counts(bag, self.word_index, len(self.word_index))

    def log_semantic(self, bag: Mapping[str, float]) -> np.ndarray:
        """log sum_C Mult(i | phi_C) Mult(S | W_C) Mult(C | pi) for every place (K,) (Eq. 28, last factor)."""
        lw = log_multinomial(self.log_W, self.bag_vector(bag)) + self.log_pi
        return _lse(lw[:, None] + self.log_phi, axis=0)

    def normalise(self, log_semantic: np.ndarray) -> np.ndarray:
        """log p(i | S) over active places from :meth:`log_semantic`'s output (K,)."""
        ls = np.where(self.active, log_semantic, -np.inf)
        return ls - _lse(ls, axis=0)

    def log_place_given_words(self, bag: Mapping[str, float]) -> np.ndarray:
        """log p(i | S) over active places, normalised (K,)."""
        return self.normalise(self.log_semantic(bag))

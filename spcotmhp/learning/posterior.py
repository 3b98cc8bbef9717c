"""Sufficient statistics of an assignment (i_{1:E}, C_{1:E}), the posterior-mean model they imply, and the
collapsed log joint probability used to compare runs.

Saturated weak-limit truncations: when every place (or concept) component of a learned model holds events, K (or
L) may be too small for the home (Johnson and Willsky 2013's truncation is then no longer loose).
:func:`record_truncation` lists them in ``model.info["truncation_saturated"]`` and warns
(:class:`TruncationWarning`); :func:`truncation_messages` words them for the command line.

Shared by the Gibbs sampler (final estimate, run selection) and the supervised fit (truth assignments).
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numba import njit

from spcotmhp.learning.distributions import DirichletCategoricals, GaussianStats, NIWGaussians
from spcotmhp.learning.model import Hyperparameters, SpatialConceptModel
from spcotmhp.learning.observations import Observations
from spcotmhp.logspace import logsumexp


@dataclass
class SufficientStats:
    """Counts behind every conditional of Eqs. 5-17 for one assignment.

    gauss: place statistics of the positions; concepts (L,): events per concept (pi);
    place_given_concept (L, K): events per (concept, place) (phi); features (L, D) or None: summed feature
    counts per concept (theta); words (L, V): summed word counts per concept (W).
    """

    gauss: GaussianStats
    concepts: np.ndarray
    place_given_concept: np.ndarray
    features: np.ndarray | None
    words: np.ndarray
    background: np.ndarray | None = None

    @classmethod
    def from_assignments(
        cls,
        obs: Observations,
        places: np.ndarray,
        concepts: np.ndarray,
        K: int,
        L: int,
        concept_words: np.ndarray | None = None,
        background: np.ndarray | None = None,
    ) -> SufficientStats:
        """Counts of one assignment; ``concept_words`` (E, V) are the word counts of each event explained by its
        concept (default: all of them) and ``background`` (V,) the counts of background tokens, if any."""
        onehot_i = np.zeros((obs.E, K))
        onehot_i[np.arange(obs.E), places] = 1.0
        n = onehot_i.sum(axis=0)
        sx = onehot_i.T @ obs.X
        sxx = (onehot_i.T @ (obs.X[:, :, None] * obs.X[:, None, :]).reshape(obs.E, 4)).reshape(K, 2, 2)
        # counts by scatter-add rather than (E, L) x (E, K) products (the same numbers for integer counts)
        place_given_concept = np.zeros((L, K))
        np.add.at(place_given_concept, (concepts, places), 1.0)
        words = np.zeros((L, obs.words.shape[1]))
        _add_rows(words, np.asarray(concepts, dtype=np.int64), obs.words if concept_words is None else concept_words)
        features = None
        if obs.features is not None:
            onehot_c = np.zeros((obs.E, L))
            onehot_c[np.arange(obs.E), concepts] = 1.0
            features = onehot_c.T @ obs.features
        return cls(
            gauss=GaussianStats(n, sx, sxx),
            concepts=np.bincount(concepts, minlength=L).astype(float),
            place_given_concept=place_given_concept,
            features=features,
            words=words,
            background=background,
        )


@njit(cache=True)
def _add_rows(out, rows, M):  # pragma: no cover - numba
    """out[rows[e]] += M[e] for e = 0, 1, ... in order: ``np.add.at(out, rows, M)``, the same sums in the same
    order, without its per-element dispatch."""
    for e in range(rows.shape[0]):
        for v in range(M.shape[1]):
            out[rows[e], v] += M[e, v]


@dataclass
class Priors:
    """The conjugate prior objects of one model size (K places, L concepts, V words, D features)."""

    gauss: NIWGaussians
    pi: DirichletCategoricals
    phi: DirichletCategoricals
    theta: DirichletCategoricals | None
    W: DirichletCategoricals
    psi: DirichletCategoricals
    background: DirichletCategoricals
    switch: DirichletCategoricals
    place_concepts: DirichletCategoricals | None = None  # eta_i, K rows over L concepts (opt-in, not the paper's)

    @classmethod
    def build(cls, hyper: Hyperparameters, K: int, L: int, V: int, D: int | None) -> Priors:
        eta = hyper.place_concepts
        return cls(
            gauss=NIWGaussians(K, np.asarray(hyper.m0), hyper.kappa0, np.asarray(hyper.V0), hyper.nu0),
            pi=DirichletCategoricals(1, L, hyper.alpha),
            phi=DirichletCategoricals(L, K, hyper.gamma),
            theta=None if D is None else DirichletCategoricals(L, D, hyper.chi),
            W=DirichletCategoricals(L, V, hyper.beta),
            psi=DirichletCategoricals(K, K, hyper.omega),
            background=DirichletCategoricals(1, V, hyper.beta),
            switch=DirichletCategoricals(1, 2, 1.0),
            place_concepts=None if eta is None else DirichletCategoricals(K, L, eta / L),
        )


def posterior_mean_model(
    priors: Priors,
    stats: SufficientStats,
    transitions: np.ndarray | None,
    vocabulary: list[str],
    hyper: Hyperparameters,
    info: dict | None = None,
    psi: np.ndarray | None = None,
) -> SpatialConceptModel:
    """The model Theta' whose every parameter is its posterior mean given ``stats`` (and transition counts).

    ``transitions`` (K, K) are the counts behind psi (None: uniform psi, the GMM/SpCoSLAM mode); ``psi`` given
    explicitly overrides them (e.g. from an adjacency).  Active components are those holding events.
    """
    mu, Sigma = priors.gauss.posterior_mean(stats.gauss)
    K = mu.shape[0]
    if psi is None:
        psi = np.full((K, K), 1.0 / K) if transitions is None else priors.psi.posterior_mean(transitions)
    W = priors.W.posterior_mean(stats.words)
    if stats.background is not None:  # p(w | l) = lambda W_l(w) + (1 - lambda) W_0(w)
        lam = priors.switch.posterior_mean(np.array([[stats.background.sum(), stats.words.sum()]]))[0, 1]
        W = lam * W + (1.0 - lam) * priors.background.posterior_mean(stats.background[None, :])
    return SpatialConceptModel(
        mu=mu,
        Sigma=Sigma,
        psi=psi,
        pi=priors.pi.posterior_mean(stats.concepts[None, :])[0],
        phi=priors.phi.posterior_mean(stats.place_given_concept),
        W=W,
        vocabulary=list(vocabulary),
        theta=None if priors.theta is None or stats.features is None else priors.theta.posterior_mean(stats.features),
        active_places=stats.gauss.n > 0,
        active_concepts=stats.concepts > 0,
        hyper=hyper,
        info=dict(info or {}),
    )


def log_place_prior(priors: Priors, stats: SufficientStats) -> np.ndarray:
    """log p(k) = log sum_l pi_l phi_l(k) with pi and phi the posterior means given ``stats``, -inf on places
    without events: (K,).  Equal to ``log_place_prior()`` of the ``posterior_mean_model`` of the same stats."""
    log_pi = np.log(priors.pi.posterior_mean(stats.concepts[None, :])[0])
    log_phi = np.log(priors.phi.posterior_mean(stats.place_given_concept))
    lp = logsumexp(log_pi[:, None] + log_phi, axis=0)
    return np.where(stats.gauss.n > 0, lp, -np.inf)


ExtraTerms = Callable[[SufficientStats], dict[str, float]]
"""A research variant's terms of the log joint, by name, given the counts (spcotmhp.experimental)."""


def log_joint(
    priors: Priors, stats: SufficientStats, transitions: np.ndarray | None, extra: ExtraTerms | None = None
) -> float:
    """Collapsed log joint log p(x, S, f, i, C | h) with every parameter integrated out: the sum of
    ``log_joint_terms``.  Deterministic given an assignment, so it ranks runs without the noise of the last
    parameter draw."""
    return float(sum(log_joint_terms(priors, stats, transitions, extra).values()))


def log_joint_terms(
    priors: Priors, stats: SufficientStats, transitions: np.ndarray | None, extra: ExtraTerms | None = None
) -> dict[str, float]:
    """The terms of the collapsed log joint, by the parameter integrated out: "positions" (the NIW marginal of
    the positions per place, Eqs. 5-6), "pi" (C), "phi" (i given C), "W" (the concept words), "theta" (f, when
    there are features), "psi" (the place transitions, unless ``transitions`` is None), "background" (the
    background words and the switches, when kept), "place_concepts" (with ``Hyperparameters.place_concepts``
    = eta: sum_i log DirMult(n_{i,.} | eta / L) over the concepts of each place's events, a term the paper's
    model does not have); Dirichlet-multinomial marginals but the first; then ``extra(stats)``, a research
    variant's terms (e.g. "off_name", spcotmhp.experimental.off_name).

    Eq. 9 combines psi and phi as a product of experts; here both enter as their own multinomial terms (the
    normaliser of the product is not part of the comparison)."""
    terms = {
        "positions": priors.gauss.log_marginal(stats.gauss),
        "pi": priors.pi.log_marginal(stats.concepts[None, :]),
        "phi": priors.phi.log_marginal(stats.place_given_concept),
        "W": priors.W.log_marginal(stats.words),
    }
    if priors.theta is not None and stats.features is not None:
        terms["theta"] = priors.theta.log_marginal(stats.features)
    if transitions is not None:
        terms["psi"] = priors.psi.log_marginal(transitions)
    if stats.background is not None:
        terms["background"] = priors.background.log_marginal(stats.background[None, :]) + priors.switch.log_marginal(
            np.array([[stats.background.sum(), stats.words.sum()]])
        )
    if priors.place_concepts is not None:
        terms["place_concepts"] = priors.place_concepts.log_marginal(stats.place_given_concept.T)
    if extra is not None:
        terms.update(extra(stats))
    return terms


def mutual_information(pi: np.ndarray, W: np.ndarray) -> float:
    """I(C; S) = sum_l sum_w p(l) W_l(w) log(W_l(w) / p(w)) with p(w) = sum_l p(l) W_l(w): the word-concept
    mutual information the authors used to choose among runs (SpCoSLAM)."""
    pw = pi @ W
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = pi[:, None] * W * (np.log(W) - np.log(pw)[None, :])
    return float(np.nansum(terms))


class TruncationWarning(UserWarning):
    """Every place (or concept) component of the weak-limit truncation holds events: K (or L) may be too small."""


def record_truncation(model: SpatialConceptModel, K: int, L: int) -> None:
    """List the saturated truncations ("places" when all K place components hold events, "concepts" when all L
    concept components do) in ``model.info["truncation_saturated"]`` and warn about each (TruncationWarning,
    attributed to the caller's caller: the code that called ``fit``)."""
    full = [
        what
        for what, used, cap in (
            ("places", model.active_places.sum(), K),
            ("concepts", model.active_concepts.sum(), L),
        )
        if used >= cap
    ]
    model.info["truncation_saturated"] = full
    for message in truncation_messages(model):
        warnings.warn(message, TruncationWarning, stacklevel=3)


def truncation_messages(model: SpatialConceptModel) -> list[str]:
    """One sentence per saturated truncation listed in ``model.info["truncation_saturated"]``."""
    hint = {
        "places": ("place", "K", model.K, "--max-places", "SpCoTMHP(K=...)"),
        "concepts": ("concept", "L", model.L, "--max-concepts", "SpCoTMHP(L=...)"),
    }
    out = []
    for what in model.info.get("truncation_saturated", []):
        noun, symbol, size, option, api = hint[what]
        out.append(
            f"all {symbol} = {size} {noun} components hold events (the weak-limit truncation is "
            f"saturated, so {what} may have been merged): learn again with a larger {option} ({api})"
        )
    return out

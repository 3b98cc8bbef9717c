"""The opt-in "off-name" term (``Hyperparameters.off_name`` = lambda), a DEPARTURE from the paper and a research
variant (docs/experimental.md; measured in docs/learning-model-study.md, section 9, and not adopted): a place is
expected to hold one name, and every event whose concept is not its place's majority concept costs lambda nats.
``SpCoTMHP(hyper=Hyperparameters(off_name=lam), variant=OffName())`` fits with it.

The joint of Eqs. 5-17 gains the energy factor g(i, C) with

    log g(i, C) = -lambda * sum_i (n_i - max_l n_{i,l})

where n_{i,l} counts the events at place i with concept l and n_i = sum_l n_{i,l}.  Empty places and places of
one concept cost 0, so splitting a place is never priced (unlike the per-place Dirichlet-multinomial of
``Hyperparameters.place_concepts``, which charges each place once for choosing its concept).  A tie in the max
does not matter: the value is the same whichever concept is called the majority.  g is not normalised over
(i, C); like Eq. 9's unigram rescaling it is a factor of an unnormalised target.

This module is the term's one home:

* :func:`off_name_events` and :func:`log_off_name` — the count and log g of an assignment, which the collapsed
  log joint carries (the ``extra`` terms of ``posterior.log_joint_terms``, so run selection sees it);
* :func:`add_off_name_gain` — step 5 (a ``ConceptTerm``, learning/concepts.py, compiled): the conditional of C_e = l
  gains the change of log g when e's concept is set to l, counts without e. With M = max_l' n_{i_e,l'} (without e),
  setting C_e = l gives n_{i_e} + 1 - max(M, n_{i_e,l} + 1) off-name events at place i_e, so l gains lambda exactly
  when n_{i_e,l} = M (a concept tied for the majority; every concept when the place holds no other event) and 0
  otherwise; the other places do not change;
* :class:`OffNamePlaces` — step 4 (``VariantRun.places``, learning/gibbs.py): g couples the events of a place, so
  the FFBS of Eq. 9 is no longer the exact conditional of the place sequence. The FFBS (the paper's exact
  conditional without g) becomes the proposal of an independence Metropolis-Hastings step for the target conditional
  x g: the proposed sequence i' is accepted with probability min(1, g(i', C) / g(i, C)), the proposal's own density
  cancelling against the target's (one block: the FFBS draws the whole event sequence at once). One uniform from the
  run's stream per step; the acceptance rate is kept.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from spcotmhp.errors import ModelError
from spcotmhp.learning.concepts import CollapsedConceptSampler, ConceptTerm
from spcotmhp.learning.init import VariantRun
from spcotmhp.learning.model import Hyperparameters
from spcotmhp.learning.posterior import SufficientStats

# The fraction of the sweeps before the term enters the sampler (``SpCoTMHP(term_from=None)``): none.  Chosen on
# four development homes of the battery (21, 42, 0, 5) before the rest were run: from the first sweep they planned
# at via 0.986, 0.990, 0.886, 0.990; from half the sweeps at 0.988, 0.709, 0.984, 0.988 (docs/learning-model-study.md,
# section 9, which also records what it costs in the runs' own ARI).
OFF_NAME_FROM = 0.0


def off_name_events(places: np.ndarray, concepts: np.ndarray, K: int, L: int) -> int:
    """sum_i (n_i - max_l n_{i,l}): the events whose concept is not their place's majority concept."""
    n_lk = np.zeros((L, K), dtype=np.int64)
    np.add.at(n_lk, (np.asarray(concepts, dtype=np.int64), np.asarray(places, dtype=np.int64)), 1)
    return off_name_of_counts(n_lk)


def off_name_of_counts(place_given_concept: np.ndarray) -> int:
    """The off-name count of the (L, K) events per (concept, place)."""
    n = np.asarray(place_given_concept)
    return int(round(float(n.sum() - n.max(axis=0).sum()))) if n.size else 0


def log_off_name(lam: float, place_given_concept: np.ndarray) -> float:
    """log g = -lambda times the off-name count of the (L, K) events per (concept, place)."""
    return -float(lam) * off_name_of_counts(place_given_concept)


@njit(cache=True)
def add_off_name_gain(lam, n_lk, k, logp):  # pragma: no cover - numba
    """Step 5's change of log g (module docstring): adds ``lam`` to ``logp[l]`` for every concept l tied for the
    majority of place k in ``n_lk`` (L, K), the counts without the event being resampled.  No allocation."""
    m = 0.0
    for l in range(n_lk.shape[0]):
        if n_lk[l, k] > m:
            m = n_lk[l, k]
    for l in range(n_lk.shape[0]):
        if n_lk[l, k] == m:
            logp[l] += lam


@dataclass(frozen=True)
class OffName:
    """The off-name term as a variant of the batch sampler (``gibbs.SweepVariant``): lambda is
    ``hyper.off_name`` (kept with the model's priors)."""

    def start(
        self, sampler: CollapsedConceptSampler, hyper: Hyperparameters, K: int, L: int, features: bool
    ) -> OffNamePlaces:
        if hyper.off_name is None:
            raise ModelError("the off-name variant needs hyper.off_name (lambda, nats per off-name event)")
        return OffNamePlaces(hyper.off_name, K, L)


class OffNamePlaces(VariantRun):
    """One fit's hooks (``gibbs.VariantRun``): step 4 with the term, the independence Metropolis-Hastings
    correction of the FFBS proposal (module docstring), with its acceptance counts; step 5's gain; log g in the
    log joint."""

    term_from = OFF_NAME_FROM

    def __init__(self, lam: float, K: int, L: int) -> None:
        self.lam, self.K, self.L = float(lam), K, L
        self.proposed = 0
        self.accepted = 0
        self.concept_term = ConceptTerm(add_off_name_gain, self.lam)

    def places(
        self, old: np.ndarray, proposal: np.ndarray, concepts: np.ndarray, rng: np.random.Generator
    ) -> np.ndarray:
        return self.step(old, proposal, concepts, rng)

    def log_terms(self, stats: SufficientStats) -> dict[str, float]:
        """log g of the counts (``posterior.log_joint``'s ``extra``)."""
        return {"off_name": log_off_name(self.lam, stats.place_given_concept)}

    def info(self) -> dict:
        return {"off_name_acceptance": self.acceptance}

    def log_ratio(self, old: np.ndarray, new: np.ndarray, concepts: np.ndarray) -> float:
        """log g(new, C) - log g(old, C)."""
        before = off_name_events(old, concepts, self.K, self.L)
        after = off_name_events(new, concepts, self.K, self.L)
        return -self.lam * (after - before)

    def step(self, old: np.ndarray, proposal: np.ndarray, concepts: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """The places kept: ``proposal`` with probability min(1, g(proposal) / g(old)), else ``old``."""
        self.proposed += 1
        log_u = np.log(rng.random())
        if log_u < self.log_ratio(old, proposal, concepts):
            self.accepted += 1
            return proposal
        return old

    @property
    def acceptance(self) -> float | None:
        """The share of proposals accepted (None before the first)."""
        return self.accepted / self.proposed if self.proposed else None

"""Split-merge moves for the spatial concepts C_{1:E}: Dahl's (2005) sequentially-allocated merge-split (SAMS), a
research variant of the batch sampler (docs/experimental.md; ``SpCoTMHP(variant=SplitMergeMoves())``).

The direct-assignment sampler of concepts.py moves one event at a time.  A concept that has taken in two
differently named rooms cannot split that way: the first event moved out would form a concept of one event,
far less probable than staying, although the split state as a whole is much more probable (the sampler is stuck,
not the model wrong).  A SAMS move changes a whole group at once and is accepted by Metropolis-Hastings on the
exact collapsed conditional of the concepts,

    p(C | i, S, z, f) proportional to DirMult(C | alpha) prod_l DirMult(i_{C=l} | gamma) DirMult(f_{C=l} | chi)
                                       DirMult(concept tokens of C=l | beta)            (Eqs. 14-17, collapsed)

(the counts of concepts.py; the token switches z and every other variable are held fixed, so the background
and switch terms cancel), so it is a valid move of the same chain: with ``SpCoTMHP(variant=SplitMergeMoves())``
each sweep of step 5 is the Gibbs pass followed by these moves.  Not adopted: on words-only homes they fix
merged concepts, but the joint they then reach prefers one place for two adjacent rooms of the same name, which
costs more plans than it saves (docs/results.md, "Split-merge moves for the concepts").

One move (pair and labels chosen with the sampler's generator):

* Pick an ordered pair of distinct events (i, j) uniformly.  S = the other events of concepts C_i and C_j,
  in a uniformly random order.
* C_i = C_j = l: propose a split.  i goes to an empty label l' drawn uniformly among the m empty labels (none
  empty: no move), j stays in l; each event of S in turn joins the side of i or of j with probability
  proportional to its collapsed conditional given the events placed so far (the terms of concepts.py on two
  count rows), q = product of those probabilities.  Accept with min(1, p(split) / p(C) * m / q).
* C_i != C_j: propose merging both concepts into C_j's label.  Its reverse is the split that draws C_i's
  label (1 / m', m' empty labels after the merge) and rebuilds the current sides (q computed by the same
  sequential allocation, forced).  Accept with min(1, p(merge) / p(C) * q / m').

Number of moves per sweep: one per occupied concept, so every concept is, in expectation, touched by the same
number of proposals per sweep whatever the number of concepts.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import log

import numpy as np
from numba import njit

from spcotmhp.errors import ModelError
from spcotmhp.learning.collapsed_terms import (
    digamma_series,
    feature_term,
    move_features,
    move_words,
    refresh_digamma,
    word_term,
)
from spcotmhp.learning.concepts import CollapsedConceptSampler
from spcotmhp.learning.distributions import DirichletCategoricals
from spcotmhp.learning.init import VariantRun
from spcotmhp.learning.model import Hyperparameters


@njit(cache=True)
def _allocate(
    order, forced, uniforms, places, K, alpha, gamma, beta, V, t_ptr, t_word, z, use_features, chi, D, f_ptr,
    f_idx, f_cnt, c_val, c_mult, n_feat,
):  # fmt: skip
    """Sequential allocation of ``order`` to side 0 (the side of order[0]) or side 1 (of order[1]).

    ``forced`` (len(order),) gives the sides to rebuild (a merge's reverse), or is empty to draw them with
    ``uniforms``.  Returns the sides and log q, the log probability of the allocation of order[2:]."""
    n = np.zeros(2)
    n_k = np.zeros((2, K))
    W = np.zeros((2, int(V)))
    W_tot = np.zeros(2)
    Dv = D if use_features else 1
    F = np.zeros((2, Dv))
    F_tot = np.zeros(2)
    digamma_tab = np.full((2, Dv), digamma_series(chi))
    side = np.zeros(order.shape[0], dtype=np.int64)
    side[1] = 1
    logq = 0.0
    lp = np.empty(2)
    for t in range(order.shape[0]):
        e = order[t]
        if t >= 2:
            for s in range(2):
                lp[s] = log(n[s] + alpha) + log(n_k[s, places[e]] + gamma) - log(n[s] + K * gamma)
                lp[s] += word_term(s, e, beta, V, W, W_tot, t_ptr, t_word, z)
                if use_features:
                    lp[s] += feature_term(
                        s, e, n[s], chi, float(D), F, F_tot, digamma_tab, f_ptr, f_idx, f_cnt, c_val, c_mult, n_feat[e]
                    )
            m = max(lp[0], lp[1])
            p1 = np.exp(lp[1] - m) / (np.exp(lp[0] - m) + np.exp(lp[1] - m))
            if forced.shape[0]:
                side[t] = forced[t]
            else:
                side[t] = 1 if uniforms[t] < p1 else 0
            logq += log(p1) if side[t] == 1 else log(1.0 - p1)
        s = side[t]
        n[s] += 1.0
        n_k[s, places[e]] += 1.0
        move_words(s, e, 1.0, W, W_tot, t_ptr, t_word, z)
        if use_features:
            move_features(s, e, 1.0, F, F_tot, f_ptr, f_idx, f_cnt, n_feat[e])
            refresh_digamma(digamma_tab, s, e, chi, F, f_ptr, f_idx)
    return side, logq


@dataclass(frozen=True)
class SplitMergeMoves:
    """The moves as a variant of the batch sampler (``gibbs.SweepVariant``): ``mode`` True (every fit) or "auto"
    (fits without image features: with features the collapsed joint they follow prefers merged concepts, the
    reason the run selection's "auto" keeps the mutual information there).  They price neither opt-in term."""

    mode: bool | str = True

    def __post_init__(self) -> None:
        if self.mode not in (True, False, "auto"):
            raise ModelError(f"split_merge must be True, False or 'auto', got {self.mode!r}")

    def start(
        self, sampler: CollapsedConceptSampler, hyper: Hyperparameters, K: int, L: int, features: bool
    ) -> SplitMerge | NoMoves:
        if not (not features if self.mode == "auto" else bool(self.mode)):
            return NoMoves()
        for name in ("place_concepts", "off_name"):
            if getattr(hyper, name) is not None:
                raise ModelError(f"split_merge moves do not price {name}: use one or the other")
        return SplitMerge(sampler, K, L, hyper.alpha, hyper.gamma, hyper.beta, hyper.chi)


class NoMoves(VariantRun):
    """``mode="auto"`` on a fit with image features: the paper's sweep."""

    def info(self) -> dict:
        return {"split_merge": False}


class SplitMerge(VariantRun):
    """SAMS moves (module docstring) over the state of one :class:`CollapsedConceptSampler`; as a fit's hooks
    (``gibbs.VariantRun``), one ``sweep`` after each Gibbs pass over the concepts."""

    def __init__(self, sampler: CollapsedConceptSampler, K: int, L: int, alpha, gamma, beta, chi) -> None:
        self.s = sampler
        self.K, self.L = K, L
        self.alpha, self.gamma, self.beta, self.chi = alpha, gamma, beta, chi
        self.pi = DirichletCategoricals(1, L, alpha)
        self.phi = DirichletCategoricals(1, K, gamma)
        self.W = DirichletCategoricals(1, sampler.V, beta)
        self.full_features = sampler.features
        self.theta = None if sampler.features is None else DirichletCategoricals(1, sampler.D, chi)
        self.event_of_token = sampler.t_event

    def concepts(self, concepts: np.ndarray, places: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        return self.sweep(concepts, places, rng)

    def info(self) -> dict:
        return {"split_merge": True}

    # ---- the exact target --------------------------------------------------------------------------------
    def log_group(self, members: np.ndarray, places: np.ndarray) -> float:
        """The terms of one concept holding ``members``: DirMult of their places (phi), concept tokens (W) and
        features (theta)."""
        if members.size == 0:
            return 0.0
        lp = self.phi.log_marginal(np.bincount(places[members], minlength=self.K)[None, :])
        mask = np.zeros(len(self.s.t_ptr) - 1, dtype=bool)
        mask[members] = True
        tok = mask[self.event_of_token] & self.s.z
        lp += self.W.log_marginal(np.bincount(self.s.t_word[tok], minlength=self.s.V)[None, :])
        if self.theta is not None and self.full_features is not None:
            lp += self.theta.log_marginal(self.full_features[members].sum(axis=0)[None, :])
        return lp

    def log_pi(self, concepts: np.ndarray) -> float:
        return self.pi.log_marginal(np.bincount(concepts, minlength=self.L)[None, :])

    # ---- moves -------------------------------------------------------------------------------------------
    def sweep(self, concepts: np.ndarray, places: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """One move per occupied concept; returns the new concepts (E,)."""
        C = concepts.astype(np.int64).copy()
        for _ in range(len(np.unique(C))):
            C = self.move(C, places, rng)
        return C

    def move(self, C: np.ndarray, places: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """One SAMS proposal and its accept / reject step; returns the (possibly unchanged) concepts."""
        E = len(C)
        if E < 2:
            return C
        i, j = rng.choice(E, size=2, replace=False)
        li, lj = int(C[i]), int(C[j])
        rest = np.flatnonzero((C == li) | (C == lj))
        rest = rest[(rest != i) & (rest != j)]
        order = np.concatenate(([i, j], rng.permutation(rest))).astype(np.int64)
        new = -1
        if li == lj:
            empty = np.flatnonzero(np.bincount(C, minlength=self.L) == 0)
            if empty.size == 0:
                return C
            new = int(empty[rng.integers(empty.size)])
            side, logq = self.allocate(order, places, uniforms=rng.random(len(order)))
        else:
            side = (C[order] == lj).astype(np.int64)
            _, logq = self.allocate(order, places, forced=side)
        proposal, log_ratio = self.propose(C, places, order, side, logq, new)
        return proposal if np.log(rng.random()) < log_ratio else C

    def propose(
        self, C: np.ndarray, places: np.ndarray, order: np.ndarray, side: np.ndarray, logq: float, new: int
    ) -> tuple[np.ndarray, float]:
        """The proposed concepts and the log Metropolis-Hastings ratio of one move (module docstring).

        ``order`` = (i, j, the rest of both concepts in allocation order); ``side`` (len(order),) the side of
        each (0: i's, 1: j's) with log probability ``logq`` of the allocation; ``new`` the empty label that i's
        side takes in a split (C_i = C_j), ignored in a merge (C_i != C_j)."""
        i, j = order[0], order[1]
        mine, theirs = order[side == 0], order[side == 1]
        proposal = C.copy()
        empty = int(np.sum(np.bincount(C, minlength=self.L) == 0))
        if C[i] == C[j]:
            proposal[mine] = new
            log_ratio = self.log_group(mine, places) + self.log_group(theirs, places) - self.log_group(order, places)
            log_ratio += np.log(empty) - logq
        else:
            proposal[order] = C[j]
            log_ratio = self.log_group(order, places) - self.log_group(mine, places) - self.log_group(theirs, places)
            log_ratio += logq - np.log(empty + 1)
        return proposal, float(log_ratio + self.log_pi(proposal) - self.log_pi(C))

    def allocate(
        self,
        order: np.ndarray,
        places: np.ndarray,
        uniforms: np.ndarray | None = None,
        forced: np.ndarray | None = None,
    ) -> tuple[np.ndarray, float]:
        """Sides of ``order`` drawn with ``uniforms`` (or the ``forced`` ones) and their log proposal probability."""
        return self._allocate(
            np.asarray(order, dtype=np.int64),
            np.zeros(0, dtype=np.int64) if forced is None else np.asarray(forced, dtype=np.int64),
            np.zeros(0) if uniforms is None else uniforms,
            places,
        )

    def _allocate(self, order, forced, uniforms, places) -> tuple[np.ndarray, float]:
        s = self.s
        return _allocate(
            order, forced, uniforms, places.astype(np.int64), self.K, self.alpha, self.gamma, self.beta,
            float(s.V), s.t_ptr, s.t_word, s.z, s.features is not None, self.chi, s.D, s.f_ptr, s.f_idx,
            s.f_cnt, s.c_val, s.c_mult, s.n_feat,
        )  # fmt: skip

"""Collapsed (direct-assignment) sampling of the spatial concepts C_{1:E} (Eqs. 14-17), with background words.

p(C_e = l | C_-e, i, S, f) is proportional to pi_l phi_l(i_e) theta_l(f_e) prod_b W_l(S_e,b) (Eq. 17) with pi, phi,
theta and W integrated out under their Dirichlet priors (Johnson and Willsky's direct-assignment sampler):

    (n_l + alpha) * (n_{l,i_e} + gamma) / (n_l + K gamma) * DirMult(f_e | chi + F_l) * DirMult(S_e | beta + W_l)

with every count taken without event e.  (The unigram-rescaling denominator of Eq. 17, sum_c' W_c'(S_e,b), does
not depend on C_e and cancels here.)  With the opt-in ``Hyperparameters.place_concepts`` = eta (not the paper's)
the product gains (eta / L + n_{l,i_e}) / (eta + n_{i_e}): place i_e's concept distribution integrated out
(gibbs.py); a research variant may add its own term (``ConceptTerm``, e.g. spcotmhp.experimental.off_name).
Drawing theta from its posterior instead adds so much noise to a 365-dimensional feature likelihood that small
concepts lose to large ones and everything merges.

Background words: each token b of S_e carries a switch z_eb ~ Bernoulli(lambda), lambda ~ Beta(1, 1); a concept
token is drawn from W_{C_e}, a background token from one shared W_0 ~ Dir(beta).  Phrases that every concept
uses ("this is", "です") go to W_0, so concepts form around the words that tell places apart, which is what
unigram rescaling is meant to achieve; without it a bag-of-words mixture splits concepts by function phrases.
The exported W_l is the token distribution lambda W_l + (1 - lambda) W_0.

The per-event terms and count moves are the kernels of :mod:`spcotmhp.learning.collapsed_terms`.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from math import log
from types import FunctionType
from typing import Any

import numpy as np
from numba import njit

from spcotmhp.learning.collapsed_terms import (
    concept_tokens,
    count_logs,
    feature_term,
    move_features,
    move_words,
    refresh_digamma,
    tokens_terms,
    total_logs,
    word_logs,
)

SWITCH_PRIOR = 1.0  # Beta(1, 1) prior of the concept / background switch


@dataclass(frozen=True)
class ConceptTerm:
    """An extra log-term of the concept conditional, a research variant's (spcotmhp.experimental; the paper's step
    has none): ``add(param, n_lk, k, logp)``, a numba function that adds to ``logp[l]`` the term of concept l for
    an event at place k, ``n_lk`` (L, K) the concept-place counts without that event; it must neither allocate nor
    draw.  The pass is compiled with it once per process (``_sweep_with``)."""

    add: Any  # a numba dispatcher
    param: float


@njit(cache=True)
def _variant_term(param, n_lk, k, logp):  # pragma: no cover - numba
    """The paper's conditional has no term beyond Eq. 17's: nothing added (``ConceptTerm`` for a variant's)."""


@njit(cache=True)
def _draw(logp: np.ndarray, uniform: float, w: np.ndarray) -> int:
    """Index drawn from unnormalised log probabilities with one uniform variate (inverse CDF); ``w`` is scratch
    space of the same length."""
    m = logp.max()
    total = 0.0
    for l in range(logp.shape[0]):
        w[l] = np.exp(logp[l] - m)
        total += w[l]
    target = uniform * total
    acc = 0.0
    for l in range(logp.shape[0]):
        acc += w[l]
        if acc > target:
            return l
    return logp.shape[0] - 1


@njit(cache=True)
def _resample_switches(l, e, uniforms, u, beta, V, W_lv, W_l, bg_v, bg_tot, z_tot, t_ptr, t_word, z):
    """z_eb for every token of event e (in concept l): concept word or background word."""
    for p in range(t_ptr[e], t_ptr[e + 1]):
        v = t_word[p]
        if z[p]:
            W_lv[l, v] -= 1.0
            W_l[l] -= 1.0
            z_tot[1] -= 1.0
        else:
            bg_v[v] -= 1.0
            bg_tot[0] -= 1.0
            z_tot[0] -= 1.0
        p1 = (z_tot[1] + SWITCH_PRIOR) * (W_lv[l, v] + beta) / (W_l[l] + V * beta)
        p0 = (z_tot[0] + SWITCH_PRIOR) * (bg_v[v] + beta) / (bg_tot[0] + V * beta)
        z[p] = uniforms[u] * (p0 + p1) < p1
        if z[p]:
            W_lv[l, v] += 1.0
            W_l[l] += 1.0
            z_tot[1] += 1.0
        else:
            bg_v[v] += 1.0
            bg_tot[0] += 1.0
            z_tot[0] += 1.0
        u += 1
    return u


@njit(cache=True)
def _feature_scores(
    e, k, L, n_l, log_a, log_kl, log_c, words_lp, chi, D, F_ld, F_l, digamma_ld, f_ptr, f_idx, f_cnt, c_val, c_mult,
    n_feat, logp,
):  # fmt: skip
    """log p(C_e = l | ...) for every concept l with the feature term: the count and word terms plus
    DirMult(f_e | chi + F_l), evaluated once for all empty concepts (exchangeable: the same value, bit for bit)."""
    empty_value = 0.0
    empty_done = False
    for l in range(L):
        if n_l[l] == 0.0 and empty_done:
            logp[l] = empty_value
            continue
        lp = log_a[l] + log_kl[k, l] - log_c[l] + words_lp[l]
        lp += feature_term(l, e, n_l[l], chi, D, F_ld, F_l, digamma_ld, f_ptr, f_idx, f_cnt, c_val, c_mult, n_feat[e])
        logp[l] = lp
        if n_l[l] == 0.0:
            empty_value = lp
            empty_done = True


@njit(cache=True)
def _concept_sweep(
    C,
    places,
    order,
    uniforms,
    L,
    K,
    alpha,
    gamma,
    beta,
    chi,
    t_ptr,
    t_word,
    z,
    V,
    background,
    bg_v,
    bg_tot,
    z_tot,
    f_ptr,
    f_idx,
    f_cnt,
    D,
    c_val,
    c_mult,
    n_feat,
    n_l,
    n_lk,
    W_lv,
    W_l,
    F_ld,
    F_l,
    digamma_ld,
    use_features,
    eta_each,
    term_param,
):
    """One pass over the events in ``order``: C_e, then (with ``background``) the switch of each token.
    ``eta_each`` > 0 (eta / L of ``Hyperparameters.place_concepts``) adds log(eta / L + n_{l, i_e}) to concept
    l's score, eta_i integrated out; 0 leaves the paper's conditional.  ``_variant_term(term_param, ...)`` adds a
    research variant's term (nothing in this compiled pass; ``_sweep_with`` compiles it with another).
    Every count array is updated in place. The logs of the concept, concept-place and token counts are kept in
    tables refreshed where the counts change (the same values as computing them for every event and concept), and
    the word terms of all concepts are summed at once (``tokens_terms``)."""
    logp = np.empty(L)
    scratch = np.empty(L)
    words_lp = np.empty(L)
    saved = np.empty(f_idx.shape[0])  # psi of the old concept before removal, restored if e stays there
    longest = 0
    for e in range(t_ptr.shape[0] - 1):
        longest = max(longest, t_ptr[e + 1] - t_ptr[e])
    tok_words = np.empty(longest, np.int64)
    tok_reps = np.empty(longest)
    log_a, log_c, log_kl, log_tot = np.empty(L), np.empty(L), np.empty((K, L)), np.empty((longest, L))
    log_wt = np.empty((W_lv.shape[1], L))  # log(beta + W_lv[l, v]) at [v, l]
    for l in range(L):
        total_logs(l, beta, V, W_l, log_tot)
        for v in range(W_lv.shape[1]):
            log_wt[v, l] = log(beta + W_lv[l, v])
        for k in range(K):
            count_logs(l, k, n_l, n_lk, alpha, gamma, K, log_a, log_c, log_kl)
    u = 0
    for t in range(order.shape[0]):
        e = order[t]
        k = places[e]
        old = C[e]
        n_l[old] -= 1.0
        n_lk[old, k] -= 1.0
        count_logs(old, k, n_l, n_lk, alpha, gamma, K, log_a, log_c, log_kl)
        move_words(old, e, -1.0, W_lv, W_l, t_ptr, t_word, z)
        word_logs(old, e, beta, W_lv, log_wt, t_ptr, t_word)
        total_logs(old, beta, V, W_l, log_tot)
        m = concept_tokens(e, t_ptr, t_word, z, tok_words, tok_reps)
        tokens_terms(beta, W_lv, log_wt, tok_words, tok_reps, m, log_tot, words_lp)
        if use_features:
            for p in range(f_ptr[e], f_ptr[e + 1]):
                saved[p] = digamma_ld[old, f_idx[p]]
            move_features(old, e, -1.0, F_ld, F_l, f_ptr, f_idx, f_cnt, n_feat[e])
            refresh_digamma(digamma_ld, old, e, chi, F_ld, f_ptr, f_idx)
            _feature_scores(e, k, L, n_l, log_a, log_kl, log_c, words_lp, chi, D, F_ld, F_l, digamma_ld, f_ptr,
                            f_idx, f_cnt, c_val, c_mult, n_feat, logp)  # fmt: skip
        else:  # the same value for every empty concept, so no special case
            for l in range(L):
                logp[l] = log_a[l] + log_kl[k, l] - log_c[l] + words_lp[l]
        if eta_each > 0.0:
            for l in range(L):
                logp[l] += log(eta_each + n_lk[l, k])
        _variant_term(term_param, n_lk, k, logp)
        new = _draw(logp, uniforms[u], scratch)
        u += 1
        C[e] = new
        n_l[new] += 1.0
        n_lk[new, k] += 1.0
        count_logs(new, k, n_l, n_lk, alpha, gamma, K, log_a, log_c, log_kl)
        move_words(new, e, 1.0, W_lv, W_l, t_ptr, t_word, z)
        if use_features:
            move_features(new, e, 1.0, F_ld, F_l, f_ptr, f_idx, f_cnt, n_feat[e])
            if new == old:
                for p in range(f_ptr[e], f_ptr[e + 1]):
                    digamma_ld[new, f_idx[p]] = saved[p]
            else:
                refresh_digamma(digamma_ld, new, e, chi, F_ld, f_ptr, f_idx)
        if background:
            u = _resample_switches(new, e, uniforms, u, beta, V, W_lv, W_l, bg_v, bg_tot, z_tot, t_ptr, t_word, z)
        word_logs(new, e, beta, W_lv, log_wt, t_ptr, t_word)
        total_logs(new, beta, V, W_l, log_tot)
    return C


@functools.cache
def _sweep_with(add: Any) -> Any:
    """``_concept_sweep`` compiled with ``add`` in place of ``_variant_term`` (``ConceptTerm``).  Compiled without
    numba's disk cache, which keeps no entry for a kernel whose callee is chosen at run time (measured: every
    process compiled it again), so once per process and variant; the paper's pass keeps its cached kernel."""
    body = _concept_sweep.py_func
    names = dict(body.__globals__, _variant_term=add)
    return njit(FunctionType(body.__code__, names, body.__name__, body.__defaults__, body.__closure__))


def _csr(M: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Row pointers, column indices and values of the non-zero entries of a dense (E, M) matrix."""
    rows, cols = np.nonzero(M)
    ptr = np.zeros(M.shape[0] + 1, dtype=np.int64)
    np.add.at(ptr, rows + 1, 1)
    return np.cumsum(ptr), cols.astype(np.int64), M[rows, cols].astype(np.float64)


@dataclass
class CollapsedConceptSampler:
    """State (token switches) and precomputed sparse views for repeated concept sweeps over one dataset.

    With ``background=True`` the switches start as a fair coin per token; otherwise every token is a concept
    token and the model is the paper's plain bag of words.
    """

    words: np.ndarray
    features: np.ndarray | None
    background: bool
    rng: np.random.Generator

    def __post_init__(self) -> None:
        E, self.V = self.words.shape
        counts = np.rint(self.words).astype(np.int64)
        rows, cols = np.nonzero(counts)
        reps = counts[rows, cols]
        self.t_ptr = np.concatenate(([0], np.cumsum(counts.sum(axis=1)))).astype(np.int64)
        self.t_word = np.repeat(cols, reps).astype(np.int64)
        self.t_event = np.repeat(rows, reps).astype(np.int64)
        n_tok = len(self.t_word)
        self.z = (self.rng.random(n_tok) < 0.5) if self.background else np.ones(n_tok, dtype=bool)
        F = np.zeros((E, 1)) if self.features is None else self.features
        self.D = F.shape[1]
        self.const = (F == F[0]).all(axis=0)
        vals, mult = np.unique(F[0, self.const], return_counts=True)
        keep = vals != 0
        self.c_val, self.c_mult = vals[keep].astype(float), mult[keep].astype(float)
        self.varying = np.where(self.const, 0.0, F)
        self.f_ptr, self.f_idx, self.f_cnt = _csr(self.varying)
        self.n_feat = F.sum(axis=1).astype(float)

    def concept_words(self) -> np.ndarray:
        """(E, V) counts of the tokens currently explained by their event's concept (z = 1)."""
        out = np.zeros((len(self.t_ptr) - 1, self.V))
        np.add.at(out, (self.t_event[self.z], self.t_word[self.z]), 1.0)
        return out

    def background_words(self) -> np.ndarray:
        """(V,) counts of the tokens currently explained by the background (z = 0)."""
        return np.bincount(self.t_word[~self.z], minlength=self.V).astype(float)

    def sweep(
        self,
        concepts: np.ndarray,
        places: np.ndarray,
        L: int,
        K: int,
        alpha: float,
        gamma: float,
        beta: float,
        chi: float,
        rng: np.random.Generator,
        place_concepts: float | None = None,
        term: ConceptTerm | None = None,
    ) -> np.ndarray:
        """One collapsed Gibbs pass in random order: the new concepts (E,); opt-in: ``place_concepts``, ``term``."""
        E = len(concepts)
        eta_each = 0.0 if place_concepts is None else float(place_concepts) / L
        C = concepts.astype(np.int64).copy()
        n_l, n_lk, W_lv, bg_v, z_tot, F_ld, F_l, digamma_ld = self._counts(C, places, L, K, chi)
        use_features = self.features is not None
        order = rng.permutation(E).astype(np.int64)
        uniforms = rng.random(E + len(self.t_word))
        kernel = _concept_sweep if term is None else _sweep_with(term.add)
        return kernel(
            C,
            places.astype(np.int64),
            order,
            uniforms,
            L,
            K,
            alpha,
            gamma,
            beta,
            chi,
            self.t_ptr,
            self.t_word,
            self.z,
            float(self.V),
            self.background,
            bg_v,
            np.array([bg_v.sum()]),
            z_tot,
            self.f_ptr,
            self.f_idx,
            self.f_cnt,
            float(self.D),
            self.c_val,
            self.c_mult,
            self.n_feat,
            n_l,
            n_lk,
            W_lv,
            W_lv.sum(axis=1),
            F_ld,
            F_l,
            digamma_ld,
            use_features,
            eta_each,
            0.0 if term is None else float(term.param),
        )

    def _counts(self, C: np.ndarray, places: np.ndarray, L: int, K: int, chi: float) -> tuple[np.ndarray, ...]:
        """The counts the sweep starts from, for concepts ``C``: n_l, n_lk (concept, concept-place), W_lv (concept
        tokens per concept and word), the background's word counts, the switch totals (z = 0, z = 1), F_ld and F_l
        (features per concept), and the digamma table psi(chi + F_ld) (F_ld itself without features: unused)."""
        E = len(C)
        n_l = np.bincount(C, minlength=L).astype(float)
        n_lk = np.bincount(C * K + places, minlength=L * K).astype(float).reshape(L, K)
        # integer counts, so scatter-adds give the numbers of the one-hot products exactly
        cell = C[self.t_event[self.z]] * self.V + self.t_word[self.z]
        W_lv = np.bincount(cell, minlength=L * self.V).astype(float).reshape(L, self.V)
        bg_v = self.background_words()
        z_tot = np.array([float((~self.z).sum()), float(self.z.sum())])
        if self.features is None:  # one all-zero column (what the product with ``varying`` gives)
            return n_l, n_lk, W_lv, bg_v, z_tot, np.zeros((L, 1)), np.zeros(L), np.zeros((L, 1))
        onehot = np.zeros((E, L))
        onehot[np.arange(E), C] = 1.0
        F_ld = onehot.T @ self.varying
        F_l = onehot.T @ self.n_feat
        return n_l, n_lk, W_lv, bg_v, z_tot, F_ld, F_l, _digamma_table(chi + F_ld)


def _digamma_table(a: np.ndarray) -> np.ndarray:
    from scipy.special import digamma

    return digamma(a)

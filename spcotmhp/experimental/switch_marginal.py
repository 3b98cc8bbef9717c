"""log p(S | C): the words of every event given the concepts, with the background-word switches z summed out.

The word model (concepts.py): each token w of an event in concept C is a concept token (z = 1) drawn from W_C or
a background token (z = 0) drawn from W_0, with z ~ Bernoulli(lambda); W_C ~ Dir(beta), W_0 ~ Dir(beta),
lambda ~ Beta(1, 1).  Summing over z is a sum over 2^T settings; two identities make it tractable:

1. **Given W_0 and lambda, the concepts are independent and each is an exact finite sum**
   (``log_words_given_background``).  For concept l with n_v tokens of word v, a setting of its switches
   matters through the concept-token counts m_v only (Pi_v binom(n_v, m_v) settings give the same value), and
   with W_l integrated out

       p(S_l | W_0, lambda) = sum_M  Gamma(V beta) / Gamma(V beta + M) * lambda^M (1 - lambda)^(n_l - M)
                                     * [x^M] Pi_v sum_{m=0}^{n_v} binom(n_v, m) Gamma(beta + m) / Gamma(beta)
                                                                   W_0(v)^(n_v - m) x^m,

   a product of polynomials (one per word) computed by convolution in log space.
2. **Chib's identity** (Chib 1995) for the remaining (W_0, lambda), at any point theta* = (W_0*, lambda*):

       log p(S | C) = log p(S | C, theta*) + log p(theta*) - log p(theta* | S, C).

   The posterior ordinate is Rao-Blackwellised over draws of the switches from p(z | S, C):
   p(theta* | S, C) = E_z[ Dir(W_0* | beta + background counts) Beta(lambda* | 1 + concept tokens,
   1 + background tokens) ], both conditionals exact.  The draws come from a Gibbs chain over the switches
   given C (single tokens, then whole-word flips), started from the run's own final switches; theta* is the
   Rao-Blackwellised posterior mean.

The estimate is consistent (exact as the chain grows); its error is the ordinate's Monte Carlo error, over a
space of V dimensions (W_0 and lambda) instead of the L * V of every word distribution.  Being the log of a
mean, the ordinate is biased low by about half the variance of its estimate, so log p(S | C) is biased high by
as much; the tests check the value against brute force over every switch setting.
"""

from __future__ import annotations

from math import exp, lgamma, log

import numpy as np
from numba import njit
from scipy.special import gammaln

from spcotmhp.errors import ModelError
from spcotmhp.logspace import logsumexp

SWITCH_PRIOR = 1.0  # Beta(1, 1) prior of the concept / background switch (as concepts.py)
SWEEPS = 300
BURN_IN = 50


def log_words_given_concepts(
    words: np.ndarray,
    concepts: np.ndarray,
    V: int,
    beta: float,
    rng: np.random.Generator,
    switches: np.ndarray | None = None,
    sweeps: int = SWEEPS,
    burn_in: int = BURN_IN,
) -> float:
    """Chib's estimate of log p(S | C) (module docstring) for tokens ``words`` (T,) of events in concepts
    ``concepts`` (T,); the switch chain starts from ``switches`` (T,) (default: every token a concept token),
    makes ``sweeps`` sweeps and keeps those after ``burn_in``."""
    words = np.asarray(words, dtype=np.int64)
    if words.ndim != 1 or words.shape != np.shape(concepts) or not 0 <= burn_in < sweeps:
        raise ModelError("words and concepts must be equal-length 1-D arrays, and 0 <= burn_in < sweeps")
    if words.size == 0:
        return 0.0
    c = np.unique(np.asarray(concepts, dtype=np.int64), return_inverse=True)[1].astype(np.int64)
    L, T = int(c.max()) + 1, words.size
    z = np.ones(T, dtype=np.bool_) if switches is None else np.array(switches, dtype=np.bool_)
    N = np.zeros((L, V))
    np.add.at(N, (c, words), 1.0)
    background, on = _switch_chain(words, c, N, beta, z, sweeps, int(rng.integers(2**31 - 1)))
    background, on = background[burn_in:], on[burn_in:]
    off = T - on
    W0 = ((background + beta) / (off[:, None] + V * beta)).mean(axis=0)
    lam = float(((on + SWITCH_PRIOR) / (T + 2.0 * SWITCH_PRIOR)).mean())
    ordinates = _log_dirichlet(W0, background + beta) + (
        gammaln(T + 2.0) - gammaln(on + 1.0) - gammaln(off + 1.0) + on * np.log(lam) + off * np.log1p(-lam)
    )
    log_ordinate = float(logsumexp(ordinates) - np.log(len(ordinates)))
    log_prior = float(_log_dirichlet(W0, np.full(V, beta)))  # lambda ~ Beta(1, 1) has density 1
    return log_words_given_background(N, W0, lam, beta) + log_prior - log_ordinate


def log_words_given_background(N: np.ndarray, W0: np.ndarray, lam: float, beta: float) -> float:
    """log p(S | C, W_0, lambda), exact: tokens ``N`` (L, V) per concept and word, each concept's word
    distribution integrated out under Dir(beta) and the switches summed out (module docstring, 1).

    One token of word 0, W_0 = (1/4, 3/4), lambda = 1/2, beta = 1: (1/2)(1/2) + (1/2)(1/4) = 3/8.

    >>> round(log_words_given_background(np.array([[1.0, 0.0]]), np.array([0.25, 0.75]), 0.5, 1.0), 6)
    -0.980829
    """
    L, V = N.shape
    log_w0 = np.log(W0)
    total = 0.0
    for l in range(L):
        poly = np.zeros(1)  # log coefficients of the product so far, by number of concept tokens
        for v in np.nonzero(N[l])[0]:
            n = int(N[l, v])
            m = np.arange(n + 1)
            factor = gammaln(n + 1.0) - gammaln(m + 1.0) - gammaln(n - m + 1.0)
            factor += gammaln(beta + m) - gammaln(beta) + (n - m) * log_w0[v]
            shifted = np.full((n + 1, len(poly) + n), -np.inf)
            for j in range(n + 1):
                shifted[j, j : j + len(poly)] = poly + factor[j]
            poly = logsumexp(shifted, axis=0)
        M = np.arange(len(poly))
        rest = gammaln(V * beta) - gammaln(V * beta + M) + M * log(lam) + (N[l].sum() - M) * np.log1p(-lam)
        total += float(logsumexp(poly + rest))
    return total


def _log_dirichlet(theta: np.ndarray, a: np.ndarray) -> np.ndarray:
    """log Dir(theta | a) along the last axis."""
    return gammaln(a.sum(axis=-1)) - gammaln(a).sum(axis=-1) + ((a - 1.0) * np.log(theta)).sum(axis=-1)


@njit(cache=True)
def _switch_chain(words, concepts, N, beta, z, sweeps, seed):  # pragma: no cover - numba
    """Gibbs sampling of the switches ``z`` given the concepts (each sweep: every token, then the whole-word
    flips of every word, over all concepts and within each): the background counts per word (sweeps, V) and
    the number of concept tokens (sweeps,) after each sweep."""
    np.random.seed(seed)  # numba's own generator (one per thread), seeded for this call
    L, V = N.shape
    Wc, Wt, Bg = np.zeros((L, V)), np.zeros(L), np.zeros(V)
    for t in range(words.shape[0]):
        if z[t]:
            Wc[concepts[t], words[t]] += 1.0
            Wt[concepts[t]] += 1.0
        else:
            Bg[words[t]] += 1.0
    n1 = Wt.sum()
    out_bg, out_on = np.empty((sweeps, V)), np.empty(sweeps)
    for s in range(sweeps):
        n1 = _token_sweep(words, concepts, V, beta, z, Wc, Wt, Bg, n1)
        for only in range(-1, L):
            n1 = _word_flips(words, concepts, V, beta, z, Wc, Wt, Bg, N, n1, only)
        out_bg[s] = Bg
        out_on[s] = n1
    return out_bg, out_on


@njit(cache=True)
def _token_sweep(words, concepts, V, beta, z, Wc, Wt, Bg, n1):  # pragma: no cover - numba
    """Every token's switch drawn given the others (concepts.py's step); returns the number of concept tokens."""
    T = words.shape[0]
    Bt = Bg.sum()
    for t in range(T):
        v, c = words[t], concepts[t]
        if z[t]:
            Wc[c, v] -= 1.0
            Wt[c] -= 1.0
            n1 -= 1.0
        else:
            Bg[v] -= 1.0
            Bt -= 1.0
        p1 = (n1 + SWITCH_PRIOR) * (Wc[c, v] + beta) / (Wt[c] + V * beta)
        p0 = (T - 1 - n1 + SWITCH_PRIOR) * (Bg[v] + beta) / (Bt + V * beta)
        z[t] = np.random.random() * (p0 + p1) < p1
        if z[t]:
            Wc[c, v] += 1.0
            Wt[c] += 1.0
            n1 += 1.0
        else:
            Bg[v] += 1.0
            Bt += 1.0
    return n1


@njit(cache=True)
def _word_flips(words, concepts, V, beta, z, Wc, Wt, Bg, N, n1, only):  # pragma: no cover - numba
    """For each word v, a Metropolis-Hastings move that flips the switch of every token of v (of concept
    ``only``, or of every concept when it is -1): an involution, so a symmetric proposal.  It moves between
    "v is a background word" and "v is a concept word", which single-token steps cross only through improbable
    mixed states.  ``N`` (L, V): tokens per concept and word.  Returns the number of concept tokens."""
    L, T = Wc.shape[0], words.shape[0]
    lo, hi = (0, L) if only < 0 else (only, only + 1)
    Bt = Bg.sum()
    for v in range(V):
        n_v = N[lo:hi, v].sum()
        if n_v == 0.0:
            continue
        on_v = Wc[lo:hi, v].sum()
        bg_new = Bg[v] - (n_v - on_v) + on_v
        delta = _dirmult_part(bg_new, Bt - Bg[v] + bg_new, beta, V) - _dirmult_part(Bg[v], Bt, beta, V)
        for l in range(lo, hi):
            if N[l, v] > 0.0:
                new = N[l, v] - Wc[l, v]
                delta += _dirmult_part(new, Wt[l] - Wc[l, v] + new, beta, V) - _dirmult_part(Wc[l, v], Wt[l], beta, V)
        n1_new = n1 - on_v + (n_v - on_v)
        delta += lgamma(1.0 + n1_new) + lgamma(1.0 + T - n1_new) - lgamma(1.0 + n1) - lgamma(1.0 + T - n1)
        if np.random.random() < exp(min(delta, 0.0)):
            for t in range(T):
                if words[t] == v and (only < 0 or concepts[t] == only):
                    z[t] = not z[t]
            for l in range(lo, hi):
                new = N[l, v] - Wc[l, v]
                Wt[l] += new - Wc[l, v]
                Wc[l, v] = new
            Bt += bg_new - Bg[v]
            Bg[v] = bg_new
            n1 = n1_new
    return n1


@njit(cache=True)
def _dirmult_part(count, total, beta, V):  # pragma: no cover - numba
    """The part of a symmetric Dirichlet-multinomial's log marginal that depends on one entry's count and the
    total."""
    return lgamma(beta + count) - lgamma(V * beta + total)

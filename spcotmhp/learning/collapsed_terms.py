"""The collapsed per-event terms of Eq. 17 and their count bookkeeping (numba kernels), shared by the concept
sweep (:mod:`spcotmhp.learning.concepts`) and the split-merge proposals (:mod:`spcotmhp.experimental.split_merge`).

With the Dirichlet priors integrated out, an event's features and words enter p(C_e = l | ...) as Dirichlet-
multinomial predictive terms of concept l's counts without event e: DirMult(f_e | chi + F_l) (:func:`feature_term`)
and DirMult(S_e | beta + W_l) over the concept tokens (:func:`word_term`, or :func:`tokens_terms` for every
concept at once from tables kept up to date by :func:`word_logs`, :func:`total_logs` and :func:`count_logs`).
The ``move_*`` kernels add or remove an event's counts.

Feature terms: log Gamma(a + x) - log Gamma(a) is exact (a sum of logs for small integer x, log-gamma
otherwise), except for tiny counts x <= SMALL_COUNT, where x psi(a) is used (psi the digamma function) with psi(a)
cached per concept and column in ``digamma_ld`` (error below x^2 psi'(1) / 2, under 1e-3 nats per event for
features scaled to weight 1).  Columns that hold the same value in every event (the "+1" of the authors' counts)
are evaluated once per distinct value.
"""

from __future__ import annotations

from math import lgamma, log

import numpy as np
from numba import njit

SMALL_COUNT = 1e-3


@njit(cache=True)
def log_rising(a: float, x: float) -> float:
    """log Gamma(a + x) - log Gamma(a) (the log rising factorial), by a sum of logs for small integer x."""
    if x == 0.0:
        return 0.0
    if x <= 8.0 and x == np.floor(x):
        s = 0.0
        for j in range(int(x)):
            s += log(a + j)
        return s
    return lgamma(a + x) - lgamma(a)


@njit(cache=True)
def digamma_series(x: float) -> float:
    """psi(x) for x > 0: recurrence up to x >= 10, then the asymptotic series (error < 1e-13)."""
    r = 0.0
    while x < 10.0:
        r -= 1.0 / x
        x += 1.0
    f = 1.0 / (x * x)
    return r + log(x) - 0.5 / x - f * (1.0 / 12 - f * (1.0 / 120 - f * (1.0 / 252 - f * (1.0 / 240 - f / 132))))


@njit(cache=True)
def refresh_digamma(digamma_ld, l, e, chi, F_ld, f_ptr, f_idx):
    for p in range(f_ptr[e], f_ptr[e + 1]):
        digamma_ld[l, f_idx[p]] = digamma_series(chi + F_ld[l, f_idx[p]])


@njit(cache=True)
def move_features(l, e, sign, F_ld, F_l, f_ptr, f_idx, f_cnt, n_e_feat):
    for p in range(f_ptr[e], f_ptr[e + 1]):
        F_ld[l, f_idx[p]] += sign * f_cnt[p]
    F_l[l] += sign * n_e_feat


@njit(cache=True)
def feature_term(l, e, n_l, chi, D, F_ld, F_l, digamma_ld, f_ptr, f_idx, f_cnt, c_val, c_mult, n_e_feat):
    """log DirMult(f_e | chi + F_l) for concept l (event e removed from the counts)."""
    lp = 0.0
    for p in range(f_ptr[e], f_ptr[e + 1]):
        x = f_cnt[p]
        if x <= SMALL_COUNT:
            lp += x * digamma_ld[l, f_idx[p]]
        else:
            lp += log_rising(chi + F_ld[l, f_idx[p]], x)
    for g in range(c_val.shape[0]):  # constant columns: F_ld = n_l * value
        lp += c_mult[g] * log_rising(chi + n_l * c_val[g], c_val[g])
    return lp - log_rising(D * chi + F_l[l], n_e_feat)


@njit(cache=True)
def concept_tokens(e, t_ptr, t_word, z, words, reps):
    """The concept tokens (z = 1) of S_e into ``words``, each with the number of earlier concept tokens of the
    same word in the utterance into ``reps``; returns their number. The same for every concept, so found once
    per event."""
    m = 0
    for p in range(t_ptr[e], t_ptr[e + 1]):
        if z[p]:
            rep = 0.0
            for q in range(t_ptr[e], p):
                if z[q] and t_word[q] == t_word[p]:
                    rep += 1.0
            words[m] = t_word[p]
            reps[m] = rep
            m += 1
    return m


@njit(cache=True)
def word_term(l, e, beta, V, W_lv, W_l, t_ptr, t_word, z):
    """log DirMult of the concept tokens (z = 1) of S_e under concept l (event e removed from the counts)."""
    words = np.empty(t_ptr[e + 1] - t_ptr[e], np.int64)
    reps = np.empty(t_ptr[e + 1] - t_ptr[e])
    m = concept_tokens(e, t_ptr, t_word, z, words, reps)
    lp = 0.0
    j = 0.0
    for t in range(m):
        lp += log(beta + W_lv[l, words[t]] + reps[t]) - log(V * beta + W_l[l] + j)
        j += 1.0
    return lp


@njit(cache=True)
def tokens_terms(beta, W_lv, log_wt, words, reps, m, log_tot, out):
    """:func:`word_term` of every concept at once into ``out`` (L,), from the event's concept tokens
    (``concept_tokens``, found once per event) and the tables ``log_wt[v, l]`` = log(beta + W_lv[l, v])
    (:func:`word_logs`) and ``log_tot[j, l]`` = log(V beta + W_l + j) (:func:`total_logs`).

    The same value as :func:`word_term`, bit for bit: per concept the same terms added in the same order, and a
    token without an earlier repeat (``reps`` 0, nearly all of them) reads its log from the table, since
    (beta + W) + 0 is beta + W. The loops over concepts are contiguous rows of the tables."""
    out[:] = 0.0
    for t in range(m):
        v = words[t]
        if reps[t] == 0.0:
            for l in range(out.shape[0]):
                out[l] += log_wt[v, l] - log_tot[t, l]
        else:
            for l in range(out.shape[0]):
                out[l] += log(beta + W_lv[l, v] + reps[t]) - log_tot[t, l]


@njit(cache=True)
def word_logs(l, e, beta, W_lv, log_wt, t_ptr, t_word):
    """Refresh ``log_wt[v, l]`` = log(beta + W_lv[l, v]) for the words of event e, after concept l's counts of
    them changed."""
    for p in range(t_ptr[e], t_ptr[e + 1]):
        v = t_word[p]
        log_wt[v, l] = log(beta + W_lv[l, v])


@njit(cache=True)
def total_logs(l, beta, V, W_l, log_tot):
    """log(V beta + W_l + j) into ``log_tot[j, l]`` for j = 0 .. (longest utterance - 1), after concept l's token
    count changed."""
    j = 0.0
    for t in range(log_tot.shape[0]):
        log_tot[t, l] = log(V * beta + W_l[l] + j)
        j += 1.0


@njit(cache=True)
def count_logs(l, k, n_l, n_lk, alpha, gamma, K, log_a, log_c, log_kl):
    """The cached logs of concept l's counts (:func:`~spcotmhp.learning.concepts._concept_sweep`), after they
    changed; ``log_kl[k, l]`` = log(n_lk[l, k] + gamma) (a contiguous row per place)."""
    log_a[l] = log(n_l[l] + alpha)
    log_c[l] = log(n_l[l] + K * gamma)
    log_kl[k, l] = log(n_lk[l, k] + gamma)


@njit(cache=True)
def move_words(l, e, sign, W_lv, W_l, t_ptr, t_word, z):
    for p in range(t_ptr[e], t_ptr[e + 1]):
        if z[p]:
            W_lv[l, t_word[p]] += sign
            W_l[l] += sign

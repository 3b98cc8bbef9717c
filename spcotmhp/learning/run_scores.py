"""Scores of one fitted Gibbs run by which selection.py compares runs, each with the background-word switches z
handled in its own way (a run is judged by its places and concepts (i, C); the switches are a nuisance).

The collapsed log joint of a run (``posterior.log_joint``) is log p(x, S, f, i, C, z | h) at the run's last
draw of z; its word part is the "W" term (concept tokens) and the "background" term (background tokens and the
switch counts).  The scores here:

* ``switch_mode_log_joint``: z at a local mode given (i, C) (iterated conditional modes).
* ``switch_marginal_log_joint``: z summed out, log p(x, S, f, i, C | h) = (the non-word terms) +
  log p(S | C, h) with log p(S | C, h) = log sum_z p(S, z | C, h), estimated by annealed importance
  sampling (``log_words_given_concepts``).  The estimate p-hat of p(S | C) is unbiased (E p-hat = p; Neal
  2001), so log p-hat is biased low by Jensen's inequality, by about half the variance of log p-hat; with
  enough annealing steps that variance is far below the differences between runs, and the same kind of bias
  applies to every run.
* ``switch_plugin_log_joint``: the word likelihood at the run's posterior-mean distributions with z summed per
  token, sum over tokens of log [lambda W_C(w) + (1 - lambda) B(w)] (the exported ``model.W``), plus the
  collapsed non-word terms.  A plug-in likelihood at parameters estimated from the same words is biased high
  against the marginal it stands in for, by an Occam factor that grows with the number of word distributions
  (about (V - 1) / 2 log n per concept): it favours runs with more concepts.
* ``tail_mean_log_joint``: the mean of the run's log joint over its last quarter of sweeps
  (``SpCoTMHP.log_joint_trace_``), an estimate of the expected log joint under the run's local posterior.  As
  an average over z of log p(..., z) it equals log p(x, S, f, i, C) - H(z | ...) on average (Jensen: a lower
  bound), so it also prices how uncertain a run's switches are.
"""

from __future__ import annotations

from math import exp, lgamma, log

import numpy as np
from numba import njit

from spcotmhp.errors import ModelError
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.learner_state import state_of_member
from spcotmhp.learning.online_split_merge import state_stats
from spcotmhp.learning.posterior import Priors, log_joint, log_joint_terms

SWITCH_PRIOR = 1.0  # Beta(1, 1) prior of the concept / background switch (as concepts.py)
CHAINS = 16
STEPS = 500
TAIL_FRACTION = 0.25
WORD_TERMS = ("W", "background")


def switch_mode_log_joint(estimator) -> float:
    """The collapsed log joint (``posterior.log_joint``) of a fitted run's final places and concepts with its
    background-word switches at a local mode (``CollapsedState.switch_mode``) instead of their last draw."""
    st, priors, trans = _final_state(estimator)
    st.switch_mode()
    return log_joint(priors, state_stats(st), trans)


def switch_marginal_log_joint(estimator, chains: int = CHAINS, steps: int = STEPS, seed: int = 0) -> float:
    """log p(x, S, f, i, C | h) of a fitted run's final sample with the switches summed out: the collapsed
    non-word terms plus ``log_words_given_concepts`` (module docstring); ``seed`` seeds its chains."""
    st, priors, trans = _final_state(estimator)
    if not st.background:
        return log_joint(priors, state_stats(st), trans)
    words, concepts = _tokens(st)
    rng = np.random.default_rng(seed)
    return _non_word_terms(st, priors, trans) + log_words_given_concepts(
        words, concepts, st.V, st.hyper.beta, rng, chains, steps
    )


def switch_plugin_log_joint(estimator) -> float:
    """The collapsed non-word terms plus the word likelihood at the posterior-mean mixture ``model.W`` (the
    switches summed per token; module docstring)."""
    st, priors, trans = _final_state(estimator)
    words, concepts = _tokens(st)
    W = estimator.model_.W
    return _non_word_terms(st, priors, trans) + float(np.log(W[concepts, words]).sum())


def tail_mean_log_joint(estimator, fraction: float = TAIL_FRACTION) -> float:
    """The mean of the last ``fraction`` of a run's per-sweep log joints (at least one)."""
    trace = np.asarray(estimator.log_joint_trace_, dtype=float)
    if not 0.0 < fraction <= 1.0 or trace.size == 0:
        raise ModelError(f"the tail fraction must be in (0, 1] and the trace non-empty, got {fraction}")
    return float(trace[-max(1, int(round(fraction * trace.size))) :].mean())


def log_words_given_concepts(
    words: np.ndarray,
    concepts: np.ndarray,
    V: int,
    beta: float,
    rng: np.random.Generator,
    chains: int = CHAINS,
    steps: int = STEPS,
) -> float:
    """Estimate of log p(S | C) = log sum_z p(S, z | C) for tokens ``words`` (T,) of events in concepts
    ``concepts`` (T,): each token is a concept token (z = 1, from W_C ~ Dir(beta)) or a background token (z = 0,
    from W_0 ~ Dir(beta)), z ~ Bernoulli(lambda), lambda ~ Beta(1, 1), every distribution integrated out.

    Annealed importance sampling (Neal 2001) from the prior p(z) to the posterior p(z | S, C): each of ``chains``
    chains starts from an exact draw of p(z), and at each of ``steps`` inverse temperatures 0 < b_1 < ... < b_K
    = 1 (b_k = (k / K)^4, dense near the prior) adds (b_k - b_{k-1}) log p(S | z, C) to its log weight, then
    makes one Gibbs sweep over the switches under p(z) p(S | z, C)^b_k.  The mean weight is unbiased for
    p(S | C)."""
    words = np.asarray(words, dtype=np.int64)
    if words.ndim != 1 or words.shape != np.shape(concepts) or chains < 1 or steps < 1:
        raise ModelError("words and concepts must be equal-length 1-D arrays; chains and steps must be >= 1")
    if words.size == 0:
        return 0.0
    _, compact = np.unique(np.asarray(concepts, dtype=np.int64), return_inverse=True)
    L = int(compact.max()) + 1
    temps = (np.arange(steps + 1) / steps) ** 4
    seed = int(rng.integers(2**31 - 1))
    logw = _ais(words, compact.astype(np.int64), L, V, beta, chains, temps, seed)
    m = logw.max()
    return float(m + np.log(np.mean(np.exp(logw - m))))


@njit(cache=True)
def _ais(words, concepts, L, V, beta, chains, temps, seed):  # pragma: no cover - numba
    """The log weights of the AIS chains (``log_words_given_concepts``)."""
    np.random.seed(seed)  # numba's own generator (one per thread), seeded for this call
    T = words.shape[0]
    N = np.zeros((L, V))
    for t in range(T):
        N[concepts[t], words[t]] += 1.0
    logw = np.zeros(chains)
    for n in range(chains):
        Wc, Wt, Bg = np.zeros((L, V)), np.zeros(L), np.zeros(V)
        z = np.zeros(T, np.bool_)
        lam = np.random.random()  # an exact draw of p(z): lambda ~ Beta(1, 1), then z_t ~ Bernoulli(lambda)
        ell = 0.0  # log p(S | z, C), built token by token (the chain rule of the Dirichlet-multinomials)
        for t in range(T):
            v, c = words[t], concepts[t]
            z[t] = np.random.random() < lam
            if z[t]:
                ell += log((Wc[c, v] + beta) / (Wt[c] + V * beta))
                Wc[c, v] += 1.0
                Wt[c] += 1.0
            else:
                ell += log((Bg[v] + beta) / (Bg.sum() + V * beta))
                Bg[v] += 1.0
        n1 = float(z.sum())
        for k in range(1, temps.shape[0]):
            logw[n] += (temps[k] - temps[k - 1]) * ell
            ell, n1 = _tempered_sweep(words, concepts, V, beta, temps[k], z, Wc, Wt, Bg, n1, ell)
            ell, n1 = _word_flips(words, concepts, V, beta, temps[k], z, Wc, Wt, Bg, N, n1, ell, -1)
            for c in range(L):
                ell, n1 = _word_flips(words, concepts, V, beta, temps[k], z, Wc, Wt, Bg, N, n1, ell, c)
    return logw


@njit(cache=True)
def _word_flips(words, concepts, V, beta, b, z, Wc, Wt, Bg, N, n1, ell, only):  # pragma: no cover - numba
    """For each word v, a Metropolis-Hastings move that flips the switch of every token of v (of concept
    ``only``, or of every concept when it is -1): an involution, so a symmetric proposal, under
    p(z) p(S | z, C)^b.  It moves between "v is a background word" and "v is a concept word", which single-token
    Gibbs steps cross only through improbable mixed states.  ``N`` (L, V) are the tokens per concept and word.
    Returns the new log p(S | z, C) and number of concept tokens."""
    L, T = Wc.shape[0], words.shape[0]
    lo, hi = (0, L) if only < 0 else (only, only + 1)
    Bt = Bg.sum()
    for v in range(V):
        n_v = N[lo:hi, v].sum()
        if n_v == 0.0:
            continue
        on_v = Wc[lo:hi, v].sum()
        bg_new = Bg[v] - (n_v - on_v) + on_v
        d_ell = _lg_bg(bg_new, Bt - Bg[v] + bg_new, beta, V) - _lg_bg(Bg[v], Bt, beta, V)
        for l in range(lo, hi):
            if N[l, v] > 0.0:
                new = N[l, v] - Wc[l, v]
                d_ell += _lg_bg(new, Wt[l] - Wc[l, v] + new, beta, V) - _lg_bg(Wc[l, v], Wt[l], beta, V)
        n1_new = n1 - on_v + (n_v - on_v)
        d_prior = lgamma(1.0 + n1_new) + lgamma(1.0 + T - n1_new) - lgamma(1.0 + n1) - lgamma(1.0 + T - n1)
        if log(np.random.random()) < d_prior + b * d_ell:
            for t in range(T):
                if words[t] == v and (only < 0 or concepts[t] == only):
                    z[t] = not z[t]
            for l in range(lo, hi):
                new = N[l, v] - Wc[l, v]
                Wt[l] += new - Wc[l, v]
                Wc[l, v] = new
            Bt += bg_new - Bg[v]
            Bg[v] = bg_new
            ell += d_ell
            n1 = n1_new
    return ell, n1


@njit(cache=True)
def _lg_bg(count, total, beta, V):  # pragma: no cover - numba
    """The part of a Dirichlet-multinomial's log marginal that depends on one entry's count and the total."""
    return lgamma(beta + count) - lgamma(V * beta + total)


@njit(cache=True)
def _tempered_sweep(words, concepts, V, beta, b, z, Wc, Wt, Bg, n1, ell):  # pragma: no cover - numba
    """One Gibbs sweep over the switches under p(z) p(S | z, C)^b; returns the new log p(S | z, C) and the
    number of concept tokens."""
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
        la1 = log((Wc[c, v] + beta) / (Wt[c] + V * beta))
        la0 = log((Bg[v] + beta) / (Bt + V * beta))
        l1 = log(n1 + SWITCH_PRIOR) + b * la1
        l0 = log(T - 1 - n1 + SWITCH_PRIOR) + b * la0
        on = np.random.random() * (1.0 + exp(l0 - l1)) < 1.0
        ell += (la1 if on else la0) - (la1 if z[t] else la0)
        z[t] = on
        if on:
            Wc[c, v] += 1.0
            Wt[c] += 1.0
            n1 += 1.0
        else:
            Bg[v] += 1.0
            Bt += 1.0
    return ell, n1


def _final_state(estimator) -> tuple[CollapsedState, Priors, np.ndarray | None]:
    """The collapsed state of a run's final sample, its priors and (with transitions) event transitions."""
    model = estimator.model_
    if model.learner is None:
        raise ModelError("the run keeps no final sample (learner member) to score")
    st = state_of_member(model.learner, model)
    priors = Priors.build(st.hyper, st.K, st.L, st.V, st.D)
    return st, priors, st.trans if estimator.transitions == "hmm" else None


def _non_word_terms(st: CollapsedState, priors: Priors, trans: np.ndarray | None) -> float:
    """The collapsed log joint's terms but the words' (positions, pi, phi, theta, psi)."""
    terms = log_joint_terms(priors, state_stats(st), trans)
    return float(sum(v for k, v in terms.items() if k not in WORD_TERMS))


def _tokens(st: CollapsedState) -> tuple[np.ndarray, np.ndarray]:
    """Every token's word and its event's concept, in event order."""
    lengths = np.array([len(t) for t in st.tokens], dtype=np.int64)
    words = np.concatenate(st.tokens).astype(np.int64) if st.tokens else np.zeros(0, np.int64)
    return words, np.repeat(st.concept, lengths)


__all__ = [
    "log_words_given_concepts",
    "switch_marginal_log_joint",
    "switch_mode_log_joint",
    "switch_plugin_log_joint",
    "tail_mean_log_joint",
]

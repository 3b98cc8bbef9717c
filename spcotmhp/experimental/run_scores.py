"""Scores of one fitted Gibbs run by which the research run-selection criteria (experimental/selection.py)
compare runs, each with the background-word switches z
handled in its own way (a run is judged by its places and concepts (i, C); the switches are a nuisance).

The collapsed log joint of a run (``posterior.log_joint``) is log p(x, S, f, i, C, z | h) at the run's last
draw of z; its word part is the "W" term (concept tokens) and the "background" term (background tokens and the
switch counts).  The scores here:

* ``switch_mode_log_joint``: z at a local mode given (i, C) (iterated conditional modes).
* ``switch_marginal_log_joint``: z summed out, log p(x, S, f, i, C | h) = (the non-word terms) +
  log p(S | C, h) with log p(S | C, h) = log sum_z p(S, z | C, h), by Chib's estimator with the concepts' word
  distributions and the switches summed exactly given the background distribution
  (``switch_marginal.log_words_given_concepts``; its bias and error are stated there).
* ``switch_plugin_log_joint``: the word likelihood at the run's posterior-mean distributions with z summed per
  token, sum over tokens of log [lambda W_C(w) + (1 - lambda) B(w)] (the exported ``model.W``), plus the
  collapsed non-word terms.  A plug-in likelihood at parameters estimated from the same words is biased high
  against the marginal it stands in for, by an Occam factor that grows with the number of word distributions
  (about (V - 1) / 2 log n per concept): it favours runs with more concepts.
* ``held_out_words``: cross-validation (Stone 1977): the sum over events of log p(S_e | x_e, everything but
  event e), each event's words predicted from its position alone by the run's other events, summed over the
  place and concept it would take: how well a run's places and concepts tell which words are said where, the
  link the planner uses.  A held-out predictive carries its own Occam factor: a run that merges two names
  into one concept or place predicts their mixture, one that splits a room predicts from fewer events.
* ``tail_mean_log_joint``: the mean of the run's log joint over its last quarter of sweeps
  (``SpCoTMHP.log_joint_trace_``), an estimate of the expected log joint under the run's local posterior.  As
  an average over z of log p(..., z) it equals log p(x, S, f, i, C) - H(z | ...) on average (Jensen: a lower
  bound), so it also prices how uncertain a run's switches are.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.errors import ModelError
from spcotmhp.experimental.off_name import OffNamePlaces
from spcotmhp.experimental.switch_marginal import log_words_given_concepts
from spcotmhp.learning.collapsed import CollapsedState
from spcotmhp.learning.learner_state import state_of_member
from spcotmhp.learning.online_split_merge import state_stats
from spcotmhp.learning.posterior import ExtraTerms, Priors, log_joint, log_joint_terms
from spcotmhp.logspace import logsumexp

SWITCH_PRIOR = 1.0  # Beta(1, 1) prior of the concept / background switch (as concepts.py)
TAIL_FRACTION = 0.25
WORD_TERMS = ("W", "background")


def switch_mode_log_joint(estimator) -> float:
    """The collapsed log joint (``posterior.log_joint``) of a fitted run's final places and concepts with its
    background-word switches at a local mode (``CollapsedState.switch_mode``) instead of their last draw."""
    st, priors, trans = _final_state(estimator)
    st.switch_mode()
    return log_joint(priors, state_stats(st), trans, _extra(st))


def switch_marginal_log_joint(estimator, seed: int = 0) -> float:
    """log p(x, S, f, i, C | h) of a fitted run's final sample with the switches summed out: the collapsed
    non-word terms plus ``switch_marginal.log_words_given_concepts``, its switch chain started from the run's
    final switches and seeded with ``seed``."""
    st, priors, trans = _final_state(estimator)
    if not st.background:
        return log_joint(priors, state_stats(st), trans, _extra(st))
    words, concepts = _tokens(st)
    z = np.concatenate(st.z) if st.z else np.zeros(0, dtype=bool)
    rng = np.random.default_rng(seed)
    return _non_word_terms(st, priors, trans) + log_words_given_concepts(
        words, concepts, st.V, st.hyper.beta, rng, switches=z
    )


def switch_plugin_log_joint(estimator) -> float:
    """The collapsed non-word terms plus the word likelihood at the posterior-mean mixture ``model.W`` (the
    switches summed per token; module docstring)."""
    st, priors, trans = _final_state(estimator)
    words, concepts = _tokens(st)
    W = estimator.model_.W
    return _non_word_terms(st, priors, trans) + float(np.log(W[concepts, words]).sum())


def held_out_words(estimator) -> float:
    """Sum over events e of log p(S_e | x_e, the other events' assignments and data) under a fitted run's final
    sample (``held_out_event``, each event taken out of the counts in turn)."""
    st, _, _ = _final_state(estimator)
    total = 0.0
    for e in range(st.E):
        k, l = st.place[e], st.concept[e]
        st.move(e, -1.0)
        total += held_out_event(st, e)
        st.place[e], st.concept[e] = k, l
        st.move(e, 1.0)
    return total


def held_out_event(st: CollapsedState, e: int) -> float:
    """log p(S_e | x_e, rest) for event e, out of the counts of ``st``:
    sum_{k, l} p(l) phi_l(k) t(x_e | k) p(S_e | l) / sum_{k, l} p(l) phi_l(k) t(x_e | k), every parameter
    integrated out given the other events (the generative order of Eqs. 5-17 without transitions; image
    features left out), each token's switch summed out at the predictive values:
    p(w | l) = lambda W_l(w) + (1 - lambda) W_0(w)."""
    h = st.hyper
    log_pl = np.log(st.n_l + h.alpha) + np.log((st.n_lk + h.gamma) / (st.n_l + st.K * h.gamma)[:, None]).T
    prior = st.log_predictive(st.X[e])[:, None] + log_pl  # (K, L)
    lam = (st.z_tot[1] + SWITCH_PRIOR) / (st.z_tot.sum() + 2.0 * SWITCH_PRIOR)
    concept = (st.W_lv + h.beta) / (st.W_lv.sum(axis=1) + st.V * h.beta)[:, None]
    background = (st.bg_v + h.beta) / (st.bg_v.sum() + st.V * h.beta)
    words = np.log(lam * concept[:, st.tokens[e]] + (1.0 - lam) * background[st.tokens[e]]).sum(axis=1)
    return float(logsumexp((prior + words[None, :]).ravel()) - logsumexp(prior.ravel()))


def tail_mean_log_joint(estimator, fraction: float = TAIL_FRACTION) -> float:
    """The mean of the last ``fraction`` of a run's per-sweep log joints (at least one)."""
    trace = np.asarray(estimator.log_joint_trace_, dtype=float)
    if not 0.0 < fraction <= 1.0 or trace.size == 0:
        raise ModelError(f"the tail fraction must be in (0, 1] and the trace non-empty, got {fraction}")
    return float(trace[-max(1, int(round(fraction * trace.size))) :].mean())


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
    terms = log_joint_terms(priors, state_stats(st), trans, _extra(st))
    return float(sum(v for k, v in terms.items() if k not in WORD_TERMS))


def _extra(st: CollapsedState) -> ExtraTerms | None:
    """The off-name term of a run fitted with it (the log joint its sampler reported carries it)."""
    return None if st.hyper.off_name is None else OffNamePlaces(st.hyper.off_name, st.K, st.L).log_terms


def _tokens(st: CollapsedState) -> tuple[np.ndarray, np.ndarray]:
    """Every token's word and its event's concept, in event order."""
    lengths = np.array([len(t) for t in st.tokens], dtype=np.int64)
    words = np.concatenate(st.tokens).astype(np.int64) if st.tokens else np.zeros(0, np.int64)
    return words, np.repeat(st.concept, lengths)


__all__ = [
    "held_out_event",
    "held_out_words",
    "switch_marginal_log_joint",
    "switch_mode_log_joint",
    "switch_plugin_log_joint",
    "tail_mean_log_joint",
]

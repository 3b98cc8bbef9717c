"""HMM pieces of the place layer: blocked sampling of the event place sequence, transition counts, and the
place sequence of a continuous trajectory.

Section 3.2: with utterances observed only at event times, inference of i_{1:E} "is equivalent to a HMM" with
transitions psi and, per event, the emission N(x_e | mu_k, Sigma_k) phi[C_e, k] / sum_c phi[c, k] (Eq. 9).
Forward filtering, backward sampling (FFBS) draws the whole sequence i_{1:E} jointly from that conditional,
which mixes far better than resampling one i_e at a time.

Transition counts come from the event sequence, plus (reverse replay, Section 3.2) the reversed sequence,
plus (when the dataset has a trajectory) the places visited along the trajectory: each pose is given its most
probable place, argmax_k N(x_t | mu_k, Sigma_k) p(k) with p(k) = sum_l pi_l phi_l(k) over the places holding
events (``hmm.trajectory_places``, the same labelling as ``connectivity.walk_adjacency``), runs shorter than
``min_dwell`` poses are dropped as boundary flicker, consecutive repeats collapse, and every remaining place
change a -> b counts ``trajectory_weight`` (and b -> a as well under reverse replay).  Each traversal of a
doorway thus counts like one observed event transition.  During sampling the labelling uses the current draw
of the Gaussians and the posterior-mean p(k) of the current counts; for the exported psi it uses the exported
means, so the exported psi is the posterior mean of Dir(omega + counts) for counts consistent with the
exported places.  (The Gibbs sampler, :mod:`spcotmhp.learning.gibbs`, uses these counts in its step 3.)
"""

from __future__ import annotations

import numpy as np
from numba import njit

from spcotmhp.learning.territory import posterior_arg_max
from spcotmhp.logspace import logsumexp_vector

EMIT_FLOOR = 60.0
"""Nats below an event's best emission under which a state is dropped from the forward pass (``_forward_scaled``)."""


@njit(cache=True)
def _forward_scaled(log_emit, log_trans, log_init, alpha):
    """Forward pass in probability space, each step scaled by its row maximum; alpha[e] holds log filtered
    probabilities up to a constant per e.  Returns False when a step underflows (then use the log pass).

    Sparse: a state whose emission is more than :data:`EMIT_FLOOR` nats below the event's best (a Gaussian many
    standard deviations away, relative weight under 1e-26) gets filtered probability 0 without its sum, and
    the sum runs over the states of non-zero filtered probability only, in the same order (the terms left out
    are exact zeros), at a cost of (places near x_e) x (places near x_{e-1}) per event instead of K^2. Only
    the floor departs from the dense product; the draws on the bundled datasets are the same.
    The first event and the log-space fallback stay dense."""
    E, K = log_emit.shape
    into = np.exp(log_trans).T.copy()  # into[k, j] = p(k | j): a contiguous row per target state
    prev = np.empty(K)
    cur = np.empty(K)
    support = np.empty(K, dtype=np.int64)
    m = (log_init + log_emit[0]).max()
    for k in range(K):
        prev[k] = np.exp(log_init[k] + log_emit[0, k] - m)
        alpha[0, k] = np.log(prev[k]) if prev[k] > 0 else -np.inf
    for e in range(1, E):
        me = log_emit[e].max()
        n = 0
        for j in range(K):
            if prev[j] != 0.0:
                support[n] = j
                n += 1
        total = 0.0
        for k in range(K):
            if log_emit[e, k] - me < -EMIT_FLOOR:
                cur[k] = 0.0
                continue
            scale = np.exp(log_emit[e, k] - me)
            acc = 0.0
            for t in range(n):
                acc += prev[support[t]] * into[k, support[t]]
            cur[k] = acc * scale
            total += cur[k]
        if not total > 1e-280:
            return False
        for k in range(K):
            prev[k] = cur[k] / total
            alpha[e, k] = np.log(prev[k]) if prev[k] > 0 else -np.inf
    return True


@njit(cache=True)
def _forward_log(log_emit, log_trans, log_init, alpha):
    E, K = log_emit.shape
    alpha[0] = log_init + log_emit[0]
    tmp = np.empty(K)
    for e in range(1, E):
        for k in range(K):
            for j in range(K):
                tmp[j] = alpha[e - 1, j] + log_trans[j, k]
            alpha[e, k] = logsumexp_vector(tmp) + log_emit[e, k]


@njit(cache=True)
def ffbs_kernel(log_emit: np.ndarray, log_trans: np.ndarray, log_init: np.ndarray, uniforms: np.ndarray) -> np.ndarray:
    """Forward filtering, backward sampling.

    log_emit (E, K), log_trans (K, K) with log_trans[a, b] = log p(b | a), log_init (K,), uniforms (E,) in [0, 1).
    Returns a state sequence (E,) drawn from p(i_{1:E} | emissions) exactly.  The forward pass runs on scaled
    probabilities (a matrix-vector product per event) and falls back to log space if a step underflows.
    """
    E, K = log_emit.shape
    alpha = np.empty((E, K))
    if not _forward_scaled(log_emit, log_trans, log_init, alpha):
        _forward_log(log_emit, log_trans, log_init, alpha)
    states = np.empty(E, dtype=np.int64)
    w = np.empty(K)
    for e in range(E - 1, -1, -1):
        for k in range(K):
            w[k] = alpha[e, k]
            if e < E - 1:
                w[k] += log_trans[k, states[e + 1]]
        m = w.max()
        total = 0.0
        for k in range(K):
            w[k] = np.exp(w[k] - m)
            total += w[k]
        target = uniforms[e] * total
        acc = 0.0
        s = K - 1
        for k in range(K):
            acc += w[k]
            if acc > target:
                s = k
                break
        states[e] = s
    return states


def ffbs(log_emit: np.ndarray, log_trans: np.ndarray, log_init: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Draw i_{1:E} from the HMM posterior (see ``ffbs_kernel``); seeded through ``rng``. The Gibbs sweep uses
    :func:`~spcotmhp.learning.place_ffbs.sample_places`, the same draws with the emissions of Eq. 9 computed in
    the kernel."""
    return ffbs_kernel(
        np.ascontiguousarray(log_emit, dtype=np.float64),
        np.ascontiguousarray(log_trans, dtype=np.float64),
        np.ascontiguousarray(log_init, dtype=np.float64),
        rng.random(int(log_emit.shape[0])),
    )


def transition_counts(seq: np.ndarray, K: int, reverse_replay: bool = False) -> np.ndarray:
    """n[a, b] = number of e with seq[e-1] = a and seq[e] = b; with reverse replay (Section 3.2) the reversed
    sequence i'_{E:1} is counted too, which adds the transposed counts."""
    n = np.zeros((K, K))
    if len(seq) > 1:
        np.add.at(n, (seq[:-1], seq[1:]), 1.0)
    return n + n.T if reverse_replay else n


def runs(labels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Run-length encoding of a label sequence: (label of each run, its length)."""
    labels = np.asarray(labels)
    if len(labels) == 0:
        return labels, np.zeros(0, dtype=np.int64)
    starts = np.concatenate(([0], np.flatnonzero(np.diff(labels)) + 1))
    return labels[starts], np.diff(np.concatenate((starts, [len(labels)])))


def dwell_filtered_sequence(labels: np.ndarray, min_dwell: float) -> np.ndarray:
    """The sequence of places visited along a per-pose label sequence: runs shorter than ``min_dwell`` poses are
    dropped (flicker at a boundary between two places is not a visit), then consecutive duplicates collapse."""
    run_labels, lengths = runs(labels)
    kept = run_labels[lengths >= min_dwell]
    if len(kept) == 0:
        return kept
    return kept[np.concatenate(([True], kept[1:] != kept[:-1]))]


def trajectory_places(
    trajectory: np.ndarray, mu: np.ndarray, Sigma: np.ndarray, log_prior: np.ndarray, min_dwell: int = 3
) -> np.ndarray:
    """The places visited along ``trajectory`` (T, 2): each pose gets its most probable place,
    argmax_k N(x_t | mu_k, Sigma_k) p(k) over the places with p(k) > 0 (``log_prior`` -inf elsewhere; cf. Eq. 3;
    compiled, :func:`~spcotmhp.learning.territory.posterior_arg_max`, without a (T, K) table), then
    ``dwell_filtered_sequence``.  The one labelling used by the sampler (current draws, place prior of the
    current counts), the exported psi and the walk adjacency (a model's means and ``log_place_prior``)."""
    active = np.flatnonzero(np.isfinite(log_prior))
    if not len(active):
        return active
    best = posterior_arg_max(
        np.asarray(trajectory, dtype=float).reshape(-1, 2), mu[active], Sigma[active], log_prior[active]
    )
    return active[dwell_filtered_sequence(best, min_dwell)]

"""Step 4 of the Gibbs sweep compiled: the event places i_{1:E} drawn by FFBS with the emissions of Eq. 9
computed on the fly (gibbs.py, ``SpCoTMHP._sample_places``).

The emission of place k at event e is

    log N(x_e | mu_k, Sigma_k) + log phi[C_e, k] - log sum_c phi[c, k]        (Eqs. 3, 8-9, unigram rescaling)

and the draw is forward filtering, backward sampling over the HMM with transitions psi (Eq. 7), as
:func:`~spcotmhp.learning.hmm.ffbs_kernel`, with the same arithmetic in the same order, so the same uniforms
give the same places bit for bit (tested). What changes is the bookkeeping: no (E, K) table of emissions or
filtered probabilities is written. Each event's emissions are computed into one row (the Gaussian term with the
arithmetic of :func:`~spcotmhp.logspace.log_gaussian`, from contiguous columns of the means and
covariances); the forward pass keeps, per event, only the states of non-zero filtered probability (the states
within :data:`~spcotmhp.learning.hmm.EMIT_FLOOR` nats of the event's best emission that some state of the previous event
can reach), in a compressed row list; and the backward pass draws from those states only (the others have weight
exactly 0 in the dense draw, and adding 0 changes no partial sum). When a step underflows, the dense emissions
are built and the dense kernel (with its log-space fallback) draws instead, as before.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from spcotmhp.learning.hmm import EMIT_FLOOR, ffbs_kernel
from spcotmhp.logspace import gaussian_log_density, log_gaussian, logsumexp

__all__ = ["place_emissions", "sample_places"]

DONE, UNDERFLOW, FULL = 0, 1, 2  # outcomes of the sparse forward pass


@njit(cache=True)
def _columns(mu, Sigma):  # pragma: no cover - numba
    """mu_k and the entries of Sigma_k as contiguous columns (K,) each: x, y of the mean, a, b + c, d of the
    covariance [[a, b], [c, d]], so that a row of emissions is one contiguous loop."""
    K = mu.shape[0]
    m0, m1, sa, sbc, sd = np.empty(K), np.empty(K), np.empty(K), np.empty(K), np.empty(K)
    for k in range(K):
        m0[k], m1[k] = mu[k, 0], mu[k, 1]
        sa[k], sbc[k], sd[k] = Sigma[k, 0, 0], Sigma[k, 0, 1] + Sigma[k, 1, 0], Sigma[k, 1, 1]
    return m0, m1, sa, sbc, sd


@njit(cache=True)
def _emission_row(X, e, c, cols, det, log_det, log_phi, log_norm, row):  # pragma: no cover - numba
    """The emissions of event e (concept c) at every place into ``row`` (K,): Eq. 9, with the Gaussian term
    evaluated exactly as :func:`~spcotmhp.logspace.log_gaussian` does (``cols`` from ``_columns``)."""
    m0, m1, sa, sbc, sd = cols
    x0, x1 = X[e, 0], X[e, 1]
    for k in range(row.shape[0]):
        dx = x0 - m0[k]
        dy = x1 - m1[k]
        row[k] = (gaussian_log_density(dx, dy, sa[k], sbc[k], sd[k], det[k], log_det[k]) + log_phi[c, k]) - log_norm[k]


@njit(cache=True)
def _dense_emissions(X, concepts, mu, Sigma, det, log_det, log_phi, log_norm):  # pragma: no cover - numba
    out = np.empty((X.shape[0], mu.shape[0]))
    cols = _columns(mu, Sigma)
    for e in range(X.shape[0]):
        _emission_row(X, e, concepts[e], cols, det, log_det, log_phi, log_norm, out[e])
    return out


@njit(cache=True)
def _first_event(row, log_init, prev, ptr, idx, val):  # pragma: no cover - numba
    """Filtered probabilities of event 0 (dense, scaled by the maximum) into ``prev`` and the row list."""
    m = (log_init + row).max()
    n = 0
    for k in range(row.shape[0]):
        prev[k] = np.exp(log_init[k] + row[k] - m)
        if prev[k] > 0:
            idx[n] = k
            val[n] = np.log(prev[k])
            n += 1
    ptr[1] = n


@njit(cache=True)
def _sparse_forward(
    X, concepts, mu, Sigma, det, log_det, log_phi, log_norm, log_trans, log_init, ptr, idx, val
):  # pragma: no cover - numba
    """Forward pass of :func:`~spcotmhp.learning.hmm.ffbs_kernel` (scaled, floored) that stores, per event e,
    the states of non-zero filtered probability in ``idx[ptr[e]:ptr[e + 1]]`` (increasing) and their log
    filtered probabilities (up to a constant per e) in ``val``. Returns :data:`DONE`, :data:`UNDERFLOW` when a
    step underflows, or :data:`FULL` when ``idx`` has no room left."""
    E, K = X.shape[0], mu.shape[0]
    into = np.exp(log_trans).T.copy()  # into[k, j] = p(k | j): a contiguous row per target state
    cols = _columns(mu, Sigma)
    row = np.empty(K)
    prev = np.zeros(K)
    cur = np.empty(K)
    cand = np.empty(K, dtype=np.int64)
    _emission_row(X, 0, concepts[0], cols, det, log_det, log_phi, log_norm, row)
    ptr[0] = 0
    _first_event(row, log_init, prev, ptr, idx, val)
    for e in range(1, E):
        _emission_row(X, e, concepts[e], cols, det, log_det, log_phi, log_norm, row)
        me = row.max()
        n = 0
        for k in range(K):
            if not row[k] - me < -EMIT_FLOOR:
                cand[n] = k
                n += 1
        lo, hi = ptr[e - 1], ptr[e]
        total = 0.0
        for t in range(n):
            k = cand[t]
            scale = np.exp(row[k] - me)
            acc = 0.0
            for q in range(lo, hi):
                acc += prev[idx[q]] * into[k, idx[q]]
            cur[k] = acc * scale
            total += cur[k]
        if not total > 1e-280:
            return UNDERFLOW
        if hi + n > idx.shape[0]:
            return FULL
        for t in range(lo, hi):
            prev[idx[t]] = 0.0
        out = hi
        for t in range(n):
            k = cand[t]
            prev[k] = cur[k] / total
            if prev[k] > 0:
                idx[out] = k
                val[out] = np.log(prev[k])
                out += 1
        ptr[e + 1] = out
    return DONE


@njit(cache=True)
def _sparse_backward(log_trans, uniforms, K, ptr, idx, val):  # pragma: no cover - numba
    """Backward sampling of :func:`~spcotmhp.learning.hmm.ffbs_kernel` over the stored states only."""
    E = ptr.shape[0] - 1
    states = np.empty(E, dtype=np.int64)
    w = np.empty(K)
    for e in range(E - 1, -1, -1):
        lo, hi = ptr[e], ptr[e + 1]
        m = -np.inf
        for t in range(lo, hi):
            w[t - lo] = val[t]
            if e < E - 1:
                w[t - lo] += log_trans[idx[t], states[e + 1]]
            m = max(m, w[t - lo])
        total = 0.0
        for t in range(hi - lo):
            w[t] = np.exp(w[t] - m)
            total += w[t]
        target = uniforms[e] * total
        acc = 0.0
        s = K - 1
        for t in range(hi - lo):
            acc += w[t]
            if acc > target:
                s = idx[lo + t]
                break
        states[e] = s
    return states


def _gaussian_terms(mu: np.ndarray, Sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """mu and Sigma as contiguous float arrays, det Sigma_k and its log (the numbers of ``log_gaussian``); raises
    ValueError for a covariance that is not positive definite, as ``log_gaussian`` does."""
    mu = np.ascontiguousarray(mu, dtype=np.float64)
    Sigma = np.ascontiguousarray(Sigma, dtype=np.float64)
    log_gaussian(mu[:1], mu, Sigma)  # checks the covariances
    det = Sigma[:, 0, 0] * Sigma[:, 1, 1] - Sigma[:, 0, 1] * Sigma[:, 1, 0]
    return mu, Sigma, det, np.log(det)


def place_emissions(
    X: np.ndarray, concepts: np.ndarray, mu: np.ndarray, Sigma: np.ndarray, log_phi: np.ndarray, log_norm: np.ndarray
) -> np.ndarray:
    """(E, K) emissions of Eq. 9: log N(x_e | mu_k, Sigma_k) + log_phi[C_e, k] - log_norm[k], the numbers of
    ``log_gaussian(X, mu, Sigma) + log_phi[concepts] - log_norm``."""
    mu, Sigma, det, log_det = _gaussian_terms(mu, Sigma)
    X = np.ascontiguousarray(X, dtype=np.float64)
    return _dense_emissions(X, np.asarray(concepts, dtype=np.int64), mu, Sigma, det, log_det, log_phi, log_norm)


def sample_places(
    X: np.ndarray,
    concepts: np.ndarray,
    mu: np.ndarray,
    Sigma: np.ndarray,
    log_phi: np.ndarray,
    log_trans: np.ndarray,
    log_init: np.ndarray,
    rng: np.random.Generator,
    log_eta: np.ndarray | None = None,
) -> np.ndarray:
    """i_{1:E} drawn from the HMM posterior of Eq. 9 (module docstring): the draw of
    ``hmm.ffbs(place_emissions(X, concepts, mu, Sigma, log_phi, logsumexp(log_phi, axis=0)), log_trans,
    log_init, rng)``, the same random numbers used the same way.

    ``log_eta`` (K, L), the opt-in ``Hyperparameters.place_concepts`` term (not the paper's): event e's emission
    at place k gains log eta[k, C_e], carried in the phi term as log phi[c, k] + log eta[k, c] while the unigram
    rescaling of Eq. 9 stays sum_c phi[c, k].  None (or zeros) draws the paper's places, bit for bit."""
    log_phi = np.ascontiguousarray(log_phi, dtype=np.float64)
    log_norm = np.ascontiguousarray(logsumexp(log_phi, axis=0), dtype=np.float64)  # unigram rescaling, Eq. 9
    if log_eta is not None:
        log_phi = np.ascontiguousarray(log_phi + np.asarray(log_eta, dtype=np.float64).T)
    log_trans = np.ascontiguousarray(log_trans, dtype=np.float64)
    log_init = np.ascontiguousarray(log_init, dtype=np.float64)
    mu, Sigma, det, log_det = _gaussian_terms(mu, Sigma)
    X = np.ascontiguousarray(X, dtype=np.float64)
    concepts = np.asarray(concepts, dtype=np.int64)
    E, K = X.shape[0], mu.shape[0]
    uniforms = rng.random(int(E))
    if E == 0:
        return np.zeros(0, dtype=np.int64)
    ptr = np.empty(E + 1, dtype=np.int64)
    room = min(E * K, 8 * E + K)  # the states kept per event are a few; all K at worst (then a second pass)
    while True:
        idx, val = np.empty(room, dtype=np.int64), np.empty(room)
        args = (X, concepts, mu, Sigma, det, log_det, log_phi, log_norm, log_trans, log_init, ptr, idx, val)
        status = _sparse_forward(*args)
        if status != FULL or room == E * K:
            break
        room = E * K
    if status == DONE:
        return _sparse_backward(log_trans, uniforms, K, ptr, idx, val)
    log_emit = _dense_emissions(X, concepts, mu, Sigma, det, log_det, log_phi, log_norm)
    return ffbs_kernel(log_emit, log_trans, log_init, uniforms)

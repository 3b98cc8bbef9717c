"""Step 4 compiled (place_ffbs.py) against the numpy emissions and the dense FFBS kernel: the same numbers and the
same draws, bit for bit, including the underflow fallback."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.learning.hmm import ffbs
from spcotmhp.learning.place_ffbs import FULL, UNDERFLOW, _sparse_forward, place_emissions, sample_places
from spcotmhp.logspace import log_gaussian, logsumexp


def _case(seed: int, K: int, L: int, E: int, spread: float):
    rng = np.random.default_rng(seed)
    mu = rng.uniform(0, 30, (K, 2))
    A = rng.normal(size=(K, 2, 2)) * rng.uniform(0.1, spread, (K, 1, 1))
    Sigma = A @ A.transpose(0, 2, 1) + 0.05 * np.eye(2)
    X = np.clip(np.cumsum(rng.normal(scale=1.5, size=(E, 2)), axis=0) + 15, 0, 30)
    concepts = rng.integers(0, L, E)
    log_phi = np.log(rng.dirichlet(np.full(K, 0.2), size=L))
    log_trans = np.log(rng.dirichlet(np.full(K, 0.3), size=K))
    return rng, X, concepts, mu, Sigma, log_phi, log_trans


@settings(max_examples=40, deadline=None, derandomize=True)
@given(st.integers(0, 2**31), st.integers(1, 30), st.integers(1, 6), st.integers(1, 120), st.sampled_from([0.3, 3.0]))
def test_compiled_place_step_draws_what_the_numpy_emissions_and_dense_ffbs_draw(seed, K, L, E, spread):
    rng, X, concepts, mu, Sigma, log_phi, log_trans = _case(seed, K, L, E, spread)
    norm = logsumexp(log_phi, axis=0)
    want_emit = log_gaussian(X, mu, Sigma) + log_phi[concepts] - norm
    assert np.array_equal(place_emissions(X, concepts, mu, Sigma, log_phi, norm), want_emit)
    log_init = np.full(K, -np.log(K))
    state = rng.bit_generator.state
    got = sample_places(X, concepts, mu, Sigma, log_phi, log_trans, log_init, rng)
    rng.bit_generator.state = state
    assert np.array_equal(got, ffbs(want_emit, log_trans, log_init, rng))


def test_underflow_falls_back_to_the_dense_kernel():
    # event 3 sits on place 1, which no state can enter; place 0 is hundreds of nats away: the scaled pass
    # underflows and the dense kernel (log-space pass) draws
    rng, X, concepts, mu, Sigma, log_phi, log_trans = _case(5, 3, 2, 6, 0.3)
    mu[:] = [[0.0, 0.0], [20.0, 0.0], [40.0, 0.0]]
    Sigma[:] = np.eye(2)
    X[:] = [[0.0, 0.0], [0.5, 0.0], [1.0, 0.0], [20.0, 0.0], [19.0, 0.0], [18.0, 0.0]]
    log_trans[:, 1] = -1e6
    log_init = np.full(3, -np.log(3))
    norm = logsumexp(log_phi, axis=0)
    emit = place_emissions(X, concepts, mu, Sigma, log_phi, norm)
    ptr, idx, val = np.empty(7, dtype=np.int64), np.empty(18, dtype=np.int64), np.empty(18)
    args = (np.ascontiguousarray(log_phi), norm, log_trans, log_init, ptr, idx, val)
    det = Sigma[:, 0, 0] * Sigma[:, 1, 1] - Sigma[:, 0, 1] * Sigma[:, 1, 0]
    assert _sparse_forward(X, concepts, mu, Sigma, det, np.log(det), *args) == UNDERFLOW
    for seed in range(20):
        got = sample_places(X, concepts, mu, Sigma, log_phi, log_trans, log_init, np.random.default_rng(seed))
        assert np.array_equal(got, ffbs(emit, log_trans, log_init, np.random.default_rng(seed)))
        assert got[3] != 1


def test_a_covariance_that_is_not_positive_definite_is_refused():
    _rng, X, concepts, mu, Sigma, log_phi, log_trans = _case(1, 3, 2, 4, 1.0)
    Sigma[1] = [[1.0, 2.0], [2.0, 1.0]]
    with pytest.raises(ValueError, match="positive definite"):
        sample_places(X, concepts, mu, Sigma, log_phi, log_trans, np.zeros(3), np.random.default_rng(0))


def test_events_with_many_likely_places_get_a_second_pass_with_room_for_all():
    # broad Gaussians and flat phi: every state of every event is kept, more than the first pass has room for
    rng, X, concepts, mu, Sigma, log_phi, log_trans = _case(7, 30, 2, 12, 0.3)
    Sigma[:] = 400.0 * np.eye(2)
    log_phi[:] = -np.log(30)
    log_init = np.full(30, -np.log(30))
    norm = logsumexp(log_phi, axis=0)
    emit = place_emissions(X, concepts, mu, Sigma, log_phi, norm)
    det = Sigma[:, 0, 0] * Sigma[:, 1, 1] - Sigma[:, 0, 1] * Sigma[:, 1, 0]
    room = 8 * 12 + 30  # the first pass's room
    buffers = (np.empty(13, dtype=np.int64), np.empty(room, dtype=np.int64), np.empty(room))
    args = (X, concepts, mu, Sigma, det, np.log(det), log_phi, norm, log_trans, log_init)
    assert _sparse_forward(*args, *buffers) == FULL
    for seed in range(5):
        got = sample_places(X, concepts, mu, Sigma, log_phi, log_trans, log_init, np.random.default_rng(seed))
        assert np.array_equal(got, ffbs(emit, log_trans, log_init, np.random.default_rng(seed)))

"""The package's one log-sum-exp (spcotmhp/logspace.py), numpy and numba, against scipy's."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from scipy.special import logsumexp as scipy_logsumexp

from spcotmhp.logspace import logsumexp, logsumexp_vector

values = st.one_of(st.floats(-700, 700), st.just(-np.inf))


@settings(deadline=None)
@given(
    arrays(np.float64, st.tuples(st.integers(1, 4), st.integers(1, 6)), elements=values), st.sampled_from([0, 1, -1])
)
def test_numpy_logsumexp_is_scipys(a, axis):
    with np.errstate(divide="ignore"):
        want = scipy_logsumexp(a, axis=axis)
    np.testing.assert_allclose(logsumexp(a, axis=axis), want, rtol=1e-12, atol=1e-12)
    assert logsumexp(a, axis=axis, keepdims=True).shape == np.sum(a, axis=axis, keepdims=True).shape


@settings(deadline=None)
@given(arrays(np.float64, st.integers(0, 12), elements=values))
def test_numba_logsumexp_is_scipys(v):
    with np.errstate(divide="ignore"):
        want = float(scipy_logsumexp(v)) if v.size else -np.inf
    got = logsumexp_vector(v)
    assert got == pytest.approx(want, rel=1e-12, abs=1e-12) or (np.isneginf(got) and np.isneginf(want))
    assert float(logsumexp(v)) == pytest.approx(got, rel=1e-12, abs=1e-12) or np.isneginf(got)


def test_an_empty_or_all_minus_infinity_sum_is_minus_infinity():
    assert logsumexp(np.array([])) == -np.inf and logsumexp_vector(np.array([])) == -np.inf
    assert logsumexp(np.full(3, -np.inf)) == -np.inf and logsumexp_vector(np.full(3, -np.inf)) == -np.inf

"""The package's one log-sum-exp (every model term is computed in log space): :func:`logsumexp` for numpy callers
and :func:`logsumexp_vector`, the same sum for one vector inside numba kernels. Our own rather than
scipy.special.logsumexp: the sampler and the planner call it on small arrays, where scipy's argument handling costs
more than the sum (tests/test_logspace.py checks both against scipy)."""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["logsumexp", "logsumexp_vector"]


def logsumexp(a: np.ndarray, axis: int = -1, keepdims: bool = False) -> np.ndarray:
    """log sum exp along ``axis`` (a lean version of scipy's for the small arrays of the sampler); an all -inf
    or empty slice gives -inf.

    >>> round(float(logsumexp(np.log([1.0, 2.0, 3.0]))), 6)  # log 6
    1.791759
    >>> float(logsumexp(np.array([-np.inf, -np.inf])))
    -inf
    """
    a = np.asarray(a, dtype=float)
    if a.shape[axis] == 0:  # an empty sum: log 0
        return np.full(np.sum(a, axis=axis, keepdims=keepdims).shape, -np.inf)
    m = np.max(a, axis=axis, keepdims=True)
    m = np.where(np.isfinite(m), m, 0.0)
    with np.errstate(divide="ignore"):
        out = np.log(np.sum(np.exp(a - m), axis=axis, keepdims=True)) + m
    return out if keepdims else np.squeeze(out, axis=axis)


@njit(cache=True)
def logsumexp_vector(a: np.ndarray) -> float:  # pragma: no cover - numba
    """log sum exp of a 1-d array inside numba kernels, as :func:`logsumexp` (an all -inf vector gives -inf)."""
    m = -np.inf
    for v in a:
        m = max(m, v)
    if not np.isfinite(m):
        m = 0.0
    total = 0.0
    for v in a:
        total += np.exp(v - m)
    return np.log(total) + m

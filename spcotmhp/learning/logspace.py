"""The package's one log-sum-exp (every model term is computed in log space)."""

from __future__ import annotations

import numpy as np

__all__ = ["logsumexp"]


def logsumexp(a: np.ndarray, axis: int = -1, keepdims: bool = False) -> np.ndarray:
    """log sum exp along ``axis`` (a lean version of scipy's for the small arrays of the sampler); an all -inf
    slice gives -inf.

    >>> round(float(logsumexp(np.log([1.0, 2.0, 3.0]))), 6)  # log 6
    1.791759
    >>> float(logsumexp(np.array([-np.inf, -np.inf])))
    -inf
    """
    m = np.max(a, axis=axis, keepdims=True)
    m = np.where(np.isfinite(m), m, 0.0)
    with np.errstate(divide="ignore"):
        out = np.log(np.sum(np.exp(a - m), axis=axis, keepdims=True)) + m
    return out if keepdims else np.squeeze(out, axis=axis)

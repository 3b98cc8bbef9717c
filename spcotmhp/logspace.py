"""The package's one log-sum-exp and one Gaussian log-density (every model term is computed in log space), each
for numpy callers and, with the same arithmetic, for numba kernels: :func:`logsumexp` and
:func:`logsumexp_vector`; :func:`log_gaussian` (the place term N(x | mu_k, Sigma_k) of Eqs. 9 and 28) and
:func:`gaussian_log_density`. Our own rather than scipy's: the sampler and the planner call them on small arrays
or per cell inside kernels, where scipy's argument handling costs more than the arithmetic (tests/test_logspace.py
checks them against scipy.special.logsumexp and scipy.stats.multivariate_normal)."""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["LOG_2PI", "gaussian_log_density", "log_gaussian", "logsumexp", "logsumexp_vector"]

LOG_2PI = float(np.log(2.0 * np.pi))


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


def log_gaussian(x: np.ndarray, mu: np.ndarray, Sigma: np.ndarray) -> np.ndarray:
    """log N(x | mu_k, Sigma_k) for 2-D Gaussians, vectorised: x (..., 2), mu (K, 2), Sigma (K, 2, 2) -> (..., K).

    Uses the closed-form 2x2 inverse and determinant; exact, no underflow.
    """
    a = Sigma[:, 0, 0]
    b = Sigma[:, 0, 1]
    c = Sigma[:, 1, 0]
    d = Sigma[:, 1, 1]
    det = a * d - b * c
    if np.any(det <= 0):
        raise ValueError("a place covariance is not positive definite")
    dx = x[..., None, 0] - mu[:, 0]
    dy = x[..., None, 1] - mu[:, 1]
    maha = (d * dx * dx - (b + c) * dx * dy + a * dy * dy) / det
    return -0.5 * (maha + np.log(det)) - LOG_2PI


@njit(cache=True)
def gaussian_log_density(dx, dy, a, bc, d, det, log_det):  # pragma: no cover - numba
    """log N(x | mu, Sigma) inside numba kernels, with :func:`log_gaussian`'s arithmetic: ``dx, dy`` = x - mu,
    ``a, bc, d`` = Sigma[0, 0], Sigma[0, 1] + Sigma[1, 0], Sigma[1, 1], ``det`` its determinant (> 0, checked by
    the caller through :func:`log_gaussian`) and ``log_det`` its log."""
    maha = (d * dx * dx - bc * dx * dy + a * dy * dy) / det
    return -0.5 * (maha + log_det) - LOG_2PI

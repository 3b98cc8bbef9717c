"""The k-means initialisation's compiled steps against their numpy formulas: the same numbers, ties included."""

from __future__ import annotations

import numpy as np
import pytest

from spcotmhp.learning.init import _lloyd_means, _nearest, kmeans_places


@pytest.mark.parametrize("seed", range(5))
def test_nearest_centre_and_means_are_the_numpy_ones(seed):
    rng = np.random.default_rng(seed)
    X = rng.normal(scale=5.0, size=(300, 2))
    if seed % 2:
        X = np.round(X)  # grid points: ties between centres, first one wins
    C = X[rng.choice(300, 12, replace=False)].copy()
    C[3] = [1e6, 1e6]  # a centre no point is nearest to stays where it is
    z = _nearest(X, C)
    assert np.array_equal(z, np.argmin(((X[:, None, :] - C[None]) ** 2).sum(-1), axis=1))
    want = C.copy()
    for j in range(len(C)):
        if np.any(z == j):
            want[j] = X[z == j].mean(axis=0)
    _lloyd_means(X, z, C)
    assert np.array_equal(C, want)


def test_kmeans_over_segments_into_min_k_e_clusters():
    X = np.concatenate([np.zeros((5, 2)), np.full((5, 2), 10.0)]) + np.arange(10)[:, None] * 1e-3
    z = kmeans_places(X, 20, np.random.default_rng(0))
    assert z.shape == (10,) and z.max() < 10
    assert set(z[:5]).isdisjoint(z[5:])

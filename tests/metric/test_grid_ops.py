"""The scipy-free grid operations (spcotmhp.metric.grid_ops) against scipy.ndimage itself: exactly equal output,
ties included, on random masks (hypothesis) and on hand-made ones."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from spcotmhp.metric.grid_ops import dilate_square, find_boxes, label4, nearest_feature

EXACT = settings(max_examples=200, deadline=None, derandomize=True)


@st.composite
def masks(draw, side: int = 24) -> np.ndarray:
    """A random bool mask up to ``side`` x ``side`` cells; sparse masks (few True cells) make many equidistant
    ties."""
    h, w = draw(st.integers(1, side)), draw(st.integers(1, side))
    p = draw(st.sampled_from([0.002, 0.02, 0.1, 0.5, 0.9]))
    seed = draw(st.integers(0, 2**32 - 1))
    return np.random.default_rng(seed).random((h, w)) < p


@EXACT
@given(st.one_of(masks(), masks(side=90)))
def test_nearest_feature_equals_scipy_indices(mask):
    if not mask.any():
        mask[mask.shape[0] // 2, mask.shape[1] // 2] = True
    _, want = ndimage.distance_transform_edt(~mask, return_indices=True)
    got = nearest_feature(mask)
    assert got.dtype == want.dtype and np.array_equal(got, want)


def test_nearest_feature_ties_as_scipy():
    """Symmetric features: every cell on a symmetry line is equidistant from two or four of them."""
    for shape, cells in [
        ((7, 7), [(0, 0), (0, 6), (6, 0), (6, 6)]),
        ((5, 9), [(2, 0), (2, 8)]),
        ((9, 5), [(0, 2), (8, 2)]),
    ]:
        mask = np.zeros(shape, dtype=bool)
        for r, c in cells:
            mask[r, c] = True
        _, want = ndimage.distance_transform_edt(~mask, return_indices=True)
        assert np.array_equal(nearest_feature(mask), want)
    assert nearest_feature(np.ones((2, 3), dtype=bool))[:, 1, 2].tolist() == [1, 2]  # a True cell is its own


@EXACT
@given(st.one_of(masks(), masks(side=90)))
def test_label4_equals_scipy(mask):
    want, n = ndimage.label(mask, structure=ndimage.generate_binary_structure(2, 1))
    got, m = label4(mask)
    assert m == n and np.array_equal(got, want)


def test_label4_numbers_by_first_cell_in_raster_order():
    mask = np.array([[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 0, 0], [1, 0, 1]], dtype=bool)
    labels, n = label4(mask)
    assert n == 3 and labels.tolist() == [[0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 0, 0], [2, 0, 3]]


@EXACT
@given(st.one_of(masks(), masks(side=90)), st.integers(-1, 6), st.booleans())
def test_find_boxes_equals_scipy(mask, top, give_max):
    labels = (np.random.default_rng(int(mask.sum())).integers(-1, 6, size=mask.shape) * mask).astype(np.int64)
    if give_max:
        assert find_boxes(labels, max_label=top) == ndimage.find_objects(labels, max_label=top)
    else:
        assert find_boxes(labels) == ndimage.find_objects(labels)


@EXACT
@given(st.one_of(masks(), masks(side=90)), st.integers(0, 7))
def test_dilate_square_equals_scipy_iterated(mask, m):
    want = ndimage.binary_dilation(mask, np.ones((3, 3), dtype=bool), iterations=m) if m else mask
    got = dilate_square(mask, m)
    assert got.dtype == bool and np.array_equal(got, want)


def test_dilate_square_by_hand():
    mask = np.zeros((5, 5), dtype=bool)
    mask[0, 0] = True
    assert dilate_square(mask, 2).sum() == 9 and dilate_square(mask, 2)[:3, :3].all()

"""Snapping to the nearest usable cell and free-space components (spcotmhp.metric.snap), by hand."""

import numpy as np
import pytest

from spcotmhp.errors import MapError
from spcotmhp.metric.snap import component_at, largest_component, nearest_index, snap


def grid() -> np.ndarray:
    """4 x 6: a left piece (rows 0-2, columns 0-1) and a right piece (rows 1-2, columns 4-5, plus (2, 3))."""
    m = np.zeros((4, 6), dtype=bool)
    m[:3, :2] = True
    m[1:3, 4:6] = True
    m[2, 3] = True
    return m


def test_snap_takes_the_nearest_true_cell_and_keeps_true_cells():
    m = grid()
    assert snap(m, np.array([0, 0])).tolist() == [0, 0]
    assert snap(m, np.array([3, 0])).tolist() == [2, 0]
    assert snap(m, np.array([0, 3])).tolist() == [1, 4]  # sqrt 2 away; (2, 3) and (0, 1) are 2 away
    assert snap(m, np.array([[3, 5], [-4, 99]])).tolist() == [[2, 5], [1, 5]]  # (-4, 99) is clipped to (0, 5)
    idx = nearest_index(m)
    assert idx.shape == (2, 4, 6) and (idx[:, 1, 4] == [1, 4]).all()


def test_components_are_4_connected():
    m = np.zeros((3, 3), dtype=bool)
    m[0, 0] = m[1, 1] = m[2, 2] = m[2, 1] = True  # (0, 0) touches the others only at a corner
    assert component_at(m, (0, 0)).sum() == 1
    assert component_at(m, (2, 2)).tolist() == [[False] * 3, [False, True, False], [False, True, True]]
    assert not component_at(m, (0, 2)).any()
    assert largest_component(m).sum() == 3 and not largest_component(np.zeros((2, 2), bool)).any()


def test_an_empty_mask_is_a_map_error():
    with pytest.raises(MapError, match="no cell to snap to: the mask has no usable cell"):
        snap(np.zeros((2, 2), bool), np.array([0, 0]))

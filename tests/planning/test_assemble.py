"""Assembly and smoothing: join legs, line-of-sight shortcuts that never lengthen or collide."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from spcotmhp.metric.grid_search import shortest_paths
from spcotmhp.planning.assemble import join_legs, path_length, smooth
from spcotmhp.planning.sight import chessboard_clearance, clear
from tests.helpers.planning import draw_blocked, draw_ends


def test_join_legs_drops_shared_junctions():
    cells, ends = join_legs(
        [
            np.array([[0, 0], [0, 1]]),
            np.array([[0, 1], [1, 2]]),
            np.array([[1, 2]]),
            np.array([[1, 2], [2, 2]]),
        ]
    )
    assert cells.tolist() == [[0, 0], [0, 1], [1, 2], [2, 2]]
    assert ends == [1, 2, 2, 3]


def test_path_length():
    assert path_length(np.array([[0, 0], [0, 1], [1, 2]]), 0.1) == pytest.approx(0.1 + 0.1 * math.sqrt(2))
    assert path_length(np.array([[3, 3]]), 0.1) == 0.0


def _clear(allowed, r0, c0, r1, c1):
    return clear(chessboard_clearance(allowed), r0, c0, r1, c1)


def test_supercover_counts_both_cells_at_an_exact_corner():
    allowed = np.ones((3, 3), bool)
    allowed[0, 1] = False
    assert not _clear(allowed, 0, 0, 1, 1)  # the segment (0,0)-(1,1) passes the corner of (0,1)
    assert _clear(allowed, 0, 0, 2, 0)
    allowed = np.ones((3, 5), bool)
    allowed[1, 2] = False
    assert not _clear(allowed, 0, 0, 2, 4)  # through the centre of the blocked cell
    assert _clear(allowed, 0, 0, 0, 4)


def test_staircase_becomes_a_straight_line():
    # a 4-connected staircase in free space is replaced by the Bresenham diagonal
    cells = np.array([[0, 0], [0, 1], [1, 1], [1, 2], [2, 2], [2, 3], [3, 3]])
    allowed = np.ones((4, 4), bool)
    out = smooth(cells, allowed, [len(cells) - 1])
    assert out.tolist() == [[0, 0], [1, 1], [2, 2], [3, 3]]
    # anchors are kept: [1, 2] must stay on the path
    out = smooth(cells, allowed, [3, len(cells) - 1])
    assert [1, 2] in out.tolist() and out[-1].tolist() == [3, 3]


@st.composite
def grids(draw):
    blocked = draw_blocked(draw)
    a, b = draw_ends(draw, blocked)
    conn = draw(st.sampled_from([4, 8]))
    return blocked, a, b, conn


@settings(max_examples=150, deadline=None, derandomize=True)
@given(grids())
def test_smoothing_properties(case):
    blocked, a, b, conn = case
    cost = np.where(blocked, np.inf, 1.0)
    path = shortest_paths(cost, a, b[None], connectivity=conn)
    if path is None:
        return
    allowed = ~blocked
    out = smooth(path.cells, allowed, [len(path.cells) - 1])
    assert (out[0] == a).all() and (out[-1] == b).all()
    assert allowed[out[:, 0], out[:, 1]].all()
    if len(out) > 1:
        steps = np.abs(np.diff(out, axis=0))
        assert (steps.max(axis=1) == 1).all()
        for (r0, c0), (r1, c1) in itertools.pairwise(out):  # no squeeze between two blocked corner cells
            if r0 != r1 and c0 != c1:
                assert allowed[r0, c1] or allowed[r1, c0]
    assert path_length(out, 1.0) <= path_length(path.cells, 1.0) + 1e-9

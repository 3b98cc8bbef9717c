"""Line of sight (planning/sight.py) against brute force: the supercover test by exact rational clipping of the
segment against every cell's closed square, the clearance field against scipy's chessboard distance transform,
and the shortcut kernel against the greedy farthest-visible scan written out in Python."""

from __future__ import annotations

import itertools
from fractions import Fraction

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from spcotmhp.planning.assemble import path_length, smooth_anchored
from spcotmhp.planning.sight import chessboard_clearance, clear

HALF = Fraction(1, 2)


def touches(r0: int, c0: int, r1: int, c1: int, r: int, c: int) -> bool:
    """Whether the segment between the centres of (r0, c0) and (r1, c1) meets the closed square of (r, c):
    Liang-Barsky clipping in exact rationals."""
    lo, hi = Fraction(0), Fraction(1)
    for p, d, x in ((r0, r1 - r0, r), (c0, c1 - c0, c)):
        a, b = x - HALF - p, x + HALF - p  # p + t d must lie in [a, b] (relative to p)
        if d == 0:
            if not a <= 0 <= b:
                return False
            continue
        ta, tb = sorted((Fraction(a, d), Fraction(b, d)))
        lo, hi = max(lo, ta), min(hi, tb)
    return lo <= hi


def brute_clear(allowed: np.ndarray, r0: int, c0: int, r1: int, c1: int) -> bool:
    rows = range(min(r0, r1), max(r0, r1) + 1)
    cols = range(min(c0, c1), max(c0, c1) + 1)
    return all(allowed[r, c] for r in rows for c in cols if touches(r0, c0, r1, c1, r, c))


@st.composite
def grid_and_segments(draw):
    h = draw(st.integers(1, 24))
    w = draw(st.integers(1, 24))
    density = draw(st.sampled_from([0.0, 0.03, 0.1, 0.3]))
    seed = draw(st.integers(0, 2**31))
    rng = np.random.default_rng(seed)
    allowed = rng.random((h, w)) >= density
    if draw(st.booleans()):  # walls: thick blocked bands with openings, as on an inflated map
        for r in rng.integers(0, h, size=2):
            allowed[max(r - 1, 0) : r + 2, :] = False
            allowed[max(r - 1, 0) : r + 2, rng.integers(0, w) :][:, :2] = True
    pts = rng.integers(0, [h, w, h, w], size=(12, 4))
    return allowed, pts


@settings(max_examples=200, deadline=None, derandomize=True)
@given(grid_and_segments())
def test_clear_is_the_exact_supercover_test(case):
    allowed, pts = case
    clearance = chessboard_clearance(allowed)
    for r0, c0, r1, c1 in pts.tolist():
        assert clear(clearance, r0, c0, r1, c1) == brute_clear(allowed, r0, c0, r1, c1)


def test_clear_on_long_segments_and_corners():
    allowed = np.ones((60, 90), bool)
    allowed[30, 45] = False
    clearance = chessboard_clearance(allowed)
    for r0, c0, r1, c1 in [(0, 0, 59, 89), (30, 0, 30, 89), (0, 45, 59, 45), (29, 44, 31, 46), (29, 46, 31, 44)]:
        assert clear(clearance, r0, c0, r1, c1) == brute_clear(allowed, r0, c0, r1, c1)
    assert not clear(clearance, 30, 0, 30, 89) and clear(clearance, 29, 0, 29, 89)
    assert not clear(clearance, 29, 44, 31, 46)  # through the centre
    assert not clear(clearance, 31, 44, 29, 46)  # the other diagonal, same cell
    assert clear(clearance, 29, 46, 28, 47) and clear(clearance, 5, 5, 5, 5)


@settings(max_examples=100, deadline=None, derandomize=True)
@given(grid_and_segments())
def test_clearance_is_the_chessboard_distance_to_a_blocked_cell_or_the_border(case):
    allowed, _ = case
    expected = ndimage.distance_transform_cdt(np.pad(allowed, 1), metric="chessboard")[1:-1, 1:-1]
    assert (chessboard_clearance(allowed) == np.where(allowed, expected, 0)).all()


def greedy(cells: np.ndarray, allowed: np.ndarray, fixed: list[int]) -> list[tuple[int, int]]:
    """The shortcut rule in Python: from each kept cell the farthest cell of its piece in sight (brute force),
    joined by the Bresenham line (round half away from zero)."""
    out = [tuple(cells[0])]
    for s, end in itertools.pairwise(fixed):
        i = s
        while i < end:
            j = end
            while j > i + 1 and not brute_clear(allowed, *cells[i], *cells[j]):
                j -= 1
            (r0, c0), (r1, c1) = cells[i], cells[j]
            n = max(abs(r1 - r0), abs(c1 - c0))
            for t in range(1, n + 1):
                out.append(
                    tuple(
                        int(a + np.sign(b - a) * ((2 * abs(b - a) * t + n) // (2 * n))) for a, b in ((r0, r1), (c0, c1))
                    )
                )
            i = j
    return out


@st.composite
def walks(draw):
    """A random 8-connected walk over allowed cells of a random map, and anchors on it."""
    allowed, _ = draw(grid_and_segments())
    free = np.argwhere(allowed)
    if len(free) == 0:
        allowed[0, 0] = True
        free = np.array([[0, 0]])
    rng = np.random.default_rng(draw(st.integers(0, 2**31)))
    cell = free[rng.integers(len(free))]
    path = [cell]
    for _ in range(draw(st.integers(0, 60))):
        steps = [cell + d for d in itertools.product((-1, 0, 1), repeat=2) if any(d)]
        ok = [s for s in steps if (s >= 0).all() and (s < allowed.shape).all() and allowed[s[0], s[1]]]
        if not ok:
            break
        cell = ok[rng.integers(len(ok))]
        path.append(cell)
    cells = np.array(path, dtype=np.int64)
    anchors = sorted(set(draw(st.lists(st.integers(0, len(cells) - 1), max_size=4))))
    return allowed, cells, anchors


@settings(max_examples=150, deadline=None, derandomize=True)
@given(walks())
def test_shortcuts_keep_every_guarantee_and_match_the_brute_force_scan(case):
    allowed, cells, anchors = case
    out, moved = smooth_anchored(cells, allowed, anchors)
    assert allowed[out[:, 0], out[:, 1]].all()  # never into a blocked cell
    assert path_length(out, 1.0) <= path_length(cells, 1.0) + 1e-9  # never longer
    assert (out[0] == cells[0]).all() and (out[-1] == cells[-1]).all()
    assert moved == sorted(moved) and all((out[m] == cells[a]).all() for m, a in zip(moved, anchors, strict=True))
    if len(out) > 1:
        assert (np.abs(np.diff(out, axis=0)).max(axis=1) <= 1).all()
    if len(cells) >= 3:
        fixed = sorted({0, len(cells) - 1, *anchors})
        assert [tuple(c) for c in out.tolist()] == greedy(cells.tolist(), allowed, fixed)

"""Place territories for path smoothing (Algorithm 1, line 13): each place's most-probable-place cells grown by
a margin, and the tube (window + mask) that a run of places spans.

:class:`~spcotmhp.planning.graph.PlanningGraph` keeps the grown territories of its active places and answers
:meth:`~spcotmhp.planning.graph.PlanningGraph.tube` with :func:`tube_window`.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.metric.grid_ops import dilate_square


def grown_territories(territory: np.ndarray, places: np.ndarray, margin_cells: float) -> dict:
    """place -> (row, col, mask): the cells of ``territory == place`` grown by ``margin_cells`` (chessboard
    distance, rounded), as a mask over the window whose corner is (row, col)."""
    m = max(0, round(margin_cells))
    h, w = territory.shape
    out = {}
    for k in places:
        own = territory == k
        if not own.any():
            continue
        rows, cols = np.flatnonzero(own.any(axis=1)), np.flatnonzero(own.any(axis=0))
        r0, r1 = max(rows[0] - m, 0), min(rows[-1] + m + 1, h)
        c0, c1 = max(cols[0] - m, 0), min(cols[-1] + m + 1, w)
        window = own[r0:r1, c0:c1]
        if m:
            window = dilate_square(window, m)
        out[int(k)] = (int(r0), int(c0), window)
    return out


def tube_window(territories: dict, places: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(origin, mask)``: the smallest window (corner at cell ``origin``) that holds the grown territories
    (:func:`grown_territories`) of ``places``, and their union in it; an empty mask when none has one."""
    parts = [territories[int(k)] for k in places if int(k) in territories]
    if not parts:
        return np.zeros(2, dtype=np.int64), np.zeros((0, 0), dtype=bool)
    lo = np.min([(r, c) for r, c, _ in parts], axis=0)
    hi = np.max([(r + m.shape[0], c + m.shape[1]) for r, c, m in parts], axis=0)
    mask = np.zeros(tuple(hi - lo), dtype=bool)
    for r, c, m in parts:
        mask[r - lo[0] : r - lo[0] + m.shape[0], c - lo[1] : c - lo[1] + m.shape[1]] |= m
    return lo, mask

"""Place territories for path smoothing (Algorithm 1, line 13): each place's most-probable-place cells grown by
a margin, and the tube (window + mask) that a run of places spans.

:class:`~spcotmhp.planning.graph.PlanningGraph` keeps the grown territories of its active places and answers
:meth:`~spcotmhp.planning.graph.PlanningGraph.tube` with :func:`tube_window`.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.metric.grid_ops import dilate_square, find_boxes


def grown_territories(territory: np.ndarray, places: np.ndarray, margin_cells: float) -> dict:
    """place -> (row, col, mask): the cells of ``territory == place`` grown by ``margin_cells`` (chessboard
    distance, rounded), as a mask over the window whose corner is (row, col). Each place's cells are sought in
    its bounding box only (:func:`find_boxes`, one pass over the crop for all places, not one a place)."""
    m = max(0, round(margin_cells))
    h, w = territory.shape
    places = np.asarray(places, dtype=np.int64)
    top = int(places.max(initial=-1)) + 1
    boxes = find_boxes(territory + 1, max_label=top) if top > 0 else []  # place k is label k + 1
    out = {}
    for k in places:
        box = boxes[k] if 0 <= k < len(boxes) else None
        if box is None:
            continue
        rows, cols = box
        r0, r1 = max(rows.start - m, 0), min(rows.stop + m, h)
        c0, c1 = max(cols.start - m, 0), min(cols.stop + m, w)
        window = territory[r0:r1, c0:c1] == k
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

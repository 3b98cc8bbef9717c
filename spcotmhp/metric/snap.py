"""Snapping points to usable grid cells: the nearest cell of a mask, and connected components of free space.

One implementation for every "move this point to the nearest free / traversable / reachable cell" of the
package (the planner's candidate points, the evaluation's place positions, the A* baseline's sampled goal, the
demo's start). The callers differ only in the mask they pass: free cells, the traversable cells, the start's
component or the largest component.

Components are 4-connected: the grid search never squeezes diagonally between two blocked cells (its
``no_squeeze`` corner rule), and a diagonal step with a free cell beside it can also be walked in two orthogonal
steps, so the cells reachable from one another with 8-connected moves are exactly the 4-connected components.
"""

from __future__ import annotations

import numpy as np

from spcotmhp.errors import MapError
from spcotmhp.metric.grid_ops import label4, nearest_feature


def nearest_index(mask: np.ndarray) -> np.ndarray:
    """For every cell, the (row, col) of the nearest True cell of ``mask`` (Euclidean distance between cell
    centres; a True cell is its own nearest): (2, H, W) int array, for snapping many cells at once."""
    mask = np.asarray(mask, dtype=bool)
    if not mask.any():
        raise MapError("no cell to snap to: the mask has no usable cell")
    return nearest_feature(mask)


def snap(mask: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """The nearest True cell of ``mask`` to each of ``cells`` ((..., 2) row, col; clipped onto the grid first):
    (..., 2) int64."""
    mask = np.asarray(mask, dtype=bool)
    rc = np.clip(np.asarray(cells, dtype=np.int64), 0, np.array(mask.shape) - 1)
    if rc.size and mask[rc[..., 0], rc[..., 1]].all():  # each its own nearest (distance 0: no tie), no transform
        return rc.copy()
    idx = nearest_index(mask)
    return np.stack([idx[0][rc[..., 0], rc[..., 1]], idx[1][rc[..., 0], rc[..., 1]]], axis=-1).astype(np.int64)


def component_at(mask: np.ndarray, cell: tuple[int, int] | np.ndarray) -> np.ndarray:
    """The (4-connected) component of ``mask`` holding ``cell`` (empty if the cell is not in the mask)."""
    labels, _ = label4(mask)
    label = labels[int(cell[0]), int(cell[1])]
    return labels == label if label else np.zeros(labels.shape, dtype=bool)


def largest_component(mask: np.ndarray) -> np.ndarray:
    """The largest (4-connected) component of ``mask`` (empty if the mask is)."""
    labels, n = label4(mask)
    if n == 0:
        return np.zeros(labels.shape, dtype=bool)
    sizes = np.bincount(labels.ravel())
    sizes[0] = 0
    return labels == int(np.argmax(sizes))

"""Whether the occupancy grid puts a wall or a door between two clusters of teaching points (the test of the
taught-merge split, :mod:`spcotmhp.learning.taught_split`).

Two clusters A and B (their means a and b) are *separated* when either holds:

* **a wall**: the straight segment from a to b crosses a cell that is not known free (occupied, unknown, or off
  the map), sampled every half cell. An obstacle on the straight line between two rooms' teaching points is a
  wall (or furniture the map cannot tell from one); unknown space counts because the map does not know it is
  open.
* **a door**: A and B lie in different components of the *open* space, the free cells with at least
  ``OPEN_CLEARANCE_M`` of clearance (the distance from the cell's centre to the nearest cell that is not free).
  An opening narrower than 2 x 0.7 m = 1.4 m (less one cell) closes in the open space: every single interior
  door and most double doors (0.6-1.2 m), while a room with a free disc 1.4 m across stays open around its
  furniture. This catches the door that lies on the straight line between the rooms, where the segment crosses
  nothing. A cluster's open component is the one holding most of its points; a cluster none of whose points has
  that clearance stands in space narrower than a door (a corridor, a closet) and is separated from every other.

The open space is computed once per map (``Separation``): one distance transform and one labelling, O(cells).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from spcotmhp.metric.grid_ops import label4, nearest_feature
from spcotmhp.metric.maps import OccupancyMap

OPEN_CLEARANCE_M = 0.7
"""Clearance of an open cell (metres; module docstring): doors up to about 1.3 m wide close."""


@dataclass
class Separation:
    """The separation test on one map (module docstring); ``between(A, B)`` gives "wall", "door" or None."""

    map: OccupancyMap
    open_clearance_m: float = OPEN_CLEARANCE_M
    _open: np.ndarray | None = field(default=None, init=False, repr=False)

    def open_labels(self) -> np.ndarray:
        """(H, W) int32 component of every open cell (0 elsewhere), computed on first use."""
        if self._open is None:
            occ = self.map
            blocked = ~occ.free
            if not blocked.any():  # no obstacle at all: the whole map is one open space
                self._open = np.ones(occ.shape, dtype=np.int32)
            else:
                near = nearest_feature(blocked)
                rows, cols = np.indices(occ.shape)
                clearance = np.hypot(near[0] - rows, near[1] - cols) * occ.resolution
                self._open = label4(occ.free & (clearance >= self.open_clearance_m))[0]
        return self._open

    def wall(self, a: np.ndarray, b: np.ndarray) -> bool:
        """Whether the segment from a to b (metres) crosses a cell that is not known free."""
        occ = self.map
        n = max(2, int(np.ceil(2.0 * np.hypot(*(b - a)) / occ.resolution)) + 1)
        cells = occ.world_to_cell(a[None, :] + np.linspace(0.0, 1.0, n)[:, None] * (b - a)[None, :])
        inside = occ.in_bounds(cells)
        if not inside.all():
            return True
        return bool(~occ.free[cells[:, 0], cells[:, 1]].all())

    def component(self, points: np.ndarray) -> int:
        """The open component holding most of ``points`` (ties: the lowest label); 0 when none is open."""
        occ = self.map
        cells = occ.world_to_cell(np.asarray(points, dtype=float))
        cells = cells[occ.in_bounds(cells)]
        labels = self.open_labels()[cells[:, 0], cells[:, 1]] if len(cells) else np.zeros(0, dtype=np.int32)
        labels = labels[labels > 0]
        return int(np.argmax(np.bincount(labels))) if len(labels) else 0

    def between(self, A: np.ndarray, B: np.ndarray) -> str | None:
        """ "wall", "door" (module docstring) or None when the clusters A, B (n, 2) share one open space."""
        a, b = np.asarray(A, dtype=float).mean(axis=0), np.asarray(B, dtype=float).mean(axis=0)
        if self.wall(a, b):
            return "wall"
        ca, cb = self.component(A), self.component(B)
        return "door" if ca == 0 or cb == 0 or ca != cb else None

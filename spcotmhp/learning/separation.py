"""Whether the occupancy grid puts a wall or a door between two clusters of teaching points (the test of the
taught-merge split, :mod:`spcotmhp.learning.taught_split`).

Two clusters A and B (their means a and b) are *separated* when either holds:

* **a wall**: the straight segment from a to b crosses a cell that is not known free (occupied, unknown, or off
  the map), sampled every half cell. An obstacle on the straight line between two rooms' teaching points is a
  wall (or furniture the map cannot tell from one); unknown space counts because the map does not know it is
  open.
* **a door**: the free space narrows between them to an opening much narrower than the space the clusters stand
  in. Take c_A, c_B, the largest clearance among each cluster's points (clearance: the distance from a cell's
  centre to the nearest cell that is not free), and the threshold t = min(``OPEN_CLEARANCE_M``, ``NARROWING`` x
  min(c_A, c_B)); A and B are separated when their best points lie in different components of the free cells of
  clearance >= t. Rooms with a free disc 1.4 m across are cut at t = 0.7 m, which closes every opening narrower
  than 2 x 0.7 m = 1.4 m (less one cell): single interior doors and most double ones (0.6-1.2 m), while such a
  room stays connected around its furniture. Two clusters in one narrow space (a corridor, a 1.2 m bathroom) are
  cut at 3/4 of their own clearance, so the space itself does not separate them; an opening narrower than 3/4 of
  the narrower side still does. This catches the door on the straight line between two rooms, where the
  segment crosses nothing. A cluster none of whose points is on a free cell has c = 0: only the wall test
  applies to it.

The clearance is computed once per map (``Separation``: one distance transform), then one labelling per pair of
clusters, O(cells).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from spcotmhp.metric.grid_ops import label4, nearest_feature
from spcotmhp.metric.maps import OccupancyMap

OPEN_CLEARANCE_M = 0.7
"""The door test's threshold between rooms (metres; module docstring): openings up to about 1.3 m wide close."""
NARROWING = 0.75
"""The door test's threshold in narrow spaces, as a fraction of the narrower cluster's clearance (module
docstring): an opening must be a quarter narrower than the space on both sides to count as a door."""


@dataclass
class Separation:
    """The separation test on one map (module docstring); ``between(A, B)`` gives "wall", "door" or None."""

    map: OccupancyMap
    open_clearance_m: float = OPEN_CLEARANCE_M
    narrowing: float = NARROWING
    _clearance: np.ndarray | None = field(default=None, init=False, repr=False)

    def clearance(self) -> np.ndarray:
        """(H, W) metres from every free cell's centre to the nearest cell that is not free (0 on those), computed
        on first use; inf everywhere on a map with no such cell."""
        if self._clearance is None:
            occ = self.map
            blocked = ~occ.free
            if not blocked.any():
                self._clearance = np.full(occ.shape, np.inf)
            else:
                near = nearest_feature(blocked)
                rows, cols = np.indices(occ.shape)
                self._clearance = np.hypot(near[0] - rows, near[1] - cols) * occ.resolution
        return self._clearance

    def wall(self, a: np.ndarray, b: np.ndarray) -> bool:
        """Whether the segment from a to b (metres) crosses a cell that is not known free."""
        occ = self.map
        n = max(2, int(np.ceil(2.0 * np.hypot(*(b - a)) / occ.resolution)) + 1)
        cells = occ.world_to_cell(a[None, :] + np.linspace(0.0, 1.0, n)[:, None] * (b - a)[None, :])
        inside = occ.in_bounds(cells)
        if not inside.all():
            return True
        return bool(~occ.free[cells[:, 0], cells[:, 1]].all())

    def best_cell(self, points: np.ndarray) -> tuple[np.ndarray | None, float]:
        """The cell of ``points`` with the largest clearance and that clearance (None, 0 when none is free)."""
        occ = self.map
        cells = occ.world_to_cell(np.asarray(points, dtype=float))
        cells = cells[occ.in_bounds(cells)]
        if not len(cells):
            return None, 0.0
        c = self.clearance()[cells[:, 0], cells[:, 1]]
        i = int(np.argmax(c))
        return (cells[i], float(c[i])) if c[i] > 0 else (None, 0.0)

    def door(self, A: np.ndarray, B: np.ndarray) -> bool:
        """The door test (module docstring) for the clusters A, B (n, 2)."""
        (ca, clear_a), (cb, clear_b) = self.best_cell(A), self.best_cell(B)
        if ca is None or cb is None:
            return False
        t = min(self.open_clearance_m, self.narrowing * min(clear_a, clear_b))
        labels = label4(self.clearance() >= t)[0]
        return bool(labels[ca[0], ca[1]] != labels[cb[0], cb[1]])

    def between(self, A: np.ndarray, B: np.ndarray) -> str | None:
        """ "wall", "door" (module docstring) or None when no wall or door separates the clusters A, B (n, 2)."""
        a, b = np.asarray(A, dtype=float).mean(axis=0), np.asarray(B, dtype=float).mean(axis=0)
        if self.wall(a, b):
            return "wall"
        return "door" if self.door(A, B) else None

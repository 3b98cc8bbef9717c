"""The reference length l of SPL and the closest goal instance of N-SPL, under both success rules of
:mod:`~spcotmhp.evaluation.metrics`.

Every length is a geodesic over the *robot cells* (:func:`robot_cells`: the map's free cells below the inscribed
cost, where the robot's centre may be without its body touching an obstacle), 8-connected, steps 1 and sqrt 2
cells, no costs (:func:`~spcotmhp.metric.grid_search.geodesic_distance`, which is symmetric).

* **footprint** (primary): the targets of a place are the robot cells whose centre lies in the place's box grown
  by the inscribed radius (``Place.region``). For a basic task ``l = min_g d(start, R_g)`` over the goal-named
  places g; through a waypoint, ``l = min_{w, g} min_{x in R_w} d(start, x) + d(x, R_g)``, computed as the minimum
  over the waypoints' target cells x of the field from the start plus the field from R_g (one field per place,
  kept). A place whose grown box holds no robot cell reachable from the start cannot be reached by a safe robot:
  the task has no footprint-safe path (l = inf) and is set apart by :mod:`~spcotmhp.evaluation.tasks`.
* **strict** (the paper's rule): the target of a place is its position (``Place.cell``, the robot cell nearest the
  mean of its teaching positions), ``l = min_{w, g} d(start, w) + d(w, g)``.

The closest instance (N-SPL, as the paper defines it) is the goal-named place nearest the start; the closest via
the waypoint (our N_via) is the one where the shortest path through a waypoint ends.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.metric.costmap import inflate
from spcotmhp.metric.grid_search import geodesic_distance


@dataclass(frozen=True)
class Reference:
    """The reference of one task under one rule: ``l`` (metres, inf when no path), and the indices into the
    task's goal places of the instance closest from the start and of the one closest via the waypoint."""

    l: float
    closest: int
    closest_via: int


def robot_cells(dataset: Dataset) -> np.ndarray:
    """(H, W) bool: the map's free cells outside the inscribed radius (costmap_2d defaults,
    :class:`~spcotmhp.metric.costmap.CostMapSettings`): where a robot can be without touching an obstacle."""
    return inflate(dataset.map).free


class HomeGeometry:
    """The geodesic fields of one home, computed on demand and kept: from a cell (a start or a place's position)
    and from a place's footprint targets (module docstring).

    Args:
        robot: (H, W) robot cells.  resolution: metres per cell.  positions: (P, 2) each place's position (cell).
        targets: per place, the (n, 2) robot cells inside its grown box (n may be 0).
    """

    def __init__(
        self, robot: np.ndarray, resolution: float, positions: np.ndarray, targets: Sequence[np.ndarray]
    ) -> None:
        self.robot, self.resolution = robot, float(resolution)
        self.positions = np.asarray(positions, dtype=np.int64).reshape(-1, 2)
        self.targets = [np.asarray(t, dtype=np.int64).reshape(-1, 2) for t in targets]
        self._from_cell: dict[tuple[int, int], np.ndarray] = {}
        self._from_place: dict[int, np.ndarray] = {}

    def from_cell(self, cell: tuple[int, int]) -> np.ndarray:
        """(H, W) geodesic distance (m) from ``cell`` (inf where unreachable)."""
        key = (int(cell[0]), int(cell[1]))
        if key not in self._from_cell:
            self._from_cell[key] = geodesic_distance(self.robot, [key], 8, self.resolution)
        return self._from_cell[key]

    def from_place(self, k: int) -> np.ndarray:
        """(H, W) geodesic distance (m) from the nearest footprint target of place k (all inf without one)."""
        if k not in self._from_place:
            cells = self.targets[k]
            self._from_place[k] = (
                geodesic_distance(self.robot, cells, 8, self.resolution)
                if len(cells)
                else np.full(self.robot.shape, np.inf)
            )
        return self._from_place[k]

    def _at(self, field: np.ndarray, k: int) -> np.ndarray:
        cells = self.targets[k]
        return field[cells[:, 0], cells[:, 1]] if len(cells) else np.full(1, np.inf)

    def to_places(self, start: tuple[int, int], places: Sequence[int]) -> np.ndarray:
        """(len(places),) the footprint distance (m) from ``start`` into each place's region (inf: none)."""
        d_start = self.from_cell(start)
        return np.array([self._at(d_start, k).min() for k in places], dtype=float)

    def footprint(self, start: tuple[int, int], goals: Sequence[int], waypoints: Sequence[int]) -> Reference:
        """The footprint rule's reference of a task from ``start`` to one of ``goals`` (place indices) through
        one of ``waypoints`` (none: a basic task)."""
        d_start = self.from_cell(start)
        direct = self.to_places(start, goals)
        if not waypoints:
            k = int(np.argmin(direct))
            return Reference(float(direct[k]), k, k)
        through = np.full(len(goals), np.inf)
        for w in waypoints:
            before = self._at(d_start, w)
            for n, g in enumerate(goals):
                through[n] = min(through[n], float((before + self._at(self.from_place(g), w)).min()))
        return Reference(float(through.min()), int(np.argmin(direct)), int(np.argmin(through)))

    def strict(self, start_place: int, goals: Sequence[int], waypoints: Sequence[int]) -> Reference:
        """The strict rule's reference of a task from place ``start_place``'s position (module docstring)."""
        d = {k: self.from_cell(tuple(self.positions[k])) for k in {start_place, *waypoints}}
        pos = self.positions
        direct = np.array([d[start_place][tuple(pos[g])] for g in goals])
        if not waypoints:
            k = int(np.argmin(direct))
            return Reference(float(direct[k]), k, k)
        via = np.array([[d[start_place][tuple(pos[w])] + d[w][tuple(pos[g])] for g in goals] for w in waypoints])
        return Reference(float(via.min()), int(np.argmin(direct)), int(np.unravel_index(np.argmin(via), via.shape)[1]))

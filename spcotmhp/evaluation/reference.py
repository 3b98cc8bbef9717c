"""The reference length l of SPL and the closest goal instance of N-SPL, under both success rules of
:mod:`~spcotmhp.evaluation.metrics`.

SPL's l is the length of the shortest path *to the goal* (Anderson et al. 2018: the goal a point, success within a
distance of it that the task chooses), not to the edge of the success region: measured to the region's edge, SPL
would reward stopping at a room's threshold and charge a plan that drives into the room. Here the goal of a place is
one cell, its *target*, and every length is a geodesic over the *robot cells* (:func:`robot_cells`: the map's free
cells below the inscribed cost, where the robot's centre may be without its body touching an obstacle), 8-connected,
steps 1 and sqrt 2 cells, no costs (:func:`~spcotmhp.metric.grid_search.geodesic_distance`, which is symmetric):

* **footprint** (primary): the target is the robot cell nearest the mean of the place's teaching positions among
  those whose centre lies in the place's region (its box grown by the inscribed radius, ``Place.region``),
  preferring the free region (4-connected robot cells) of the place's position (:func:`footprint_targets`). A place
  whose region holds no robot cell has no target, and a task whose target cannot be reached from the start has no
  footprint-safe path (l = inf): such tasks are set apart by :mod:`~spcotmhp.evaluation.tasks`, since no safe robot
  can succeed in them;
* **strict** (the paper's rule): the target is the place's position (``Place.cell``, the robot cell nearest the
  mean, wherever it lies).

Where the position lies in the region (in every place of the bundled homes), both targets are the same cell and so
are both l. For a basic task ``l = min_g d(start, t_g)`` over the goal-named places g; through a waypoint
``l = min_{w, g} d(start, t_w) + d(t_w, t_g)``. The closest instance (N-SPL, as the paper defines it) is the
goal-named place nearest the start; the closest via the waypoint (our N_via) is the one where the shortest path
through a waypoint ends.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.metric.costmap import inflate
from spcotmhp.metric.grid_ops import label4
from spcotmhp.metric.grid_search import geodesic_distance
from spcotmhp.metric.snap import snap


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


def footprint_targets(
    robot: np.ndarray, centres: np.ndarray, means: np.ndarray, regions: Sequence, positions: np.ndarray
) -> np.ndarray:
    """(P, 2) each place's footprint target (module docstring), (-1, -1) where its region holds no robot cell.

    Args:
        robot: (H, W) robot cells.  centres: (H, W, 2) the cells' centres (m).  means: (P, 2) the places' means
            as map cells.  regions: each place's region (anything with ``contains((..., 2) points)``).
        positions: (P, 2) the places' positions (robot cells): the free region of each is preferred.
    """
    components = label4(robot)[0]
    out = np.full((len(means), 2), -1, dtype=np.int64)
    for k, region in enumerate(regions):
        inside = robot & region.contains(centres)
        same = inside & (components == components[positions[k][0], positions[k][1]])
        preferred = same if same.any() else inside
        if preferred.any():
            out[k] = snap(preferred, np.asarray(means[k]))
    return out


class HomeGeometry:
    """The geodesic fields of one home, from each target cell, computed on demand and kept.

    Args:
        robot: (H, W) robot cells.  resolution: metres per cell.  positions: (P, 2) each place's position (the
            strict rule's target).  targets: (P, 2) each place's footprint target, (-1, -1) for none.
    """

    def __init__(self, robot: np.ndarray, resolution: float, positions: np.ndarray, targets: np.ndarray) -> None:
        self.robot, self.resolution = robot, float(resolution)
        self.positions = np.asarray(positions, dtype=np.int64).reshape(-1, 2)
        self.targets = np.asarray(targets, dtype=np.int64).reshape(-1, 2)
        self._fields: dict[tuple[int, int], np.ndarray] = {}

    def from_cell(self, cell: Sequence[int] | np.ndarray) -> np.ndarray:
        """(H, W) geodesic distance (m) from ``cell`` (inf where unreachable)."""
        key = (int(cell[0]), int(cell[1]))
        if key not in self._fields:
            self._fields[key] = geodesic_distance(self.robot, [key], 8, self.resolution)
        return self._fields[key]

    def _d(self, a: np.ndarray, b: np.ndarray) -> float:
        """The geodesic from target ``a`` to target ``b`` (inf when either is missing)."""
        if a[0] < 0 or b[0] < 0:
            return float("inf")
        return float(self.from_cell(a)[b[0], b[1]])

    def to_places(self, start: Sequence[int], places: Sequence[int]) -> np.ndarray:
        """(len(places),) the distance (m) from ``start`` to each place's footprint target (inf: none)."""
        return np.array([self._d(np.asarray(start), self.targets[k]) for k in places], dtype=float)

    def footprint(self, start: Sequence[int], goals: Sequence[int], waypoints: Sequence[int]) -> Reference:
        """The footprint rule's reference of a task from cell ``start`` to one of ``goals`` (place indices) through
        one of ``waypoints`` (none: a basic task)."""
        return self._reference(np.asarray(start), goals, waypoints, self.targets)

    def strict(self, start: Sequence[int], goals: Sequence[int], waypoints: Sequence[int]) -> Reference:
        """The strict rule's reference of the same task (module docstring)."""
        return self._reference(np.asarray(start), goals, waypoints, self.positions)

    def _reference(
        self, start: np.ndarray, goals: Sequence[int], waypoints: Sequence[int], targets: np.ndarray
    ) -> Reference:
        direct = np.array([self._d(start, targets[g]) for g in goals])
        closest = int(np.argmin(direct))
        if not waypoints:
            return Reference(float(direct[closest]), closest, closest)
        via = np.array(
            [[self._d(start, targets[w]) + self._d(targets[w], targets[g]) for g in goals] for w in waypoints]
        )
        return Reference(float(via.min()), closest, int(np.unravel_index(np.argmin(via), via.shape)[1]))

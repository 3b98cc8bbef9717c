"""Experiment I planning tasks (paper Section 4.2; the original evaluation protocol).

Per home, over the ground-truth places (truth.csv):

* **basic**: every ordered pair (i, j) with i != j and i, j not adjacent; instruction = the goal's name;
* **advanced**: every (i, h, j) of a basic pair and a waypoint h not in {i, j} whose name differs from the
  goal's; instruction = waypoint name, then goal name.

Each place's *position* is the robot cell nearest the mean of its teaching positions, where robot cells are the
free cells outside the inscribed radius of costmap_2d's default settings (:func:`robot_cells`: a 0.22 m robot
centred there touches no obstacle), within the free region (4-connected robot cells) where most of its teaching
positions' nearest robot cells lie (:func:`place_position`: a pocket cut off by furniture in the middle of a room
is not where the room is reached from); the start of a task is the position of place i. A place's *box* is the box of
its teaching positions plus 0.1 m (:class:`~spcotmhp.evaluation.metrics.Box`), its *region* that box grown by the
inscribed radius (where the robot's centre stands when its body reaches the box: the footprint success rule of
:mod:`~spcotmhp.evaluation.metrics`); every place sharing a name is an *instance* of that name.

Each task carries its reference length ``l`` and closest instances under both success rules
(:mod:`~spcotmhp.evaluation.reference`): ``l``, ``closest_goal``, ``closest_goal_via`` for the footprint rule
(the primary figures) and ``strict_l``, ``strict_closest_goal``, ``strict_closest_goal_via`` for the paper's.
N-SPL's "closest" instance is, as the paper defines it, the goal instance closest from the initial position; the
goal instance of the minimum through a waypoint is our variant (``closest_goal_via``; the same on basic tasks).
Both come from geodesics, not from the hand-written tables of the original.

Left out and counted: tasks that no robot path joins at all (``HomeTasks.dropped``); tasks with *no
footprint-safe path*, whose goal or waypoint region holds no robot cell reachable from the start (a place taught
against furniture whose every free cell is inscribed, too far for the body to reach: ``HomeTasks.no_safe_path``),
so that no task counts as failed only because no safe robot can succeed; tasks whose ``l`` is 0 under either rule
(a basic task from one bedroom to "bedroom": the start already satisfies it, ``HomeTasks.zero_length``). Tasks whose
start lies inside the region of a waypoint-named place are flagged (``Task.start_in_waypoint``) and reported apart
by the runner.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.errors import DatasetError
from spcotmhp.evaluation.metrics import REGION_MARGIN_M, Box
from spcotmhp.evaluation.reference import HomeGeometry, footprint_targets, robot_cells
from spcotmhp.metric.costmap import CostMapSettings
from spcotmhp.metric.grid_ops import label4
from spcotmhp.metric.snap import nearest_index, snap

TaskKind = Literal["basic", "advanced"]
TASK_KINDS = ("basic", "advanced")
ROBOT_RADIUS_M = CostMapSettings().inscribed_radius
"""The robot's inscribed radius of the evaluation (costmap_2d's default, as :func:`robot_cells`)."""


@dataclass(frozen=True)
class Place:
    """A ground-truth place: index (truth.csv), name, mean of its teaching positions, position (the robot cell
    nearest the mean), box (the strict success region) and region (the box grown by the robot's inscribed radius:
    the footprint success region)."""

    index: int
    name: str
    mean: np.ndarray
    cell: tuple[int, int]
    box: Box
    region: Box


@dataclass(frozen=True)
class Task:
    """One planning task; ``waypoint_*`` are None/empty for basic tasks."""

    home: str
    kind: TaskKind
    index: int
    start_place: int
    goal_place: int
    waypoint_place: int | None
    start_cell: tuple[int, int]
    start_xy: tuple[float, float]
    goal_name: str
    waypoint_name: str | None
    goal_places: tuple[int, ...]
    waypoint_places: tuple[int, ...]
    closest_goal: int  # index into goal_places: closest from the start (the paper's N), footprint rule
    l: float  # the reference length under the footprint rule
    closest_goal_via: int = -1  # index into goal_places: where the shortest path through a waypoint ends
    start_in_waypoint: bool = False  # the start lies inside a waypoint-named place's region
    strict_l: float = float("nan")  # the same three under the paper's strict rule (nan: not scored)
    strict_closest_goal: int = -1
    strict_closest_goal_via: int = -1

    @property
    def goal_words(self) -> list[str]:
        return self.goal_name.split()

    @property
    def waypoint_words(self) -> list[str]:
        return self.waypoint_name.split() if self.waypoint_name else []

    @property
    def all_words(self) -> list[str]:
        """Waypoint and goal words as one bag (how SpCoNavi and A* receive an advanced instruction)."""
        return self.waypoint_words + self.goal_words

    def label(self) -> str:
        via = f" via {self.waypoint_name} ({self.waypoint_place})" if self.waypoint_name else ""
        return f"{self.home} #{self.index}: {self.start_place} -> {self.goal_name} ({self.goal_place}){via}"


@dataclass
class HomeTasks:
    """The places, adjacency and tasks of one home."""

    home: str
    places: list[Place]
    adjacency: np.ndarray
    adjacency_source: str
    tasks: list[Task]
    dropped: list[str] = field(default_factory=list)  # tasks left out (no robot path at all), with the reason
    zero_length: list[str] = field(default_factory=list)  # tasks left out because l = 0
    no_safe_path: list[str] = field(default_factory=list)  # left out: no footprint-safe path (module docstring)


def build_places(dataset: Dataset) -> list[Place]:
    """The ground-truth places of a dataset (truth.csv), named from places.csv or, without it, from the words.

    Raises:
        DatasetError: the dataset has no truth.csv, or a place has no teaching event.
    """
    if dataset.truth_place is None:
        raise DatasetError(f"{dataset.name}: evaluation needs truth.csv (the true place of every teaching event)")
    truth = np.asarray(dataset.truth_place)
    n = int(truth.max()) + 1
    empty = [k for k in range(n) if not np.any(truth == k)]
    if empty:
        raise DatasetError(f"{dataset.name}: truth.csv place(s) {empty} have no teaching event")
    names = dataset.place_names if dataset.place_names is not None else names_from_words(dataset.tokens, truth)
    if len(names) < n:
        raise DatasetError(f"{dataset.name}: places.csv names {len(names)} places but truth.csv uses {n}")
    places = []
    robot = robot_cells(dataset)
    if not robot.any():
        raise DatasetError(f"{dataset.name}: the map has no free cell a robot fits in")
    regions, nearest = label4(robot)[0], nearest_index(robot)
    for k in range(n):
        pts = dataset.positions[truth == k]
        box = Box.around(pts, REGION_MARGIN_M)
        position = place_position(dataset, pts, robot, regions, nearest)
        places.append(Place(k, str(names[k]), pts.mean(axis=0), position, box, box.grown(ROBOT_RADIUS_M)))
    return places


def place_position(
    dataset: Dataset, pts: np.ndarray, robot: np.ndarray, regions: np.ndarray, nearest: np.ndarray
) -> tuple[int, int]:
    """A place's position (module docstring) from its teaching positions ``pts``: the robot cell nearest their mean
    within the free region (``regions``: labels of the 4-connected components of ``robot``) that holds the nearest
    robot cells (``nearest``: :func:`~spcotmhp.metric.snap.nearest_index` of ``robot``) of most of them (ties: the
    lower label). Where the mean's nearest robot cell already lies in that region, it is that cell."""
    occ = dataset.map
    size = np.array(robot.shape) - 1
    at = np.clip(occ.world_to_cell(np.asarray(pts, float)).reshape(-1, 2), 0, size)
    near = nearest[:, at[:, 0], at[:, 1]]
    region = int(np.argmax(np.bincount(regions[near[0], near[1]])))
    r, c = np.clip(occ.world_to_cell(np.asarray(pts, float).mean(axis=0)), 0, size)
    best = (int(nearest[0][r, c]), int(nearest[1][r, c]))
    if regions[best] == region:
        return best
    r, c = snap(regions == region, np.array([r, c]))
    return int(r), int(c)


def names_from_words(tokens: list[list[str]], truth: np.ndarray) -> list[str]:
    """A name per true place when places.csv is absent: the word w maximising n(w, k)^2 / n(w), i.e. frequent
    at the place and specific to it (function words said everywhere score low)."""
    total = Counter(w for toks in tokens for w in toks)
    names = []
    for k in range(int(truth.max()) + 1):
        here = Counter(w for toks, t in zip(tokens, truth, strict=False) if t == k for w in toks)
        if not here:
            names.append(f"place{k}")
            continue
        names.append(max(sorted(here), key=lambda w: here[w] ** 2 / total[w]))
    return names


def nearest_free_cell(dataset: Dataset, xy: np.ndarray, robot: np.ndarray | None = None) -> tuple[int, int]:
    """The robot cell (:func:`robot_cells`) whose centre is nearest to ``xy`` (Euclidean in cells;
    :func:`spcotmhp.metric.snap.snap`)."""
    robot = robot_cells(dataset) if robot is None else robot
    if not robot.any():
        raise DatasetError(f"{dataset.name}: the map has no free cell a robot fits in")
    r, c = snap(robot, dataset.map.world_to_cell(np.asarray(xy, float)))
    return int(r), int(c)


def make_tasks(
    dataset: Dataset,
    kind: TaskKind,
    adjacency: np.ndarray,
    adjacency_source: str = "adjacency.csv",
    places: list[Place] | None = None,
) -> HomeTasks:
    """All tasks of one kind for a home (see the module docstring).

    Args:
        dataset: the home (map, teaching positions, truth; names from places.csv or the words).
        kind: "basic" or "advanced".
        adjacency: (P, P) 0/1 place adjacency over the true places.
        adjacency_source: where the adjacency came from (reported with the results).
        places: precomputed :func:`build_places` output.
    """
    if kind not in TASK_KINDS:
        raise ValueError(f"task kind must be one of {TASK_KINDS}, got {kind!r}")
    places = build_places(dataset) if places is None else places
    n = len(places)
    adjacency = np.asarray(adjacency)
    if adjacency.shape != (n, n):
        raise DatasetError(f"{dataset.name}: adjacency is {adjacency.shape} but truth.csv has {n} places")
    geometry = home_geometry(dataset, places)
    by_name: dict[str, list[int]] = {}
    for p in places:
        by_name.setdefault(p.name, []).append(p.index)
    out = HomeTasks(dataset.name, places, adjacency, adjacency_source, [])
    for i, j, h in _task_places(kind, places, adjacency):
        _add_task(out, dataset, kind, geometry, by_name, i, j, h)
    return out


def home_geometry(dataset: Dataset, places: list[Place]) -> HomeGeometry:
    """The home's geodesic fields over the robot cells (:class:`~spcotmhp.evaluation.reference.HomeGeometry`),
    with each place's position and footprint target (:func:`~spcotmhp.evaluation.reference.footprint_targets`)."""
    robot = robot_cells(dataset)
    occ = dataset.map
    means = occ.world_to_cell(np.array([p.mean for p in places]))
    positions = np.array([p.cell for p in places])
    targets = footprint_targets(robot, occ.cell_centres(), means, [p.region for p in places], positions)
    return HomeGeometry(robot, occ.resolution, positions, targets)


def _task_places(kind: TaskKind, places: list[Place], adjacency: np.ndarray) -> Iterator[tuple[int, int, int | None]]:
    """Every (start i, goal j, waypoint h) of a task kind, in task order: i != j not adjacent; h is None for basic
    tasks, else every place outside {i, j} whose name differs from the goal's."""
    n = len(places)
    for i in range(n):
        for j in range(n):
            if i == j or adjacency[i, j]:
                continue
            if kind == "basic":
                yield i, j, None
                continue
            for h in range(n):
                if h not in (i, j) and places[h].name != places[j].name:
                    yield i, j, h


def _add_task(
    out: HomeTasks,
    dataset: Dataset,
    kind: TaskKind,
    geometry: HomeGeometry,
    by_name: dict[str, list[int]],
    i: int,
    j: int,
    h: int | None,
) -> None:
    """Append the task (start i, goal j, waypoint h) to ``out.tasks``, or record why it is left out (no path:
    ``out.dropped``; no footprint-safe path: ``out.no_safe_path``; l = 0: ``out.zero_length``)."""
    places = out.places
    goals = tuple(by_name[places[j].name])
    wps = () if h is None else tuple(by_name[places[h].name])
    label = f"start {i} -> {places[j].name} ({j})" + ("" if h is None else f" via {places[h].name} ({h})")
    strict = geometry.strict(places[i].cell, goals, wps)
    if not np.isfinite(strict.l):
        out.dropped.append(f"{label}: no free-space path reaches a goal-named place")
        return
    safe = geometry.footprint(places[i].cell, goals, wps)
    if not np.isfinite(safe.l):
        out.no_safe_path.append(
            f"{label}: no cell where the robot's centre fits within {ROBOT_RADIUS_M:.2f} m of a "
            + ("goal" if h is None else "waypoint and a goal")
            + "-named place's box is reachable"
        )
        return
    if safe.l == 0 or strict.l == 0:
        out.zero_length.append(f"{label}: the start is a goal instance")
        return
    x, y = dataset.map.cell_to_world(np.array(places[i].cell))
    out.tasks.append(
        Task(
            dataset.name,
            kind,
            len(out.tasks),
            i,
            j,
            h,
            places[i].cell,
            (float(x), float(y)),
            places[j].name,
            None if h is None else places[h].name,
            goals,
            wps,
            safe.closest,
            safe.l,
            safe.closest_via,
            bool(any(places[k].region.contains(np.array([x, y])) for k in wps)),
            strict.l,
            strict.closest,
            strict.closest_via,
        )
    )


def subset(tasks: list[Task], max_tasks: int | None, seed: int) -> list[Task]:
    """A seeded random subset of at most ``max_tasks`` tasks, in their original order (all when None)."""
    if max_tasks is None or max_tasks >= len(tasks):
        return list(tasks)
    if max_tasks < 1:
        raise ValueError(f"max_tasks must be >= 1, got {max_tasks}")
    keep = np.sort(np.random.default_rng(seed).choice(len(tasks), size=max_tasks, replace=False))
    return [tasks[k] for k in keep]

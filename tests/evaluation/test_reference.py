"""Reference lengths under the footprint and the strict rule, on a hand-made room with a counter against a wall
and a closet too narrow for the robot (0.1 m cells, inscribed radius 0.22 m: cells within 2 cells of a wall are
inscribed)."""

import numpy as np
import pytest

from spcotmhp.datasets.dataset import Dataset
from spcotmhp.evaluation.metrics import score_path
from spcotmhp.evaluation.reference import HomeGeometry, footprint_targets, robot_cells
from spcotmhp.evaluation.tasks import build_places, home_geometry, make_tasks
from spcotmhp.metric.grid_search import geodesic_distance
from spcotmhp.metric.maps import OccupancyMap


def room_with_closet() -> Dataset:
    """20 x 60 cells at 0.1 m (x = (col + 0.5) / 10, y = (row + 0.5) / 10), walls all round; a wall at col 40 and
    beyond, but for a slot (rows 9-11, 0.3 m wide) running to col 58. Places: 0 "room" in the open, 1 "counter"
    taught at x 3.95-3.98 against the wall (its box, x 3.85-4.08, holds only inscribed cells), 2 "closet" taught
    deep in the slot (x 5.0-5.5), where no robot centre fits."""
    data = np.zeros((20, 60), np.int8)
    data[[0, -1], :] = 100
    data[:, [0, -1]] = 100
    data[:, 40:] = 100
    data[9:12, 40:59] = 0
    positions = np.array([[1.0, 1.0], [1.5, 1.5], [3.95, 0.5], [3.98, 0.5], [5.0, 1.05], [5.5, 1.05]])
    return Dataset(
        name="closet",
        map=OccupancyMap(data, resolution=0.1),
        positions=positions,
        tokens=[["room"], ["room"], ["counter"], ["counter"], ["closet"], ["closet"]],
        truth_place=np.array([0, 0, 1, 1, 2, 2]),
        adjacency=np.eye(3, dtype=int),
        place_names=["room", "counter", "closet"],
    )


def test_the_counters_region_reaches_robot_cells_its_box_does_not():
    ds = room_with_closet()
    robot = robot_cells(ds)
    assert robot[4, 37] and not robot[4, 38]  # 3 cells from the wall at col 40: the robot fits; 2 cells: no
    places = build_places(ds)
    rows, cols = np.nonzero(robot)
    centres = ds.map.cell_to_world(np.stack([rows, cols], axis=1))
    assert not places[1].box.contains(centres).any()  # box x >= 3.85: col 38 (x 3.85) on, inscribed
    reached = places[1].region.contains(centres)  # col 37 (x 3.75) is 0.1 m from the box, col 36 0.2 m
    # rows 4-5 face the box (y 0.4-0.6); rows 3 and 6 are 0.05 m off it (col 36: hypot(0.2, 0.05) = 0.206 m);
    # row 7 only at col 37 (hypot(0.1, 0.15) = 0.18 m; col 36: hypot(0.2, 0.15) = 0.25 m); row 2 is inscribed
    assert sorted(zip(rows[reached].tolist(), cols[reached].tolist(), strict=True)) == [
        (3, 36),
        (3, 37),
        (4, 36),
        (4, 37),
        (5, 36),
        (5, 37),
        (6, 36),
        (6, 37),
        (7, 37),
    ]
    assert not places[2].region.contains(centres).any()  # the slot: the nearest robot cell is ~1 m away


def test_tasks_to_the_closet_have_no_footprint_safe_path_and_are_set_apart():
    ds = room_with_closet()
    ht = make_tasks(ds, "basic", ds.adjacency)
    assert ht.no_safe_path == [
        "start 0 -> closet (2): no cell where the robot's centre fits within 0.22 m of a goal-named place's box is "
        "reachable",
        "start 1 -> closet (2): no cell where the robot's centre fits within 0.22 m of a goal-named place's box is "
        "reachable",
    ]
    assert sorted((t.start_place, t.goal_place) for t in ht.tasks) == [(0, 1), (1, 0), (2, 0), (2, 1)]
    assert not ht.dropped and not ht.zero_length


def test_the_counters_target_is_its_position_and_a_safe_end_there_succeeds_only_under_the_footprint_rule():
    ds = room_with_closet()
    places = build_places(ds)
    ht = make_tasks(ds, "basic", ds.adjacency, places=places)
    task = next(t for t in ht.tasks if (t.start_place, t.goal_place) == (0, 1))
    geometry = home_geometry(ds, places)
    # the mean (3.965, 0.5) is in cell (5, 39), inscribed; the nearest robot cell, (5, 37), lies 0.1 m from the
    # box, inside the region: it is both the position and the footprint target
    assert places[1].cell == (5, 37) and geometry.targets[1].tolist() == [5, 37]
    assert geometry.targets[2].tolist() == [-1, -1]  # the closet's region holds no robot cell
    d = geodesic_distance(robot_cells(ds), [places[0].cell], 8, 0.1)  # an independent field from the start
    assert task.l == task.strict_l == pytest.approx(d[5, 37])
    end = ds.map.cell_to_world(np.array(places[1].cell))
    path = np.array([task.start_xy, end])
    safe = score_path(path, [places[1].region], 0, task.l, 0.0)
    strict = score_path(path, [places[1].box], 0, task.strict_l, 0.0)
    assert safe.success and safe.ratio == pytest.approx(min(1.0, task.l / safe.p)) and not strict.success


class _Right:
    """A region: the points with x >= 5 (cells of cols 5.. at 1 m per cell)."""

    def contains(self, xy):
        return np.asarray(xy)[..., 0] >= 5.0


def test_footprint_targets_by_hand():
    robot = np.ones((4, 10), bool)
    centres = np.stack(np.meshgrid(np.arange(10) + 0.5, np.arange(4) + 0.5), axis=-1)  # (row, col) -> (x, y)
    means = np.array([[1, 0], [1, 9]])
    positions = np.array([[1, 0], [1, 4]])
    # the mean at (1, 0): the region's nearest robot cell is (1, 5); at (1, 9) it is its own cell
    assert footprint_targets(robot, centres, means, [_Right(), _Right()], positions).tolist() == [[1, 5], [1, 9]]
    # a wall at col 7 cuts cols 8-9 off: the region's cells in the free region of the position (cols 0-6) first
    robot[:, 7] = False
    assert footprint_targets(robot, centres, means, [_Right(), _Right()], positions).tolist() == [[1, 5], [1, 6]]
    positions[1] = [1, 8]  # a position beyond the wall: its own free region's cells
    assert footprint_targets(robot, centres, means, [_Right(), _Right()], positions).tolist() == [[1, 5], [1, 9]]
    robot[:, 5:] = False  # no robot cell in the region at all: none
    assert footprint_targets(robot, centres, means[:1], [_Right()], positions[:1]).tolist() == [[-1, -1]]


def test_through_a_waypoint_by_brute_force():
    """l via a waypoint is the minimum over every (waypoint, goal) instance pair of d(start, w) + d(w, g), checked
    with fields computed here; and a place without a target leaves the task without a footprint-safe path."""
    positions = np.array([[0, 0], [4, 7], [0, 7], [4, 0]])
    targets = np.array([[0, 0], [4, 7], [0, 7], [2, 3]])  # place 3's target is not its position
    geometry = HomeGeometry(np.ones((5, 8), bool), 0.5, positions, targets)
    free = np.ones((5, 8), bool)
    d = {k: geodesic_distance(free, [tuple(geometry.targets[k])], 8, 0.5) for k in range(4)}
    for start, goals, wps in [((0, 0), (1, 2), (3,)), ((2, 2), (1,), (2, 3)), ((4, 4), (0, 2), (1, 3))]:
        ref = geometry.footprint(start, goals, wps)
        pairs = {(w, g): d[w][start] + d[w][tuple(geometry.targets[g])] for w in wps for g in goals}
        best = min(pairs, key=pairs.get)
        assert ref.l == pytest.approx(pairs[best]) and goals[ref.closest_via] == best[1]
        assert goals[ref.closest] == min(goals, key=lambda g: d[g][start])
    geometry.targets[3] = [-1, -1]
    assert geometry.footprint((0, 0), (1,), (3,)).l == np.inf and geometry.footprint((0, 0), (3,), ()).l == np.inf
    assert geometry.strict((0, 0), (3,), ()).l == pytest.approx(4 * 0.5)  # the position (4, 0) is reachable

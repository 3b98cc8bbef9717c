"""A place taught against a wall (datasets/against_wall.py), and what the two success rules make of it."""

import numpy as np
import pytest

from spcotmhp.datasets.against_wall import against_wall, wall_cells
from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.errors import DatasetError
from spcotmhp.evaluation.context import build_context
from spcotmhp.evaluation.reference import robot_cells
from spcotmhp.evaluation.tasks import make_tasks
from spcotmhp.evaluation.work import run_method, score_task


@pytest.fixture(scope="module")
def bath():
    home = battery_home(0)
    k = home.place_names.index("bath")
    return home, against_wall(home, k), k


def test_the_places_positions_lie_on_cells_beside_a_wall_and_the_rest_stay(bath):
    home, moved, k = bath
    truth = np.asarray(home.truth_place)
    occ = moved.map
    cells = occ.world_to_cell(moved.positions[truth == k])
    beside = {tuple(c) for c in wall_cells(moved).tolist()}
    assert all(tuple(c) in beside for c in cells.tolist())
    assert len({tuple(c) for c in cells.tolist()}) == (truth == k).sum()  # one cell each: a strip along the wall
    np.testing.assert_array_equal(moved.positions[truth != k], home.positions[truth != k])
    assert moved.name == "battery-0-wall3" and moved.tokens == home.tokens


def test_a_safe_plan_reaches_the_place_under_the_footprint_rule_only(bath):
    """Issue 25's acceptance on such a home: no task into the place fails because no safe centre fits in its box
    (every box cell is inscribed); the paper's strict rule fails every one of them."""
    _, moved, k = bath
    ctx = build_context(moved, "supervised", 0)
    robot = robot_cells(moved)
    rows, cols = np.nonzero(robot)
    assert not ctx.places[k].box.contains(moved.map.cell_to_world(np.stack([rows, cols], axis=1))).any()
    tasks = [t for t in make_tasks(moved, "basic", ctx.adjacency, places=ctx.places).tasks if t.goal_place == k]
    assert len(tasks) >= 5
    for task in tasks:
        outcome = score_task(ctx, task, run_method("spcotmhp", ctx, task, np.random.default_rng(0)), 0.0)
        assert outcome.success and not outcome.strict.success, task.label()


def test_bad_requests():
    home = battery_home(0)
    with pytest.raises(DatasetError, match="no teaching event of place 99"):
        against_wall(home, 99)
    from dataclasses import replace

    with pytest.raises(DatasetError, match="needs truth.csv"):
        against_wall(replace(home, truth_place=None), 0)

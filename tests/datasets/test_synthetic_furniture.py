"""Furniture and closed doors in synthetic homes (datasets/synthetic_furniture.py): islands of the robot's free
space inside seating groups, rooms that stay one region around them, and homes unchanged without furniture."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage

from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.datasets.synthetic_furniture import close_doors, furnish
from spcotmhp.datasets.synthetic_plan import generate_floor_plan
from spcotmhp.errors import DatasetError
from spcotmhp.metric.costmap import inflate
from spcotmhp.metric.maps import FREE, OCCUPIED

FOUR = ndimage.generate_binary_structure(2, 1)


@pytest.mark.parametrize("seed", range(5))
def test_every_group_holds_an_island_and_the_rest_of_the_home_stays_one_region(seed):
    plan = generate_floor_plan("house", seed=seed)
    before = plan.map.data.copy()
    squares = furnish(plan, np.random.default_rng(seed), share=1.0)
    assert squares
    robot = inflate(plan.map).free
    comp, n = ndimage.label(robot, structure=FOUR)
    sizes = np.bincount(comp.ravel())
    main = int(np.argmax(sizes[1:])) + 1
    for r0, c0, r1, c1 in squares:
        inner = comp[r0:r1, c0:c1]
        assert (inner > 0).any(), "the square holds cells the robot fits in"
        assert not (inner == main).any(), "and they are cut off from the room around it"
        assert (plan.map.data[r0:r1, c0:c1] == FREE).all()
    # outside the groups' squares every robot cell is in one region: the pockets are the only islands
    pockets = np.zeros_like(robot)
    for r0, c0, r1, c1 in squares:
        pockets[r0:r1, c0:c1] = True
    assert n > len(squares) and (comp[robot & ~pockets] == main).all()
    changed = plan.map.data != before
    assert (before[changed] == FREE).all() and (plan.map.data[changed] == OCCUPIED).all()


def test_some_gaps_are_free_on_the_map_but_closed_for_the_robot():
    """The pieces' gaps: the pocket touches the room through free map cells (4-connected), not through robot
    cells."""
    plan = generate_floor_plan("house", seed=3)
    squares = furnish(plan, np.random.default_rng(3), share=1.0)
    free_comp, _ = ndimage.label(plan.map.data == FREE, structure=FOUR)
    robot_comp, _ = ndimage.label(inflate(plan.map).free, structure=FOUR)
    joined = [
        free_comp[(r0 + r1) // 2, (c0 + c1) // 2] == free_comp[plan.rooms[0].doors[0]] for r0, c0, r1, c1 in squares
    ]
    assert any(joined)
    for r0, c0, r1, c1 in squares:
        assert robot_comp[(r0 + r1) // 2, (c0 + c1) // 2] != robot_comp[plan.rooms[0].doors[0]]


def test_the_battery_home_without_furniture_is_unchanged_and_with_it_only_gains_pieces():
    for seed in (0, 7):
        plain, again, furnished = battery_home(seed), battery_home(seed), battery_home(seed, furniture=True)
        np.testing.assert_array_equal(plain.map.data, again.map.data)
        np.testing.assert_array_equal(plain.positions, furnished.positions)
        np.testing.assert_array_equal(plain.trajectory, furnished.trajectory)
        assert plain.tokens == furnished.tokens
        changed = plain.map.data != furnished.map.data
        assert changed.any() and (plain.map.data[changed] == FREE).all()
        assert furnished.name == f"battery-{seed}-furniture"
        np.testing.assert_array_equal(battery_home(seed, furniture=True).map.data, furnished.map.data)


def test_closing_a_door_cuts_the_home_into_two_regions():
    plan = generate_floor_plan("house", seed=2)
    robot = inflate(plan.map).free
    assert ndimage.label(robot, structure=FOUR)[1] == 1
    closed = close_doors(plan, np.random.default_rng(0), 1)
    assert len(closed) == 1
    assert ndimage.label(inflate(plan.map).free, structure=FOUR)[1] == 2
    with pytest.raises(DatasetError, match="cannot close"):
        close_doors(plan, np.random.default_rng(0), 99)
    with pytest.raises(DatasetError, match="probability"):
        furnish(plan, np.random.default_rng(0), share=1.5)

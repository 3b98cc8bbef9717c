"""The battery's homes (spcotmhp/datasets/synthetic_battery.py): each has an unknown strip on the side of one room
away from its doors (seed 152 has no room with a single door and used to crash)."""

from __future__ import annotations

import pytest

from spcotmhp.datasets.synthetic_battery import _far_strip, battery_home
from spcotmhp.datasets.synthetic_plan import Room


def test_a_seed_with_no_single_door_room_still_gives_a_home():
    assert battery_home(152).name == "battery-152"


def test_one_door_leaves_the_side_away_from_it():
    room = Room("study", 0, (10, 20, 20, 40), doors=[(9, 30)])  # door in the top wall
    assert _far_strip(room) == (slice(16, 20), slice(20, 40))


@pytest.mark.parametrize(
    ("doors", "clear"),
    [
        ([(9, 30), (15, 19)], (slice(10, 20), slice(32, 40))),  # top and left (near the bottom strip): the right
        ([(20, 30), (9, 25)], (slice(10, 20), slice(32, 40))),  # bottom and top: the right is clear
    ],
)
def test_several_doors_leave_a_side_no_door_is_near(doors, clear):
    assert _far_strip(Room("study", 0, (10, 20, 20, 40), doors=doors)) == clear


def test_doors_on_every_side_leave_no_strip():
    doors = [(9, 30), (20, 30), (15, 19), (15, 40)]
    assert _far_strip(Room("study", 0, (10, 20, 20, 40), doors=doors)) is None

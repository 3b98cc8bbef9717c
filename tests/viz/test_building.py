"""Pictures of a plan in a building: one per segment, named per floor, marked with the start, the stops ridden
and the goal."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.building.learn import learn_building
from spcotmhp.building.planner import BuildingPlanner
from spcotmhp.building.synthetic import generate_building
from spcotmhp.viz.building import draw_building_plan, floor_picture_path, picture_paths, segment_marks


@pytest.fixture(scope="module")
def case():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        b = generate_building(3, seed=6, n_rooms=5, events_per_room=8)
        bm = learn_building(b)
    start = b.floors[1].positions[0]  # where the first teaching happened on floor 1
    return bm, BuildingPlanner(bm).plan({"goal": {"words": "bedroom", "floor": 3}, "waypoints": [
        {"words": "kitchen", "floor": 2}]}, start, 1)  # fmt: skip


def test_marks_follow_the_rides(case):
    _, plan = case
    assert len(plan.segments) == 3
    first, middle, last = (segment_marks(plan, k) for k in range(3))
    assert first[0][2] == "start" and first[-1][2] == plan.rides[0].kind
    assert np.allclose(first[-1][0], plan.rides[0].board[1])
    assert middle[0][2] == plan.rides[0].kind and np.allclose(middle[0][0], plan.rides[0].leave[1])
    assert [m[2] for m in middle[1:]] == ["waypoint", plan.rides[1].kind]
    assert last[-1][2] == "goal" and "bedroom" in last[-1][1]


def test_one_picture_per_floor(case, tmp_path):
    bm, plan = case
    written = draw_building_plan(plan, bm, tmp_path / "route.png")
    assert [p.name for p in written] == ["route-floor1.png", "route-floor2.png", "route-floor3.png"]
    assert all(p.read_bytes().startswith(b"\x89PNG") for p in written)
    assert floor_picture_path("a/b", 2).name == "b-floor2.png"
    twice = type(plan)(plan.segments + plan.segments[:1], plan.rides, plan.floor_names, 0.0, plan.instruction)
    assert picture_paths(twice, "r.png")[-1].name == "r-floor1-2.png"

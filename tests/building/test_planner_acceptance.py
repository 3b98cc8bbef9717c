"""Issue 28's acceptance battery (:mod:`spcotmhp.evaluation.building_battery`) on generated buildings of 2 to 5
floors (names repeated across floors, one floor reached only by the lift): every "go to the X" with the goal on
floor F ends on floor F in the closest instance there, every "go to the X" in the closest instance over all floors
counting the connectors' costs (within the single-floor battery's tolerance, against the independent geodesic
oracle), and no "no path" where a connector route exists. docs/buildings.md gives the figures on more seeds and
on learned models (benchmarks/building_battery.py)."""

from __future__ import annotations

import warnings

import pytest

from spcotmhp.building.learn import learn_building
from spcotmhp.building.planner import BuildingPlanner
from spcotmhp.building.synthetic import generate_building, lift_only_floor
from spcotmhp.evaluation.building_battery import battery


@pytest.mark.parametrize(("floors", "seed"), [(2, 1), (3, 2), (4, 3), (5, 4)])
def test_battery(floors, seed):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        building = generate_building(floors, seed=seed)
        planner = BuildingPlanner(learn_building(building))
    assert lift_only_floor(building.spec) is not None
    result = battery(building, planner)
    assert result["plans"] == 18 * floors * (floors + 1)  # 2 starts x 9 shared names x (each floor + any floor)
    assert result["no_path"] == 0, result["failures"]
    assert result["on_floor"] == result["plans"], result["failures"]
    assert result["closest"] == result["plans"], result["failures"]

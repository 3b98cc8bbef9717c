"""A start inside a place to avoid (issue 34): the robot standing in the kitchen hears "go to the bath avoiding the
kitchen"; the plan leaves the kitchen by the shortest footprint-safe way and never enters it again, and says so.
Checked on seeded generated homes from every place's mean to a place two or more rooms away."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.errors import PlanningError
from spcotmhp.learning.supervised import fit_supervised
from spcotmhp.planning.avoid import avoided_view
from spcotmhp.planning.planner import HierarchicalPlanner


@pytest.fixture(scope="module", params=[0, 3, 8])
def planner(request) -> HierarchicalPlanner:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return HierarchicalPlanner(fit_supervised(battery_home(request.param)))


def test_a_start_inside_a_place_to_avoid_leaves_it_and_never_comes_back(planner):
    names = planner.names
    single = [k for k in np.flatnonzero(planner.model.active_places) if names.count(names[k]) == 1]
    planned = left_it = 0
    for k in single:
        start = tuple(float(v) for v in planner.model.mu[k])
        goal = next(g for g in single if g != k and not planner.graph.connected[k, g])
        try:
            plan = planner.plan(f"go to the {names[goal]} avoiding the {names[k]}", start)
        except PlanningError:
            continue  # the goal only reachable through the avoided place: refused, as it should be
        planned += 1
        view = avoided_view(planner.graph, (int(k),))
        crop = view.to_crop(plan.cells)
        inside = view.blocked[crop[:, 0], crop[:, 1]]
        if inside.any():
            left = int(np.flatnonzero(~inside)[0])
            assert not inside[left:].any(), f"{names[k]}: the path enters the avoided place again"
            assert "leaves it by the shortest way" in plan.explanation, plan.explanation
            left_it += 1
        assert np.isfinite(planner.graph.log_p[crop[:, 0], crop[:, 1]]).all()  # every pose footprint-clear
        assert plan.places[0].name == names[k]
    assert planned >= len(single) // 2 and left_it >= planned // 2  # not vacuous: most starts were inside

"""One scoring rule for the evaluation tables and the battery (evaluation/work.py: score_task)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from spcotmhp.datasets.synthetic_battery import battery_home
from spcotmhp.evaluation import battery
from spcotmhp.evaluation.context import build_context
from spcotmhp.evaluation.methods import task_instruction
from spcotmhp.evaluation.tasks import make_tasks
from spcotmhp.evaluation.work import score_task
from spcotmhp.metric.costmap import inflate


@pytest.fixture(scope="module")
def home():
    data = battery_home(3)
    ctx = build_context(data, "supervised", 0)
    tasks = make_tasks(data, "advanced", ctx.adjacency, places=ctx.places).tasks
    return ctx, tasks


def test_a_path_that_never_leaves_the_start_passes_no_waypoint(home):
    ctx, tasks = home
    task = next(t for t in tasks if t.start_in_waypoint)
    stay = np.array([task.start_xy, task.start_xy])
    outcome = score_task(ctx, task, stay, 0.0)
    assert outcome.w_success is False
    assert not outcome.success and not outcome.collides


def test_the_battery_scores_with_score_task(home, monkeypatch):
    ctx, tasks = home
    calls = []

    def recording(*args):
        calls.append(args)
        return score_task(*args)

    monkeypatch.setattr(battery, "score_task", recording)
    costs = inflate(ctx.dataset.map, **ctx.model.costmap).costs
    out = battery.HomeBattery(ctx.dataset.name, "supervised")
    task = next(t for t in tasks if t.start_in_waypoint)
    plan = ctx.planner.plan(task_instruction(task, ctx.dataset.lang), task.start_xy)
    outcome, _ = battery._run(ctx, task, costs, out)
    assert len(calls) == 1 and calls[0][1] is task
    np.testing.assert_array_equal(calls[0][2], plan.path)
    assert untimed(outcome) == untimed(score_task(ctx, task, plan.path, 0.0))


def untimed(outcome):
    """The outcome without its planning time (in its strict reading too)."""
    strict = None if outcome.strict is None else replace(outcome.strict, time_s=0.0)
    return replace(outcome, time_s=0.0, strict=strict)


def test_a_safe_end_beside_a_box_no_robot_centre_fits_in_succeeds_only_under_the_footprint_rule(home):
    """A place taught against a wall: its box's cells are all inscribed. A path ending on the robot cell nearest
    the box, within the inscribed radius of it, succeeds under the footprint rule, not under the paper's."""
    ctx, tasks = home
    task = next(t for t in tasks if t.goal_name != t.waypoint_name and not t.start_in_waypoint)
    goal = ctx.places[task.goal_places[task.closest_goal]]
    occ = ctx.dataset.map
    robot = inflate(occ).free
    rows, cols = np.nonzero(robot)
    centres = occ.cell_to_world(np.stack([rows, cols], axis=1))
    gap = goal.box.distance(centres)
    outside = np.flatnonzero((gap > 0.05) & (gap <= 0.2))  # robot cells 0.05-0.2 m outside the box
    assert len(outside)
    wp = ctx.places[task.waypoint_places[0]]
    via = centres[np.argmin(wp.box.distance(centres))]  # the robot cell nearest the waypoint's box (inside it here)
    path = np.array([task.start_xy, via, centres[outside[0]]])
    out = score_task(ctx, task, path, 0.0)
    assert out.success and out.n_success and out.w_success and out.strict is not None
    assert not out.strict.success and not out.strict.n_success and out.strict.w_success
    assert out.ratio == min(1.0, task.l / out.p) and out.strict.ratio == min(1.0, task.strict_l / out.p)

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
    assert replace(outcome, time_s=0.0) == replace(score_task(ctx, task, plan.path, 0.0), time_s=0.0)

"""One unit of evaluation work: each method on a chunk of tasks, scored (runs in a worker process, local or Ray).

Every random draw of a method uses its own generator seeded from (seed, home, task, method), so results do not
depend on the backend, the number of workers or the order in which chunks finish. Only online planning is
timed.
"""

from __future__ import annotations

import contextlib
import time
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from spcotmhp.errors import PlanningError, SpcotmhpError
from spcotmhp.evaluation.context import HomeContext
from spcotmhp.evaluation.methods import task_instruction
from spcotmhp.evaluation.metrics import Box, Outcome, failed, off_free_space, score_path
from spcotmhp.evaluation.tasks import Task

__all__ = [
    "CHUNK",
    "TaskRecord",
    "chunks",
    "evaluate_chunk",
    "failed_task",
    "run_method",
    "score_task",
    "task_seed",
    "warm_up",
]

CHUNK = 16  # tasks per work item: large enough to amortise IPC, small enough to balance two cores


@dataclass
class TaskRecord:
    """One method on one task: the outcome plus why it failed (planner error message), if it did."""

    task_index: int
    method: str
    outcome: Outcome
    error: str | None = None
    apart: bool = False  # the task's start lies inside a waypoint-named place (summarised apart)


def task_seed(seed: int, home: str, task_index: int, method: str) -> np.random.SeedSequence:
    """The seed of one method's draws on one task (independent of scheduling)."""
    return np.random.SeedSequence([seed, zlib.crc32(home.encode()), task_index, zlib.crc32(method.encode())])


def run_method(name: str, ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray:
    """Run one method on one task: the (n, 2) world path in metres of its plan (the online work the runner
    times: understanding the task's words, planning, assembling)."""
    return ctx.planners[name].plan(task_instruction(task, ctx.dataset.lang), task.start_xy, rng=rng).path


def warm_up(ctx: HomeContext, task: Task | None = None, methods: Sequence[str] = ()) -> None:
    """Compile (or load) the numba kernels and run each method once on ``task`` (results discarded), so that no
    timed task pays for compilation or first-call caches."""
    from spcotmhp.metric.grid_search import warmup

    warmup()
    if task is None:
        return
    for name in methods:
        with contextlib.suppress(SpcotmhpError):  # warming up: a refused task has compiled what it needs
            run_method(name, ctx, task, np.random.default_rng(0))


def score_task(ctx: HomeContext, task: Task, path: np.ndarray, elapsed: float) -> Outcome:
    """Score one planned ``path`` for ``task``: the SPL family (:func:`score_path`) under the footprint rule (the
    goal and waypoint regions, the task's ``l`` and closest instances) with, as its ``strict`` reading, the
    paper's rule (the boxes, ``strict_l``, the strict closest instances); a waypoint counted only once the path has
    left the start's cell, and collisions with occupied or unknown space. The one scoring rule of the evaluation
    tables and the battery."""
    advanced = task.kind == "advanced"
    occ = ctx.dataset.map
    start_box = Box.around(np.array([task.start_xy]), occ.resolution / 2)

    def scored(kind: str, l: float, closest: int, closest_via: int) -> Outcome:
        return score_path(
            path,
            [getattr(ctx.places[k], kind) for k in task.goal_places],
            closest,
            l,
            elapsed,
            [getattr(ctx.places[k], kind) for k in task.waypoint_places] if advanced else None,
            step=occ.resolution / 2,
            closest_goal_via=closest_via if advanced else None,
            start_box=start_box,
        )

    strict = scored("box", task.strict_l, task.strict_closest_goal, task.strict_closest_goal_via)
    outcome = scored("region", task.l, task.closest_goal, task.closest_goal_via)
    collides = off_free_space(path, occ.free, occ.world_to_cell, occ.resolution / 4)
    return replace(outcome, collides=collides, strict=replace(strict, collides=collides))


def failed_task(task: Task, elapsed: float) -> Outcome:
    """The outcome of a task with no path, under both rules."""
    advanced = task.kind == "advanced"
    return failed(task.l, elapsed, advanced, advanced, task.strict_l)


def evaluate_chunk(ctx: HomeContext, tasks: Sequence[Task], methods: Sequence[str], seed: int) -> list[TaskRecord]:
    """Run each method on each task and score it (runs in a worker)."""
    out = []
    for task in tasks:
        for method in methods:
            rng = np.random.default_rng(task_seed(seed, ctx.name, task.index, method))
            t0 = time.perf_counter()
            try:
                path, error = run_method(method, ctx, task, rng), None
            except PlanningError as exc:
                path, error = None, str(exc)
            elapsed = time.perf_counter() - t0
            if path is None or len(path) == 0:
                outcome = failed_task(task, elapsed)
                error = error or "no path"
            else:
                outcome = score_task(ctx, task, path, elapsed)
            out.append(TaskRecord(task.index, method, outcome, error, task.start_in_waypoint))
    return out


def chunks(tasks: Sequence[Task], size: int | None = None) -> list[list[Task]]:
    """The tasks cut into work items of ``size`` (default :data:`CHUNK`, read at call time)."""
    size = CHUNK if size is None else size
    return [list(tasks[i : i + size]) for i in range(0, len(tasks), size)]

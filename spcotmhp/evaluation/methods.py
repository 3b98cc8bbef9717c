"""The compared methods of Experiment I (paper Section 4.2, (A)-(E)) behind one signature:
``method(ctx, task, rng) -> (n, 2) world path in metres, or None``. Everything a call does is online work
(timed by the runner); the offline parts live in the :class:`~spcotmhp.evaluation.context.HomeContext`.

For advanced tasks, A* and SpCoNavi receive the waypoint and goal words as one bag of words (as in the paper);
the hierarchical methods get them as ordered stages.

Move models (:data:`MOVE_MODELS`, reported with the results): SpCoTMHP, HPP-I/II (the partial paths of the same
planning graph) and A* move 8-connected, like the reference length l of SPL; SpCoNavi (Viterbi and its A*
approximation) keeps the paper's action set {stay, up, down, left, right}, so its paths are 4-connected and up
to sqrt 2 longer on diagonals.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable

import numpy as np

from spcotmhp.baselines.astar_goal import astar_to_sampled_goal
from spcotmhp.baselines.spconavi import astar_approximation, log_weight_map, viterbi
from spcotmhp.evaluation.context import HomeContext
from spcotmhp.evaluation.tasks import Task

SPCONAVI_T = 200   # the paper's SpCoNavi horizon
SPCONAVI_J = 10    # goal candidates of the A* approximation

Method = Callable[[HomeContext, Task, np.random.Generator], "np.ndarray | None"]

MOVE_MODELS = {
    "spcotmhp": "8-connected",
    "astar": "8-connected",
    "hpp1": "8-connected (the planning graph's partial paths)",
    "hpp2": "8-connected (the planning graph's partial paths)",
    "spconavi-viterbi": "4-connected + stay (the paper's SpCoNavi action set)",
    "spconavi-astar": "4-connected + stay (the paper's SpCoNavi action set)",
}
"""How each method moves on the grid (the SPL reference length l is an 8-connected geodesic)."""


def _world(ctx: HomeContext, cells: np.ndarray | None) -> np.ndarray | None:
    if cells is None:
        return None
    cells = np.asarray(cells).reshape(-1, 2)
    keep = np.ones(len(cells), dtype=bool)
    keep[1:] = np.any(cells[1:] != cells[:-1], axis=1)  # drop "stay" repeats
    return ctx.dataset.map.cell_to_world(cells[keep])


def spcotmhp(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray:
    """(E) SpCoTMHP: the hierarchical planner (Eq. 28, exact joint search) from the task's start."""
    from spcotmhp.planning.instructions import Instruction, PlaceQuery

    def query(words: list[str]) -> PlaceQuery:
        return PlaceQuery(dict(Counter(words)), " ".join(words))

    waypoints = (query(task.waypoint_words),) if task.waypoint_words else ()
    ins = Instruction(goal=query(task.goal_words), waypoints=waypoints, lang=ctx.dataset.lang)
    return ctx.planner.plan(ins, task.start_xy).path


def astar(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray | None:
    """(A) A* to a goal drawn from p(x | S, Theta), with SpCoTMHP's move model (8-connected)."""
    cells = astar_to_sampled_goal(ctx.model, ctx.costmap.log_p, ctx.dataset.map, task.start_cell,
                                  task.all_words, rng, connectivity=ctx.planner.graph.settings.connectivity)
    return _world(ctx, cells)


def spconavi_viterbi(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray:
    """(B) SpCoNavi, exact Viterbi over every free cell, T = 200, actions {stay, up, down, left, right}."""
    log_w = log_weight_map(ctx.model, ctx.costmap.log_p, ctx.cell_xy, task.all_words)
    return _world(ctx, viterbi(log_w, task.start_cell, SPCONAVI_T).cells)


def spconavi_astar(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray | None:
    """(C) SpCoNavi, A* approximation with J = 10 sampled goals, actions {stay, up, down, left, right}."""
    log_w = log_weight_map(ctx.model, ctx.costmap.log_p, ctx.cell_xy, task.all_words)
    return _world(ctx, astar_approximation(log_w, task.start_cell, rng, SPCONAVI_J, SPCONAVI_T))


def _hpp(name: str) -> Method:
    def run(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray:
        hpp = ctx.hpp[name]
        cell = hpp.graph.to_crop(np.array(task.start_cell))
        stages = [task.waypoint_words] if task.waypoint_words else []
        return _world(ctx, hpp.graph.to_map(hpp.plan(cell, stages + [task.goal_words], rng)))

    run.__doc__ = f"(D) {'HPP-I (edge cost: partial-path cost)' if name == 'hpp1' else 'HPP-II (edge cost: partial-path length)'}."
    return run


METHODS: dict[str, Method] = {
    "spcotmhp": spcotmhp,
    "astar": astar,
    "spconavi-viterbi": spconavi_viterbi,
    "spconavi-astar": spconavi_astar,
    "hpp1": _hpp("hpp1"),
    "hpp2": _hpp("hpp2"),
}


def run_method(name: str, ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray | None:
    """Run one method on one task."""
    return METHODS[name](ctx, task, rng)

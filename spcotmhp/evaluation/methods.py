"""The compared methods of Experiment I (paper Section 4.2, (A)-(E)) behind one signature:
``method(ctx, task, rng) -> (n, 2) world path in metres, or None``. Everything a call does is online work
(timed by the runner); the offline parts live in the :class:`~spcotmhp.evaluation.context.HomeContext`.

Variants that separate the method from its post-processing (Algorithm 1, line 13) and from the stage constraint
(:data:`~spcotmhp.evaluation.context.VARIANTS`): SpCoTMHP unsmoothed, with the paper's moving average
(:func:`~spcotmhp.baselines.smoothing.moving_average`), without the stage constraint (Eq. 28 alone); without the
stage constraint also unsmoothed or with the moving average; HPP-I/II with SpCoTMHP's own
smoothing.

For advanced tasks, A* and SpCoNavi receive the waypoint and goal words as one bag of words (as in the paper);
the hierarchical methods get them as ordered stages.

Move models (:data:`MOVE_MODELS`, reported with the results): SpCoTMHP, HPP-I/II (the partial paths of the same
planning graph) and A* move 8-connected, like the reference length l of SPL; SpCoNavi (Viterbi and its A*
approximation) keeps the paper's action set {stay, up, down, left, right}, so its paths are 4-connected and up
to sqrt 2 longer on diagonals.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Sequence

import numpy as np

from spcotmhp.baselines.astar_goal import astar_to_sampled_goal
from spcotmhp.baselines.smoothing import moving_average
from spcotmhp.baselines.spconavi import astar_approximation, log_weight_map, viterbi
from spcotmhp.evaluation.context import HomeContext
from spcotmhp.evaluation.tasks import Task

SPCONAVI_T = 200  # the paper's SpCoNavi horizon
SPCONAVI_J = 10  # goal candidates of the A* approximation

Method = Callable[[HomeContext, Task, np.random.Generator], "np.ndarray | None"]

MOVE_MODELS = {
    "spcotmhp": "8-connected",
    "astar": "8-connected",
    "hpp1": "8-connected (the planning graph's partial paths)",
    "hpp2": "8-connected (the planning graph's partial paths)",
    "hpp1-smoothed": "8-connected (the planning graph's partial paths, then SpCoTMHP's smoothing)",
    "hpp2-smoothed": "8-connected (the planning graph's partial paths, then SpCoTMHP's smoothing)",
    "spcotmhp-unsmoothed": "8-connected",
    "spcotmhp-ma": "8-connected, then a moving average (off the grid)",
    "spcotmhp-nostage": "8-connected",
    "spcotmhp-nostage-unsmoothed": "8-connected",
    "spcotmhp-nostage-ma": "8-connected, then a moving average (off the grid)",
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


def _spcotmhp(variant: str, average: bool = False) -> Method:
    """(E) SpCoTMHP: the hierarchical planner (Eq. 28, exact joint search) from the task's start, as the planner
    ``variant`` of the context; with ``average``, the path then gets the paper's moving average."""
    from spcotmhp.planning.instructions import Instruction, PlaceQuery

    def query(words: list[str]) -> PlaceQuery:
        return PlaceQuery(dict(Counter(words)), " ".join(words))

    def run(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray:
        waypoints = (query(task.waypoint_words),) if task.waypoint_words else ()
        ins = Instruction(goal=query(task.goal_words), waypoints=waypoints, lang=ctx.dataset.lang)
        path = ctx.planners[variant].plan(ins, task.start_xy).path
        return moving_average(path) if average else path

    run.__doc__ = f"(E) SpCoTMHP, planner variant {variant!r}{', moving average' if average else ''}."
    return run


def astar(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray | None:
    """(A) A* to a goal drawn from p(x | S, Theta), with SpCoTMHP's move model (8-connected)."""
    cells = astar_to_sampled_goal(
        ctx.model,
        ctx.costmap.log_p,
        ctx.dataset.map,
        task.start_cell,
        task.all_words,
        rng,
        connectivity=ctx.planner.graph.settings.connectivity,
    )
    return _world(ctx, cells)


def spconavi_viterbi(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray:
    """(B) SpCoNavi, exact Viterbi over every free cell, T = 200, actions {stay, up, down, left, right}."""
    log_w = log_weight_map(ctx.model, ctx.costmap.log_p, ctx.cell_xy, task.all_words)
    return _world(ctx, viterbi(log_w, task.start_cell, SPCONAVI_T).cells)


def spconavi_astar(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray | None:
    """(C) SpCoNavi, A* approximation with J = 10 sampled goals, actions {stay, up, down, left, right}."""
    log_w = log_weight_map(ctx.model, ctx.costmap.log_p, ctx.cell_xy, task.all_words)
    return _world(ctx, astar_approximation(log_w, task.start_cell, rng, SPCONAVI_J, SPCONAVI_T))


def _hpp(name: str, smooth: bool = False) -> Method:
    def run(ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray:
        hpp = ctx.hpp[name]
        cell = hpp.graph.to_crop(np.array(task.start_cell))
        stages = [task.waypoint_words] if task.waypoint_words else []
        return _world(ctx, hpp.graph.to_map(hpp.plan(cell, stages + [task.goal_words], rng, smooth=smooth)))

    cost = "partial-path cost" if name == "hpp1" else "partial-path length"
    run.__doc__ = f"(D) {'HPP-I' if name == 'hpp1' else 'HPP-II'} (edge cost: {cost}){', smoothed' * smooth}."
    return run


METHODS: dict[str, Method] = {
    "spcotmhp": _spcotmhp("ours"),
    "astar": astar,
    "spconavi-viterbi": spconavi_viterbi,
    "spconavi-astar": spconavi_astar,
    "hpp1": _hpp("hpp1"),
    "hpp2": _hpp("hpp2"),
    "hpp1-smoothed": _hpp("hpp1", smooth=True),
    "hpp2-smoothed": _hpp("hpp2", smooth=True),
    "spcotmhp-unsmoothed": _spcotmhp("unsmoothed"),
    "spcotmhp-ma": _spcotmhp("unsmoothed", average=True),
    "spcotmhp-nostage": _spcotmhp("nostage"),
    "spcotmhp-nostage-unsmoothed": _spcotmhp("nostage-unsmoothed"),
    "spcotmhp-nostage-ma": _spcotmhp("nostage-unsmoothed", average=True),
}
RANDOM = frozenset({"astar", "spconavi-astar", "hpp1", "hpp2", "hpp1-smoothed", "hpp2-smoothed"})
"""The methods that draw at random (goals, target places): the only ones whose result depends on the seed when
the parameters do not."""


def warm_up(ctx: HomeContext, task: Task | None = None, methods: Sequence[str] = ()) -> None:
    """Compile (or load) the numba kernels and run each method once on ``task`` (results discarded), so that no
    timed task pays for compilation or first-call caches."""
    from spcotmhp.errors import SpcotmhpError
    from spcotmhp.metric.grid_search import warmup

    warmup()
    for name in methods if task is not None else ():
        try:
            METHODS[name](ctx, task, np.random.default_rng(0))
        except SpcotmhpError:
            pass


def run_method(name: str, ctx: HomeContext, task: Task, rng: np.random.Generator) -> np.ndarray | None:
    """Run one method on one task."""
    return METHODS[name](ctx, task, rng)

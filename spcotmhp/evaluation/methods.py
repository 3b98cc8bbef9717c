"""The compared methods of Experiment I (paper Section 4.2, (A)-(E)) by name: each is a
:class:`~spcotmhp.planning.protocol.Planner` (``plan(instruction, start, rng=...) -> Plan``) made once per home
from its offline part (:class:`Offline`: the parameters, the cost map, the SpCoTMHP planner variants and the HPP
tables); the evaluation looks planners up by name (:data:`METHODS`) and only calls ``plan``, which is the online
work the runner times.

Variants that separate the method from its post-processing (Algorithm 1, line 13) and from the stage constraint
(:data:`~spcotmhp.evaluation.context.VARIANTS`): SpCoTMHP unsmoothed, with the paper's moving average
(:func:`~spcotmhp.baselines.smoothing.moving_average`), without the stage constraint (Eq. 28 alone); without the
stage constraint also unsmoothed or with the moving average; HPP-I/II with SpCoTMHP's own
smoothing. The paper's method (``spcotmhp-paper``; with the moving average ``spcotmhp-paper-ma``): Eq. 24 as
written (optimality at every step) on the paper's graph (steps only between connected places), unsmoothed
(:data:`~spcotmhp.evaluation.context.VARIANTS` says what it keeps).

For advanced tasks, A* and SpCoNavi receive the waypoint and goal words as one bag of words (as in the paper);
the hierarchical methods get them as ordered stages.

Move models (:data:`MOVE_MODELS`, reported with the results): SpCoTMHP, HPP-I/II (the partial paths of the same
planning graph) and A* move 8-connected, like the reference length l of SPL; SpCoNavi (Viterbi and its A*
approximation) keeps the paper's action set {stay, up, down, left, right}, so its paths are 4-connected and up
to sqrt 2 longer on diagonals.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from spcotmhp.baselines.astar_goal import AStarGoalPlanner
from spcotmhp.baselines.hpp import HPP, HPPPlanner
from spcotmhp.baselines.smoothing import MovingAveragePlanner
from spcotmhp.baselines.spconavi import SpCoNaviPlanner
from spcotmhp.evaluation.tasks import Task
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.planning.instructions import Instruction, PlaceQuery
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.protocol import Planner

SPCONAVI_T = 200  # the paper's SpCoNavi horizon
SPCONAVI_J = 10  # goal candidates of the A* approximation


@dataclass(frozen=True)
class Offline:
    """The offline part of one home that the planners are made from: the parameters, the cost map log p(x|m) of
    ``occ_map``, the SpCoTMHP planner variants by name (:data:`~spcotmhp.evaluation.context.VARIANTS`; "ours" is
    the planner as shipped) and the HPP-I/II tables on its planning graph."""

    model: SpatialConceptModel
    log_p: np.ndarray
    occ_map: OccupancyMap
    variants: Mapping[str, HierarchicalPlanner]
    hpp: Mapping[str, HPP]


def _astar(o: Offline) -> Planner:
    """(A) A* to a goal drawn from p(x | S, Theta), with SpCoTMHP's move model."""
    return AStarGoalPlanner(o.model, o.log_p, o.occ_map, connectivity=o.variants["ours"].graph.settings.connectivity)


METHODS: dict[str, Callable[[Offline], Planner]] = {
    "spcotmhp": lambda o: o.variants["ours"],
    "astar": _astar,
    "spconavi-viterbi": lambda o: SpCoNaviPlanner(o.model, o.log_p, o.occ_map, T=SPCONAVI_T),
    "spconavi-astar": lambda o: SpCoNaviPlanner(
        o.model, o.log_p, o.occ_map, approximation=True, T=SPCONAVI_T, J=SPCONAVI_J
    ),
    "hpp1": lambda o: HPPPlanner(o.hpp["hpp1"]),
    "hpp2": lambda o: HPPPlanner(o.hpp["hpp2"]),
    "hpp1-smoothed": lambda o: HPPPlanner(o.hpp["hpp1"], smooth=True),
    "hpp2-smoothed": lambda o: HPPPlanner(o.hpp["hpp2"], smooth=True),
    "spcotmhp-unsmoothed": lambda o: o.variants["unsmoothed"],
    "spcotmhp-ma": lambda o: MovingAveragePlanner(o.variants["unsmoothed"]),
    "spcotmhp-nostage": lambda o: o.variants["nostage"],
    "spcotmhp-nostage-unsmoothed": lambda o: o.variants["nostage-unsmoothed"],
    "spcotmhp-nostage-ma": lambda o: MovingAveragePlanner(o.variants["nostage-unsmoothed"]),
    "spcotmhp-paper": lambda o: o.variants["paper"],
    "spcotmhp-paper-ma": lambda o: MovingAveragePlanner(o.variants["paper"]),
}
"""Each method's planner, made from the home's :class:`Offline` part."""

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
    "spcotmhp-paper": "8-connected (the reference code: 4-connected + stay)",
    "spcotmhp-paper-ma": "8-connected, then a moving average (off the grid)",
    "spconavi-viterbi": "4-connected + stay (the paper's SpCoNavi action set)",
    "spconavi-astar": "4-connected + stay (the paper's SpCoNavi action set)",
}
"""How each method moves on the grid (the SPL reference length l is an 8-connected geodesic)."""


RANDOM = frozenset({"astar", "spconavi-astar", "hpp1", "hpp2", "hpp1-smoothed", "hpp2-smoothed"})
"""The methods that draw at random (goals, target places): the only ones whose result depends on the seed when
the parameters do not."""


def make_planners(offline: Offline) -> dict[str, Planner]:
    """Every method's planner for one home (the offline part, built once)."""
    return {name: make(offline) for name, make in METHODS.items()}


def task_instruction(task: Task, lang: str) -> Instruction:
    """The task as an instruction: the goal's words, and the waypoint's as one stage before it (each a bag of
    words S, Eq. 25). The flat baselines (A*, SpCoNavi) read it as one bag, as in the paper."""

    def query(words: list[str]) -> PlaceQuery:
        return PlaceQuery(dict(Counter(words)), " ".join(words))

    waypoints = (query(task.waypoint_words),) if task.waypoint_words else ()
    return Instruction(goal=query(task.goal_words), waypoints=waypoints, lang=lang)

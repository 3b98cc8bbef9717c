"""The planner interface every path planner of the package implements: SpCoTMHP's
:class:`~spcotmhp.planning.planner.HierarchicalPlanner` and each baseline of :mod:`spcotmhp.baselines`.

``planner.plan(instruction, start) -> Plan``, in the spirit of Nav2's ``nav2_core::GlobalPlanner::createPlan``:
everything offline (the model, the cost map, precomputed tables) is given when the planner is made, a query
is an instruction (a sentence, a structured mapping, an N-best list or an
:class:`~spcotmhp.planning.instructions.Instruction`) and a start pose (x, y) in metres, map frame. Planners that
draw at random (the goal-sampling baselines) take the generator of their draws as the keyword ``rng``
(default: the planner's own, seeded when it was made); the others ignore it. The evaluation
(:mod:`spcotmhp.evaluation.methods`) looks planners up by name and knows nothing else about them.

Baselines return their path as a :class:`~spcotmhp.planning.plan.Plan` built by :func:`path_plan`: the start and
the end of the path labelled with their most probable places, no log score (NaN).

    >>> from spcotmhp.baselines.hpp import HPP, HPPPlanner, path_length_edges
    >>> from spcotmhp.datasets import load_bundled
    >>> from spcotmhp.learning.supervised import fit_supervised
    >>> from spcotmhp.planning.planner import HierarchicalPlanner
    >>> ours = HierarchicalPlanner(fit_supervised(load_bundled("3LDK_06")))
    >>> hpp2 = HPPPlanner(HPP(ours.graph, path_length_edges), seed=0)
    >>> [isinstance(p, Planner) for p in (ours, hpp2)]
    [True, True]
    >>> hpp2.plan("go to the kitchen", (-3.95, -3.55)).places[-1].name
    'kitchen'
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import Any, Protocol, runtime_checkable

import numpy as np

from spcotmhp.language.said_names import shown_names
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.maps import OccupancyMap
from spcotmhp.planning.assemble import path_length
from spcotmhp.planning.instructions import Instruction, PlaceQuery, to_instruction
from spcotmhp.planning.places import most_probable_place
from spcotmhp.planning.plan import Plan, PlanPlace
from spcotmhp.planning.vocabulary import place_labels, place_vocabulary, said_words

__all__ = ["Planner", "PlanVocabulary", "StartPose", "bag_words", "merged_bag", "path_plan"]

StartPose = Sequence[float] | np.ndarray
"""A start pose (x, y) in metres, map frame."""


@runtime_checkable
class Planner(Protocol):
    """A path planner: ``plan(instruction, start) -> Plan`` (module docstring)."""

    def plan(self, instruction: Any, start: StartPose, *, rng: np.random.Generator | None = None) -> Plan:
        """The plan for ``instruction`` from ``start``; raises the package's InstructionError or PlanningError."""
        ...


class PlanVocabulary:
    """What a baseline needs to read instructions and label its plans as SpCoTMHP does: the place words of the
    model (to parse sentences) and the place names."""

    def __init__(self, model: SpatialConceptModel) -> None:
        self.model = model
        self.place_words = place_vocabulary(model)
        self.names = place_labels(model, self.place_words)
        self.shown = shown_names(self.names, model)  # as taught: 東の廊下 (said_names rule 6)
        self.said_words = said_words(self.place_words, self.names, model.active_places)

    def instruction(self, instruction: Any) -> Instruction:
        """``instruction`` understood as SpCoTMHP understands it
        (:func:`~spcotmhp.planning.instructions.to_instruction`)."""
        return to_instruction(instruction, self.said_words)


def bag_words(query: PlaceQuery) -> dict[str, float]:
    """The weighted bag of words S of one named place (Eq. 25)."""
    return dict(query.words)


def merged_bag(instruction: Instruction) -> dict[str, float]:
    """The waypoints' and the goal's words as one bag (how the flat baselines read an instruction with
    waypoints: no order, no stages)."""
    bag: dict[str, float] = {}
    for query in instruction.stages:
        for word, weight in query.words.items():
            bag[word] = bag.get(word, 0.0) + float(weight)
    return bag


def path_plan(
    vocabulary: PlanVocabulary,
    occ_map: OccupancyMap,
    cells: np.ndarray,
    instruction: Instruction,
    t0: float,
    time_precompute_s: float = 0.0,
) -> Plan:
    """A baseline's Plan from the map cells (n, 2) of its path: "stay" repeats dropped, cell centres in metres,
    the start and the end labelled with their most probable places; ``t0`` is the ``time.perf_counter()`` at the
    start of the query (online time)."""
    cells = np.asarray(cells, dtype=np.int64).reshape(-1, 2)
    keep = np.ones(len(cells), dtype=bool)
    keep[1:] = np.any(cells[1:] != cells[:-1], axis=1)
    cells = cells[keep]
    path = occ_map.cell_to_world(cells)
    ends = most_probable_place(vocabulary.model, path[[0, -1]])
    places = [
        PlanPlace(int(k), vocabulary.shown[int(k)], role, point=(float(xy[0]), float(xy[1])))
        for k, role, xy in zip(ends, ("start", "goal"), path[[0, -1]], strict=True)
    ]
    return Plan(
        path=path,
        cells=cells,
        places=places,
        length_m=path_length(cells, occ_map.resolution),
        log_prob=float("nan"),
        time_online_s=time.perf_counter() - t0,
        time_precompute_s=time_precompute_s,
        instruction=instruction,
    )

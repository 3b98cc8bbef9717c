"""Hierarchical path planning from an instruction (Algorithm 1 of Taniguchi et al. 2024).

Offline (lines 1-7): :class:`~spcotmhp.planning.graph.PlanningGraph`. Online, for an instruction and a start pose:

* line 9: understand the instruction (:mod:`spcotmhp.planning.instructions`);
* line 10: the start place i_0 is the posterior p(i_0 | x_0) over places, not only the nearest mean; it enters
  the first step of Eq. 28 through the predictive transition log sum_k p(k | x_0) psi[k, i_1] (i_0 is
  marginalised, as the sum over i_e of Eq. 24). Every step, the first included, may go from any candidate to
  any other (Algorithm 1, line 3 builds the graph "for all nodes"), with Mult(i_e | psi_{i_{e-1}}) as Eq. 28's
  transition factor: legs are free-space paths, and where one crosses other places, the explanation names them.
  (With ``adjacent_only`` steps go only between Figure 3's connected places, as in the reference code: the legs
  then run through the candidate points of the places in between, and the instance of a shared name is chosen
  by those detours, not by the path the robot drives; the README gives the measurements.) A start within the
  robot's radius of an obstacle (free on the map, inscribed in the cost map) first leaves it along the shortest
  run of free cells, and the plan says so;
* line 11: the exact joint search of Eq. 28 over (stage, candidate) (:mod:`spcotmhp.planning.search`). Stages
  are the waypoints in order, then the goal; each may only be completed at one of its instances
  (:func:`~spcotmhp.planning.places.instance_places`); avoided places get probability zero (their nodes are
  removed) and their territories are blocked for every metric leg. When no sequence satisfies the instruction
  under the transition factor (``adjacent_only``, or psi with zeros) but the robot's free space does, the same
  search runs with the transition term dropped and the explanation says so: the planner never answers "no
  path" while a free path exists;
* lines 12-13: the start leg, the partial paths, and the optional smoothing (:mod:`spcotmhp.planning.assemble`):
  every piece between the cells where a stage is completed is re-planned, exactly, under the map term of Eq. 26
  inside the territories of the places it runs through, and kept if shorter; then line-of-sight shortcuts.
  With ``arrival_quantile`` the path stops at the first cell (after the last waypoint) inside the goal place's
  region at that quantile instead of at its candidate point. The topological choice (which places, which
  instances) is Eq. 28's alone: smoothing and arrival only change how the chosen places are traversed.

Which instance of a shared name Eq. 28 picks ("bedroom": three places) is decided mostly by w-hat, which
observes optimality at the end of each leg (:mod:`spcotmhp.planning.graph`): a leg's score falls with its
length under the cost map, so the closest instance wins unless the words, the transitions or the Gaussian at
the candidate point (a few nats, a few cells of path) say otherwise. The plan's ``goal_options`` give the final
path into every instance, and the explanation says "closest of 3 bedrooms" only when the chosen one is the
shortest of them; otherwise it names the shorter one and by how much.

Every stage ends at one of its instances: places whose p(i | S) is at least 1/4 of the best (``instance_ratio``,
:func:`~spcotmhp.planning.places.instance_places`) and whose name carries the words
(:func:`~spcotmhp.planning.places.named_places`). Eq. 28 alone has no such constraint: its word term is a
factor of a few nats per step, which a shorter leg outweighs, so without it most plans end at the nearest place
whatever its name (the README gives the measurement). We keep it as a hard constraint (an instruction names
where to go; a planner that ends elsewhere misreads it), a departure from the paper stated in the README.

The horizon E defaults to 10 steps per stage (10 for "go to the kitchen", as the paper's E = 10; 20 with one
waypoint, as the reference code's two legs of 10).
"""

from __future__ import annotations

import contextlib
import functools
import itertools
import os
import time
from collections import Counter
from collections.abc import Sequence
from dataclasses import fields, replace
from typing import Any

import numpy as np

from spcotmhp.errors import (
    HorizonTooShort,
    ModelError,
    SpcotmhpError,
)
from spcotmhp.language.said_names import shown_names
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.metric.costmap import DEFAULT_COSTMAP
from spcotmhp.planning import explain
from spcotmhp.planning._paths import join_field_legs
from spcotmhp.planning.assemble import arrival, join_legs, path_length, smooth_on_graph
from spcotmhp.planning.graph import PlanningGraph
from spcotmhp.planning.graph_cache import GraphCache
from spcotmhp.planning.graph_settings import PlannerSettings
from spcotmhp.planning.instructions import Instruction, to_instruction
from spcotmhp.planning.phrases import PhraseMemo
from spcotmhp.planning.places import LabelIndex, inside_places
from spcotmhp.planning.plan import Plan
from spcotmhp.planning.relations import PlaceGeometry
from spcotmhp.planning.search import SearchProblem, SearchResult, search, solve, why_no_plan
from spcotmhp.planning.stages import StagePlaces
from spcotmhp.planning.start import start_cell
from spcotmhp.planning.terms import ModelTerms
from spcotmhp.planning.vocabulary import parse_instruction, place_labels, place_vocabulary, said_words


def instance_numbers(names: Sequence[str], active: np.ndarray) -> dict[int, tuple[int, int]]:
    """place -> (n, of): the active place is the n-th of ``of`` active places of its name (in index order), counted
    in one pass (200 places: a quadratic count took 0.3 s of every planner's construction)."""
    act = [int(k) for k in np.flatnonzero(active)]
    totals = Counter(names[k] for k in act)
    seen: Counter = Counter()
    out = {}
    for k in act:
        seen[names[k]] += 1
        out[k] = (seen[names[k]], totals[names[k]])
    return out


class HierarchicalPlanner(StagePlaces):
    """SpCoTMHP planning with one model: ``HierarchicalPlanner(model).plan("go to the bedroom via the corridor",
    start=(x, y))``. Construction runs the precomputation, or fetches it from ``cache``
    (:class:`~spcotmhp.planning.graph_cache.GraphCache`): pass one cache to every planner that should share graphs;
    a planner given none makes a cache of its own (``self.cache``). Queries are safe from several threads (the
    graph's memos have their own lock, :mod:`spcotmhp.planning.graph`)."""

    def __init__(
        self,
        model: SpatialConceptModel,
        settings: PlannerSettings | None = None,
        *,
        log_p: np.ndarray | None = None,
        cache: GraphCache | None = None,
        **overrides: Any,
    ) -> None:
        if not isinstance(model, SpatialConceptModel):
            given = type(model).__name__ + (f" {str(model)[:60]!r}" if isinstance(model, (str, os.PathLike)) else "")
            raise ModelError(
                f"HierarchicalPlanner takes a SpatialConceptModel, got a {given}; load a model folder with "
                "spcotmhp.persistence.io.load_model(folder)"
            )
        unknown = set(overrides) - {f.name for f in fields(PlannerSettings)}
        if unknown:
            raise TypeError(f"unknown planner setting(s): {', '.join(sorted(unknown))}")
        self.model = model
        self.settings = replace(settings or PlannerSettings(), **overrides)
        self.cache = cache if cache is not None else GraphCache()
        self.graph = PlanningGraph.build(model, self.settings.graph_settings(), log_p, self.cache)
        self.place_words = place_vocabulary(model)
        self.names = place_labels(model, self.place_words)
        self.shown = shown_names(self.names, model)  # as taught: 東の廊下 (said_names rule 6)
        self.said_words = said_words(self.place_words, self.names, model.active_places)  # + "aisle one"
        self.terms = ModelTerms(model)
        # inactive places hold no data, and their labels carry every word: they name nothing
        self.label_index = LabelIndex([n if a else "" for n, a in zip(self.names, model.active_places, strict=True)])
        self.numbering = instance_numbers(self.names, model.active_places)
        self.planned = self.graph.places_planned()  # (K,) places with a candidate point in some free region
        in_main = np.zeros(model.K, dtype=bool)
        in_main[self.graph.node_place] = True
        self._main_has_all = not (self.planned & ~in_main).any()  # every planned place has a node in the main region
        occ = model.require_map()
        self._width = int(self.graph.log_p.shape[1])  # the crop's flat cell indices of the nodes
        self._node_flat = np.ascontiguousarray(self.graph.node_cell[:, 0] * self._width + self.graph.node_cell[:, 1])
        self.resolution = float(occ.resolution)
        self._origin = np.array(occ.origin[:2], dtype=float)
        self._half: dict[tuple[int, int], np.ndarray] = {}  # _world's per crop corner
        # the explanation ignores territory stretches shorter than the robot's diameter, in cells
        self.diameter_cells = (
            2.0 * float(model.costmap.get("inscribed_radius", DEFAULT_COSTMAP.inscribed_radius)) / occ.resolution
        )
        self._geometries: dict[int, PlaceGeometry] = {}
        self._phrases = PhraseMemo()  # phrase_terms's

    # ---- Algorithm 1, lines 9-13 -----------------------------------------------------------------------
    def plan(
        self,
        instruction: Any,
        start: Sequence[float] | np.ndarray,
        lang: str | None = None,
        *,
        rng: np.random.Generator | None = None,
    ) -> Plan:
        """Plan from the start pose ``start`` = (x, y) in metres for ``instruction`` (a sentence, a structured
        mapping, an N-best list of (text, score) or an :class:`Instruction`). ``rng`` is not used (the Eq. 28
        search draws nothing); it is accepted as in every :class:`~spcotmhp.planning.protocol.Planner`.

        Raises:
            InstructionError: the instruction names no known place.
            PlanningError: the start is off the map or not free, inside an avoided place, or no path satisfies
                the instruction (the message says which stage cannot be reached).
        """
        t0, model, res = time.perf_counter(), self.model, self.resolution
        ins = parse_instruction(instruction, model, self.said_words, lang)
        x0, cell, escape = start_cell(model, self.graph, start)
        region, cell = self.graph.for_start(cell)  # plan within the start's free region
        S = len(ins.stages)
        chosen: dict[int, str] = {}  # places a relation picked -> what the explanation says of them
        semantic, inst = self.stage_instances(ins, chosen, region)  # (S, K) word terms of Eq. 28 and instances
        graph, avoided, way_out = self._avoid(region, ins, inst, x0, cell, escape, chosen)
        notes = []
        if len(escape):
            notes.append(
                f"the start is within the robot's radius of an obstacle: the path first moves "
                f"{path_length(np.vstack([escape, graph.to_map(cell)[None]]), res):.2f} m clear"
            )
        posterior = here = self.terms.place_posterior(x0)
        if len(way_out) > 1:  # the start is inside a place to avoid: leave it by the shortest way, never come back
            escape, cell, posterior = self._leaving(graph, way_out, escape, avoided, notes)
        result = self._solve(graph, posterior, cell, semantic, inst, ins, x0, avoided, notes)
        cells, smoothed = self.metric_path(graph, cell, result)
        node_points = self._world(graph.node_cell[result.nodes], graph.offset)
        start_place = int(np.argmax(here))  # where the robot stands, even when it first leaves an avoided place
        places = explain.path_places(self, graph, start_place, x0, result, node_points, cells)
        length = path_length(cells, res)
        options = explain.goal_options(self, graph, cell, result, inst[S - 1], length)
        map_cells = np.vstack([escape, graph.to_map(cells)]) if len(escape) else graph.to_map(cells)
        plan = Plan(
            path=self._world(map_cells),
            cells=map_cells,
            places=places,
            length_m=path_length(map_cells, res) if len(escape) else length,
            log_prob=result.log_prob,
            time_online_s=0.0,
            time_precompute_s=self.graph.time_precompute_s,
            instruction=ins,
            goal_options=options,
            n_goal_instances=int(np.count_nonzero(inst[S - 1])),
            node_points=node_points,
            smoothed=smoothed,
            notes=notes,
            chosen=chosen,
        )
        plan.time_online_s = time.perf_counter() - t0
        return plan

    def _leaving(
        self, graph: PlanningGraph, way_out: np.ndarray, escape: np.ndarray, avoided: np.ndarray, notes: list[str]
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The escape with the way out of an avoided place after it, the cell planning starts from (its end) and
        p(i | x) there; the note saying so goes into ``notes``."""
        left = ", ".join(sorted({self.shown[k] for k in np.flatnonzero(avoided)}))
        notes.append(
            f"the start is inside {left}, to be avoided: the path leaves it by the shortest way "
            f"({path_length(graph.to_map(way_out), self.resolution):.1f} m) and does not enter it again"
        )
        out = graph.to_map(way_out[:-1])
        escape = np.vstack([escape, out]) if len(escape) else out
        cell = way_out[-1]
        return escape, cell, self.terms.place_posterior(self._world(graph.to_map(cell)[None])[0])

    def _world(self, cells: np.ndarray, offset: tuple[int, int] | None = None) -> np.ndarray:
        """The map's ``cell_to_world`` of (n, 2) integer map cells (crop cells of a crop whose corner is at map cell
        ``offset``), with the origin kept as an array: the same arithmetic (exact integers + 1/2, times the
        resolution, plus the origin), so the same floats."""
        if offset is None:
            return (cells[:, ::-1] + 0.5) * self.resolution + self._origin
        half = self._half.get(offset)
        if half is None:  # (col, row) of the corner + 1/2: exact, as the sum of the integers then + 1/2
            half = self._half[offset] = np.array([offset[1] + 0.5, offset[0] + 0.5])
        return (cells[:, ::-1] + half) * self.resolution + self._origin

    def warm_up(self) -> None:
        """Plan to the first places once, from the first node, and forget the plans: this loads (or, with an empty
        cache, compiles) the numba kernels of the online path, so that a service's or robot node's first real
        instruction is answered as fast as the later ones. Refusals are ignored (they have loaded what they need)."""
        graph = self.graph
        if not graph.n_nodes:
            return
        start = self.model.require_map().cell_to_world(graph.to_map(graph.node_cell[0]))
        for name in sorted(list(dict.fromkeys(self.spoken_names(graph.node_place)))[:2]):
            with contextlib.suppress(SpcotmhpError):
                self.plan({"goal": name.split()}, tuple(start))

    def spoken_names(self, places: Sequence[int] | np.ndarray) -> list[str]:
        """The labels of ``places`` that an instruction can say (every word a place word), in the order given: a
        place whose events carry no name above chance is labelled "place k", which no instruction names."""
        known = set(self.place_words)
        return [self.names[k] for k in places if set(self.names[k].split()) <= known]

    def places_named(self, words: str | Sequence[str]) -> np.ndarray:
        """(K,) the places a place phrase names ("kitchen", ["east", "corridor"]): as a stage or an avoided place of
        an instruction would (every word must be a place word: :class:`~spcotmhp.errors.UnknownPlaceWord`)."""
        return self.instances(to_instruction({"goal": words}, self.said_words).goal)

    # ---- Algorithm 1, line 11 ------------------------------------------------------------------------
    def _solve(
        self,
        graph: PlanningGraph,
        posterior: np.ndarray,
        cell: np.ndarray,
        semantic: np.ndarray,
        inst: np.ndarray,
        ins: Instruction,
        x0: np.ndarray,
        avoided: np.ndarray,
        notes: list[str],
    ) -> SearchResult:
        """Algorithm 1, line 11: the Eq. 28 search (:meth:`_problem` of this query); when no place sequence
        satisfies the instruction, a longer horizon would (:class:`~spcotmhp.errors.HorizonTooShort`), else the
        metric fallback (noted in ``notes``), else the reason (:func:`~spcotmhp.planning.search.why_no_plan`).
        The first search reads the planner's own arrays as they are (:func:`~spcotmhp.planning.search.solve`:
        the (S, K) place terms, no (S, M) copies, no second check of what this class built)."""
        S = len(ins.stages)
        start_w_hat = graph.start_w_hat(cell)
        if not self.settings.adjacent_only:
            start = self.terms.start_terms(posterior, graph.node_place, start_w_hat)
            result = solve(graph.log_transition_all, start, semantic, inst, graph.node_place, self._horizon(S))
            if result is not None:
                return result
        problem_for = functools.partial(self._problem, graph, posterior, start_w_hat, semantic, inst, S)
        problem = problem_for(metric=False)
        result = search(problem) if self.settings.adjacent_only else None
        if result is not None:
            return result
        longest = replace(problem, max_steps=max(problem.max_steps, graph.n_nodes * S))
        if problem.max_steps < longest.max_steps and search(longest) is not None:
            raise HorizonTooShort(
                f"no sequence of at most {problem.max_steps} place-to-place steps from "
                f"({x0[0]:.2f}, {x0[1]:.2f}) satisfies '{ins.describe()}'; raise max_steps"
            )
        metric = problem_for(metric=True)
        result = search(metric)
        if result is None:
            cut = [self.shown[k] for k in graph.info.get("unreachable_places", [])]
            raise why_no_plan(metric, ins, x0, bool(avoided.any()), cut)
        notes.append("the place graph has no route for this instruction: metric route over the free space")
        return result

    def _horizon(self, S: int) -> int:
        """The topological horizon E for ``S`` stages (module docstring)."""
        E = self.settings.steps_per_stage * S if self.settings.max_steps is None else self.settings.max_steps
        return int(E)

    def _problem(
        self,
        graph: PlanningGraph,
        posterior: np.ndarray,
        start_w_hat: np.ndarray,
        semantic: np.ndarray,
        inst: np.ndarray,
        S: int,
        metric: bool = False,
    ) -> SearchProblem:
        """The arrays of Eq. 28 for this query (see :class:`SearchProblem`; ``start_w_hat``: the graph's start legs
        from the query's cell). With ``metric``, the fallback: any node may follow any other (the legs are
        free-space paths) and the transition term is dropped."""
        nodes = graph.node_place
        E = self._horizon(S)
        if metric:
            ur = self.terms.log_ur[nodes]
            return SearchProblem(
                graph.w_hat_metric - ur[None, :], start_w_hat - ur, semantic[:, nodes], inst[:, nodes], E
            )
        start = self.terms.start_terms(posterior, nodes, start_w_hat)  # log sum_k p(k|x0) psi[k, i_1] - log UR
        if not self.settings.adjacent_only:
            return SearchProblem(graph.log_transition_all, start, semantic[:, nodes], inst[:, nodes], E)
        plausible = posterior >= min(self.settings.start_min_posterior, posterior.max())
        first = graph.connected[plausible].any(axis=0)[nodes]  # i_1 next to a plausible i_0
        start = np.where(first, start, -np.inf)
        return SearchProblem(graph.log_transition, start, semantic[:, nodes], inst[:, nodes], E)

    def _assemble(self, graph: PlanningGraph, cell: np.ndarray, result: SearchResult):
        """Algorithm 1, line 12: the joined cells, the index where each node is reached, and the anchors (the
        indices where a stage is completed)."""
        nodes = result.nodes
        if graph is self.graph and graph.hier is None and isinstance(graph.next_step, np.ndarray):  # dense: one kernel
            first = int(cell[0]) * self._width + int(cell[1])
            cells, found, bad = join_field_legs(graph.dist, graph.next_step, first, nodes, self._node_flat)
            if bad < 0:
                ends = found.tolist()
                return cells, ends, [ends[e] for e, done in enumerate(result.completed) if done]
        legs = [graph.leg(cell, int(nodes[0])).cells]
        legs += [graph.edge_path(int(a), int(b)) for a, b in itertools.pairwise(nodes)]
        cells, ends = join_legs(legs)
        anchors = [ends[e] for e, done in enumerate(result.completed) if done]
        return cells, ends, anchors

    def metric_path(self, graph: PlanningGraph, cell: np.ndarray, result: SearchResult) -> tuple[np.ndarray, bool]:
        """Algorithm 1, lines 12-13, then the arrival cut: the final crop cells and whether line 13 changed them
        (module docstring; :mod:`spcotmhp.planning.assemble`). Every step keeps the path's start, its anchors
        (the cells where a waypoint is completed) and its traversable, unblocked cells, and none lengthens it."""
        settings = self.settings
        cells, ends, anchors = self._assemble(graph, cell, result)
        raw = cells
        if settings.smooth:
            cells, anchors = smooth_on_graph(graph, cells, ends, result.nodes, anchors)
        smoothed = settings.smooth and not (
            cells is raw or (cells.shape == raw.shape and bool((cells == raw).all()))
        )  # np.array_equal, without its conversions (both are arrays)
        if settings.arrival_quantile is not None:
            # the last cut: the path ends at the first cell, after the last waypoint, inside the goal's region
            goal = int(graph.node_place[result.nodes[-1]])
            first = max(anchors[:-1], default=0)
            rest = cells[first:]
            inside = (graph.territory[rest[:, 0], rest[:, 1]] == goal) & inside_places(
                self.model, graph.centres_at(rest), [goal], settings.arrival_quantile
            )
            cells = cells[: first + arrival(rest, inside) + 1]
        return cells, smoothed


def plan(
    model: SpatialConceptModel,
    instruction: Any,
    start: Sequence[float],
    lang: str | None = None,
    **settings: Any,
) -> Plan:
    """One-call planning: ``plan(model, "go to the bedroom via the corridor", (x, y))``. The precomputation is
    cached per model + map + settings, so repeated calls pay it once."""
    return HierarchicalPlanner(model, **settings).plan(instruction, start, lang)

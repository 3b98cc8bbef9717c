"""Hierarchical path planning from an instruction (Algorithm 1 of Taniguchi et al. 2024).

Offline (lines 1-7): :class:`~spcotmhp.planning.graph.PlanningGraph`. Online, for an instruction and a start pose:

* line 9: understand the instruction (:mod:`spcotmhp.planning.instructions`);
* line 10: the start place i_0 is the posterior p(i_0 | x_0) over places, not only the nearest mean; it enters
  the first step of Eq. 28 through the predictive transition log sum_k p(k | x_0) psi[k, i_1] (i_0 is
  marginalised, as the sum over i_e of Eq. 24). Like every later step, the first one moves along the place
  graph: i_1 must be a plausible start place (p(i_0 | x_0) >= ``start_min_posterior``) or connected to one, so
  the place sequence of a plan is a walk on the topological map. The most probable place names the start in
  the plan; its explanation names the waypoints, the goal and every place passed whose territory the final
  (smoothed) path enters;
* line 11: the exact joint search of Eq. 28 over (stage, candidate) (:mod:`spcotmhp.planning.search`). Stages
  are the waypoints in order, then the goal; each may only be completed at one of its instances
  (:func:`~spcotmhp.planning.places.instance_places`); avoided places get probability zero (their nodes are
  removed) and their regions are blocked for every metric leg;
* lines 12-13: the start leg (read from the precomputed field of the first node), the partial paths, and the
  optional smoothing (:mod:`spcotmhp.planning.assemble`): every piece between the cells where a stage is
  completed is re-planned, exactly, under the map term of Eq. 26 inside the territories of the places it runs
  through, and kept if shorter; then line-of-sight shortcuts. With ``arrival_quantile`` the path stops at the
  first cell (after the last waypoint) inside the goal place's region at that quantile instead of at its
  candidate point. The topological choice (which places, which instances) is Eq. 28's alone: smoothing and
  arrival only change how the chosen places are traversed.

Which instance of a shared name Eq. 28 picks ("bedroom": three places) is decided by w-hat, the log-likelihood
of the partial paths (Eqs. 26-27): hundreds of nats against a few for the transition and word terms. w-hat sums
log N(x_t | mu_b, Sigma_b) of the *destination* b over every cell of a leg, so it grows with the squared
Mahalanobis distance to b along the whole leg, not with the leg's length: a route split into legs whose
destinations lie along it, or into a goal whose Gaussian is broad along the approach, can be more probable
than a shorter direct leg. On the bundled homes (supervised parameters) 10 of 248 basic tasks end in a
bedroom other than the geodesically nearest for that reason (e.g. 3LDK_01, washroom -> bedroom: via the
toilet into bedroom #1, w-hat -501, beats the direct leg into bedroom #2, -610, 0.2 m shorter after
smoothing). This is the paper's formulation, not an accumulation error, so it is kept; the explanation names
the closer instance and by how much it is shorter.

The horizon E defaults to 10 steps per stage (10 for "go to the kitchen", as the paper's E = 10; 20 with one
waypoint, as the reference code's two legs of 10).
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, fields, replace
from typing import Any

import numpy as np

from spcotmhp.errors import PlanningError
from spcotmhp.learning.model import SpatialConceptModel
from spcotmhp.planning.assemble import (
    arrival,
    better,
    join_legs,
    path_length,
    shorten,
    smooth_anchored,
    smoothing_mask,
)
from spcotmhp.planning.graph import GraphSettings, PlanningGraph, require_int, require_range
from spcotmhp.planning.instructions import Instruction, to_instruction
from spcotmhp.planning.places import inside_places, instance_places
from spcotmhp.planning.plan import GoalOption, Plan, PlanPlace
from spcotmhp.planning.search import SearchProblem, SearchResult, search
from spcotmhp.planning.terms import ModelTerms
from spcotmhp.planning.vocabulary import place_labels, place_vocabulary

ARRIVAL_QUANTILE: float | None = None
"""Default ``arrival_quantile`` of :class:`PlannerSettings`: None, the path ends at the goal's candidate point
as in Algorithm 1. Stopping at the first cell inside the goal's region is an option: a place's Gaussian is not
its room, and with quantile 0.5 the end already falls outside the room's teaching-point box in 6 of 88 basic
tasks of 3LDK_06 (0.39, one sd: none of 248)."""


@dataclass(frozen=True)
class PlannerSettings(GraphSettings):
    """Every knob of the planner: the precomputation's :class:`GraphSettings` (inherited, with their defaults),
    then the online ones.

    steps_per_stage / max_steps: the topological horizon E (max_steps overrides steps_per_stage x stages).
    instance_ratio: instances of a name have p(i | S) >= best / ratio.  start_min_posterior: places with
    p(i_0 | x_0) at least this are plausible start places (the first step stays next to one).  region_quantile:
    chi-square quantile of a place's region (avoidance).  smooth: Algorithm 1, line 13 (tube re-planning, then
    line-of-sight shortcuts; :mod:`~spcotmhp.planning.assemble`).  arrival_quantile: the path ends at its first
    cell inside the goal place's region at this chi-square quantile (None: at the goal's candidate point).

    Out-of-range values raise :class:`~spcotmhp.errors.PlanningError` on construction.
    """

    steps_per_stage: int = 10
    max_steps: int | None = None
    instance_ratio: float = 4.0
    start_min_posterior: float = 0.01
    region_quantile: float = 0.95
    smooth: bool = True
    arrival_quantile: float | None = ARRIVAL_QUANTILE

    def __post_init__(self) -> None:
        super().__post_init__()
        require_int(self.steps_per_stage, "steps_per_stage", 1)
        if self.max_steps is not None:
            require_int(self.max_steps, "max_steps", 1)
        require_range(self.instance_ratio, "instance_ratio", 1.0, math.inf, ">= 1")
        require_range(self.start_min_posterior, "start_min_posterior", 0.0, 1.0, "in [0, 1]")
        require_range(self.region_quantile, "region_quantile", 0.0, 1.0, "in (0, 1)", open_=True)
        if self.arrival_quantile is not None:
            require_range(self.arrival_quantile, "arrival_quantile", 0.0, 1.0, "in (0, 1) (or None)", open_=True)

    def graph_settings(self) -> GraphSettings:
        return GraphSettings(**{f.name: getattr(self, f.name) for f in fields(GraphSettings)})


class HierarchicalPlanner:
    """SpCoTMHP planning with one model: ``HierarchicalPlanner(model).plan("go to the bedroom via the corridor",
    start=(x, y))``. Construction runs (or fetches from the cache) the precomputation."""

    def __init__(self, model: SpatialConceptModel, settings: PlannerSettings | None = None, *,
                 log_p: np.ndarray | None = None, use_cache: bool = True, **overrides: Any) -> None:
        unknown = set(overrides) - {f.name for f in fields(PlannerSettings)}
        if unknown:
            raise TypeError(f"unknown planner setting(s): {', '.join(sorted(unknown))}")
        self.model = model
        self.settings = replace(settings or PlannerSettings(), **overrides)
        self.graph = PlanningGraph.build(model, self.settings.graph_settings(), log_p, use_cache)
        self.place_words = place_vocabulary(model)
        self.names = place_labels(model, self.place_words)
        self.terms = ModelTerms(model)
        act = np.flatnonzero(model.active_places)
        self._numbering = {int(k): (1 + sum(self.names[j] == self.names[k] for j in act if j < k),
                                    sum(self.names[j] == self.names[k] for j in act)) for k in act}

    # ---- Algorithm 1, lines 9-13 -----------------------------------------------------------------------
    def plan(self, instruction: Any, start: Sequence[float], lang: str | None = None) -> Plan:
        """Plan from the start pose ``start`` = (x, y) in metres for ``instruction`` (a sentence, a structured
        mapping, an N-best list of (text, score) or an :class:`Instruction`).

        Raises:
            InstructionError: the instruction names no known place.
            PlanningError: the start is off the map or not free, inside an avoided place, or no path satisfies
                the instruction (the message says which stage cannot be reached).
        """
        t0 = time.perf_counter()
        model, settings = self.model, self.settings
        ins = to_instruction(instruction, self.place_words, lang)
        x0, cell = self._start_cell(start)
        stages = ins.stages
        S = len(stages)
        semantic = np.stack([self.terms.log_semantic(q.words) for q in stages])     # (S, K), Eq. 28
        inst = np.stack([instance_places(self.terms.normalise(ls), settings.instance_ratio) for ls in semantic])
        for q in ins.not_goal:     # may be passed, never the goal ("instead of the kitchen")
            inst[S - 1] &= ~instance_places(self.terms.log_place_given_words(q.words), settings.instance_ratio)
            if not inst[S - 1].any():
                raise PlanningError(f"every place named '{ins.goal.label}' is one the instruction says not to "
                                    f"end in ('{q.label}')")
        graph = self.graph
        avoided = np.zeros(model.K, dtype=bool)
        for q in ins.avoid:
            avoided |= instance_places(self.terms.log_place_given_words(q.words), settings.instance_ratio)
        if avoided.any():
            inst &= ~avoided
            for s, q in enumerate(stages):
                if not inst[s].any():
                    raise PlanningError(f"every place named '{q.label}' is also to be avoided")
            graph = graph.with_avoided(tuple(np.flatnonzero(avoided)), settings.region_quantile)
            if graph.blocked[cell[0], cell[1]]:
                inside = [self.names[k] for k in np.flatnonzero(avoided)]
                raise PlanningError(f"the start ({x0[0]:.2f}, {x0[1]:.2f}) lies inside a place to avoid "
                                    f"({', '.join(sorted(set(inside)))})")
        posterior = self.terms.place_posterior(x0)
        problem = self._problem(graph, posterior, cell, semantic, inst, S)
        result = search(problem)
        if result is None:
            raise PlanningError(self._why_not(graph, problem, ins, x0, avoided.any()))

        cells, smoothed, raw_length = self._metric_path(graph, cell, result)
        map_cells = graph.to_map(cells)
        places = self._places(graph, posterior, x0, result, S, cells)
        options = self._goal_options(graph, cell, result, inst[S - 1], raw_length)
        plan = Plan(path=model.map.cell_to_world(map_cells), cells=map_cells, places=places,
                    length_m=path_length(cells, model.map.resolution), log_prob=result.log_prob,
                    time_online_s=0.0, time_precompute_s=self.graph.time_precompute_s, instruction=ins,
                    goal_options=options, n_goal_instances=int(inst[S - 1].sum()),
                    node_points=model.map.cell_to_world(graph.to_map(graph.node_cell[result.nodes])),
                    smoothed=smoothed)
        plan.time_online_s = time.perf_counter() - t0
        return plan

    # ---- pieces ----------------------------------------------------------------------------------------
    def _start_cell(self, start: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
        try:
            x0 = np.asarray(start, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise PlanningError(f"the start must be two numbers (x, y) in metres, got {start!r}") from None
        if x0.shape != (2,) or not np.isfinite(x0).all():
            raise PlanningError(f"the start must be two finite numbers (x, y) in metres, got {start!r}")
        occ = self.model.map
        lo = occ.cell_to_world(np.array([0, 0])) - occ.resolution / 2
        hi = occ.cell_to_world(np.array([occ.height - 1, occ.width - 1])) + occ.resolution / 2
        # bounds in floats first: a huge start would overflow the integer cell index
        full = occ.world_to_cell(x0) if ((x0 >= lo) & (x0 < hi)).all() else None
        if full is None or not occ.in_bounds(full):
            raise PlanningError(f"the start ({_metres(x0[0])}, {_metres(x0[1])}) is outside the map "
                                f"(x {lo[0]:.2f}..{hi[0]:.2f}, y {lo[1]:.2f}..{hi[1]:.2f})")
        cell = self.graph.to_crop(full)
        if not (self.graph.in_crop(cell) and self.graph.traversable[cell[0], cell[1]]):
            value = int(occ.data[full[0], full[1]])
            what = {100: "an occupied", -1: "an unknown"}.get(value, "a lethal (wall-touching)")
            raise PlanningError(f"the start ({x0[0]:.2f}, {x0[1]:.2f}) is in {what} cell (row {full[0]}, "
                                f"col {full[1]}); start from a free cell")
        return x0, cell

    def _problem(self, graph: PlanningGraph, posterior: np.ndarray, cell: np.ndarray, semantic: np.ndarray,
                 inst: np.ndarray, S: int) -> SearchProblem:
        """The arrays of Eq. 28 for this query (see :class:`SearchProblem`)."""
        nodes = graph.node_place
        with np.errstate(divide="ignore"):
            log_pred = np.log(posterior @ self.model.psi)                   # log sum_k p(k|x0) psi[k, i_1]
        plausible = posterior >= min(self.settings.start_min_posterior, posterior.max())
        first = graph.connected[plausible].any(axis=0)[nodes]            # i_1 next to a plausible i_0
        start = np.where(first, log_pred[nodes] - self.terms.log_ur[nodes] + graph.start_w_hat(cell), -np.inf)
        E = self.settings.steps_per_stage * S if self.settings.max_steps is None else self.settings.max_steps
        return SearchProblem(graph.log_transition, start, semantic[:, nodes], inst[:, nodes], int(E))

    def _assemble(self, graph: PlanningGraph, cell: np.ndarray, result: SearchResult):
        """Algorithm 1, line 12: the joined cells, the index where each node is reached, and the anchors (the
        indices where a stage is completed)."""
        nodes = result.nodes
        legs = [graph.leg(cell, int(nodes[0])).cells]
        legs += [graph.edge_path(int(a), int(b)) for a, b in itertools.pairwise(nodes)]
        cells, ends = join_legs(legs)
        anchors = [ends[e] for e, done in enumerate(result.completed) if done]
        return cells, ends, anchors

    def _metric_path(self, graph: PlanningGraph, cell: np.ndarray,
                     result: SearchResult) -> tuple[np.ndarray, bool, float]:
        """Algorithm 1, lines 12-13, then the arrival cut: the final crop cells, whether line 13 changed them
        and the length in metres of the assembled path (line 12) (module docstring;
        :mod:`spcotmhp.planning.assemble`). Every step keeps the path's start, its anchors (the cells where a
        waypoint is completed) and its traversable, unblocked cells, and none lengthens it."""
        settings = self.settings
        cells, ends, anchors = self._assemble(graph, cell, result)
        raw = cells
        if settings.smooth:
            node_place = graph.node_place[result.nodes]
            ends_arr = np.asarray(ends)

            def tube(a: int, b: int) -> tuple[np.ndarray, np.ndarray]:
                piece = raw[a:b + 1]
                own = node_place[(ends_arr >= a) & (ends_arr <= b)]
                return graph.tube(np.union1d(graph.territory[piece[:, 0], piece[:, 1]], own))

            def shortcut(path: np.ndarray, marks: list[int]) -> tuple[np.ndarray, list[int]]:
                short, moved = smooth_anchored(path, smoothing_mask(graph.traversable, graph.log_p, path), marks,
                                               graph.settings.connectivity)
                return (short, moved) if better(short, path, graph.map_cost) else (path, marks)

            # line-of-sight shortcuts on the re-planned path and on the assembled one: the re-planned path
            # keeps off the walls, so shortcuts of the assembled one are occasionally shorter still
            replanned = shortcut(*shorten(cells, anchors, tube, graph.map_cost, graph.settings.connectivity))
            direct = shortcut(cells, anchors)
            cells, anchors = replanned if better(replanned[0], direct[0], graph.map_cost) else direct
        smoothed = settings.smooth and not np.array_equal(cells, raw)
        if settings.arrival_quantile is not None:
            # the last cut: the path ends at the first cell, after the last waypoint, inside the goal's region
            goal = int(graph.node_place[result.nodes[-1]])
            first = max(anchors[:-1], default=0)
            rest = cells[first:]
            inside = (graph.territory[rest[:, 0], rest[:, 1]] == goal) & inside_places(
                self.model, graph.centres[rest[:, 0], rest[:, 1]], [goal], settings.arrival_quantile)
            cells = cells[:first + arrival(rest, inside) + 1]
        return cells, smoothed, path_length(raw, self.model.map.resolution)

    def _places(self, graph: PlanningGraph, posterior: np.ndarray, x0: np.ndarray, result: SearchResult,
                S: int, cells: np.ndarray) -> list[PlanPlace]:
        """Start, then the places of the chosen sequence with their roles. A place passed on the way ("via")
        is named only if the final path enters its territory: smoothing may cut past a place whose centre the
        assembled path went through, and the explanation describes the path the robot drives."""
        visited = set(np.unique(graph.territory[cells[:, 0], cells[:, 1]]).tolist())
        i0 = int(np.argmax(posterior))
        out = [self._place(i0, "start", x0)]
        points = self.model.map.cell_to_world(graph.to_map(graph.node_cell[result.nodes]))
        for node, done, xy in zip(result.nodes, result.completed, points):
            k = int(graph.node_place[node])
            role = "goal" if S - 1 in done else "waypoint" if done else "via"
            if role == "via" and (k == out[-1].id or k not in visited):
                continue
            out.append(self._place(k, role, xy))
        return out

    def _place(self, k: int, role: str, xy: np.ndarray | None = None) -> PlanPlace:
        number, count = self._numbering[k]
        point = None if xy is None else (float(xy[0]), float(xy[1]))
        return PlanPlace(k, self.names[k], role, number, count, point)

    def _goal_options(self, graph: PlanningGraph, cell: np.ndarray, result: SearchResult,
                      goal_places: np.ndarray, chosen_length: float) -> list[GoalOption]:
        """The best plan into each goal instance, with the length of its assembled path (Algorithm 1, line 12:
        the partial paths Eq. 28 compared, before smoothing), the same measure for every instance; only when the
        name is shared. (Smoothing every alternative would cost one re-planning per instance: tens of ms per
        instance on a 100 m office.)"""
        if goal_places.sum() < 2:
            return []
        options = []
        end_place = int(graph.node_place[result.nodes[-1]])
        for k in np.flatnonzero(goal_places):
            ks = np.flatnonzero(graph.node_place == k)
            if not len(ks) or not np.isfinite(result.terminal[ks]).any():
                continue
            node = int(ks[np.argmax(result.terminal[ks])])
            if k == end_place:
                alt, length = result, chosen_length
                node = int(result.nodes[-1])
            else:
                alt = result.ending_at(node)
                length = path_length(self._assemble(graph, cell, alt)[0], self.model.map.resolution)
            options.append(GoalOption(int(k), self._place(int(k), "goal").label, length, alt.log_prob))
        return sorted(options, key=lambda o: -o.log_prob)

    def _why_not(self, graph: PlanningGraph, problem: SearchProblem, ins: Instruction, x0: np.ndarray,
                 avoiding: bool) -> str:
        """A one-line reason why no plan exists."""
        where = f"from ({x0[0]:.2f}, {x0[1]:.2f})"
        tail = " without entering the places to avoid" if avoiding else ""
        reach = np.isfinite(problem.start)
        if not reach.any():
            return f"no place can be reached {where}{tail} (the start is cut off from every place)"
        frontier = reach.copy()
        step = np.isfinite(problem.transition)
        while frontier.any():
            new = step[frontier].any(axis=0) & ~reach
            reach |= new
            frontier = new
        for s, q in enumerate(ins.stages):
            if not (reach & problem.completes[s]).any():
                role = "goal" if s == len(ins.stages) - 1 else f"waypoint {s + 1}"
                return f"no path {where} reaches a place named '{q.label}' ({role}){tail}"
        return (f"no sequence of at most {problem.max_steps} place-to-place steps {where} satisfies "
                f"'{ins.describe()}'{tail}; raise max_steps")


def _metres(v: float) -> str:
    """A coordinate for a message: 2 decimals, or 4 significant digits when huge (no 300-digit numbers)."""
    return f"{v:.2f}" if abs(v) < 1e6 else f"{v:.4g}"


def plan(model: SpatialConceptModel, instruction: Any, start: Sequence[float], lang: str | None = None,
         **settings: Any) -> Plan:
    """One-call planning: ``plan(model, "go to the bedroom via the corridor", (x, y))``. The precomputation is
    cached per model + map + settings, so repeated calls pay it once."""
    return HierarchicalPlanner(model, **settings).plan(instruction, start, lang)

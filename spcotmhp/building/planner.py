"""Planning in a building: the Eq. 28 search over every floor's candidate graph and the connectors at once.

:class:`BuildingPlanner` is a thin layer over one :class:`~spcotmhp.planning.planner.HierarchicalPlanner` per floor
(each on the floor's view of the building's model, :meth:`~spcotmhp.building.model.BuildingModel.floor_model`,
with its own precomputed graph, Algorithm 1 lines 1-7): a query

1. reads the instruction with the place words of every floor, and the floor of each place it names
   (:mod:`spcotmhp.building.floors`; the start's floor is given with the start);
2. finds each stage's instances on each floor as the floor's planner does (the same words, relations, avoided
   places and places not to end in), keeps only the floors whose places carry the name when some do (so "the
   library" on floor 3 is not guessed on floor 1 from p(i | S)), and only the floor a stage names;
3. stitches the floors' graphs and the connectors' stops into one search problem (:mod:`spcotmhp.building.stitch`:
   connectors are edges whose partial-path log-likelihood is their cost_m in the grid's units) and runs the exact
   search of Eq. 28 (:func:`~spcotmhp.planning.search.search`); the horizon E gains two steps per floor change a
   stage may need (board, ride) over the single-floor default; with no sequence under psi, the metric fallback as
   on one floor;
4. cuts the sequence into one segment per floor (:mod:`spcotmhp.building.route`) and names the places.

So "go to the kitchen" ends at the kitchen with the best Eq. 28 score over every floor: the closest instance
counting the connectors' costs, as "closest of 3 bedrooms" on one floor (w-hat dominates the few nats of the
word and transition terms). One-floor datasets and models never come here: the single-floor planner is unchanged.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from spcotmhp.building.floors import PlaceFloors, split_floors
from spcotmhp.building.model import BuildingModel
from spcotmhp.building.options import goal_options
from spcotmhp.building.plan import BuildingPlan, Ride
from spcotmhp.building.queries import FloorQueries, floor_queries, joint_instances
from spcotmhp.building.route import Segment, assemble
from spcotmhp.building.stitch import Endpoint, FloorPart, Skeleton, StopFields, skeleton, skeleton_key, stitch
from spcotmhp.errors import HorizonTooShort, SpcotmhpError, StartInAvoidedPlace
from spcotmhp.planning import explain
from spcotmhp.planning.avoid import avoided_view
from spcotmhp.planning.graph_cache import GraphCache
from spcotmhp.planning.graph_settings import PlannerSettings
from spcotmhp.planning.planner import HierarchicalPlanner
from spcotmhp.planning.search import search
from spcotmhp.planning.start import start_cell
from spcotmhp.planning.vocabulary import parse_instruction

SKELETONS = 64  # stitched transitions kept (floor graphs and avoidance views; least recently used go first)


class BuildingPlanner:
    """``BuildingPlanner(building_model).plan("go to the bedroom", start=(x, y), floor=1, goal_floor=2)``."""

    def __init__(
        self, bm: BuildingModel, settings: PlannerSettings | None = None, *, cache: GraphCache | None = None,
        **overrides: Any,
    ) -> None:  # fmt: skip
        t0 = time.perf_counter()
        self.bm = bm
        self.cache = cache if cache is not None else GraphCache(max(8, 2 * len(bm.indices)))
        self.floors = {
            i: HierarchicalPlanner(bm.floor_model(i), settings, cache=self.cache, **overrides) for i in bm.indices
        }
        self.settings = next(iter(self.floors.values())).settings
        self.place_words = sorted({w for p in self.floors.values() for w in p.place_words})
        self.said_words = sorted({w for p in self.floors.values() for w in p.said_words})
        self.stops = self._endpoints()
        by_connector: dict[int, list[Endpoint]] = {}
        for e in self.stops:
            by_connector.setdefault(e.connector, []).append(e)
        self.rides = {
            (a.id, b.id): bm.spec.connectors[c].cost_m
            for c, ends in by_connector.items()
            for a in ends
            for b in ends
            if a.floor != b.floor and a.region and b.region
        }
        self.fields = StopFields()
        self.skeletons = GraphCache(SKELETONS)
        self.time_precompute_s = time.perf_counter() - t0

    def _endpoints(self) -> list[Endpoint]:
        """Every connector stop, located on its floor's graph (:func:`~spcotmhp.planning.start.start_cell`: a stop
        within the robot's radius of an obstacle escapes to the nearest free cell, as a start does); a stop cut
        off from its floor's places is kept unusable, with the reason."""
        out: list[Endpoint] = []
        for c, conn in enumerate(self.bm.spec.connectors):
            for s in conn.stops:
                planner = self.floors[s.floor]
                try:
                    _, cell, escape = start_cell(planner.model, planner.graph, (s.x, s.y))
                except SpcotmhpError as exc:
                    out.append(Endpoint(len(out), c, s.floor, (s.x, s.y), None, None, why=str(exc)))
                    continue
                region, cell = planner.graph.for_start(cell)
                out.append(Endpoint(len(out), c, s.floor, (s.x, s.y), region.key, (int(cell[0]), int(cell[1])),
                                    np.asarray(escape, np.int64).reshape(-1, 2)))  # fmt: skip
        return out

    # ---- a query -------------------------------------------------------------------------------------------
    def plan(
        self,
        instruction: Any,
        start: Sequence[float] | np.ndarray,
        floor: object,
        *,
        goal_floor: object = None,
        lang: str | None = None,
        rng: np.random.Generator | None = None,
    ) -> BuildingPlan:
        """Plan from ``start`` = (x, y) on floor ``floor`` (the start's floor: index or name) for ``instruction``
        (a sentence, a structured mapping whose places may carry ``"floor"``, an N-best list or an
        Instruction); ``goal_floor``: the floor the goal must be on (index, name, "upstairs", "downstairs").
        ``rng`` is not used (the search draws nothing).

        Raises:
            UnknownFloor: a floor the building lacks. PlaceNotOnFloor: no place of a stage's name on its floor.
            InstructionError, PlanningError: as the single-floor planner; FloorUnreachable: no connector route
            reaches a floor a stage must end on.
        """
        t0 = time.perf_counter()
        f0 = self.bm.check_floor(floor)
        raw, given = split_floors(instruction, goal_floor)
        ins = parse_instruction(raw, self.bm.model, self.said_words, lang, floors=True)
        resolved = self._resolve(PlaceFloors.of(ins, given), f0)
        home = self.floors[f0]
        x0, cell, escape = start_cell(home.model, home.graph, start)
        region, cell = home.graph.for_start(cell)
        queries = {
            f: floor_queries(p, ins, resolved, f, region if f == f0 else p.graph) for f, p in self.floors.items()
        }
        inst, avoided = joint_instances(queries, ins, resolved, self.bm)
        parts = self._parts(queries, inst, avoided, f0, region)
        self._check_start(parts[f0], cell, escape, x0)
        result, metric, st = self._search(parts, f0, cell, ins, x0)
        segments = assemble(st, result, parts, cell, escape, self.fields, self.settings.smooth)
        plan = self._plan(segments, st, result, parts, ins, resolved.stages, x0)
        if metric:
            plan.notes.append("the place graph has no route for this instruction: metric route over the free space")
        plan.time_online_s = time.perf_counter() - t0
        return plan

    def _resolve(self, floors: PlaceFloors, f0: int) -> PlaceFloors:
        def one(v: object) -> int | None:
            return None if v is None else self.bm.resolve_floor(v, f0)

        return PlaceFloors(tuple(map(one, floors.stages)), tuple(map(one, floors.avoid)),
                           tuple(map(one, floors.not_goal)))  # fmt: skip

    def _parts(self, queries: dict[int, FloorQueries], inst, avoided, f0: int, region) -> dict[int, FloorPart]:
        """Each floor's part of the stitched search (avoidance views where places are avoided)."""
        parts = {}
        for f, planner in self.floors.items():
            graph = region if f == f0 else planner.graph
            key = graph.key
            if avoided[f].any():
                graph = avoided_view(graph, tuple(int(k) for k in np.flatnonzero(avoided[f])))
            stops = [e for e in self.stops if e.floor == f and e.region == key]
            if graph.blocked is not None:
                stops = [e for e in stops if not graph.blocked[e.cell]]
            parts[f] = FloorPart(f, planner, graph, queries[f].semantic, inst[f], stops=stops)
        return parts

    def _check_start(self, part: FloorPart, cell: np.ndarray, escape: np.ndarray, x0: np.ndarray) -> None:
        blocked = part.graph.blocked
        if blocked is None:
            return
        esc = part.graph.to_crop(escape) if len(escape) else escape
        inside = [tuple(c) for c in np.asarray(esc).reshape(-1, 2) if part.graph.in_crop(c)]
        if blocked[int(cell[0]), int(cell[1])] or any(blocked[c] for c in inside):
            raise StartInAvoidedPlace(f"the start ({x0[0]:.2f}, {x0[1]:.2f}) lies inside a place to avoid")

    def horizon(self, n_stages: int) -> int:
        """E: the single floor's (``steps_per_stage`` per stage, or ``max_steps``) plus, per stage, two steps
        (board a connector, ride it) for each floor change it may need."""
        s = self.settings
        base = s.steps_per_stage * n_stages if s.max_steps is None else s.max_steps
        return int(base + 2 * (len(self.floors) - 1) * n_stages)

    def _search(self, parts: dict[int, FloorPart], f0: int, cell: np.ndarray, ins, x0: np.ndarray):
        """The stitched search, its horizon check and the metric fallback (as the single-floor planner's)."""
        from spcotmhp.building.reasons import why_not

        order = [parts[f] for f in sorted(parts)]
        E = self.horizon(len(ins.stages))
        st = stitch(self._skeleton(order, False), order, parts[f0], cell, self.fields, E)
        result = search(st.problem)
        if result is not None:
            return result, False, st
        longer = dataclasses.replace(st.problem, max_steps=max(E, st.problem.start.shape[0] * len(ins.stages)))
        if longer.max_steps > E and search(longer) is not None:
            raise HorizonTooShort(
                f"no sequence of at most {E} place-to-place steps from ({x0[0]:.2f}, {x0[1]:.2f}) on floor {f0} "
                f"satisfies '{ins.describe()}'; raise max_steps"
            )
        metric = stitch(self._skeleton(order, True), order, parts[f0], cell, self.fields, E, metric=True)
        result = search(metric.problem)
        if result is None:
            raise why_not(metric, ins, x0, f0, any(p.graph.blocked is not None for p in order))
        return result, True, metric

    def _skeleton(self, order: list[FloorPart], metric: bool) -> Skeleton:
        """The stitched transition of these floor graphs and stops, made once (a query without avoided places
        starting in a floor's main region reuses it: only its start row and word terms are new)."""
        key = skeleton_key(order, metric)
        return self.skeletons.get_or_build(key, lambda: skeleton(order, self.rides, self.fields, metric))

    def _plan(self, segments: list[Segment], st, result, parts, ins, floors, x0) -> BuildingPlan:
        """The plan: the segments' places named, the rides, the goal options over every floor."""
        last = len(ins.stages) - 1
        for k, seg in enumerate(segments):
            planner = parts[seg.floor].planner
            g = parts[seg.floor].graph
            if k == 0:
                start_place = int(np.argmax(planner.terms.place_posterior(x0)))
                seg.places.append(explain.place(planner, start_place, "start", x0))
            for node, done in seg.items:
                local = int(st.local[node])
                if local < 0:
                    continue
                role = "goal" if last in done else ("waypoint" if done else "via")
                xy = planner.model.require_map().cell_to_world(g.to_map(g.node_cell[local]))
                seg.places.append(explain.place(planner, int(g.node_place[local]), role, xy))
        rides = [self._ride(a.leave, b.arrive) for a, b in zip(segments, segments[1:], strict=False)]
        names = {f.index: f.name for f in self.bm.spec.floors}
        pre = max(p.graph.time_precompute_s for p in self.floors.values()) + self.time_precompute_s
        plan = BuildingPlan(segments, rides, names, result.log_prob, ins, tuple(floors), time_precompute_s=pre)
        chosen = (plan.goal[1].id, plan.route_m)
        plan.goal_options = goal_options(st, result, parts, last, chosen, self.rides, self.fields, self.settings.smooth)
        return plan

    def _ride(self, board: Endpoint | None, leave: Endpoint | None) -> Ride:
        assert board is not None and leave is not None
        c = self.bm.spec.connectors[board.connector]
        return Ride(c.name, c.kind, (board.floor, board.point), (leave.floor, leave.point), c.cost_m)

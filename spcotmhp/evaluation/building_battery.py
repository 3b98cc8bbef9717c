"""Issue 28's acceptance battery for buildings, scored by an independent oracle: geodesic route lengths over the
robot cells of every floor (no cost map: :func:`~spcotmhp.evaluation.reference.robot_cells`, steps 1 and sqrt 2),
joined by the connectors' cost_m, by Dijkstra over the connectors' stops; the ground-truth places of each floor's
dataset (:func:`~spcotmhp.evaluation.tasks.build_places`). The planner optimises Eq. 28 (walked cells weighted by
the cost map, rides at their cost_m in metres of free floor); the oracle measures plain metres, so two instances
whose routes differ by less than the single-floor battery's CLOSEST_TOLERANCE_M count as equally close."""

from __future__ import annotations

import heapq
import math

import numpy as np

from spcotmhp.building.loader import Building
from spcotmhp.evaluation.tasks import Place, build_places, home_geometry


class BuildingOracle:
    """``oracle.routes(floor, xy)`` -> {(floor, truth place): route metres} from a start (x, y) on ``floor``."""

    def __init__(self, building: Building) -> None:
        self.building = building
        self.places: dict[int, list[Place]] = {f: build_places(d) for f, d in building.floors.items()}
        self.geometry = {f: home_geometry(d, self.places[f]) for f, d in building.floors.items()}
        self.stops = [(c, s.floor, self.cell(s.floor, (s.x, s.y))) for c, conn in enumerate(building.spec.connectors)
                      for s in conn.stops]  # fmt: skip

    def cell(self, floor: int, xy) -> tuple[int, int]:
        r, c = self.building.floors[floor].map.world_to_cell(np.asarray(xy, float))
        return int(r), int(c)

    def _to_stops(self) -> dict[int, float]:
        """Dijkstra over the stops: {stop index: metres from the start}, from ``self._seed``."""
        dist = dict(self._seed)
        heap = [(d, k) for k, d in dist.items()]
        heapq.heapify(heap)
        cost = self.building.spec.connectors
        while heap:
            d, k = heapq.heappop(heap)
            if d > dist.get(k, math.inf):
                continue
            c, f, cell = self.stops[k]
            field = self.geometry[f].from_cell(cell)
            for j, (c2, f2, cell2) in enumerate(self.stops):
                step = cost[c].cost_m if (c2 == c and f2 != f) else (field[cell2] if f2 == f else math.inf)
                if d + step < dist.get(j, math.inf):
                    dist[j] = d + step
                    heapq.heappush(heap, (d + step, j))
        return dist

    def routes(self, floor: int, xy) -> dict[tuple[int, int], float]:
        """Route metres to every truth place's footprint target of every floor."""
        start = self.cell(floor, xy)
        here = self.geometry[floor].from_cell(start)
        self._seed = {k: float(here[cell]) for k, (_, f, cell) in enumerate(self.stops) if f == floor}
        stops = self._to_stops()
        out = {}
        for f, places in self.places.items():
            geo = self.geometry[f]
            for g in range(len(places)):
                t = geo.targets[g]
                if t[0] < 0:
                    continue
                best = float(here[t[0], t[1]]) if f == floor else math.inf
                for k, (_, f2, cell) in enumerate(self.stops):
                    if f2 == f and k in stops:
                        best = min(best, stops[k] + float(geo.from_cell(cell)[t[0], t[1]]))
                out[(f, g)] = best
        return out

    def named(self, name: str) -> list[tuple[int, int]]:
        """(floor, truth place) of every place called ``name``."""
        return [(f, g) for f, ps in self.places.items() for g, p in enumerate(ps) if p.name == name]

    def ends_in(self, floor: int, xy) -> list[int]:
        """The truth places of ``floor`` whose footprint region holds the point ``xy``."""
        return [g for g, p in enumerate(self.places[floor]) if p.region.contains(np.asarray(xy, float))]


def battery(building: Building, planner, starts_per_floor: int = 2) -> dict:
    """The acceptance battery of issue 28 on one building: from ``starts_per_floor`` truth positions of every
    floor, for every name with instances on two floors or more, "go to the X" with the goal on each floor F (ends
    on F in the closest instance there) and on any floor (the closest over all floors, counting connector
    costs). Returns counts: plans, on_floor (ended on the floor asked), closest, no_path (a planning error
    where the oracle has a route), failures (the first few, described)."""
    from spcotmhp.errors import SpcotmhpError
    from spcotmhp.evaluation.battery import CLOSEST_TOLERANCE_M

    oracle = BuildingOracle(building)
    names = sorted({p.name for ps in oracle.places.values() for p in ps})
    shared = [n for n in names if len({f for f, _ in oracle.named(n)}) > 1]
    out: dict = {"plans": 0, "on_floor": 0, "closest": 0, "no_path": 0, "failures": []}
    for f0, d in building.floors.items():
        for p in oracle.places[f0][:starts_per_floor]:
            xy = tuple(d.map.cell_to_world(np.array(p.cell)))
            routes = oracle.routes(f0, xy)
            for name in shared:
                for goal_floor in [*building.floors, None]:
                    allowed = [fg for fg in oracle.named(name) if goal_floor is None or fg[0] == goal_floor]
                    best = min(routes[fg] for fg in allowed)
                    if not math.isfinite(best):
                        continue
                    out["plans"] += 1
                    what = f"{name} on {goal_floor} from floor {f0} {np.round(xy, 2).tolist()}"
                    try:
                        plan = planner.plan(f"go to the {name}", xy, f0, goal_floor=goal_floor)
                    except SpcotmhpError as exc:
                        out["no_path"] += 1
                        out["failures"].append(f"{what}: {type(exc).__name__}: {exc}")
                        continue
                    end = plan.segments[-1]
                    hit = [(end.floor, g) for g in oracle.ends_in(end.floor, end.path[-1]) if (end.floor, g) in allowed]
                    out["on_floor"] += int(goal_floor is None or end.floor == goal_floor)
                    ok = bool(hit) and min(routes[fg] for fg in hit) <= best + CLOSEST_TOLERANCE_M
                    out["closest"] += int(ok)
                    if not ok:
                        got = min((routes[fg] for fg in hit), default=math.inf)
                        out["failures"].append(
                            f"{what}: ends on floor {end.floor}, route {got:.2f} m, best {best:.2f} m"
                        )
    return out

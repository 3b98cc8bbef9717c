"""An independent oracle for plans in a building: geodesic route lengths over the robot cells of every floor
(no cost map: :func:`~spcotmhp.evaluation.reference.robot_cells`, steps 1 and sqrt 2) joined by the connectors'
cost_m, by Dijkstra over the connectors' stops; the ground-truth places of each floor's dataset
(:func:`~spcotmhp.evaluation.tasks.build_places`)."""

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

"""The result of planning in a building: one path segment per floor, in order, with the connector ridden between
consecutive segments, the places with their roles and floors, and an explanation that says where the robot
changes floor."""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

from spcotmhp.building.route import Segment
from spcotmhp.planning.plan import PlanPlace, instruction_dict
from spcotmhp.planning.query import Instruction


@dataclass(frozen=True)
class Ride:
    """A connector ridden between two floors: its name and kind, the stops (floor, (x, y)) it is boarded at and
    left at, and its cost in metres."""

    name: str
    kind: str
    board: tuple[int, tuple[float, float]]
    leave: tuple[int, tuple[float, float]]
    cost_m: float


@dataclass(frozen=True)
class FloorOption:
    """The best plan ending in one instance of the goal's name (any floor): its place, floor, label, the metres of
    its route (walked plus connectors' cost_m; a lower bound when ``exact`` is False:
    :mod:`spcotmhp.building.options`) and its Eq. 28 log score."""

    id: int
    floor: int
    label: str
    route_m: float
    log_prob: float
    exact: bool = True


@dataclass
class BuildingPlan:
    """A plan across floors.

    Attributes:
        segments: the path on each floor, in order (:class:`~spcotmhp.building.route.Segment`).
        rides: the connector between segment k and k + 1.
        floor_names: floor index -> name.
        log_prob: the Eq. 28 log score of the stitched sequence.
        instruction: what was understood; ``floors`` the floor each stage must end on (None: any).
        goal_options: the best plan into each goal instance over all floors (only when the name is shared).
        route_m: walked metres (smoothed) plus the rides' cost_m.
    """

    segments: list[Segment]
    rides: list[Ride]
    floor_names: dict[int, str]
    log_prob: float
    instruction: Instruction
    floors: tuple[int | None, ...] = ()
    goal_options: list[FloorOption] = field(default_factory=list)
    time_online_s: float = 0.0
    time_precompute_s: float = 0.0
    notes: list[str] = field(default_factory=list)

    @property
    def places(self) -> list[tuple[int, PlanPlace]]:
        """(floor, place) in the order reached, the start first; place ids are the building model's."""
        return [(s.floor, p) for s in self.segments for p in s.places]

    @property
    def goal(self) -> tuple[int, PlanPlace]:
        return self.places[-1]

    @property
    def length_m(self) -> float:
        """Metres walked on the floors."""
        return float(sum(s.length_m for s in self.segments))

    @property
    def route_m(self) -> float:
        return self.length_m + float(sum(r.cost_m for r in self.rides))

    def floor_label(self, index: int) -> str:
        return f"floor {index} ({self.floor_names.get(index, '?')})"

    @property
    def explanation(self) -> str:
        """E.g. "floor 1 (ground): entrance -> corridor; stairs 1-2 to floor 2 (first) at (3.20, 1.00); floor 2
        (first): corridor -> bedroom #2 (goal, closest of 6 bedrooms on 3 floors); 14.2 m walked + 9.8 m of
        stairs"."""
        parts = []
        for k, seg in enumerate(self.segments):
            said = " -> ".join(self._said(p) for p in seg.places) or "passes through"
            parts.append(f"{self.floor_label(seg.floor)}: {said}")
            if k < len(self.rides):
                r = self.rides[k]
                (bx, by), (lx, ly) = r.board[1], r.leave[1]
                parts.append(
                    f"{r.kind} '{r.name}' at ({bx:.2f}, {by:.2f}) to {self.floor_label(r.leave[0])}, off at "
                    f"({lx:.2f}, {ly:.2f})"
                )
        walked = f"{self.length_m:.1f} m walked"
        if self.rides:
            walked += " + " + " + ".join(f"{r.cost_m:g} m of {r.kind}" for r in self.rides)
        text = "; ".join(parts) + f"; {walked}"
        if self.instruction.avoid:
            text += ", avoiding " + " and ".join(a.describe() for a in self.instruction.avoid)
        for note in self.notes:
            text += f"; {note}"
        return text

    def _said(self, p: PlanPlace) -> str:
        if p.role == "goal":
            return f"{p.label} (goal{self._goal_note(p)})"
        if p.role == "waypoint":
            return f"{p.label} (waypoint)"
        return p.label

    def _goal_note(self, goal: PlanPlace) -> str:
        if len(self.goal_options) < 2:
            return ""
        floors = len({o.floor for o in self.goal_options})
        where = f" on {floors} floors" if floors > 1 else ""
        best = min(self.goal_options, key=lambda o: o.route_m)
        if best.id == goal.id:
            return f", closest of {len(self.goal_options)} reachable{where}"
        return f", most probable of {len(self.goal_options)}{where}; {best.label} on floor {best.floor} is closer"

    def to_dict(self) -> dict:
        """JSON-ready: the single-floor plan's keys (``path`` is the first segment's, on the start's floor, in that
        floor's map frame; places and goal options carry their floor; goal options' ``length_m`` is the route's
        metres, walked plus ridden) and ``floor`` (the start's), ``goal_floor``, ``segments`` [{floor, path [[x, y],
        ...], length_m}] in order, ``rides`` (the connector between consecutive segments) and ``route_m``."""
        ins = self.instruction
        return {
            "path": np.round(self.segments[0].path, 4).tolist(),
            "places": [
                {
                    "floor": f,
                    "id": p.id,
                    "name": p.name,
                    "role": p.role,
                    "label": p.label,
                    "chosen_by": None,
                    "point": None if p.point is None else [round(float(v), 4) for v in p.point],
                }
                for f, p in self.places
            ],  # fmt: skip
            "speed": ins.speed,
            "waits": [],
            "length_m": round(self.length_m, 4),
            "log_prob": self.log_prob,
            "time_online_s": self.time_online_s,
            "time_precompute_s": self.time_precompute_s,
            "explanation": self.explanation,
            "instruction": {**instruction_dict(ins), "floors": list(self.floors)},
            "goal_options": [
                {
                    "id": o.id,
                    "floor": o.floor,
                    "label": o.label,
                    "length_m": round(o.route_m, 4),
                    "route_m": round(o.route_m, 4),
                    "log_prob": o.log_prob,
                }
                for o in self.goal_options
            ],  # fmt: skip
            "notes": list(self.notes),
            "floor": self.segments[0].floor,
            "goal_floor": self.goal[0],
            "segments": [
                {"floor": s.floor, "path": np.round(s.path, 4).tolist(), "length_m": round(s.length_m, 4)}
                for s in self.segments
            ],
            "rides": [
                {
                    "name": r.name,
                    "kind": r.kind,
                    "from": {"floor": r.board[0], "x": r.board[1][0], "y": r.board[1][1]},
                    "to": {"floor": r.leave[0], "x": r.leave[1][0], "y": r.leave[1][1]},
                    "cost_m": r.cost_m,
                }
                for r in self.rides
            ],  # fmt: skip
            "route_m": round(self.route_m, 4),
        }

    def to_json(self, **kwargs) -> str:
        return json.dumps(self.to_dict(), ensure_ascii=False, **kwargs)

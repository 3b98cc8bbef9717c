"""The result of hierarchical planning: the path, the places it visits with their roles, and an explanation."""

from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np

from spcotmhp.planning.instructions import Instruction

ROLES = ("start", "via", "waypoint", "goal")


@dataclass(frozen=True)
class PlanPlace:
    """A place on the plan. ``role``: start (the most probable place of x_0), via (passed on the way),
    waypoint, goal. ``instance``/``n_instances``: "bedroom #2" of 3 places sharing the name (1-based).
    ``point``: the candidate point (map frame) where the plan reaches the place; the start pose for the start."""

    id: int
    name: str
    role: str
    instance: int = 1
    n_instances: int = 1
    point: tuple[float, float] | None = None

    @property
    def label(self) -> str:
        return f"{self.name} #{self.instance}" if self.n_instances > 1 else self.name


@dataclass(frozen=True)
class GoalOption:
    """The best plan ending in one instance of the goal name (for "closest of 3 bedrooms"); ``length_m`` is the
    length of that option's final path (assembled, smoothed, cut on arrival: the same as the chosen plan's), or,
    with ``exact`` False, a lower bound of it that already exceeds the length of a shorter option (the chosen
    plan's or another's), so the shortest option is always exact."""

    id: int
    label: str
    length_m: float
    log_prob: float
    exact: bool = True


@dataclass
class Plan:
    """A planned path (Algorithm 1's output).

    Attributes:
        path: (n, 2) map-frame metres of the cell centres, from the start cell to the goal candidate (to
            the first cell inside the goal place when the planner's ``arrival_quantile`` is set).
        cells: (n, 2) map cells (row, col) of the same path (8-connected).
        places: the place sequence with roles.
        length_m: path length in metres.
        log_prob: the Eq. 28 log score of the chosen place/candidate sequence (before smoothing).
        time_online_s: online planning time (instruction understanding to assembled path).
        time_precompute_s: time of the precomputation it used (Algorithm 1, lines 1-7).
        instruction: what was understood.
        goal_options: the best plan into each reachable instance of the goal name, most probable first (only
            when the name has several instances).
        n_goal_instances: how many places the goal name denotes.
        node_points: (e, 2) map-frame candidate points of the topological plan, in order (smoothing may bypass
            the points of places passed on the way; waypoint and goal points are always kept).
        smoothed: whether the path was smoothed.
        notes: what the plan did that the instruction did not ask for (leaving a start within the robot's
            radius of an obstacle; a metric route where the place graph had none), said in the explanation.
        chosen: the places a relation of the instruction picked, with what the explanation says of them
            (place id -> "the one closest to the bath").
    """

    path: np.ndarray
    cells: np.ndarray
    places: list[PlanPlace]
    length_m: float
    log_prob: float
    time_online_s: float
    time_precompute_s: float
    instruction: Instruction
    goal_options: list[GoalOption] = field(default_factory=list)
    n_goal_instances: int = 1
    node_points: np.ndarray = field(default_factory=lambda: np.empty((0, 2)))
    smoothed: bool = False
    notes: list[str] = field(default_factory=list)
    chosen: dict[int, str] = field(default_factory=dict)

    @property
    def goal(self) -> PlanPlace:
        return self.places[-1]

    @property
    def stops(self) -> list[PlanPlace]:
        """The places that complete the instruction's stages, in order: the waypoints, then the goal."""
        return [p for p in self.places if p.role in ("waypoint", "goal")]

    @property
    def waits(self) -> list[tuple[PlanPlace, float | None]]:
        """Where the robot is to wait and for how many seconds (None: until the next instruction)."""
        stops = self.stops
        return [(stops[s], seconds) for s, seconds in self.instruction.waits if s < len(stops)]

    @property
    def explanation(self) -> str:
        """E.g. "kitchen -> corridor (waypoint) -> bedroom #2 (closest of 3 bedrooms), 9.4 m"."""
        parts = []
        for p in self.places:
            said = f", {self.chosen[p.id]}" if p.id in self.chosen and p.role in ("waypoint", "goal") else ""
            if p.role == "waypoint":
                parts.append(f"{p.label} (waypoint{said})")
            elif p.role == "goal":
                parts.append(p.label + (f" ({said[2:]})" if said else self._goal_note(p)))
            else:
                parts.append(p.label)
        text = " -> ".join(parts) + f", {self.length_m:.1f} m"
        if self.instruction.avoid:
            text += ", avoiding " + " and ".join(a.describe() for a in self.instruction.avoid)
        if self.instruction.not_goal:
            text += ", instead of " + " and ".join(a.describe() for a in self.instruction.not_goal)
        for place, seconds in self.waits:
            text += f"; waits at {place.label} " + ("until told" if seconds is None else f"for {seconds:g} s")
        if self.instruction.speed:
            text += "; " + {"slow": "slowly", "fast": "quickly"}[self.instruction.speed]
        for note in self.notes:
            text += f"; {note}"
        if self.instruction.heard:
            text += "; heard: " + "; ".join(self.instruction.heard)
        return text

    def _goal_note(self, goal: PlanPlace) -> str:
        if self.n_goal_instances < 2 or len(self.goal_options) < 2:
            return ""
        names = sorted({o.label.split(" #")[0] for o in self.goal_options} | {goal.name})
        said = [w for w, c in self.instruction.goal.words.items() if c > 0]
        shared = len(said) == 1 and all(said[0] in n.split() for n in names)  # "corridor": east and south corridor
        plural = _plural(goal.name if len(names) == 1 else said[0]) if len(names) == 1 or shared else (
            "places named " + " or ".join(names))  # fmt: skip
        n = self.n_goal_instances
        reachable = len(self.goal_options)
        shortest = min(self.goal_options, key=lambda o: o.length_m)
        chosen = next((o for o in self.goal_options if o.id == goal.id), None)
        of = f"{n} {plural}" if reachable == n else f"{reachable} reachable of {n} {plural}"
        if chosen is None or chosen.length_m <= shortest.length_m + 1e-9:
            return f" (closest of {of})"
        return (
            f" (most probable of {of}; {shortest.label} would be {chosen.length_m - shortest.length_m:.1f} m shorter)"
        )

    def to_dict(self) -> dict:
        """JSON-ready: path, places [{id, name, role}], length_m, log_prob, time_online_s, explanation, plus
        time_precompute_s, instruction, goal_options."""
        ins = self.instruction
        return {
            "path": np.round(self.path, 4).tolist(),
            "places": [
                {
                    "id": p.id,
                    "name": p.name,
                    "role": p.role,
                    "label": p.label,
                    "point": None if p.point is None else [round(float(v), 4) for v in p.point],
                    "chosen_by": self.chosen.get(p.id),
                }
                for p in self.places
            ],
            "speed": ins.speed,
            "waits": [{"id": p.id, "label": p.label, "seconds": seconds} for p, seconds in self.waits],
            "length_m": round(self.length_m, 4),
            "log_prob": self.log_prob,
            "time_online_s": self.time_online_s,
            "time_precompute_s": self.time_precompute_s,
            "explanation": self.explanation,
            "instruction": instruction_dict(ins),
            "goal_options": [
                {
                    "id": o.id,
                    "label": o.label,
                    "length_m": round(o.length_m, 4),
                    "log_prob": o.log_prob,
                    "exact": o.exact,
                }
                for o in self.goal_options
            ],
            "notes": list(self.notes),
        }

    def to_json(self, **kwargs) -> str:
        return json.dumps(self.to_dict(), ensure_ascii=False, **kwargs)


def _plural(name: str) -> str:
    if not name.isascii() or not name.isalpha():
        return f"places named {name}"
    return name + ("es" if name.endswith(("s", "sh", "ch", "x", "z")) else "s")


def instruction_dict(ins: Instruction) -> dict:
    """What a plan's JSON says of the instruction understood: its text, bags of words, relations, in words."""
    return {
        "text": ins.text,
        "goal": dict(ins.goal.words),
        "waypoints": [dict(w.words) for w in ins.waypoints],
        "avoid": [dict(a.words) for a in ins.avoid],
        "not_goal": [dict(a.words) for a in ins.not_goal],
        "relations": {q.label: q.relation.describe() for q in (*ins.stages, *ins.avoid, *ins.not_goal) if q.relation},
        "understood": ins.describe(),
        "heard": list(ins.heard),
    }

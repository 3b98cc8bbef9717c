"""Which floor each place of an instruction is on, as a building's planner reads it.

Floors come from the words (the grammar's floor phrases, :mod:`spcotmhp.language.floors`: "the bedroom on the
second floor", "upstairs", 2階の寝室, on each :class:`~spcotmhp.planning.query.PlaceQuery`'s ``floor``) and as
structured values:

* ``floor=F`` (the API's keyword, the CLI's ``--floor`` with the start, the HTTP ``floor``) is the *start's*
  floor; ``goal_floor=G`` the goal's;
* in a structured instruction a place object may carry ``"floor"``: ``{"goal": {"words": "bedroom", "floor":
  2}, "waypoints": [{"words": "kitchen", "floor": "downstairs"}], "avoid": [{"words": "bath", "floor": 1}]}``,
  and a top-level ``"floor"`` is the goal's;
* a floor given both ways must agree (MalformedInstruction otherwise).

A floor value is a floor's index (an int), its name ("ground"), or "upstairs" / "downstairs" (the next floor up or
down from the start's, in index order: :meth:`~spcotmhp.building.model.BuildingModel.resolve_floor`). A place with
no floor may be on any floor. Malformed values are one MalformedInstruction line; floors the building lacks are
UnknownFloor when resolved.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from spcotmhp.errors import MalformedInstruction
from spcotmhp.planning.query import Instruction
from spcotmhp.planning.structured import _json_value
from spcotmhp.safe_read import excerpt

MAX_FLOOR_CHARS = 64
PLACE_KEYS = ("goal", "waypoints", "avoid", "not_goal")


@dataclass(frozen=True)
class PlaceFloors:
    """The floor value (unresolved) of each stage (waypoints in order, then the goal), avoided place and place
    not to end in; None: any floor."""

    stages: tuple[object, ...]
    avoid: tuple[object, ...] = ()
    not_goal: tuple[object, ...] = ()

    @classmethod
    def of(cls, ins: Instruction, given: PlaceFloors | None = None) -> PlaceFloors:
        """The floors the instruction's places carry (``floor``, from the words), with those ``given`` by a
        structured form or ``goal_floor`` (for the goal alone when their counts differ); MalformedInstruction
        when both give a place different floors."""
        said = cls(
            tuple(getattr(q, "floor", None) for q in ins.stages),
            tuple(getattr(q, "floor", None) for q in ins.avoid),
            tuple(getattr(q, "floor", None) for q in ins.not_goal),
        )
        if given is None:
            return said
        if len(given.stages) != len(ins.stages):  # goal_floor with a sentence
            given = cls((None,) * (len(ins.stages) - 1) + (given.stages[-1],))
        return cls(
            _merge(said.stages, given.stages, [q.label for q in ins.stages]),
            _merge(said.avoid, given.avoid, [q.label for q in ins.avoid]),
            _merge(said.not_goal, given.not_goal, [q.label for q in ins.not_goal]),
        )


def _merge(said: tuple[object, ...], given: tuple[object, ...], labels: list[str]) -> tuple[object, ...]:
    """Each place's floor from the words or from the structured value (missing values: None)."""
    out = []
    for k, label in enumerate(labels):
        a = said[k] if k < len(said) else None
        b = given[k] if k < len(given) else None
        if a is not None and b is not None and str(a).lower() != str(b).lower():
            raise MalformedInstruction(
                f"the floor of '{excerpt(label)}' is given twice ({excerpt(a)} and {excerpt(b)})"
            )
        out.append(a if a is not None else b)
    return tuple(out)


def check_value(value: Any, where: str) -> object:
    """``value`` when it can name a floor (an int that is not a bool, or a short string); else
    MalformedInstruction."""
    if value is None or (isinstance(value, int) and not isinstance(value, bool)):
        return value
    if isinstance(value, str) and value.strip() and len(value) <= MAX_FLOOR_CHARS:
        return value
    raise MalformedInstruction(f"{where} must be a floor (its index, its name, upstairs or downstairs), got "
                               f"{excerpt(value)}")  # fmt: skip


def split_floors(instruction: Any, goal_floor: object = None) -> tuple[Any, PlaceFloors | None]:
    """``instruction`` without its floor fields (what the single-floor parser reads) and the floors they gave
    (None when the instruction is not a structured form and no ``goal_floor`` is given: the places' own
    ``floor`` attributes, if any, are read after parsing, :meth:`PlaceFloors.of`)."""
    goal_floor = check_value(goal_floor, "goal_floor")
    if isinstance(instruction, str) and instruction.lstrip().startswith("{"):
        instruction = _json_value(instruction)  # a structured form as JSON text (the CLI's, HTTP's)
    if not isinstance(instruction, Mapping):
        return instruction, None if goal_floor is None else PlaceFloors((goal_floor,))
    obj = dict(instruction)
    top = check_value(obj.pop("floor", None), "'floor'")
    if top is not None and goal_floor is not None and top != goal_floor:
        raise MalformedInstruction(f"the goal's floor is given twice ({excerpt(top)} and {excerpt(goal_floor)})")
    found: dict[str, list[object]] = {}
    for key in PLACE_KEYS:
        value = obj.get(key)
        if key == "goal":
            obj[key], floor = _strip(value, "goal")
            found[key] = [floor]
        elif isinstance(value, (list, tuple)):
            pairs = [_strip(v, f"{key}[{i}]") for i, v in enumerate(value)]
            obj[key] = [p for p, _ in pairs]
            found[key] = [f for _, f in pairs]
    goal = found["goal"][0]
    for extra in (top, goal_floor):
        if extra is not None and goal is not None and extra != goal:
            raise MalformedInstruction(f"the goal's floor is given twice ({excerpt(goal)} and {excerpt(extra)})")
        goal = goal if goal is not None else extra
    stages = (*found.get("waypoints", []), goal)
    return obj, PlaceFloors(tuple(stages), tuple(found.get("avoid", [])), tuple(found.get("not_goal", [])))


def _strip(place: Any, where: str) -> tuple[Any, object]:
    """A place of the structured form without its "floor", and that floor."""
    if not isinstance(place, Mapping) or "floor" not in place:
        return place, None
    rest = {k: v for k, v in place.items() if k != "floor"}
    return rest, check_value(place["floor"], f"{where}.floor")

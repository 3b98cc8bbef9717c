"""What an instruction means: the places to visit in order (the last is the goal), to avoid and not to end in, a
speed and waits; each place a name with an optional relation that picks one of its instances.

These are what the grammar's derivations produce (:mod:`spcotmhp.language.reading`); the planner turns the names
into places of the map (:mod:`spcotmhp.planning.instructions`) and answers the relations
(:mod:`spcotmhp.planning.relations`).
"""

from __future__ import annotations

from dataclasses import dataclass

from spcotmhp.language.floors import FloorValue, describe_floor

RELATIONS = ("closest", "farthest", "next_to", "between", "largest", "smallest")
"""The relations a place phrase may carry."""
ARITY = {"closest": 1, "farthest": 1, "next_to": 1, "between": 2, "largest": 0, "smallest": 0}
"""How many other places each relation names."""
WORDING = {
    "closest": "closest to",
    "farthest": "farthest from",
    "next_to": "next to",
    "between": "between",
    "largest": "largest",
    "smallest": "smallest",
}
SPEEDS = ("slow", "fast")


@dataclass(frozen=True)
class Relation:
    """A relation of a place phrase: its kind (one of :data:`RELATIONS`) and the other places it names
    (``args``, as many as :data:`ARITY` says)."""

    kind: str
    args: tuple[PlaceRef, ...] = ()

    def __post_init__(self) -> None:
        if self.kind not in RELATIONS or len(self.args) != ARITY[self.kind]:
            raise ValueError(f"a relation is one of {', '.join(RELATIONS)} with its places, got {self.kind!r}")

    def describe(self) -> str:
        """E.g. "closest to the bath", "between the kitchen and the bath", "largest"."""
        if not self.args:
            return WORDING[self.kind]
        return f"{WORDING[self.kind]} the " + " and the ".join(a.label for a in self.args)


@dataclass(frozen=True)
class PlaceRef:
    """A place as said: its place words (a multi-word name has several), how it was said, an optional relation,
    ``every`` for "all the bedrooms" / "both corridors" (every place of that name), the floor it is on as said
    (``floor``: :mod:`spcotmhp.language.floors`; None: any floor) with the words that said it (``floor_said``), and
    the number of the instance meant, as the robot numbers the places of one name (``number``: "bedroom 2")."""

    words: tuple[str, ...]
    label: str
    relation: Relation | None = None
    every: bool = False
    floor: FloorValue | None = None
    floor_said: str = ""
    number: int | None = None  # "bedroom 2", "2番の寝室": the instance the robot shows as "bedroom #2"

    def describe(self) -> str:
        """E.g. "bedroom (closest to the bath)", "every bedroom (on floor 2)"."""
        return ("every " if self.every else "") + qualified(self.label, self.relation, self.floor)


def qualified(label: str, relation: Relation | None, floor: FloorValue | None) -> str:
    """A place's label with what picks it: "bedroom (on floor 2, closest to the bath)"."""
    said = [describe_floor(floor)] if floor is not None else []
    said += [relation.describe()] if relation is not None else []
    return f"{label} ({', '.join(said)})" if said else label


@dataclass(frozen=True)
class Reading:
    """The meaning of an instruction: ``visit`` in order (the last is the goal), ``avoid``, ``not_goal``, the
    speed ("slow", "fast" or None) and the waits, each (index into ``visit``, seconds or None: until the next
    instruction); ``heard``: what the reading did beyond the grammar, said in the plan's explanation."""

    visit: tuple[PlaceRef, ...]
    avoid: tuple[PlaceRef, ...] = ()
    not_goal: tuple[PlaceRef, ...] = ()
    speed: str | None = None
    waits: tuple[tuple[int, float | None], ...] = ()
    heard: tuple[str, ...] = ()  # what the reading did beyond the grammar: corrections, talk passed over

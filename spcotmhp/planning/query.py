"""What an understood instruction is, whatever it came from (a sentence, the structured form, an N-best list):
the places to visit in order, to avoid and not to end in, each a weighted bag of words (Eq. 25) with an optional
relation, and the speed and waits; and the limits every parser enforces."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from spcotmhp.errors import InstructionTooLarge, MalformedInstruction
from spcotmhp.language.floors import FloorValue
from spcotmhp.language.meaning import PlaceRef, Relation, qualified
from spcotmhp.language.wording import excerpt

MAX_CHARS = 500
"""Longest instruction text (characters) :func:`parse_text` accepts."""
MAX_WAYPOINTS = 10
"""Most waypoints an instruction may name."""
MAX_AVOIDED = 10
"""Most places an instruction may name to avoid plus not to end in."""
MAX_HYPOTHESES = 50
"""Most hypotheses of an N-best list."""
MAX_JSON_CHARS = 20_000
"""Longest JSON text of a structured instruction (its places are then bounded by the limits above)."""
MAX_PLACE_WORDS = 8
"""Most words in the name of one place of a structured instruction."""


@dataclass(frozen=True)
class PlaceQuery:
    """One named place of an instruction: a weighted bag of words S (Eq. 25) and a readable label.

    ``alternatives``: for a bag merged from N-best hypotheses, each hypothesis's own bag (one of them names the
    place; empty for a single phrase, whose words all name it). ``relation``: what picks one of the places so named
    ("closest to the bath": :mod:`spcotmhp.planning.relations`); ``every``: every place so named ("both
    corridors", only to avoid); ``floor``: the floor it is on, as the words ``floor_said`` said it ("the bedroom
    upstairs": :mod:`spcotmhp.language.floors`; a building's planner honours it, a one-floor planner refuses it);
    ``number``: the instance meant, as plans number the places of one name ("bedroom 2" is "bedroom #2")."""

    words: Mapping[str, float]
    label: str
    alternatives: tuple[Mapping[str, float], ...] = ()
    relation: Relation | None = None
    every: bool = False
    floor: FloorValue | None = None
    floor_said: str = ""
    number: int | None = None

    @property
    def phrases(self) -> tuple[Mapping[str, float], ...]:
        """The bags each of which names the place on its own: the alternatives, or the words."""
        return self.alternatives or (self.words,)

    def __post_init__(self) -> None:
        if not self.words:
            raise MalformedInstruction(f"the place {excerpt(self.label)} has no words")

    def describe(self) -> str:
        """E.g. "bedroom (closest to the bath)", "bedroom (upstairs)"."""
        return qualified(self.label, self.relation, self.floor)

    @classmethod
    def of(cls, ref: PlaceRef) -> PlaceQuery:
        """The query of a place as the grammar read it (:class:`~spcotmhp.language.meaning.PlaceRef`)."""
        bag: dict[str, float] = {}
        for word in ref.words:
            bag[word] = bag.get(word, 0) + 1
        return cls(bag, ref.label, relation=ref.relation, every=ref.every, floor=ref.floor,
                   floor_said=ref.floor_said, number=ref.number)  # fmt: skip


@dataclass(frozen=True)
class Instruction:
    """An understood instruction: stages are the waypoints in order, then the goal (Eq. 28 uses the bag of the
    stage being pursued at each step); ``avoid`` places get zero probability; ``not_goal`` places may be passed
    but never end the plan ("instead of the kitchen"). ``speed`` ("slow", "fast" or None) and ``waits`` ((stage,
    seconds or None: until the next instruction), ...) are for whoever drives the path: the planner carries them
    in the plan (its JSON, the ROS 2 status) and says them in the explanation; the path is the same. ``heard``:
    what reading the sentence did beyond its grammar (a self-correction applied, talk passed over), said in the
    explanation."""

    goal: PlaceQuery
    waypoints: tuple[PlaceQuery, ...] = ()
    avoid: tuple[PlaceQuery, ...] = ()
    text: str = ""
    lang: str = "en"
    not_goal: tuple[PlaceQuery, ...] = ()
    speed: str | None = None
    waits: tuple[tuple[int, float | None], ...] = ()
    heard: tuple[str, ...] = ()

    @property
    def stages(self) -> tuple[PlaceQuery, ...]:
        return (*self.waypoints, self.goal)

    def describe(self) -> str:
        """E.g. "bedroom (closest to the bath) via corridor, avoiding living, slowly"."""
        out = self.goal.describe()
        if self.waypoints:
            out += " via " + ", then ".join(w.describe() for w in self.waypoints)
        if self.avoid:
            out += ", avoiding " + " and ".join(a.describe() for a in self.avoid)
        if self.not_goal:
            out += ", instead of " + " and ".join(a.describe() for a in self.not_goal)
        for stage, seconds in self.waits:
            length = "until told" if seconds is None else f"{seconds:g} s"
            out += f", waiting at {self.stages[stage].describe()} ({length})"
        if self.speed:
            out += ", " + {"slow": "slowly", "fast": "quickly"}[self.speed]
        return out


def limit(value: int | None, default: int) -> int:
    return default if value is None else int(value)


def within_limits(ins: Instruction, max_waypoints: int | None, max_avoided: int | None) -> Instruction:
    """``ins``, or :class:`~spcotmhp.errors.InstructionTooLarge` when it names too many places."""
    most_ways, most_avoided = limit(max_waypoints, MAX_WAYPOINTS), limit(max_avoided, MAX_AVOIDED)
    if len(ins.waypoints) > most_ways:
        raise InstructionTooLarge(
            f"the instruction names {len(ins.waypoints)} waypoints, more than the {most_ways} accepted"
        )
    if len(ins.avoid) + len(ins.not_goal) > most_avoided:
        raise InstructionTooLarge(
            f"the instruction names {len(ins.avoid) + len(ins.not_goal)} places to avoid or "
            f"not to end in, more than the {most_avoided} accepted"
        )
    return ins

"""What the planner cannot honour, refused naming the words (rules 2b, 8 and 9 of
:mod:`spcotmhp.planning.sentence`).

The planner plans from the robot's pose, through named places in order, to a named place, keeping out of the
places to avoid. An instruction that asks for anything else is refused with
:class:`~spcotmhp.errors.UnsupportedPhrase` naming the word, never read as something close to it:

* **Leaving a place** ("leave the kitchen", "get out of the kitchen", キッチンから出て): the goal is "anywhere but
  here", not a place; read as a place phrase it would send the robot into the kitchen.
* **A self-correction** ("go to the kitchen, no wait, the bath", "I mean", "sorry", "actually", やっぱり, いや):
  which part it replaces is a guess; read literally, the wrong place becomes a waypoint. Before any place is
  named it corrects nothing of this instruction ("actually, go to the kitchen") and is a filler, unless a place
  follows it at once in English ("no kitchen, ...": a negation of that place; やっぱり風呂 is fine). "instead" is
  refused only after two places with no negation before it ("go to the kitchen, go to the bath instead"; "go to
  the bath instead" and "not the kitchen, go to the bath instead" are fine),
  "wait" only between two places (a correction or a stop on the way: the planner does not wait; "go to the
  corridor and wait" is fine).
* **A cancellation** ("never mind the kitchen", "forget", やめて): what it cancels is a guess.
* **A condition** ("if", "unless", "when", "in case"; なら, たら, もし): the planner cannot check it, and dropped it
  would turn its place into a waypoint. Polite phrases ("if you can", よかったら) are fillers, and a たら after a
  verb of motion (キッチンに行ったら) is a marker: "once you are in the kitchen", a sequence.
* **A way back** ("and come back", "and back", "then return", 戻ってきて): the start is a pose, not a place, and
  the planner can only end at a place. English "back" right before a goal marker or a place ("go back into the
  kitchen") names its own goal and is a filler there.
* **A waiver** ("no need to avoid", "I don't mind passing", 避けなくていい): it neither requires nor forbids
  anything; read as "avoid" it would forbid what it allows. Likewise a negated avoidance, two avoid markers with
  only fillers between ("do not avoid the living", "don't skip", "without avoiding").
* **Containment** ("the toilet in the corridor", "the kitchen of the living", 廊下にあるトイレ): a word that puts
  one place inside another, between two place phrases; the map holds no containment between places, and read as
  two places the first would become a waypoint.
* **A start place** ("from the bath", リビングから): the start is the pose given with the instruction.
* **A Japanese list with no goal** (風呂、キッチン経由): a 、 lets the phrase before it share the marker after the
  next one, so both are waypoints and the last would silently become the goal, while a person may mean the first
  (bath, via the kitchen). When no place has the goal role, such a list is refused naming the 、 (with a goal, the
  list is one: キッチン、トイレを経由して寝室へ).
* **Two places with only fillers between** ("the kitchen with the bath"): nothing says how they relate; read as
  two goals the first would become a waypoint (Japanese places must be joined already, rule 6).

Every other word must be a place word or a word of the grammar tables (rule 9): an unknown word anywhere is an
:class:`~spcotmhp.errors.UnknownPlaceWord` naming it ("did you mean" near misses included), never skipped.
"""

from __future__ import annotations

from collections.abc import Sequence
from itertools import pairwise

from spcotmhp.errors import UnknownPlaceWord, UnsupportedPhrase
from spcotmhp.planning.grammar import Grammar
from spcotmhp.planning.scan import Item
from spcotmhp.language.wording import excerpt, named, unknown_tail

REASONS = {
    "leave": "asks to leave a place, which is no destination: the planner plans to a named place; say where to go",
    "correction": "corrects what was said before it, and the planner does not guess which place it replaces; "
    "say the instruction again as meant",
    "cancel": "cancels something, and the planner does not guess what; say only what to do",
    "conditional": "makes the instruction depend on a condition the planner cannot check; say where to go",
    "round_trip": "asks to come back to the start, a pose that a plan cannot end at (it ends at a named place); "
    "name the place to come back to (e.g. 'then back to the entrance')",
    "mid_correction": "between two places is a correction or a stop on the way, and the planner honours neither "
    "(it does not wait); name the places only",
    "waiver": "says what need not be done, which is no constraint the planner can honour; say only where to go, "
    "what to pass and what to avoid",
}
_REASON_OF = {"late_correction": "correction", "back": "round_trip"}


def _places_around(items: Sequence[Item], idx: int) -> tuple[Item | None, Item | None]:
    """The place phrases right before and after ``items[idx]``, through fillers and containment words only."""
    out: list[Item | None] = []
    for step in (-1, 1):
        j = idx + step
        while 0 <= j < len(items) and items[j].kind in ("filler", "containment"):
            j += step
        out.append(items[j] if 0 <= j < len(items) and items[j].kind == "place" else None)
    return out[0], out[1]


def _harmless(items: Sequence[Item], idx: int, grammar: Grammar, places_before: int) -> bool:
    """Whether the refused-kind phrase ``items[idx]`` asks for nothing here (module docstring)."""
    kind = items[idx].value
    if kind == "correction":  # nothing to correct yet, and it does not negate a place right after it ("no kitchen")
        j = idx + 1
        while j < len(items) and items[j].kind == "filler":
            j += 1
        negates = grammar.attach == "prefix" and j < len(items) and items[j].kind == "place"
        return places_before == 0 and not negates
    if kind == "late_correction":  # fine when what it replaces is already excluded: "not the kitchen, ... instead"
        negated = any(x.kind == "marker" and x.value in ("avoid", "not_goal") for x in items[:idx])
        return places_before < 2 or negated
    if kind == "mid_correction":
        return places_before == 0 or not any(x.kind == "place" for x in items[idx + 1 :])
    if kind == "back" and grammar.attach == "prefix":
        j = idx + 1
        while j < len(items) and items[j].kind == "filler":
            j += 1
        return j < len(items) and (items[j].kind == "place" or (items[j].kind == "marker" and items[j].value == "goal"))
    return False


def refuse_unsupported(items: list[Item], grammar: Grammar) -> None:
    """Refused phrases and containment words (module docstring); those that are harmless where they stand, and
    containment words not between two places, become fillers (or stay the marker they are)."""
    places_before = 0
    for idx, it in enumerate(items):
        places_before += it.kind == "place"
        if it.kind == "refused":
            if _harmless(items, idx, grammar, places_before):
                it.kind = "filler"
                continue
            raise UnsupportedPhrase(f"{excerpt(it.surface)} {REASONS[_REASON_OF.get(it.value, it.value)]}")
        if it.surface in grammar.containment:
            inner, outer = _places_around(items, idx)
            if inner is not None and outer is not None:
                raise UnsupportedPhrase(
                    f"{excerpt(it.surface)} puts {excerpt(inner.surface)} inside or at {excerpt(outer.surface)}; "
                    "the map holds no place inside another: name one place (the planner goes to the closest "
                    "place with that name)"
                )
            if it.kind == "containment":
                it.kind = "filler"


def refuse_unjoined(items: Sequence[Item], grammar: Grammar) -> None:
    """English place phrases with only fillers between them ("the kitchen with the bath") do not say how the two
    places relate (Japanese has the same rule in :mod:`spcotmhp.planning.sentence`): refused naming the words."""
    if grammar.attach != "prefix":
        return
    last: int | None = None
    for idx, it in enumerate(items):
        if it.kind == "place":
            between = list(items[last + 1 : idx]) if last is not None else []
            if last is not None and between and all(x.kind == "filler" for x in between):
                words = [x.surface for x in between if x.surface not in grammar.determiners]
                raise UnsupportedPhrase(
                    f"{named(words or [x.surface for x in between])} between {excerpt(items[last].surface)} and "
                    f"{excerpt(it.surface)} does not say how the two places relate; join places with 'and' or "
                    "'then', or give each its own word ('via the corridor', 'to the bedroom')"
                )
            last = idx
        elif it.kind != "filler":
            last = None


def refuse_double_negation(first: Item, second: Item) -> UnsupportedPhrase:
    """The error for a negation followed by an avoid marker ("do not avoid", "don't skip")."""
    return UnsupportedPhrase(
        f"{excerpt(first.surface)} negates {excerpt(second.surface)}: a place not to avoid is neither required "
        "nor forbidden, which is no constraint the planner can honour; say 'via' to pass it, or leave it out"
    )


def refuse_start_place(marker: Item, place: Item) -> UnsupportedPhrase:
    """The error for a start given as a place ("from the bath")."""
    return UnsupportedPhrase(
        f"{excerpt(marker.surface)} gives {excerpt(place.surface)} as the start, but a plan starts at the robot's "
        "pose given with the instruction, not at a named place; leave the start place out"
    )


def refuse_unknown(items: Sequence[Item], place_words: Sequence[str]) -> None:
    """Rule 9: a word that is neither a place word nor a grammar word is refused naming it, wherever it stands."""
    others = [it.surface for it in items if it.kind == "other"]
    if others:
        verb = "is neither a known place word nor" if len(others) == 1 else "are neither known place words nor"
        raise UnknownPlaceWord(f"{named(others)} {verb} a word instructions use{unknown_tail(others, place_words)}")


def refuse_list_without_goal(
    items: Sequence[Item], places: Sequence[int], roles: Sequence[tuple[str, int]], grammar: Grammar
) -> None:
    """Japanese places listed with 、 under one waypoint marker when no place is the goal (module docstring)."""
    if grammar.attach != "postfix" or any(role == "goal" for role, _ in roles):
        return
    for (a, (role_a, src_a)), (b, (_, src_b)) in pairwise(zip(places, roles, strict=True)):
        between = items[a + 1 : b]
        soft = [x for x in between if x.kind == "connector" and x.surface in grammar.soft_connectors]
        if (
            role_a == "waypoint"
            and soft
            and src_a == src_b >= 0
            and all(x.kind == "filler" or x in soft for x in between)
        ):
            raise UnsupportedPhrase(
                f"{excerpt(soft[0].surface)} lists {excerpt(items[a].surface)} with {excerpt(items[b].surface)} "
                f"under {excerpt(items[src_a].surface)}, and no place is the goal: say where to end with its own "
                f"word (e.g. {items[a].surface}へ、{items[b].surface}{items[src_a].surface})"
            )

"""The structured form of an instruction, for programs that already know what they want (the HTTP service's
``structured``, the ROS 2 node's JSON instructions):

    {"goal": ["bedroom"], "waypoints": [["corridor"]], "avoid": [["kitchen"]], "not_goal": [["bath"]],
     "speed": "slow", "waits": [[0, 120]]}

Each place is a token list, or one string of space-separated tokens (so ``"waypoints": ["corridor", "entrance
corridor"]`` is two waypoints), or an object ``{"words": ..., "relation": "closest", "of": [place, ...]}`` that
picks one instance of its name as a sentence's relation does (:data:`~spcotmhp.language.meaning.RELATIONS`, with as
many places in ``of`` as the relation takes: one, two for "between", none for "largest" and "smallest"). Every
token must be a place word. ``speed`` is "slow" or "fast"; ``waits`` pairs a stage (0-based: the waypoints in
order, then the goal) with seconds, or null for "until the next instruction" (the goal only). A JSON string is
accepted too.
"""

from __future__ import annotations

import json
import math
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from spcotmhp.errors import InstructionTooLarge, MalformedInstruction, UnknownPlaceWord
from spcotmhp.language.lexicon import MAX_WAIT_S
from spcotmhp.language.meaning import ARITY, RELATIONS, SPEEDS, PlaceRef, Relation
from spcotmhp.language.wording import excerpt, unknown_tail
from spcotmhp.planning.arguments import check_parse_arguments
from spcotmhp.planning.query import (
    MAX_AVOIDED,
    MAX_CHARS,
    MAX_JSON_CHARS,
    MAX_PLACE_WORDS,
    MAX_WAYPOINTS,
    Instruction,
    PlaceQuery,
    limit,
    within_limits,
)

KEYS = ("goal", "waypoints", "avoid", "not_goal", "speed", "waits")


def parse_structured(
    obj: Mapping[str, Any] | str,
    place_words: Sequence[str],
    lang: str = "en",
    *,
    max_waypoints: int | None = None,
    max_avoided: int | None = None,
) -> Instruction:
    """The :class:`~spcotmhp.planning.query.Instruction` of a structured form (module docstring).

    Raises:
        MalformedInstruction: not a JSON object of that shape. UnknownPlaceWord: a token is no place word.
        InstructionTooLarge: too long a JSON text, too many places or words, too long a wait.

    >>> ins = parse_structured({"goal": {"words": "bedroom", "relation": "closest", "of": ["bath"]}, "speed": "slow"},
    ...                        ["bath", "bedroom"])
    >>> ins.describe()
    'bedroom (closest to the bath), slowly'
    """
    check_parse_arguments("parse_structured", place_words, max_waypoints=max_waypoints, max_avoided=max_avoided)
    if isinstance(obj, str):
        obj = _json_value(obj)
    if not isinstance(obj, Mapping):
        raise MalformedInstruction("a structured instruction must be a JSON object with keys goal, waypoints, avoid")
    unknown_keys = [k for k in obj if k not in KEYS]
    if unknown_keys:
        raise MalformedInstruction(
            f"unknown key(s) [{', '.join(excerpt(str(k), 30) for k in unknown_keys[:5])}] in "
            f"the structured instruction; accepted: {', '.join(KEYS)}"
        )
    if "goal" not in obj:
        raise MalformedInstruction("the structured instruction has no 'goal'")
    reader = _Places(frozenset(place_words), place_words)
    limits = {
        "waypoints": limit(max_waypoints, MAX_WAYPOINTS),
        "avoid": limit(max_avoided, MAX_AVOIDED),
        "not_goal": limit(max_avoided, MAX_AVOIDED),
    }

    def queries(key: str) -> tuple[PlaceQuery, ...]:
        value = obj.get(key, [])
        if not isinstance(value, (list, tuple)):
            raise MalformedInstruction(f"'{key}' must be a list of places (each a list of words), got {excerpt(value)}")
        if len(value) > limits[key]:
            raise InstructionTooLarge(f"'{key}' lists {len(value)} places, more than the {limits[key]} accepted")
        return tuple(reader.query(v, f"{key}[{i}]") for i, v in enumerate(value))

    ins = Instruction(
        goal=reader.query(obj["goal"], "goal"),
        waypoints=queries("waypoints"),
        avoid=queries("avoid"),
        text="",
        lang=lang,
        not_goal=queries("not_goal"),
        speed=_speed(obj.get("speed")),
    )
    ins = replace(ins, waits=_waits(obj.get("waits", []), len(ins.stages)))
    text = json.dumps(
        {
            "goal": ins.goal.describe(),
            **{k: [q.describe() for q in getattr(ins, k)] for k in ("waypoints", "avoid", "not_goal") if obj.get(k)},
            **({"speed": ins.speed} if ins.speed else {}),
            **({"waits": [list(w) for w in ins.waits]} if ins.waits else {}),
        },
        ensure_ascii=False,
    )
    return within_limits(replace(ins, text=text), max_waypoints, max_avoided)


class _Places:
    """Reads the places of a structured form against a vocabulary."""

    def __init__(self, known: frozenset[str], place_words: Sequence[str]) -> None:
        self.known = known
        self.place_words = place_words

    def words(self, tokens: Any, where: str) -> list[str]:
        if isinstance(tokens, str):
            if len(tokens) > MAX_CHARS:
                raise InstructionTooLarge(f"{where} has {len(tokens)} characters: {excerpt(tokens)}")
            tokens = tokens.split()
        if not isinstance(tokens, (list, tuple)) or not tokens or not all(isinstance(t, str) for t in tokens):
            listed = tokens if isinstance(tokens, (list, tuple)) else ()
            wrong = [f"{where}[{i}] is {excerpt(t)}" for i, t in enumerate(listed) if not isinstance(t, str)]
            got = f"{wrong[0]}, not a word" if wrong else f"got {excerpt(tokens)}"
            raise MalformedInstruction(f"{where} must be a non-empty list of words; {got}")
        if len(tokens) > MAX_PLACE_WORDS:
            raise InstructionTooLarge(f"{where} has {len(tokens)} words, more than the {MAX_PLACE_WORDS} accepted")
        bad = list(dict.fromkeys(t for t in tokens if t not in self.known))
        if bad:
            raise UnknownPlaceWord(
                f"{where}: unknown place word(s) {', '.join(excerpt(t, 30) for t in bad[:5])}"
                f"{unknown_tail(bad, self.place_words)}"
            )
        return list(tokens)

    def query(self, place: Any, where: str) -> PlaceQuery:
        """A place: words, or ``{"words": ..., "relation": kind, "of": [places]}``."""
        if not isinstance(place, Mapping):
            words = self.words(place, where)
            return PlaceQuery(dict(Counter(words)), " ".join(words))
        extra = sorted(set(place) - {"words", "relation", "of"})
        if extra or "words" not in place:
            raise MalformedInstruction(f"{where} must have 'words' (and 'relation', 'of'), got keys {extra}")
        words = self.words(place["words"], f"{where}.words")
        relation = self.relation(place.get("relation"), place.get("of", []), where)
        return PlaceQuery(dict(Counter(words)), " ".join(words), relation=relation)

    def relation(self, kind: Any, of: Any, where: str) -> Relation | None:
        if kind is None:
            return None
        if kind not in RELATIONS:
            raise MalformedInstruction(f"{where}.relation must be one of {', '.join(RELATIONS)}, got {excerpt(kind)}")
        if not isinstance(of, (list, tuple)) or len(of) != ARITY[kind]:
            raise MalformedInstruction(f"{where}.of must list {ARITY[kind]} place(s) for {kind!r}, got {excerpt(of)}")
        args = tuple(self.words(a, f"{where}.of[{i}]") for i, a in enumerate(of))
        return Relation(kind, tuple(PlaceRef(tuple(a), " ".join(a)) for a in args))


def _speed(value: Any) -> str | None:
    if value is None or value in SPEEDS:
        return value
    raise MalformedInstruction(f"'speed' must be one of {', '.join(SPEEDS)} or null, got {excerpt(value)}")


def _waits(value: Any, stages: int) -> tuple[tuple[int, float | None], ...]:
    """``[[stage, seconds or null], ...]``: stages in range, lengths finite and at most MAX_WAIT_S; only the goal
    may wait until the next instruction."""
    if not isinstance(value, (list, tuple)) or len(value) > stages:
        raise MalformedInstruction(f"'waits' must be a list of [stage, seconds] pairs, got {excerpt(value)}")
    out = []
    for i, pair in enumerate(value):
        ok = isinstance(pair, (list, tuple)) and len(pair) == 2 and type(pair[0]) is int and 0 <= pair[0] < stages
        seconds = pair[1] if ok else None
        if ok and seconds is not None:
            ok = isinstance(seconds, (int, float)) and not isinstance(seconds, bool) and math.isfinite(seconds)
            ok = ok and seconds >= 0
        if not ok:
            raise MalformedInstruction(
                f"waits[{i}] must be [stage 0..{stages - 1}, seconds >= 0 or null], got {excerpt(pair)}"
            )
        if seconds is None and pair[0] != stages - 1:
            raise MalformedInstruction(f"waits[{i}]: only the goal may wait with no length (null)")
        if seconds is not None and seconds > MAX_WAIT_S:
            raise InstructionTooLarge(f"waits[{i}]: {seconds:g} s is longer than the {MAX_WAIT_S:.0f} s accepted")
        out.append((int(pair[0]), None if seconds is None else float(seconds)))
    return tuple(out)


def _json_value(text: str) -> Any:
    """The JSON value of a structured instruction's text (InstructionTooLarge / MalformedInstruction)."""
    if len(text) > MAX_JSON_CHARS:
        raise InstructionTooLarge(
            f"the structured instruction has {len(text)} characters, more than the {MAX_JSON_CHARS} accepted"
        )
    try:
        return json.loads(text)
    except (json.JSONDecodeError, RecursionError) as exc:
        why = exc.msg if isinstance(exc, json.JSONDecodeError) else "nested too deeply"
        raise MalformedInstruction(f"structured instruction is not valid JSON: {why}") from None

"""Instruction understanding: text, structured JSON or an N-best list -> ordered waypoints, goal, places to avoid.

Algorithm 1, line 9 of Taniguchi et al. (2024): the robot extracts the words naming the waypoints and the goal
(Section 3.3: "the waypoint word is input in the first half and the target word in the second half"). Each named
place becomes a weighted bag of words S_e; an N-best list of recogniser hypotheses becomes bags weighted by the
normalised hypothesis scores (Eq. 25). A sentence is read by the declarative grammar of its language
(:mod:`spcotmhp.language.reading`: the places to visit in order, to avoid and not to end in, the relations that
pick one instance of a name, a speed and waits); the place words come from the model
(:func:`spcotmhp.planning.vocabulary.place_vocabulary`); the checks, weights and grouping of an N-best list are
:mod:`spcotmhp.planning.nbest`.

Bounded work (every limit is a keyword argument of the parse functions and of :func:`to_instruction`, defaulting
to the module constants below, which a program may also set): an instruction longer than ``max_chars``
characters (a spoken instruction is one or two sentences; 500 characters is about 80 English words), naming
more than ``max_waypoints`` waypoints or more than ``max_avoided`` places to avoid or not to end in, an N-best
list of more than ``max_hypotheses`` hypotheses, or a structured instruction whose JSON text exceeds
``MAX_JSON_CHARS`` is refused with :class:`~spcotmhp.errors.InstructionTooLarge` before any costly work (the
planner's search grows with the number of stages). Every error is a subclass of
:class:`~spcotmhp.errors.InstructionError` with a one-line message quoting at most a short excerpt of the input.
"""

from __future__ import annotations

import json
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from typing import Any

from spcotmhp.errors import (
    EmptyInstruction,
    InstructionError,
    InstructionTooLarge,
    MalformedInstruction,
    UnknownPlaceWord,
    UnsupportedLanguage,
)
from spcotmhp.language.meaning import PlaceRef, Relation
from spcotmhp.language.reading import LANGUAGES, read
from spcotmhp.language.text import is_japanese
from spcotmhp.language.wording import excerpt, unknown_tail
from spcotmhp.planning.arguments import check_keywords, check_parse_arguments
from spcotmhp.planning.nbest import heaviest_group, nbest_weights

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
    corridors", only to avoid)."""

    words: Mapping[str, float]
    label: str
    alternatives: tuple[Mapping[str, float], ...] = ()
    relation: Relation | None = None
    every: bool = False

    @property
    def phrases(self) -> tuple[Mapping[str, float], ...]:
        """The bags each of which names the place on its own: the alternatives, or the words."""
        return self.alternatives or (self.words,)

    def __post_init__(self) -> None:
        if not self.words:
            raise MalformedInstruction(f"the place {excerpt(self.label)} has no words")

    def describe(self) -> str:
        """E.g. "bedroom (closest to the bath)"."""
        return self.label if self.relation is None else f"{self.label} ({self.relation.describe()})"

    @classmethod
    def of(cls, ref: PlaceRef) -> PlaceQuery:
        """The query of a place as the grammar read it (:class:`~spcotmhp.language.meaning.PlaceRef`)."""
        return cls(dict(Counter(ref.words)), ref.label, relation=ref.relation, every=ref.every)


@dataclass(frozen=True)
class Instruction:
    """An understood instruction: stages are the waypoints in order, then the goal (Eq. 28 uses the bag of the
    stage being pursued at each step); ``avoid`` places get zero probability; ``not_goal`` places may be passed
    but never end the plan ("instead of the kitchen"). ``speed`` ("slow", "fast" or None) and ``waits`` ((stage,
    seconds or None: until the next instruction), ...) are for whoever drives the path: the planner carries them
    in the plan (its JSON, the ROS 2 status) and says them in the explanation; the path is the same."""

    goal: PlaceQuery
    waypoints: tuple[PlaceQuery, ...] = ()
    avoid: tuple[PlaceQuery, ...] = ()
    text: str = ""
    lang: str = "en"
    not_goal: tuple[PlaceQuery, ...] = ()
    speed: str | None = None
    waits: tuple[tuple[int, float | None], ...] = ()

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


def detect_language(text: str) -> str:
    """ "ja" when the text holds kana or kanji (half-width katakana too), else "en"."""
    return "ja" if is_japanese(text) else "en"


def parse_text(
    text: str,
    place_words: Sequence[str],
    lang: str | None = None,
    *,
    max_chars: int | None = None,
    max_waypoints: int | None = None,
    max_avoided: int | None = None,
) -> Instruction:
    """Understand one instruction sentence (the rules of :mod:`spcotmhp.planning.sentence` and
    :mod:`spcotmhp.planning.sequence`); limits default to the module constants.

    Raises:
        EmptyInstruction: empty text, or only places to avoid / not to end in.
        UnknownPlaceWord: no known place word, or an unknown word where a place word is expected (the message
            suggests near misses and lists the known place words).
        UnsupportedPhrase: alternatives ("or"), spatial relations ("next to"), modifiers ("second", "on the
            left"), or a before / after that cannot be honoured.
        MalformedInstruction: a marker with no place after it; the text is not a string.
        InstructionTooLarge: past ``max_chars``, ``max_waypoints`` or ``max_avoided``.
        UnsupportedLanguage: no grammar for ``lang``.

    >>> ins = parse_text("go to the bedroom via the corridor avoiding the kitchen", ["bedroom", "corridor", "kitchen"])
    >>> [q.label for q in ins.stages], [q.label for q in ins.avoid]
    (['corridor', 'bedroom'], ['kitchen'])
    """
    check_parse_arguments(
        "parse_text", place_words, max_chars=max_chars, max_waypoints=max_waypoints, max_avoided=max_avoided
    )
    if not isinstance(text, str):
        raise MalformedInstruction(f"an instruction text must be a string, got {excerpt(text)}")
    limit = MAX_CHARS if max_chars is None else max_chars
    if len(text) > limit:
        raise InstructionTooLarge(
            f"the instruction has {len(text)} characters, more than the {limit} accepted: {excerpt(text)}"
        )
    if not text.strip():
        raise EmptyInstruction("the instruction is empty; say where to go, e.g. 'go to the kitchen'")
    lang = lang or detect_language(text)
    if lang not in LANGUAGES:
        raise UnsupportedLanguage(
            f"no grammar for language {excerpt(lang, 20)}; supported: {', '.join(sorted(LANGUAGES))}"
        )
    if not place_words:
        raise UnknownPlaceWord(f"no known place word in {excerpt(text)}; the model knows no place words")
    reading = read(text, place_words, lang)
    visit = [PlaceQuery.of(r) for r in reading.visit]
    ins = Instruction(
        goal=visit[-1],
        waypoints=tuple(visit[:-1]),
        avoid=tuple(PlaceQuery.of(r) for r in reading.avoid),
        text=text,
        lang=lang,
        not_goal=tuple(PlaceQuery.of(r) for r in reading.not_goal),
        speed=reading.speed,
        waits=reading.waits,
    )
    return _within_limits(ins, max_waypoints, max_avoided)


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


def parse_structured(
    obj: Mapping[str, Any] | str,
    place_words: Sequence[str],
    lang: str = "en",
    *,
    max_waypoints: int | None = None,
    max_avoided: int | None = None,
) -> Instruction:
    """The structured form ``{"goal": [...], "waypoints": [[...], ...], "avoid": [[...], ...]}`` (optionally
    ``"not_goal": [[...], ...]``, places that must not be the goal).

    Each place is a token list, or one string of space-separated tokens (so ``"waypoints": ["corridor",
    "entrance corridor"]`` is two waypoints); every token must be a place word. A JSON string is accepted too.

    Raises:
        MalformedInstruction: not a JSON object of that shape. UnknownPlaceWord: a token is no place word.
        InstructionTooLarge: too long a JSON text, too many places or words.
    """
    check_parse_arguments("parse_structured", place_words, max_waypoints=max_waypoints, max_avoided=max_avoided)
    if isinstance(obj, str):
        obj = _json_value(obj)
    if not isinstance(obj, Mapping):
        raise MalformedInstruction("a structured instruction must be a JSON object with keys goal, waypoints, avoid")
    unknown_keys = [k for k in obj if k not in ("goal", "waypoints", "avoid", "not_goal")]
    if unknown_keys:
        raise MalformedInstruction(
            f"unknown key(s) [{', '.join(excerpt(str(k), 30) for k in unknown_keys[:5])}] in "
            "the structured instruction; accepted: goal, waypoints, avoid, not_goal"
        )
    if "goal" not in obj:
        raise MalformedInstruction("the structured instruction has no 'goal'")
    known = set(place_words)
    limits = {
        "waypoints": _limit(max_waypoints, MAX_WAYPOINTS),
        "avoid": _limit(max_avoided, MAX_AVOIDED),
        "not_goal": _limit(max_avoided, MAX_AVOIDED),
    }

    def query(tokens: Any, where: str) -> PlaceQuery:
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
        bad = list(dict.fromkeys(t for t in tokens if t not in known))
        if bad:
            raise UnknownPlaceWord(
                f"{where}: unknown place word(s) {', '.join(excerpt(t, 30) for t in bad[:5])}"
                f"{unknown_tail(bad, place_words)}"
            )
        return PlaceQuery(dict(Counter(tokens)), " ".join(tokens))

    def queries(key: str) -> tuple[PlaceQuery, ...]:
        value = obj.get(key, [])
        if not isinstance(value, (list, tuple)):
            raise MalformedInstruction(f"'{key}' must be a list of places (each a list of words), got {excerpt(value)}")
        if len(value) > limits[key]:
            raise InstructionTooLarge(f"'{key}' lists {len(value)} places, more than the {limits[key]} accepted")
        return tuple(query(v, f"{key}[{i}]") for i, v in enumerate(value))

    ins = Instruction(
        goal=query(obj["goal"], "goal"),
        waypoints=queries("waypoints"),
        avoid=queries("avoid"),
        text="",
        lang=lang,
        not_goal=queries("not_goal"),
    )
    text = json.dumps(
        {
            "goal": ins.goal.label,
            **{k: [q.label for q in getattr(ins, k)] for k in ("waypoints", "avoid", "not_goal") if obj.get(k)},
        },
        ensure_ascii=False,
    )
    return _within_limits(replace(ins, text=text), max_waypoints, max_avoided)


def parse_nbest(
    hypotheses: Sequence[tuple[str, float]],
    place_words: Sequence[str],
    lang: str | None = None,
    *,
    max_hypotheses: int | None = None,
    **limits: int | None,
) -> Instruction:
    """N-best recogniser hypotheses ``[(text, score), ...]`` -> one instruction with weighted bags (Eq. 25).

    Scores are confidences >= 0 (normalised to sum 1) or, when all are <= 0 and some < 0, log-probabilities
    (soft-maxed). Each hypothesis is parsed (``limits``: the keyword arguments of :func:`parse_text`); those that
    do not parse are dropped. Hypotheses are grouped by shape (number of waypoints, avoided places and excluded
    goals); the group with the largest total weight wins and stage e's bag is sum_h w_h S_{h,e} with the weights
    renormalised in the group.

    Raises:
        EmptyInstruction: an empty list. MalformedInstruction: an entry is not [text, score] or a score not a
        finite number. InstructionTooLarge: more than ``max_hypotheses`` entries. When no hypothesis parses,
        the first hypothesis' error class, with its message.
    """
    check_keywords("parse_nbest", limits, ("max_hypotheses", "max_chars", "max_waypoints", "max_avoided"))
    check_parse_arguments("parse_nbest", place_words, max_hypotheses=max_hypotheses, **limits)
    texts, weights = nbest_weights(hypotheses, _limit(max_hypotheses, MAX_HYPOTHESES))
    parsed: list[tuple[Instruction, float]] = []
    first_error: InstructionError | None = None
    for text, w in zip(texts, weights, strict=False):
        try:
            parsed.append((parse_text(text, place_words, lang, **limits), float(w)))
        except InstructionError as exc:
            first_error = first_error or exc
    if not parsed:
        assert first_error is not None  # every hypothesis failed, and there is at least one
        raise type(first_error)(f"no N-best hypothesis names a known place (first: {first_error})")
    rel = heaviest_group(parsed, _shape)
    top = max(rel, key=lambda p: p[1])[0]

    def merged(role: str, j: int = 0) -> PlaceQuery:
        place = _role_place(top, role, j)
        bag = _merged_place([(_role_place(ins, role, j), w) for ins, w in rel], place.label)
        return replace(bag, relation=place.relation, every=place.every)

    return Instruction(
        goal=merged("goal"),
        waypoints=tuple(merged("waypoints", j) for j in range(len(top.waypoints))),
        avoid=tuple(merged("avoid", j) for j in range(len(top.avoid))),
        text=top.text,
        lang=top.lang,
        not_goal=tuple(merged("not_goal", j) for j in range(len(top.not_goal))),
        speed=top.speed,
        waits=top.waits,
    )


def _shape(ins: Instruction) -> tuple:
    """What hypotheses must share to be merged place by place: how many places of each role, and the relation
    kinds of the places (a relation's places are the top hypothesis's)."""
    kinds = tuple(q.relation.kind if q.relation else "" for q in (*ins.stages, *ins.avoid, *ins.not_goal))
    return len(ins.waypoints), len(ins.avoid), len(ins.not_goal), kinds


def _role_place(ins: Instruction, role: str, j: int) -> PlaceQuery:
    """The goal of ``ins`` (role "goal"), or its j-th waypoint, avoided place or excluded goal."""
    return ins.goal if role == "goal" else getattr(ins, role)[j]


def _merged_place(weighted: Sequence[tuple[PlaceQuery, float]], label: str) -> PlaceQuery:
    """One place named by weighted hypotheses as one query (Eq. 25): the bag sum_h w_h S_h, with each distinct
    hypothesis bag as an alternative (none when they all agree)."""
    bag: dict[str, float] = {}
    for place, w in weighted:
        for word, c in place.words.items():
            bag[word] = bag.get(word, 0) + w * c
    alternatives = tuple(dict.fromkeys(tuple(sorted(place.words.items())) for place, _ in weighted))
    return PlaceQuery(bag, label, tuple(dict(a) for a in alternatives) if len(alternatives) > 1 else ())


def to_instruction(
    source: Any,
    place_words: Sequence[str],
    lang: str | None = None,
    *,
    max_chars: int | None = None,
    max_waypoints: int | None = None,
    max_avoided: int | None = None,
    max_hypotheses: int | None = None,
) -> Instruction:
    """Accept an :class:`Instruction`, a sentence, a structured mapping (or a JSON object string), or an N-best
    list of (text, score) pairs; the limits are those of the parse functions (module docstring)."""
    bounds = {"max_waypoints": max_waypoints, "max_avoided": max_avoided}
    if isinstance(source, Instruction):
        return _within_limits(source, max_waypoints, max_avoided)
    if isinstance(source, Mapping):
        return parse_structured(source, place_words, lang or "en", **bounds)
    if isinstance(source, str):
        if source.lstrip().startswith("{"):
            return parse_structured(source, place_words, lang or "en", **bounds)
        return parse_text(source, place_words, lang, max_chars=max_chars, **bounds)
    if isinstance(source, (list, tuple)):
        return parse_nbest(source, place_words, lang, max_hypotheses=max_hypotheses, max_chars=max_chars, **bounds)
    raise MalformedInstruction(f"cannot understand an instruction of type {type(source).__name__}")


# ---- internals ---------------------------------------------------------------------------------------------
def _limit(value: int | None, default: int) -> int:
    return default if value is None else int(value)


def _within_limits(ins: Instruction, max_waypoints: int | None, max_avoided: int | None) -> Instruction:
    most_ways, most_avoided = _limit(max_waypoints, MAX_WAYPOINTS), _limit(max_avoided, MAX_AVOIDED)
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

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

from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

from spcotmhp.errors import (
    EmptyInstruction,
    InstructionError,
    InstructionTooLarge,
    MalformedInstruction,
    UnknownPlaceWord,
    UnsupportedLanguage,
)
from spcotmhp.language.reading import LANGUAGES, read
from spcotmhp.language.text import is_japanese
from spcotmhp.language.wording import excerpt
from spcotmhp.planning.arguments import check_keywords, check_parse_arguments
from spcotmhp.planning.nbest import heaviest_group, nbest_weights
from spcotmhp.planning.query import (
    MAX_AVOIDED,
    MAX_CHARS,
    MAX_HYPOTHESES,
    MAX_JSON_CHARS,
    MAX_PLACE_WORDS,
    MAX_WAYPOINTS,
    Instruction,
    PlaceQuery,
    limit,
    within_limits,
)
from spcotmhp.planning.structured import parse_structured

__all__ = [
    "MAX_AVOIDED",
    "MAX_CHARS",
    "MAX_HYPOTHESES",
    "MAX_JSON_CHARS",
    "MAX_PLACE_WORDS",
    "MAX_WAYPOINTS",
    "Instruction",
    "PlaceQuery",
    "detect_language",
    "parse_nbest",
    "parse_structured",
    "parse_text",
    "to_instruction",
]


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
    """Understand one instruction sentence into its stages (goal, waypoints in order, places to avoid): read by
    the grammar of its language (:func:`spcotmhp.language.reading.read`), its roles and order by
    :mod:`spcotmhp.language.walk_en` / :mod:`spcotmhp.language.walk_ja`; limits default to the module constants.

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
        heard=reading.heard,
    )
    return within_limits(ins, max_waypoints, max_avoided)


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
    texts, weights = nbest_weights(hypotheses, limit(max_hypotheses, MAX_HYPOTHESES))
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
        return replace(bag, relation=place.relation, every=place.every, floor=place.floor,
                       floor_said=place.floor_said, number=place.number)  # fmt: skip

    return Instruction(
        goal=merged("goal"),
        waypoints=tuple(merged("waypoints", j) for j in range(len(top.waypoints))),
        avoid=tuple(merged("avoid", j) for j in range(len(top.avoid))),
        text=top.text,
        lang=top.lang,
        not_goal=tuple(merged("not_goal", j) for j in range(len(top.not_goal))),
        speed=top.speed,
        waits=top.waits,
        heard=top.heard,
    )


def _shape(ins: Instruction) -> tuple:
    """What hypotheses must share to be merged place by place: how many places of each role, and the relation
    kinds and floors of the places (a relation's places are the top hypothesis's)."""
    kinds = tuple(
        (q.relation.kind if q.relation else "", q.floor, q.number) for q in (*ins.stages, *ins.avoid, *ins.not_goal)
    )
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
        return within_limits(source, max_waypoints, max_avoided)
    if isinstance(source, Mapping):
        return parse_structured(source, place_words, lang or "en", **bounds)
    if isinstance(source, str):
        if source.lstrip().startswith("{"):
            return parse_structured(source, place_words, lang or "en", **bounds)
        return parse_text(source, place_words, lang, max_chars=max_chars, **bounds)
    if isinstance(source, (list, tuple)):
        return parse_nbest(source, place_words, lang, max_hypotheses=max_hypotheses, max_chars=max_chars, **bounds)
    raise MalformedInstruction(f"cannot understand an instruction of type {type(source).__name__}")

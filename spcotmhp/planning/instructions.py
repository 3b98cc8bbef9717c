"""Instruction understanding: text, structured JSON or an N-best list -> ordered waypoints, goal, places to avoid.

Algorithm 1, line 9 of Taniguchi et al. (2024): the robot extracts the words naming the waypoints and the goal
(Section 3.3: "the waypoint word is input in the first half and the target word in the second half"). Each named
place becomes a weighted bag of words S_e; an N-best list of recogniser hypotheses becomes bags weighted by the
normalised hypothesis scores (Eq. 25). The grammar words come from :mod:`spcotmhp.planning.grammar`; the place
words from the model (:func:`spcotmhp.planning.vocabulary.place_vocabulary`).

The sentence grammar (how a text is cut into place phrases and what role each phrase plays, including the errors
for unknown words, alternatives and spatial relations) is :mod:`spcotmhp.planning.sentence`.
"""

from __future__ import annotations

import json
import math
import re
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.special import logsumexp

from spcotmhp.errors import InstructionError
from spcotmhp.planning.grammar import GRAMMARS
from spcotmhp.planning.sentence import Item, known_words, read_sentence

_CJK = re.compile(r"[\u3040-\u30ff\u3400-\u9fff\uff66-\uff9f]")


@dataclass(frozen=True)
class PlaceQuery:
    """One named place of an instruction: a weighted bag of words S (Eq. 25) and a readable label."""

    words: Mapping[str, float]
    label: str

    def __post_init__(self) -> None:
        if not self.words:
            raise InstructionError(f"the place '{self.label}' has no words")


@dataclass(frozen=True)
class Instruction:
    """An understood instruction: stages are the waypoints in order, then the goal (Eq. 28 uses the bag of the
    stage being pursued at each step); ``avoid`` places get zero probability; ``not_goal`` places may be passed
    but never end the plan ("instead of the kitchen")."""

    goal: PlaceQuery
    waypoints: tuple[PlaceQuery, ...] = ()
    avoid: tuple[PlaceQuery, ...] = ()
    text: str = ""
    lang: str = "en"
    not_goal: tuple[PlaceQuery, ...] = ()

    @property
    def stages(self) -> tuple[PlaceQuery, ...]:
        return (*self.waypoints, self.goal)

    def describe(self) -> str:
        """E.g. "bedroom via corridor, avoiding living"."""
        out = self.goal.label
        if self.waypoints:
            out += " via " + ", then ".join(w.label for w in self.waypoints)
        if self.avoid:
            out += ", avoiding " + " and ".join(a.label for a in self.avoid)
        if self.not_goal:
            out += ", instead of " + " and ".join(a.label for a in self.not_goal)
        return out


def detect_language(text: str) -> str:
    """"ja" when the text holds kana or kanji, else "en"."""
    return "ja" if _CJK.search(text) else "en"


def parse_text(text: str, place_words: Sequence[str], lang: str | None = None) -> Instruction:
    """Understand one instruction sentence (the rules of :mod:`spcotmhp.planning.sentence`).

    Raises:
        InstructionError: empty text, no known place word, an unknown word where a place word is expected, a
            dangling marker, alternatives ("or"), a spatial relation ("next to"), or only places to avoid; the
            message lists the known place words.
    """
    if not isinstance(text, str) or not text.strip():
        raise InstructionError("the instruction is empty; say where to go, e.g. 'go to the kitchen'")
    lang = lang or detect_language(text)
    if lang not in GRAMMARS:
        raise InstructionError(f"no grammar for language {lang!r}; supported: {', '.join(sorted(GRAMMARS))}")
    return _build(read_sentence(text, GRAMMARS[lang], place_words), text, lang, place_words)


def parse_structured(obj: Mapping[str, Any] | str, place_words: Sequence[str], lang: str = "en") -> Instruction:
    """The structured form ``{"goal": [...], "waypoints": [[...], ...], "avoid": [[...], ...]}`` (optionally
    ``"not_goal": [[...], ...]``, places that must not be the goal).

    Each place is a token list, or one string of space-separated tokens (so ``"waypoints": ["corridor",
    "entrance corridor"]`` is two waypoints); every token must be a place word. A JSON string is accepted too.
    """
    if isinstance(obj, str):
        try:
            obj = json.loads(obj)
        except json.JSONDecodeError as exc:
            raise InstructionError(f"structured instruction is not valid JSON: {exc}") from None
    if not isinstance(obj, Mapping):
        raise InstructionError("a structured instruction must be a JSON object with keys goal, waypoints, avoid")
    unknown_keys = set(obj) - {"goal", "waypoints", "avoid", "not_goal"}
    if unknown_keys:
        raise InstructionError(f"unknown key(s) {sorted(unknown_keys)} in the structured instruction; "
                               "accepted: goal, waypoints, avoid, not_goal")
    if "goal" not in obj:
        raise InstructionError("the structured instruction has no 'goal'")
    known = set(place_words)

    def query(tokens: Any, where: str) -> PlaceQuery:
        if isinstance(tokens, str):
            tokens = tokens.split()
        if not isinstance(tokens, (list, tuple)) or not tokens or not all(isinstance(t, str) for t in tokens):
            raise InstructionError(f"{where} must be a non-empty list of words, got {tokens!r}")
        bad = [t for t in tokens if t not in known]
        if bad:
            raise InstructionError(f"{where}: unknown place word(s) {', '.join(map(repr, bad))}; "
                                   f"{known_words(place_words)}")
        return PlaceQuery(dict(Counter(tokens)), " ".join(tokens))

    def queries(key: str) -> tuple[PlaceQuery, ...]:
        value = obj.get(key, [])
        if not isinstance(value, (list, tuple)):
            raise InstructionError(f"'{key}' must be a list of places (each a list of words), got {value!r}")
        return tuple(query(v, f"{key}[{i}]") for i, v in enumerate(value))

    return Instruction(goal=query(obj["goal"], "goal"), waypoints=queries("waypoints"), avoid=queries("avoid"),
                       text=json.dumps(obj, ensure_ascii=False), lang=lang, not_goal=queries("not_goal"))


def parse_nbest(hypotheses: Sequence[tuple[str, float]], place_words: Sequence[str],
                lang: str | None = None) -> Instruction:
    """N-best recogniser hypotheses ``[(text, score), ...]`` -> one instruction with weighted bags (Eq. 25).

    Scores are confidences >= 0 (normalised to sum 1) or, when all are <= 0 and some < 0, log-probabilities
    (soft-maxed). Each hypothesis is parsed; those that do not parse are dropped. Hypotheses are grouped by shape
    (number of waypoints, avoided places and excluded goals); the group with the largest total weight wins and stage e's bag is
    sum_h w_h S_{h,e} with the weights renormalised in the group.
    """
    if not hypotheses:
        raise InstructionError("the N-best list is empty")
    texts, scores = [], []
    for i, h in enumerate(hypotheses):
        if not isinstance(h, (list, tuple)) or len(h) != 2 or not isinstance(h[0], str):
            raise InstructionError(f"N-best entry {i} must be [text, score], got {h!r}")
        try:
            s = float(h[1])
        except (TypeError, ValueError):
            raise InstructionError(f"N-best entry {i} has a non-numeric score {h[1]!r}") from None
        if not math.isfinite(s):
            raise InstructionError(f"N-best entry {i} has a non-finite score {h[1]!r}")
        texts.append(h[0])
        scores.append(s)
    weights = _normalise_scores(np.array(scores))
    parsed, first_error = [], None
    for text, w in zip(texts, weights):
        try:
            parsed.append((parse_text(text, place_words, lang), float(w)))
        except InstructionError as exc:
            first_error = first_error or exc
    if not parsed:
        raise InstructionError(f"no N-best hypothesis names a known place (first: {first_error})")
    groups: dict[tuple[int, int, int], list[tuple[Instruction, float]]] = {}
    for ins, w in parsed:
        groups.setdefault((len(ins.waypoints), len(ins.avoid), len(ins.not_goal)), []).append((ins, w))
    group = max(groups.values(), key=lambda g: (sum(w for _, w in g), -len(g)))
    total = sum(w for _, w in group)
    rel = [(ins, w / total if total > 0 else 1.0 / len(group)) for ins, w in group]
    top = max(rel, key=lambda p: p[1])[0]

    def combine(pick) -> PlaceQuery:
        bag: Counter = Counter()
        for ins, w in rel:
            for word, c in pick(ins).words.items():
                bag[word] += w * c
        return PlaceQuery(dict(bag), pick(top).label)

    return Instruction(
        goal=combine(lambda i: i.goal),
        waypoints=tuple(combine(lambda i, j=j: i.waypoints[j]) for j in range(len(top.waypoints))),
        avoid=tuple(combine(lambda i, j=j: i.avoid[j]) for j in range(len(top.avoid))),
        text=top.text, lang=top.lang,
        not_goal=tuple(combine(lambda i, j=j: i.not_goal[j]) for j in range(len(top.not_goal))))


def to_instruction(source: Any, place_words: Sequence[str], lang: str | None = None) -> Instruction:
    """Accept an :class:`Instruction`, a sentence, a structured mapping (or a JSON object string), or an N-best
    list of (text, score) pairs."""
    if isinstance(source, Instruction):
        return source
    if isinstance(source, Mapping):
        return parse_structured(source, place_words, lang or "en")
    if isinstance(source, str):
        if source.lstrip().startswith("{"):
            return parse_structured(source, place_words, lang or "en")
        return parse_text(source, place_words, lang)
    if isinstance(source, (list, tuple)):
        return parse_nbest(source, place_words, lang)
    raise InstructionError(f"cannot understand an instruction of type {type(source).__name__}")


# ---- internals ---------------------------------------------------------------------------------------------
def _build(phrases: list[tuple[Item, str]], text: str, lang: str, place_words) -> Instruction:
    """Rules 4-5 of :mod:`spcotmhp.planning.sentence`: the instruction from the place phrases and their roles."""
    def query(it: Item) -> PlaceQuery:
        return PlaceQuery(dict(Counter(it.words)), it.surface)

    kept = [(it, r) for it, r in phrases if r != "from"]
    goals = [i for i, (_, r) in enumerate(kept) if r == "goal"]
    if not goals:
        ways = [i for i, (_, r) in enumerate(kept) if r == "waypoint"]
        if not ways:
            raise InstructionError(f"{text!r} names no place to go to, only places to avoid, not to end in or "
                                   f"to start from; {known_words(place_words)}")
        goals = [ways[-1]]
    goal = goals[-1]
    waypoints = tuple(query(it) for i, (it, r) in enumerate(kept)
                      if i != goal and (r == "waypoint" or r == "goal"))
    avoid = tuple(query(it) for it, r in kept if r == "avoid")
    not_goal = tuple(query(it) for it, r in kept if r == "not_goal")
    return Instruction(goal=query(kept[goal][0]), waypoints=waypoints, avoid=avoid, text=text, lang=lang,
                       not_goal=not_goal)


def _normalise_scores(scores: np.ndarray) -> np.ndarray:
    if (scores >= 0).all():
        total = scores.sum()
        return scores / total if total > 0 else np.full(len(scores), 1.0 / len(scores))
    if (scores <= 0).all():
        return np.exp(scores - logsumexp(scores))
    raise InstructionError("N-best scores must be all >= 0 (confidences) or all <= 0 (log-probabilities), "
                           f"got {scores.tolist()}")

"""Instruction understanding: text, structured JSON or an N-best list -> ordered waypoints, goal, places to avoid.

Algorithm 1, line 9 of Taniguchi et al. (2024): the robot extracts the words naming the waypoints and the goal
(Section 3.3: "the waypoint word is input in the first half and the target word in the second half"). Each named
place becomes a weighted bag of words S_e; an N-best list of recogniser hypotheses becomes bags weighted by the
normalised hypothesis scores (Eq. 25). The grammar words come from :mod:`spcotmhp.planning.grammar`; the place
words from the model (:func:`spcotmhp.planning.vocabulary.place_vocabulary`).

Parse rules (documented behaviour, tested):
1. The text is cut into place phrases (maximal runs of adjacent place words, so multi-word names such as
   "entrance corridor" form one phrase), grammar markers, connectors and other words.
2. A phrase takes the role of its marker (English: the last marker before it; Japanese: the first marker after
   it). A phrase with only a connector takes its neighbour's role (English: the previous phrase's; Japanese:
   the next phrase's). A phrase with no marker at all is a goal.
3. Waypoints are kept in the order spoken. If several phrases are goals ("go to the toilet and then to the
   kitchen"), the last one is the goal and the earlier ones become waypoints at their place in the sentence;
   if none is ("through the corridor and then the bedroom"), the last waypoint is the goal.
4. "from" phrases are dropped (the start is the pose given to the planner).
5. A waypoint or avoid marker with no place word (e.g. "via the garage" with "garage" not learned) is an error
   that names the words not understood and lists the known place words.
"""

from __future__ import annotations

import json
import math
import re
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.special import logsumexp

from spcotmhp.errors import InstructionError
from spcotmhp.planning.grammar import GRAMMARS, Grammar

_EN_UNIT = re.compile(r"[^\W_]+(?:['\u2019][^\W_]+)*|[,;&]")
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
    stage being pursued at each step); ``avoid`` places get zero probability."""

    goal: PlaceQuery
    waypoints: tuple[PlaceQuery, ...] = ()
    avoid: tuple[PlaceQuery, ...] = ()
    text: str = ""
    lang: str = "en"

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
        return out


@dataclass
class _Item:
    kind: str          # "place", "marker", "connector", "filler", "other"
    value: str         # the place word / the role / ""
    surface: str
    words: list[str] = field(default_factory=list)  # place words of a merged phrase


def detect_language(text: str) -> str:
    """"ja" when the text holds kana or kanji, else "en"."""
    return "ja" if _CJK.search(text) else "en"


def parse_text(text: str, place_words: Sequence[str], lang: str | None = None) -> Instruction:
    """Understand one instruction sentence (rules in the module docstring).

    Raises:
        InstructionError: empty text, no known place word, a dangling "via"/"avoiding" marker, or only places
            to avoid; the message lists the known place words.
    """
    if not isinstance(text, str) or not text.strip():
        raise InstructionError("the instruction is empty; say where to go, e.g. 'go to the kitchen'")
    lang = lang or detect_language(text)
    if lang not in GRAMMARS:
        raise InstructionError(f"no grammar for language {lang!r}; supported: {', '.join(sorted(GRAMMARS))}")
    grammar = GRAMMARS[lang]
    items = _merge_phrases(_scan(text, grammar, place_words), grammar)
    phrases = [it for it in items if it.kind == "place"]
    if not phrases:
        raise InstructionError(f"no known place word in {text!r}{_not_understood(items)}; "
                               f"{_known(place_words)}")
    roles = _assign_roles(items, grammar, place_words)
    return _build(phrases, roles, text, lang, place_words)


def parse_structured(obj: Mapping[str, Any] | str, place_words: Sequence[str], lang: str = "en") -> Instruction:
    """The structured form ``{"goal": [...], "waypoints": [[...], ...], "avoid": [[...], ...]}``.

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
    unknown_keys = set(obj) - {"goal", "waypoints", "avoid"}
    if unknown_keys:
        raise InstructionError(f"unknown key(s) {sorted(unknown_keys)} in the structured instruction; "
                               "accepted: goal, waypoints, avoid")
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
                                   f"{_known(place_words)}")
        return PlaceQuery(dict(Counter(tokens)), " ".join(tokens))

    def queries(key: str) -> tuple[PlaceQuery, ...]:
        value = obj.get(key, [])
        if not isinstance(value, (list, tuple)):
            raise InstructionError(f"'{key}' must be a list of places (each a list of words), got {value!r}")
        return tuple(query(v, f"{key}[{i}]") for i, v in enumerate(value))

    return Instruction(goal=query(obj["goal"], "goal"), waypoints=queries("waypoints"), avoid=queries("avoid"),
                       text=json.dumps(obj, ensure_ascii=False), lang=lang)


def parse_nbest(hypotheses: Sequence[tuple[str, float]], place_words: Sequence[str],
                lang: str | None = None) -> Instruction:
    """N-best recogniser hypotheses ``[(text, score), ...]`` -> one instruction with weighted bags (Eq. 25).

    Scores are confidences >= 0 (normalised to sum 1) or, when all are <= 0 and some < 0, log-probabilities
    (soft-maxed). Each hypothesis is parsed; those that do not parse are dropped. Hypotheses are grouped by shape
    (number of waypoints and avoided places); the group with the largest total weight wins and stage e's bag is
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
    groups: dict[tuple[int, int], list[tuple[Instruction, float]]] = {}
    for ins, w in parsed:
        groups.setdefault((len(ins.waypoints), len(ins.avoid)), []).append((ins, w))
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

    n_way, n_avoid = len(top.waypoints), len(top.avoid)
    return Instruction(
        goal=combine(lambda i: i.goal),
        waypoints=tuple(combine(lambda i, j=j: i.waypoints[j]) for j in range(n_way)),
        avoid=tuple(combine(lambda i, j=j: i.avoid[j]) for j in range(n_avoid)),
        text=top.text, lang=top.lang)


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
def _units(text: str, grammar: Grammar) -> list[str]:
    if grammar.by_character:
        return [ch for ch in text if not ch.isspace()]
    return _EN_UNIT.findall(text.lower())


_LEXICONS: dict = {}


def _lexicon(grammar: Grammar, place_words: Sequence[str]) -> tuple[dict, dict, int]:
    """(place lexicon, grammar lexicon, longest entry) keyed by unit tuples; memoised per language and
    vocabulary."""
    memo_key = (grammar.lang, tuple(place_words))
    if memo_key not in _LEXICONS:
        if len(_LEXICONS) > 32:
            _LEXICONS.clear()
        _LEXICONS[memo_key] = _build_lexicon(grammar, place_words)
    return _LEXICONS[memo_key]


def _build_lexicon(grammar: Grammar, place_words: Sequence[str]) -> tuple[dict, dict, int]:
    def key(phrase: str) -> tuple[str, ...]:
        return tuple(_units(phrase, grammar))

    grammar_lex = {key(p): ("marker", role) for p, role in grammar.markers.items()}
    grammar_lex.update({key(p): ("connector", "") for p in grammar.connectors})
    place_lex = {key(w): ("place", w) for w in place_words if key(w)}
    return place_lex, grammar_lex, max(map(len, [*place_lex, *grammar_lex]), default=1)


def _scan(text: str, grammar: Grammar, place_words: Sequence[str]) -> list[_Item]:
    """Longest-match segmentation into places, markers, connectors and other units (places win ties)."""
    units = _units(text, grammar)
    place_lex, grammar_lex, longest = _lexicon(grammar, place_words)
    joiner = "" if grammar.by_character else " "
    items: list[_Item] = []
    i = 0
    while i < len(units):
        for n in range(min(longest, len(units) - i), 0, -1):
            k = tuple(units[i:i + n])
            hit = place_lex.get(k) or grammar_lex.get(k)
            if hit:
                items.append(_Item(hit[0], hit[1], joiner.join(k), [hit[1]] if hit[0] == "place" else []))
                i += n
                break
        else:
            if grammar.by_character and items and items[-1].kind == "other":
                items[-1].surface += units[i]
            else:
                kind = "filler" if units[i] in grammar.fillers else "other"
                items.append(_Item(kind, "", units[i]))
            i += 1
    return items


def _merge_phrases(items: list[_Item], grammar: Grammar) -> list[_Item]:
    """Adjacent place words form one phrase (a multi-word name)."""
    out: list[_Item] = []
    joiner = "" if grammar.by_character else " "
    for it in items:
        if it.kind == "place" and out and out[-1].kind == "place":
            out[-1].words.extend(it.words)
            out[-1].surface += joiner + it.surface
        else:
            out.append(it)
    return out


def _assign_roles(items: list[_Item], grammar: Grammar, place_words: Sequence[str]) -> list[str]:
    """One role per place phrase (module docstring, rule 2)."""
    roles: list[str] = []
    if grammar.attach == "prefix":
        role, dangling = None, None
        for idx, it in enumerate(items):
            if it.kind == "marker":
                _check_dangling(dangling, items, idx, place_words, "followed by")
                role, dangling = it.value, (idx if it.value in ("waypoint", "avoid") else None)
            elif it.kind == "place":
                roles.append(role or "goal")
                dangling = None
        _check_dangling(dangling, items, len(items), place_words, "followed by")
        return roles
    # postfix: the first marker after a phrase decides; connectors defer to the next phrase
    pending: list[int] = []  # phrase indices waiting for a role
    since_phrase = True      # no marker yet after the last phrase
    for idx, it in enumerate(items):
        if it.kind == "place":
            roles.append("")
            pending.append(len(roles) - 1)
            since_phrase = True
        elif it.kind == "marker":
            if pending and since_phrase:
                for p in pending:
                    roles[p] = it.value
                pending = []
            elif it.value in ("waypoint", "avoid"):
                last = max((j for j in range(idx) if items[j].kind in ("place", "marker")), default=-1)
                between = [x.surface for x in items[last + 1:idx] if x.kind == "other"]
                raise InstructionError(f"'{it.surface}' follows no known place word"
                                       f"{_not_understood_words(between)}; {_known(place_words)}")
            since_phrase = False
    for p in pending:
        roles[p] = "goal"
    return roles


def _check_dangling(dangling: int | None, items: list[_Item], end: int, place_words, how: str) -> None:
    if dangling is None:
        return
    between = [x.surface for x in items[dangling + 1:end] if x.kind == "other"]
    raise InstructionError(f"'{items[dangling].surface}' is {how} no known place word"
                           f"{_not_understood_words(between)}; {_known(place_words)}")


def _build(phrases: list[_Item], roles: list[str], text: str, lang: str, place_words) -> Instruction:
    def query(it: _Item) -> PlaceQuery:
        return PlaceQuery(dict(Counter(it.words)), it.surface)

    kept = [(it, r) for it, r in zip(phrases, roles) if r != "from"]
    goals = [i for i, (_, r) in enumerate(kept) if r == "goal"]
    if not goals:
        ways = [i for i, (_, r) in enumerate(kept) if r == "waypoint"]
        if not ways:
            raise InstructionError(f"{text!r} names no place to go to, only places to avoid or to start from; "
                                   f"{_known(place_words)}")
        goals = [ways[-1]]
    goal = goals[-1]
    waypoints = tuple(query(it) for i, (it, r) in enumerate(kept)
                      if i != goal and (r == "waypoint" or r == "goal"))
    avoid = tuple(query(it) for it, r in kept if r == "avoid")
    return Instruction(goal=query(kept[goal][0]), waypoints=waypoints, avoid=avoid, text=text, lang=lang)


def _normalise_scores(scores: np.ndarray) -> np.ndarray:
    if (scores >= 0).all():
        total = scores.sum()
        return scores / total if total > 0 else np.full(len(scores), 1.0 / len(scores))
    if (scores <= 0).all():
        return np.exp(scores - logsumexp(scores))
    raise InstructionError("N-best scores must be all >= 0 (confidences) or all <= 0 (log-probabilities), "
                           f"got {scores.tolist()}")


def _not_understood(items: list[_Item]) -> str:
    return _not_understood_words([it.surface for it in items if it.kind == "other"])


def _not_understood_words(words: list[str]) -> str:
    return f" (not understood: {', '.join(words)})" if words else ""


def _known(place_words: Sequence[str]) -> str:
    words = sorted(set(place_words))
    if not words:
        return "the model knows no place words"
    shown = ", ".join(words[:60]) + (f", ... ({len(words)} in all)" if len(words) > 60 else "")
    return f"known place words: {shown}"

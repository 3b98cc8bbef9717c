"""Instruction understanding: text, structured JSON or an N-best list -> ordered waypoints, goal, places to avoid.

Algorithm 1, line 9 of Taniguchi et al. (2024): the robot extracts the words naming the waypoints and the goal
(Section 3.3: "the waypoint word is input in the first half and the target word in the second half"). Each named
place becomes a weighted bag of words S_e; an N-best list of recogniser hypotheses becomes bags weighted by the
normalised hypothesis scores (Eq. 25). The grammar words come from :mod:`spcotmhp.planning.grammar`; the place
words from the model (:func:`spcotmhp.planning.vocabulary.place_vocabulary`).

Parse rules (documented behaviour, tested):
1. The text is cut into place phrases (maximal runs of adjacent place words, so multi-word names such as
   "entrance corridor" form one phrase; in Japanese also two names joined by a lone の, 玄関の廊下), grammar
   markers, connectors, alternatives, relations, fillers and other words.
2. Refused outright, with an error saying why: an alternative ("or", または, a lone か between two places: the
   choice is the user's to make) and a spatial relation ("next to", の隣: not modelled).
3. A phrase takes the role of its marker (English: the last marker before it; Japanese: the first marker after
   it). A phrase with only a connector takes its neighbour's role (English: the previous phrase's; Japanese:
   the next phrase's). A phrase with no marker at all is a goal. A negation ("don't", "never", "instead of")
   followed, through fillers only, by another marker keeps its own role: "I don't want to go to the kitchen"
   avoids the kitchen.
4. Waypoints are kept in the order spoken. If several phrases are goals ("go to the toilet and then to the
   kitchen"), the last one is the goal and the earlier ones become waypoints at their place in the sentence;
   if none is ("through the corridor and then the bedroom"), the last waypoint is the goal. "not_goal" phrases
   ("instead of the kitchen") may be passed but are never the goal.
5. "from" phrases are dropped (the start is the pose given to the planner).
6. Words where a place word is expected must be place words: other words (not place words, grammar words or
   fillers) between a goal / waypoint / avoid / not_goal marker or a connector and the next grammar word or the
   end of the sentence, with no place word there (English "go to the garage via the kitchen", "go to the kitchen
   and the attic"), or between the previous grammar word and such a marker (Japanese ガレージへ行って), are an
   error naming them and listing the known place words. Not counted: words between a marker and its place
   ("go to the big kitchen", 寝室のほうへ), words after a marker that the next marker of the same role takes
   over ("want to quickly go to"; 寝室に早く行って), and words after a punctuation connector unless they follow
   a determiner ("go to the kitchen, thanks" is fine; "go to the kitchen, the attic" is not). In Japanese two
   place phrases must be joined by a connector (と, や) or belong to different markers.
7. A waypoint, avoid or not_goal marker with no place word (e.g. "via the garage" with "garage" not learned), or
   a goal marker ending the sentence, is an error that names the words not understood and lists the known
   place words.
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


@dataclass
class _Item:
    kind: str          # "place", "marker", "connector", "alternative", "relation", "filler", "other"
    value: str         # the place word / the role / ""
    surface: str
    words: list[str] = field(default_factory=list)  # place words of a merged phrase


def detect_language(text: str) -> str:
    """"ja" when the text holds kana or kanji, else "en"."""
    return "ja" if _CJK.search(text) else "en"


def parse_text(text: str, place_words: Sequence[str], lang: str | None = None) -> Instruction:
    """Understand one instruction sentence (rules in the module docstring).

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
    grammar = GRAMMARS[lang]
    items = _merge_phrases(_scan(text, grammar, place_words), grammar)
    _refuse(items, grammar, place_words)
    phrases = [it for it in items if it.kind == "place"]
    if not phrases:
        raise InstructionError(f"no known place word in {text!r}{_not_understood(items)}; "
                               f"{_known(place_words)}")
    _check_place_positions(items, grammar, place_words)
    roles = _assign_roles(items, grammar, place_words)
    return _build(phrases, roles, text, lang, place_words)


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
                                   f"{_known(place_words)}")
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
    grammar_lex.update({key(p): ("alternative", "") for p in grammar.alternatives})
    grammar_lex.update({key(p): ("relation", "") for p in grammar.relations})
    place_lex = {key(w): ("place", w) for w in place_words if key(w)}
    return place_lex, grammar_lex, max(map(len, [*place_lex, *grammar_lex]), default=1)


def _scan(text: str, grammar: Grammar, place_words: Sequence[str]) -> list[_Item]:
    """Longest-match segmentation into places, grammar phrases and other units (places win ties)."""
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
    """Adjacent place words form one phrase (a multi-word name); a word of ``grammar.between_places`` standing
    alone between two phrases joins them or marks an alternative."""
    out: list[_Item] = []
    joiner = "" if grammar.by_character else " "
    for it in items:
        if it.kind == "place" and out and out[-1].kind == "place":
            out[-1].words.extend(it.words)
            out[-1].surface += joiner + it.surface
            continue
        if (it.kind == "place" and len(out) >= 2 and out[-2].kind == "place" and out[-1].kind == "other"
                and out[-1].surface in grammar.between_places):
            if grammar.between_places[out[-1].surface] == "join":
                between = out.pop()
                out[-1].words.extend(it.words)
                out[-1].surface += between.surface + it.surface
                continue
            out[-1].kind = "alternative"
        out.append(it)
    return out


_ANCHORS = ("place", "marker", "connector", "alternative", "relation")


def _neighbour_place(items: list[_Item], idx: int, step: int) -> _Item | None:
    """The place phrase next to ``items[idx]`` in direction ``step`` with only fillers/other words between."""
    j = idx + step
    while 0 <= j < len(items) and items[j].kind in ("filler", "other"):
        j += step
    return items[j] if 0 <= j < len(items) and items[j].kind == "place" else None


def _refuse(items: list[_Item], grammar: Grammar, place_words: Sequence[str]) -> None:
    """Rule 2: alternatives and spatial relations are errors, not guesses."""
    for idx, it in enumerate(items):
        if it.kind == "alternative":
            around = [p.surface for p in (_neighbour_place(items, idx, -1), _neighbour_place(items, idx, 1)) if p]
            choice = f" ({' or '.join(around)})" if around else ""
            raise InstructionError(f"'{it.surface}' leaves the choice of a place open{choice}; the planner needs "
                                   "one place for each waypoint and one goal: say which one")
        if it.kind == "relation":
            step = 1 if grammar.attach == "prefix" else -1
            other = _neighbour_place(items, idx, step)
            what = f" ({other.surface})" if other else ""
            raise InstructionError(f"'{it.surface}' describes a place by where it lies relative to another"
                                   f"{what}; the map does not model spatial relations between places: name the "
                                   f"place itself; {_known(place_words)}")


def _expects_place(it: _Item) -> bool:
    return (it.kind == "marker" and it.value != "from") or it.kind == "connector"


def _check_place_positions(items: list[_Item], grammar: Grammar, place_words: Sequence[str]) -> None:
    """Rule 6: other words where a place word is expected are an error naming them."""
    anchors = [i for i, it in enumerate(items) if it.kind in _ANCHORS]
    prefix = grammar.attach == "prefix"
    for a, idx in enumerate(anchors):
        it = items[idx]
        if not _expects_place(it):
            continue
        if prefix:
            end = anchors[a + 1] if a + 1 < len(anchors) else len(items)
            run, neighbour = items[idx + 1:end], (items[end] if end < len(items) else None)
        else:
            begin = anchors[a - 1] if a > 0 else -1
            run, neighbour = items[begin + 1:idx], (items[begin] if begin >= 0 else None)
        if neighbour is not None and neighbour.kind == "place":
            continue       # a marker and its place, words between being modifiers
        if (it.kind == "marker" and neighbour is not None and neighbour.kind == "marker"
                and neighbour.value == it.value):
            continue       # taken over by the next (English) / previous (Japanese) marker of the same role
        if it.kind == "connector" and it.surface in grammar.soft_connectors:
            first = next((k for k, x in enumerate(run) if x.kind == "other"), None)
            if first is None or not any(x.surface in grammar.determiners for x in run[:first]):
                continue
        others = [x.surface for x in run if x.kind == "other"]
        if others:
            where = "after" if prefix else "before"
            words = ", ".join(f"'{w}'" for w in others)
            verb = "is not a known place word" if len(others) == 1 else "are not known place words"
            raise InstructionError(f"{words} ({where} '{it.surface}') {verb}; {_known(place_words)}")


def _assign_roles(items: list[_Item], grammar: Grammar, place_words: Sequence[str]) -> list[str]:
    """One role per place phrase (module docstring, rules 3 and 7)."""
    if grammar.attach == "prefix":
        return _prefix_roles(items, place_words)
    return _postfix_roles(items, place_words)


def _prefix_roles(items: list[_Item], place_words: Sequence[str]) -> list[str]:
    roles: list[str] = []
    role, dangling = None, None
    for idx, it in enumerate(items):
        if it.kind == "marker":
            if dangling is not None:
                d = items[dangling]
                only_fillers = all(x.kind == "filler" or (x.kind == "marker" and x.value != "from")
                                   for x in items[dangling + 1:idx])
                if d.value in ("avoid", "not_goal") and it.value != "from" and only_fillers:
                    continue   # a negation governs the marker after it ("don't want to go to the kitchen")
                if d.value != "goal":
                    _check_dangling(dangling, items, idx, place_words, "followed by")
            role, dangling = it.value, (idx if it.value != "from" else None)
        elif it.kind == "place":
            roles.append(role or "goal")
            dangling = None
    _check_dangling(dangling, items, len(items), place_words, "followed by")
    return roles


def _postfix_roles(items: list[_Item], place_words: Sequence[str]) -> list[str]:
    """The first marker after a phrase decides; connectors defer to the next phrase."""
    roles: list[str] = []
    pending: list[int] = []  # phrase indices waiting for a role
    since_phrase = True      # no marker yet after the last phrase
    last_place = -1
    for idx, it in enumerate(items):
        if it.kind == "place":
            if pending and not any(x.kind == "connector" for x in items[last_place + 1:idx]):
                between = [x.surface for x in items[last_place + 1:idx] if x.kind == "other"]
                raise InstructionError(f"'{items[last_place].surface}' and '{it.surface}' are not joined by a "
                                       f"connector or a marker{_not_understood_words(between)}; join places with "
                                       f"と or give each its own marker")
            roles.append("")
            pending.append(len(roles) - 1)
            since_phrase = True
            last_place = idx
        elif it.kind == "marker":
            if pending and since_phrase:
                for p in pending:
                    roles[p] = it.value
                pending = []
            elif it.value in ("waypoint", "avoid", "not_goal"):
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
            raise InstructionError(f"{text!r} names no place to go to, only places to avoid, not to end in or "
                                   f"to start from; {_known(place_words)}")
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

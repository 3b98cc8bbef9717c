"""The sentence grammar of instructions: a text -> place phrases, each with its role (goal, waypoint, avoid,
not_goal, from), or an :class:`~spcotmhp.errors.InstructionError` saying what was not understood.

The grammar words of each language are tables in :mod:`spcotmhp.planning.grammar`; the place words are the
model's. :func:`spcotmhp.planning.instructions.parse_text` turns the phrases into an instruction (rules 4-5).

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

import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from spcotmhp.errors import InstructionError
from spcotmhp.planning.grammar import Grammar

_EN_UNIT = re.compile(r"[^\W_]+(?:['\u2019][^\W_]+)*|[,;&]")


@dataclass
class Item:
    """A unit of a scanned sentence: a place phrase (its place words), a grammar phrase or another word."""

    kind: str          # "place", "marker", "connector", "alternative", "relation", "filler", "other"
    value: str         # the place word / the role / ""
    surface: str
    words: list[str] = field(default_factory=list)  # place words of a merged phrase


def read_sentence(text: str, grammar: Grammar, place_words: Sequence[str]) -> list[tuple[Item, str]]:
    """The place phrases of ``text`` in order, each with its role (rules 1-3, 6-7).

    Raises:
        InstructionError: no known place word, an unknown word where a place word is expected, a dangling
            marker, an alternative or a spatial relation; the message lists the known place words.
    """
    items = _merge_phrases(_scan(text, grammar, place_words), grammar)
    _refuse(items, grammar, place_words)
    phrases = [it for it in items if it.kind == "place"]
    if not phrases:
        raise InstructionError(f"no known place word in {text!r}{_not_understood(items)}; "
                               f"{known_words(place_words)}")
    _check_place_positions(items, grammar, place_words)
    return list(zip(phrases, _assign_roles(items, grammar, place_words)))


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


def _scan(text: str, grammar: Grammar, place_words: Sequence[str]) -> list[Item]:
    """Longest-match segmentation into places, grammar phrases and other units (places win ties)."""
    units = _units(text, grammar)
    place_lex, grammar_lex, longest = _lexicon(grammar, place_words)
    joiner = "" if grammar.by_character else " "
    items: list[Item] = []
    i = 0
    while i < len(units):
        for n in range(min(longest, len(units) - i), 0, -1):
            k = tuple(units[i:i + n])
            hit = place_lex.get(k) or grammar_lex.get(k)
            if hit:
                items.append(Item(hit[0], hit[1], joiner.join(k), [hit[1]] if hit[0] == "place" else []))
                i += n
                break
        else:
            if grammar.by_character and items and items[-1].kind == "other":
                items[-1].surface += units[i]
            else:
                kind = "filler" if units[i] in grammar.fillers else "other"
                items.append(Item(kind, "", units[i]))
            i += 1
    return items


def _merge_phrases(items: list[Item], grammar: Grammar) -> list[Item]:
    """Adjacent place words form one phrase (a multi-word name); a word of ``grammar.between_places`` standing
    alone between two phrases joins them or marks an alternative."""
    out: list[Item] = []
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


def _neighbour_place(items: list[Item], idx: int, step: int) -> Item | None:
    """The place phrase next to ``items[idx]`` in direction ``step`` with only fillers/other words between."""
    j = idx + step
    while 0 <= j < len(items) and items[j].kind in ("filler", "other"):
        j += step
    return items[j] if 0 <= j < len(items) and items[j].kind == "place" else None


def _refuse(items: list[Item], grammar: Grammar, place_words: Sequence[str]) -> None:
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
                                   f"place itself; {known_words(place_words)}")


def _expects_place(it: Item) -> bool:
    return (it.kind == "marker" and it.value != "from") or it.kind == "connector"


def _check_place_positions(items: list[Item], grammar: Grammar, place_words: Sequence[str]) -> None:
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
            raise InstructionError(f"{words} ({where} '{it.surface}') {verb}; {known_words(place_words)}")


def _assign_roles(items: list[Item], grammar: Grammar, place_words: Sequence[str]) -> list[str]:
    """One role per place phrase (module docstring, rules 3 and 7)."""
    if grammar.attach == "prefix":
        return _prefix_roles(items, place_words)
    return _postfix_roles(items, place_words)


def _prefix_roles(items: list[Item], place_words: Sequence[str]) -> list[str]:
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


def _postfix_roles(items: list[Item], place_words: Sequence[str]) -> list[str]:
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
                                       f"{_not_understood_words(between)}; {known_words(place_words)}")
            since_phrase = False
    for p in pending:
        roles[p] = "goal"
    return roles


def _check_dangling(dangling: int | None, items: list[Item], end: int, place_words, how: str) -> None:
    if dangling is None:
        return
    between = [x.surface for x in items[dangling + 1:end] if x.kind == "other"]
    raise InstructionError(f"'{items[dangling].surface}' is {how} no known place word"
                           f"{_not_understood_words(between)}; {known_words(place_words)}")


def _not_understood(items: list[Item]) -> str:
    return _not_understood_words([it.surface for it in items if it.kind == "other"])


def _not_understood_words(words: list[str]) -> str:
    return f" (not understood: {', '.join(words)})" if words else ""


def known_words(place_words: Sequence[str]) -> str:
    """"known place words: a, b, ..." (at most 60 shown) for error messages."""
    words = sorted(set(place_words))
    if not words:
        return "the model knows no place words"
    shown = ", ".join(words[:60]) + (f", ... ({len(words)} in all)" if len(words) > 60 else "")
    return f"known place words: {shown}"

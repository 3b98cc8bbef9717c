"""Longest-match segmentation of an instruction into place words, grammar phrases and other units (rule 1 of
:mod:`spcotmhp.planning.sentence`).

A text is cut into *units* (English: words, with apostrophes inside, and the punctuation , ; &; Japanese: single
characters); the lexicon of a language and a vocabulary maps unit sequences to what they are (a place word, a
marker, an order word, ...). Scanning takes, at each unit, the longest entry starting there (place words win
over grammar phrases of the same units); a unit that starts no entry is an "other" word. The lexicon, with each
entry's surface form and the longest entry per first unit, is built once per language and vocabulary, so a
scan is a few dictionary look-ups per unit.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field

from spcotmhp.planning.grammar import Grammar

_EN_UNIT = re.compile(r"[^\W_]+(?:['\u2019][^\W_]+)*|[,;&]")


@dataclass(slots=True)
class Item:
    """A unit of a scanned sentence: a place phrase (its place words), a grammar phrase or another word."""

    kind: str  # place, marker, connector, order, alternative, relation, modifier, filler, other
    value: str  # the place word / role / order kind / "seq" for a sequencer / ""
    surface: str
    words: list[str] = field(default_factory=list)  # place words of a merged phrase


def units_of(text: str, grammar: Grammar) -> list[str]:
    """The units of ``text`` (module docstring), lower-cased, typographic apostrophes made plain."""
    if grammar.by_character:
        return [ch for ch in text if not ch.isspace()]
    return _EN_UNIT.findall(text.lower().replace("\u2019", "'"))


_LEXICONS: dict = {}


def _lexicon(grammar: Grammar, place_words: Sequence[str]) -> tuple[dict, dict]:
    """(lexicon, longest entry per first unit): the lexicon maps unit tuples to (kind, value, surface), place
    words winning over grammar phrases of the same units; memoised per language and vocabulary in a bounded
    table that needs no lock (its values are never changed; a concurrent clear at worst makes a query build its
    lexicon again)."""
    memo_key = (grammar.lang, tuple(place_words))
    lexicon = _LEXICONS.get(memo_key)  # one lookup: a concurrent clear cannot make it fail (read-only values)
    if lexicon is None:
        lexicon = _build_lexicon(grammar, place_words)
        if len(_LEXICONS) > 32:
            _LEXICONS.clear()
        _LEXICONS[memo_key] = lexicon
    return lexicon


def _build_lexicon(grammar: Grammar, place_words: Sequence[str]) -> tuple[dict, dict]:
    def key(phrase: str) -> tuple[str, ...]:
        return tuple(units_of(phrase, grammar))

    grammar_lex = {key(p): ("filler", "") for p in grammar.fillers}
    grammar_lex.update({key(p): ("modifier", "") for p in grammar.modifiers})
    grammar_lex.update({key(p): ("marker", role) for p, role in grammar.markers.items()})
    grammar_lex.update({key(p): ("order", kind) for p, kind in grammar.order.items()})
    grammar_lex.update({key(p): ("connector", "seq" if p in grammar.sequencers else "") for p in grammar.connectors})
    grammar_lex.update({key(p): ("alternative", "") for p in grammar.alternatives})
    grammar_lex.update({key(p): ("relation", "") for p in grammar.relations})
    grammar_lex.pop((), None)
    lexicon = {**grammar_lex, **{key(w): ("place", w) for w in place_words if key(w)}}  # places win ties
    joiner = "" if grammar.by_character else " "
    longest: dict[str, int] = {}  # the longest entry starting with each unit: a unit starting none is "other"
    for entry in lexicon:
        longest[entry[0]] = max(longest.get(entry[0], 0), len(entry))
    return {k: (kind, value, joiner.join(k)) for k, (kind, value) in lexicon.items()}, longest


def scan(text: str, grammar: Grammar, place_words: Sequence[str]) -> list[Item]:
    """Longest-match segmentation into places, grammar phrases and other units (places win ties); "the first" /
    "the last" before a place or an unknown word are modifiers (an ordinal), elsewhere order words."""
    units = units_of(text, grammar)
    lexicon, longest = _lexicon(grammar, place_words)
    items: list[Item] = []
    i, n_units = 0, len(units)
    while i < n_units:
        unit = units[i]
        for n in range(min(longest.get(unit, 0), n_units - i), 0, -1):
            hit = lexicon.get(tuple(units[i : i + n]))
            if hit:
                kind, value, surface = hit
                items.append(Item(kind, value, surface, [value] if kind == "place" else []))
                i += n
                break
        else:
            if grammar.by_character and items and items[-1].kind == "other":
                items[-1].surface += unit
            else:
                items.append(Item("other", "", unit))
            i += 1
    for a, b, c in zip(items, items[1:], items[2:], strict=False):  # "the first bedroom": an ordinal, not an order word
        if (
            b.kind == "order"
            and b.value in ("first", "last")
            and a.surface in grammar.determiners
            and c.kind in ("place", "other")
        ):
            b.kind = "modifier"
    return items

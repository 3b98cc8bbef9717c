"""Rule 1 of the sentence grammar (:mod:`spcotmhp.planning.sentence`): a text cut into items, the longest match
first, against the lexicon of its language's grammar words (:mod:`spcotmhp.planning.grammar`) and the model's
place words: place phrases (runs of adjacent place words form one multi-word name; in Japanese also two names
joined by a lone の), grammar markers, order words, connectors, alternatives, relations, modifiers, fillers and
other words. "the first" / "the last" before a place are modifiers, elsewhere "first" / "last" are order words.

The :class:`Lexicon` of a grammar and a vocabulary (about a millisecond to build, longer than a plan) is compiled
once per pair and kept in a bounded table (:func:`lexicon`, ``functools.lru_cache``): a compile-once table of a
pure function, whose values are read-only mappings, so no query can change what another sees, and the table is
thread-safe (the standard library's lock). A grammar is keyed by identity (the tables of
:data:`~spcotmhp.planning.grammar.GRAMMARS` are read once and never replaced).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import NamedTuple

from spcotmhp.planning.grammar import Grammar

_EN_UNIT = re.compile(r"[^\W_]+(?:['\u2019][^\W_]+)*|[,;&.!?:]")
"""English units: words (with inner apostrophes) and the punctuation that separates clauses (a full stop, "!",
"?" and ":" end a clause as a comma does: "go to the bedroom. First, stop at the toilet"); other symbols are
space."""


_NO_WORD_START = frozenset("っゃゅょぁぃぅぇぉゎッャュョァィゥェォヮーんン")
"""Characters no Japanese word starts with (small kana, the long-vowel mark, ん): an unknown run starting with one
is glued to the one-character grammar word before it, so that errors name the word as written."""


@dataclass(slots=True)
class Item:
    """A unit of a scanned sentence: a place phrase (its place words), a grammar phrase or another word."""

    kind: str  # place, marker, connector, order, alternative, relation, modifier, filler, containment, refused, other
    value: str  # the place word / role / order kind / "seq" for a sequencer / ""
    surface: str
    words: list[str] = field(default_factory=list)  # place words of a merged phrase


def units(text: str, grammar: Grammar) -> list[str]:
    """The units a sentence is matched on: characters (Japanese) or lower-cased word tokens and , ; &."""
    if grammar.by_character:
        return [ch for ch in text if not ch.isspace()]
    return _EN_UNIT.findall(text.lower().replace("\u2019", "'"))


class Lexicon(NamedTuple):
    """The phrases a sentence is matched against, keyed by unit tuples (read-only)."""

    places: Mapping[tuple[str, ...], tuple[str, str]]  # -> ("place", place word)
    grammar: Mapping[tuple[str, ...], tuple[str, str]]  # -> (kind, role / order kind / "seq" / "")
    longest: int  # units in the longest entry
    entries: Mapping[tuple[str, ...], tuple[str, str, str]]  # both, places winning ties -> (kind, value, surface)
    longest_from: Mapping[str, int]  # units in the longest entry starting with a unit (none: an "other" unit)


@functools.lru_cache(maxsize=32)
def lexicon(grammar: Grammar, place_words: tuple[str, ...]) -> Lexicon:
    """The :class:`Lexicon` of a grammar and a vocabulary, compiled once per pair (module docstring)."""
    return _build_lexicon(grammar, place_words)


def _build_lexicon(grammar: Grammar, place_words: Sequence[str]) -> Lexicon:
    def key(phrase: str) -> tuple[str, ...]:
        return tuple(units(phrase, grammar))

    grammar_lex = {key(p): ("filler", "") for p in grammar.fillers}
    grammar_lex.update({key(p): ("containment", "") for p in grammar.containment})
    grammar_lex.update({key(p): ("modifier", "") for p in grammar.modifiers})
    grammar_lex.update({key(p): ("marker", role) for p, role in grammar.markers.items()})
    grammar_lex.update({key(p): ("order", kind) for p, kind in grammar.order.items()})
    grammar_lex.update({key(p): ("connector", "seq" if p in grammar.sequencers else "") for p in grammar.connectors})
    grammar_lex.update({key(p): ("alternative", "") for p in grammar.alternatives})
    grammar_lex.update({key(p): ("relation", "") for p in grammar.relations})
    grammar_lex.update({key(p): ("refused", kind) for p, kind in grammar.refused.items()})
    grammar_lex.pop((), None)
    place_lex = {key(w): ("place", w) for w in place_words if key(w)}
    for prefix in grammar.honorifics:  # お風呂 is 風呂 (unless a place is called お風呂)
        for w in place_words:
            if key(w) and key(prefix + w) not in place_lex:
                place_lex[key(prefix + w)] = ("place", w)
    if grammar.hiragana_places:  # キッチン is also きっちん (unless a place is called so)
        for w in place_words:
            kana = _hiragana(w)
            if kana != w and len(w) >= 3 and key(kana) not in place_lex:
                place_lex[key(kana)] = ("place", w)
    longest = max(map(len, [*place_lex, *grammar_lex]), default=1)
    joiner = "" if grammar.by_character else " "
    entries = {k: (kind, value, joiner.join(k)) for k, (kind, value) in {**grammar_lex, **place_lex}.items()}
    longest_from: dict[str, int] = {}
    for entry in entries:
        longest_from[entry[0]] = max(longest_from.get(entry[0], 0), len(entry))
    return Lexicon(
        MappingProxyType(place_lex),
        MappingProxyType(grammar_lex),
        longest,
        MappingProxyType(entries),
        MappingProxyType(longest_from),
    )


def scan(text: str, grammar: Grammar, place_words: Sequence[str]) -> list[Item]:
    """Longest-match segmentation into places, grammar phrases and other units (places win ties)."""
    units_ = units(text, grammar)
    lex = lexicon(grammar, tuple(place_words))
    entries, longest_from = lex.entries, lex.longest_from
    items: list[Item] = []
    i, n_units = 0, len(units_)
    while i < n_units:  # one look-up per candidate length, from the longest entry starting with this unit
        unit = units_[i]
        for n in range(min(longest_from.get(unit, 0), n_units - i), 0, -1):
            hit = entries.get(tuple(units_[i : i + n]))
            if hit:
                kind, value, surface = hit
                items.append(Item(kind, value, surface, [value] if kind == "place" else []))
                i += n
                break
        else:
            if grammar.by_character and items and items[-1].kind == "other":
                items[-1].surface += unit
            elif grammar.by_character and unit in _NO_WORD_START and items and _one_grammar_unit(items[-1]):
                items[-1] = Item("other", "", items[-1].surface + unit)  # や+っぱり: one unknown word, やっぱり
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


def _hiragana(word: str) -> str:
    """``word`` with katakana letters (ァ..ヶ) as hiragana, or ``word`` itself when it holds anything else but the
    long-vowel mark ー (a mixed word such as 物置き keeps its one spelling).

    >>> _hiragana("キッチン"), _hiragana("トイレ"), _hiragana("風呂")
    ('きっちん', 'といれ', '風呂')
    """
    if not all("\u30a1" <= ch <= "\u30f6" or ch == "ー" for ch in word):
        return word
    return "".join(chr(ord(ch) - 0x60) if ch != "ー" else ch for ch in word)


def _one_grammar_unit(it: Item) -> bool:
    return it.kind not in ("place", "other") and len(it.surface) == 1


def merge_phrases(items: list[Item], grammar: Grammar) -> list[Item]:
    """Adjacent place words form one phrase (a multi-word name); a word of ``grammar.between_places`` standing
    alone between two phrases joins them or marks an alternative."""
    out: list[Item] = []
    joiner = "" if grammar.by_character else " "
    for it in items:
        if it.kind == "place" and out and out[-1].kind == "place":
            out[-1].words.extend(it.words)
            out[-1].surface += joiner + it.surface
            continue
        if (
            it.kind == "place"
            and len(out) >= 2
            and out[-2].kind == "place"
            and out[-1].kind == "other"
            and out[-1].surface in grammar.between_places
        ):
            if grammar.between_places[out[-1].surface] == "join":
                between = out.pop()
                out[-1].words.extend(it.words)
                out[-1].surface += between.surface + it.surface
                continue
            out[-1].kind = "alternative"
        out.append(it)
    return out

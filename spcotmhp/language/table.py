"""The word classes of one language's instruction grammar (``grammars/<lang>.json``), read once: which phrase is
which terminal, the refusal classes with their reasons, the fillers (a small closed class left out before the
grammar reads a sentence) and the generic nouns.

A phrase may write alternatives as ``(a|b)`` (:func:`expand`); English phrases are matched as their word units with
the fillers left out, the same way sentences are (:func:`strip_fillers`), so that a filler said inside a phrase
never breaks it.
"""

from __future__ import annotations

import functools
import json
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from importlib import resources
from types import MappingProxyType
from typing import Any

from spcotmhp.language.english_words import known

EN_UNIT = re.compile(r"\d+(?:\.\d+)?|[^\W_]+(?:'[^\W_]+)*|'s\b|\.\.\.|[,;:.!?&\-]")
_TEXT_SPEAK = {"u": ("you",), "goto": ("go", "to"), "da": ("the",), "ty": ("thank", "you"), "n": ("and",),
               "thru": ("through",), "rn": ("right", "now"), "tho": ("though",), "ur": ("your",),
               "d": ("the",)}  # fmt: skip
"""Spellings of texts and chats for the words they stand for (as dictionaries of text abbreviations give them:
"u" you, "ur" your, "ty" thank you, "n" and, "rn" right now; "da" and "d" the, as some speak and write it (d in
Nigerian texting); "goto" typed without its space; "thru" and "tho", the informal spellings of through and though
in Merriam-Webster). The one-letter ones ("n", "d") only between two longer words, not a word spelt out."""
_G_DROPPED = re.compile(r"[a-z]{2,}in")
"""A word said with its -ing as -in ("goin", "fixin", "sittin room", "darlin"; the apostrophe of "goin'" is not
part of the unit): the -ing form, where the dictionary holds it and not the word as said ("robin", "cabin" stay)."""
_DEFINITE_T = re.compile(r"t'[a-z]{2,}")
"""Northern English's reduced article written with the word it goes with ("go through to t'kitchen", "t'other
room"): "the" and the word. No standard English word begins with "t'" ("'twas" begins with the apostrophe)."""
_DRAWN_OUT = re.compile(r"([a-z])\1{2,}")
"""A letter written three times or more ("pleeease", "kitchennn"): no English word has one, so it is drawn out."""


def en_units(text: str, restore_g: bool = True) -> list[str]:
    """The English units of ``text`` (:data:`EN_UNIT`), the words of :data:`_TEXT_SPEAK` written out, a letter
    drawn out ("pleeease") written once and a dropped g put back ("goin"): one splitter for sentences, phrases of
    the table and place words alike. ``restore_g`` false: the table's own phrases, written in full spellings, which
    the dropped g's dictionary check leaves as they are (``tests/language/test_table.py`` checks every one), so
    reading the table does not load the dictionary (0.6 s, most of a ``plan`` command's reading)."""
    drawn = (_DRAWN_OUT.sub(r"\1", u) for u in EN_UNIT.findall(text))
    drawn = (w for u in drawn for w in (("the", u[2:]) if _DEFINITE_T.fullmatch(u) else (u,)))
    units = [_g_restored(u) for u in drawn] if restore_g else list(drawn)
    return [
        w
        for k, u in enumerate(units)
        for w in (_TEXT_SPEAK.get(u, (u,)) if u not in ("n", "d") or _between_words(units, k) else (u,))
    ]


def _written_out(classes: Mapping[str, Any], source: str) -> None:
    """Refuse a class phrase holding a text-speak word (:data:`_TEXT_SPEAK`) unless its written-out form is a phrase
    of the same class ("thru" beside "through"): written out, "goto" in GO would make "go to" one GO token and
    silently take the "to" from every "go to the kitchen"."""
    for kind, items in classes.items():
        phrases = items if isinstance(items, list) else items.get("phrases", ())
        texted = [p for p in phrases if any(u in _TEXT_SPEAK for u in EN_UNIT.findall(p))]
        own = {tuple(en_units(p, restore_g=False)) for p in phrases if p not in texted}
        for phrase in texted:
            if tuple(en_units(phrase, restore_g=False)) not in own:
                raise ValueError(
                    f"{source}: {phrase!r} in {kind} is written out as {' '.join(en_units(phrase, restore_g=False))!r},"
                    f" which is no phrase of {kind}; write that phrase instead"
                )


def _g_restored(unit: str) -> str:
    """``unit`` with a dropped g put back (:data:`_G_DROPPED`)."""
    if _G_DROPPED.fullmatch(unit) is None:
        return unit
    return unit + "g" if not known(unit) and known(unit + "g") else unit


def _between_words(units: list[str], k: int) -> bool:
    """Whether ``units[k]`` stands between two words of more than one letter ("bath n toilet", not the letters of
    "d-i-n-i-n-g")."""
    return 0 < k < len(units) - 1 and len(units[k - 1]) > 1 and len(units[k + 1]) > 1


"""English units: numbers, words (inner apostrophes kept), an ellipsis and the punctuation that separates
clauses."""


@dataclass(frozen=True, eq=False)
class WordTable:
    """The word classes of one language (``grammars/<lang>.json``), read once; equal and hashed by identity."""

    lang: str
    by_character: bool
    fillers: frozenset[str]
    phrases: Mapping[tuple[str, ...], str]  # units (fillers left out) -> class; "" for a filler phrase
    reasons: Mapping[str, str]  # refusal class -> why such a word is refused
    misplaced: Mapping[str, str]  # class -> why it is refused where the grammar does not accept it
    nouns: frozenset[str]
    honorifics: tuple[str, ...] = ()
    surfaces: Mapping[str, tuple[str, ...]] = field(default_factory=dict)  # class -> its phrases (for messages)
    extra_function_words: frozenset[str] = frozenset()  # words that never name a place, beyond the classes
    filler_keys: frozenset[tuple[str, ...]] = frozenset()  # filler phrases as units (English)
    phrase_from: Mapping[str, int] = field(default_factory=dict)  # first unit -> units of its longest phrase
    filler_from: Mapping[str, int] = field(default_factory=dict)  # first unit -> units of its longest filler phrase
    synonyms: Mapping[str, tuple[str, ...]] = field(default_factory=dict)  # place word -> other names of it
    talk: Mapping[str, Any] = field(default_factory=dict)  # what talk around an instruction may hold (talk.py)
    contents: Mapping[str, tuple[str, ...]] = field(default_factory=dict)  # what is in a place -> its place words
    senses: Mapping[str, tuple[str, ...]] = field(default_factory=dict)  # other name -> place words, first sense first
    told_senses: Mapping[str, tuple[str, ...]] = field(default_factory=dict)  # other name -> places told by contents
    spellings: Mapping[str, str] = field(default_factory=dict)  # a dialect's spelling -> the word (lexicon rule 1b)

    @property
    def function_words(self) -> frozenset[str]:
        """Words that never name a place: the fillers and every phrase of the word classes (as written, so that a
        learned vocabulary word such as "ここは" or "the" is recognised), save generic nouns and the words that
        only refuse something a place could be called (leave, modifiers, relations: "exit", "front")."""
        keep = ("LEAVE", "MODIFIER", "UNSUPPORTED_RELATION", "CONTAINMENT")
        words = {p for kind, items in self.surfaces.items() if kind not in keep for p in items}
        return frozenset((words | self.fillers | self.extra_function_words) - self.nouns)

    def units(self, phrase: str) -> tuple[str, ...]:
        """The units of a table phrase or a place word, fillers left out as they are from sentences (English:
        rule 3, so that a phrase matches whatever fillers are said inside it), or its characters (Japanese)."""
        if self.by_character:
            return tuple(ch for ch in phrase if not ch.isspace())
        return strip_fillers(tuple(en_units(phrase, restore_g=False)), self.fillers, self.filler_keys)


def read_table(text: str, source: str) -> WordTable:
    """A :class:`WordTable` from the JSON of ``grammars/<lang>.json`` (a malformed table raises ValueError naming
    ``source``)."""
    table = json.loads(text)
    if not isinstance(table, dict) or not isinstance(table.get("classes"), dict):
        raise ValueError(f"{source}: a word table is a JSON object with 'lang' and 'classes'")
    by_char = bool(table.get("by_character", False))
    fillers = frozenset(table.get("fillers", ()) if not by_char else ())
    filler_phrases = [*table.get("filler_phrases", ()), *(table.get("fillers", ()) if by_char else ())]
    fillers_written = [p for item in filler_phrases for p in expand(item)]
    filler_keys = frozenset(
        key
        for p in fillers_written
        if not by_char and (key := tuple(u for u in en_units(p, restore_g=False) if u not in fillers))
    )
    draft = WordTable(table["lang"], by_char, fillers, {}, {}, {}, frozenset(), filler_keys=filler_keys)
    phrases: dict[tuple[str, ...], str] = {}
    surfaces: dict[str, tuple[str, ...]] = {}

    def add(kind: str, items: Sequence[str]) -> None:
        items = [p for item in items for p in expand(item)]
        surfaces[kind] = tuple(items)
        for phrase in items:
            key = draft.units(phrase)
            if key and phrases.setdefault(key, kind) != kind:
                raise ValueError(f"{source}: {phrase!r} is in two classes, {phrases[key]} and {kind}")

    for kind, items in table["classes"].items():
        add(kind, items)
    if not by_char:
        _written_out(table["classes"], source)
    reasons = {}
    for kind, spec in table.get("refusals", {}).items():
        add(kind, spec["phrases"])
        reasons[kind] = spec["reason"]
    for phrase in fillers_written:
        key = (
            tuple(ch for ch in phrase if not ch.isspace())
            if by_char
            else tuple(u for u in en_units(phrase, restore_g=False) if u not in fillers)
        )
        if key:
            phrases.setdefault(key, "")
    surfaces["FILLER"] = tuple(fillers_written)
    return WordTable(
        lang=table["lang"],
        by_character=by_char,
        fillers=fillers,
        phrases=MappingProxyType(phrases),
        reasons=MappingProxyType(reasons),
        misplaced=MappingProxyType(dict(table.get("misplaced", {}))),
        nouns=frozenset(table.get("nouns", ())),
        honorifics=tuple(table.get("honorifics", ())),
        surfaces=MappingProxyType(surfaces),
        extra_function_words=frozenset(table.get("not_names", ())),
        filler_keys=filler_keys,
        phrase_from=MappingProxyType(longest_from(phrases)),
        filler_from=MappingProxyType(longest_from(filler_keys)),
        synonyms=MappingProxyType(_with_activities(table)),
        talk=MappingProxyType({str(k): v for k, v in table.get("talk", {}).items()}),
        contents=MappingProxyType({str(k): tuple(map(str, v)) for k, v in table.get("contents", {}).items()}),
        senses=MappingProxyType({str(k): tuple(map(str, v)) for k, v in table.get("senses", {}).items()}),
        told_senses=MappingProxyType({str(k): tuple(map(str, v)) for k, v in table.get("told_senses", {}).items()}),
        spellings=MappingProxyType({str(k): str(v) for k, v in table.get("spellings", {}).items()}),
    )


def _with_activities(table: Mapping[str, Any]) -> dict[str, tuple[str, ...]]:
    """The table's ``synonyms``, and for each place word the rooms told by what people do there (``activities``):
    each activity followed by each of ``activity_nouns`` ("cooking" + "room", ご飯食べる + とこ) or after each of
    ``activity_heads`` ("room for" + "bathing"), everyday names of the room as the synonyms are (read only where
    the map has that place word)."""
    out = {str(k): tuple(map(str, v)) for k, v in table.get("synonyms", {}).items()}
    joiner = "" if table.get("by_character") else " "
    nouns = [str(n) for n in table.get("activity_nouns", ())]
    heads = [str(h) for h in table.get("activity_heads", ())]
    for word, activities in table.get("activities", {}).items():
        named = tuple(f"{a}{joiner}{n}" for a in map(str, activities) for n in nouns)
        named += tuple(f"{h}{joiner}{a}" for a in map(str, activities) for h in heads)
        out[str(word)] = (*out.get(str(word), ()), *named)
    return out


def longest_from(keys: Any) -> dict[str, int]:
    """First unit -> the number of units of the longest key starting with it (what a longest match tries)."""
    out: dict[str, int] = {}
    for key in keys:
        out[key[0]] = max(out.get(key[0], 0), len(key))
    return out


def expand(phrase: str) -> list[str]:
    """A table phrase with its alternatives written out: "(に|へ)行って" -> ["に行って", "へ行って"]; an empty
    alternative leaves the group out ("(を|)通って" -> ["を通って", "通って"]).

    >>> expand("(に|へ|)行(って|く)")
    ['に行って', 'に行く', 'へ行って', 'へ行く', '行って', '行く']
    """
    match = _GROUP.search(phrase)
    if match is None:
        return [phrase]
    head, tail = phrase[: match.start()], phrase[match.end() :]
    return [head + alt + rest for alt in match.group(1).split("|") for rest in expand(tail)]


_GROUP = re.compile(r"\(([^()]*)\)")


@functools.cache
def word_table(lang: str) -> WordTable:
    """The word table of ``lang`` (package data, read once per process)."""
    path = resources.files("spcotmhp.language") / "grammars" / f"{lang}.json"
    return read_table(path.read_text(encoding="utf-8"), f"grammars/{lang}.json")


def strip_fillers(units: tuple[str, ...], fillers: frozenset[str], keys: frozenset[tuple[str, ...]]) -> tuple[str, ...]:
    """Rule 3 on a phrase of the table: its fillers left out as they would be from a sentence."""
    draft = _filler_table(fillers, keys)
    items: list[Any] = list(units)
    while True:
        kept = [u for u in items if u not in fillers]
        out, i = [], 0
        while i < len(kept):
            n = filler_at(kept, i, draft, frozenset())
            if not n:
                out.append(kept[i])
            i += n or 1
        if len(out) == len(items):
            return tuple(out)
        items = out


@functools.lru_cache(maxsize=8)
def _filler_table(fillers: frozenset[str], keys: frozenset[tuple[str, ...]]) -> WordTable:
    """The table :func:`strip_fillers` matches with: made once per table's fillers, not once a phrase (reading
    the word tables took 0.3-0.4 s of every command, most of it rebuilding this for each of ~900 phrases)."""
    return WordTable("", False, fillers, {}, {}, {}, frozenset(), filler_keys=keys, filler_from=longest_from(keys))


def filler_at(units: Sequence[Any], i: int, table: WordTable, keep: frozenset[str]) -> int:
    """Units in the longest filler phrase starting at ``units[i]`` (0: none); never a place word or a token."""
    first = units[i]
    if not isinstance(first, str):
        return 0
    for n in range(min(table.filler_from.get(first, 0), len(units) - i), 1, -1):
        key = tuple(units[i : i + n])
        if key in table.filler_keys and all(isinstance(u, str) and u not in keep for u in key):
            return n
    return 0

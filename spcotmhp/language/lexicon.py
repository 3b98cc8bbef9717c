"""Words -> terminals: a normalised sentence cut into the tokens its grammar reads (``grammars/<lang>.json`` gives the
word classes; the model gives the place words).

Rules, in this order (English; Japanese below):

1. The text is normalised (:func:`spcotmhp.language.text.normalise`) and cut into units: words (inner apostrophes
   kept) and the punctuation that separates clauses; a hyphen inside a word is a space ("living-room").
2. Lengths of time become one DURATION token: an optional "for", a number (digits or a number word, "a", "an",
   "half a") and a unit (seconds, minutes, hours): "for two minutes" is 120 s.
3. Fillers (the table's small closed class: articles, politeness, hesitations) are left out, single words first,
   then filler phrases; nothing else is ever left out.
4. Longest match, place words winning ties, against the place words and the table's phrases (each phrase as its
   units with the fillers left out, so "on the way" also matches "on way"). A place word also matches written
   without its apostrophe ("alices"), as its compound written open or glued ("bed room", "livingroom"), and in
   the plural ("bedrooms", by the noun lemmas of lemminflect): spellings of the same word, not guesses.
5. A generic noun of the table ("room") right after a place word belongs to its name ("living room"); adjacent
   place words form one name ("east corridor"). Any other unit is a WORD: no rule of the grammar accepts it.

Japanese: units are characters; the longest match (rule 4) runs on characters over the place words (also in
hiragana for a katakana name, and after an honorific お/ご) and the table's phrases; fillers are left out after
matching; a run of unmatched characters is one WORD. Digits before 秒, 分 or 時間 are a DURATION.
"""

from __future__ import annotations

import functools
import json
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from importlib import resources
from types import MappingProxyType
from typing import Any, NamedTuple

from spcotmhp.language.text import normalise

MAX_WAIT_S = 3600.0
"""Longest wait an instruction may ask for (an hour); a longer one is refused (the planner's plans are for now)."""

_EN_UNIT = re.compile(r"\d+(?:\.\d+)?|[^\W_]+(?:'[^\W_]+)*|'s\b|\.\.\.|[,;:.!?&\-]")
_INNER_HYPHEN = re.compile(r"(?<=\w)-(?=\w)")
_DASHES = str.maketrans({"\u2013": "-", "\u2014": "-", "\u2015": "-"})
_NUMBERS = {
    "a": 1, "an": 1, "one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7, "eight": 8,
    "nine": 9, "ten": 10, "eleven": 11, "twelve": 12, "fifteen": 15, "twenty": 20, "thirty": 30, "forty": 40,
    "forty-five": 45, "fifty": 50, "sixty": 60, "ninety": 90,
}  # fmt: skip
_UNITS = {"second": 1, "seconds": 1, "sec": 1, "secs": 1, "minute": 60, "minutes": 60, "min": 60, "mins": 60,
    "hour": 3600, "hours": 3600}  # fmt: skip
_JA_DURATION = re.compile(r"(\d+(?:\.\d+)?|[一二三四五六七八九十]+)(秒|分|時間)(半)?(?:間)?(?:ほど|くらい|ぐらい)?")
_KANJI_DIGITS = {"一": 1, "二": 2, "三": 3, "四": 4, "五": 5, "六": 6, "七": 7, "八": 8, "九": 9}
_JA_UNITS = {"秒": 1, "分": 60, "時間": 3600}


class Token(NamedTuple):
    """One token of a sentence: its terminal (``kind``), its surface, the place words of a PLACE, the seconds of a
    DURATION, and whether a place word was said in the plural (a tuple: made for every word of every
    instruction)."""

    kind: str
    surface: str
    words: tuple[str, ...] = ()
    seconds: float = 0.0
    plural: bool = False
    start: int = 0  # index of its first unit in the sentence (fillers included)
    end: int = 0  # index after its last unit


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
        return _strip_fillers(tuple(_EN_UNIT.findall(phrase)), self.fillers, self.filler_keys)


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
        if not by_char and (key := tuple(u for u in _EN_UNIT.findall(p) if u not in fillers))
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
    reasons = {}
    for kind, spec in table.get("refusals", {}).items():
        add(kind, spec["phrases"])
        reasons[kind] = spec["reason"]
    for phrase in fillers_written:
        key = (
            tuple(ch for ch in phrase if not ch.isspace())
            if by_char
            else tuple(u for u in _EN_UNIT.findall(phrase) if u not in fillers)
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
        phrase_from=MappingProxyType(_longest_from(phrases)),
        filler_from=MappingProxyType(_longest_from(filler_keys)),
    )


def _longest_from(keys: Any) -> dict[str, int]:
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


class PlaceLexicon:
    """The place words of one vocabulary as the units they match, with their spelling variants (module docstring,
    rule 4), built once per table and vocabulary (:func:`place_lexicon`)."""

    def __init__(self, table: WordTable, place_words: Sequence[str]) -> None:
        self.words = frozenset(place_words)
        keys: dict[tuple[str, ...], str] = {}
        for w in place_words:
            key = table.units(w) if table.by_character else tuple(_EN_UNIT.findall(w))
            if key:
                keys[key] = w
        variants: dict[tuple[str, ...], str] = {}
        glued: set[tuple[str, ...]] = set()
        for w in place_words:
            for key in _variants(w, table):
                if key and key not in keys:
                    variants.setdefault(key, w)
            glued.update((w + noun,) for noun in table.nouns if not table.by_character)
        self.keys: Mapping[tuple[str, ...], str] = MappingProxyType({**variants, **keys})
        self.glued = frozenset(glued - set(keys))
        self.longest = max(map(len, self.keys), default=1)
        self.longest_from: Mapping[str, int] = MappingProxyType(_longest_from(self.keys))

    def singular(self, unit: str) -> str | None:
        """The place word ``unit`` is the plural of ("bedrooms" -> "bedroom"), or None (English)."""
        if not unit.endswith(("s", "i", "a")) or len(unit) <= 2:
            return None
        return next((lemma for lemma in _noun_lemmas(unit) if lemma in self.words and lemma != unit), None)


def _variants(word: str, table: WordTable) -> list[tuple[str, ...]]:
    """Other spellings of a place word (module docstring, rule 4)."""
    if table.by_character:
        spellings = [word]
        kana = _hiragana(word)
        if kana != word and len(word) >= 3:
            spellings.append(kana)  # キッチン, きっちん
        if any("\u4e00" <= ch <= "\u9fff" for ch in word):
            reading = _reading(word)
            if reading and len(reading) >= 2:
                spellings.append(reading)  # 風呂, ふろ
            if len(word) >= 3 and "\u3041" <= word[-1] <= "\u3096" and "\u4e00" <= word[-2] <= "\u9fff":
                spellings.append(word[:-1])  # 物置き, 物置: okurigana written or left out
        return [tuple(p + w) for w in spellings for p in ("", *table.honorifics) if (p + w) != word]
    bare = word.replace("'", "")
    out: list[tuple[str, ...]] = [(bare,)] if bare != word and " " not in word else []
    if " " not in word and "'" not in word:
        out += [(word + noun,) for noun in table.nouns]
        out += [(word[:i], word[i:]) for i in range(3, len(word) - 2)]
    return out


def _hiragana(word: str) -> str:
    """``word`` with katakana letters as hiragana, or ``word`` itself when it holds anything but katakana and ー.

    >>> _hiragana("キッチン"), _hiragana("トイレ"), _hiragana("風呂")
    ('きっちん', 'といれ', '風呂')
    """
    if not all("\u30a1" <= ch <= "\u30f6" or ch == "ー" for ch in word):
        return word
    return "".join(chr(ord(ch) - 0x60) if ch != "ー" else ch for ch in word)


def _reading(word: str) -> str:
    """The hiragana reading of a Japanese word by janome's dictionary ("" when a part is unknown)."""
    from spcotmhp.language.text import reading

    return _hiragana(reading(word))


@functools.lru_cache(maxsize=4096)
def _noun_lemmas(unit: str) -> tuple[str, ...]:
    import lemminflect  # loaded on the first word no table or place word matches (about 0.2 s)

    return tuple(lemminflect.getLemma(unit, upos="NOUN"))


@functools.lru_cache(maxsize=4096)
def _dictionary_word(unit: str) -> bool:
    """Whether ``unit`` is an English word of its own ("bathroom": a room of its own, not "bath" glued to "room";
    "livingroom" is not), by lemminflect's dictionary."""
    import lemminflect

    return bool(lemminflect.getAllLemmas(unit))


@functools.lru_cache(maxsize=32)
def place_lexicon(table: WordTable, place_words: tuple[str, ...]) -> PlaceLexicon:
    """The :class:`PlaceLexicon` of a vocabulary, built once per table and vocabulary (a bounded cache of a pure
    function whose values are never changed, so it is safe across threads)."""
    return PlaceLexicon(table, place_words)


def tokens(text: str, table: WordTable, place_words: Sequence[str]) -> list[Token]:
    """The tokens of ``text`` (module docstring)."""
    places = place_lexicon(table, tuple(place_words))
    if table.by_character:
        return _glue_ja(_join_no(_merge(_tokens_ja(normalise(text), table, places))))
    return _merge(_tokens_en(normalise(text), table, places))


def english_units(text: str) -> list[str]:
    """Rule 1: the units of a normalised English sentence."""
    units = _EN_UNIT.findall(_INNER_HYPHEN.sub(" ", normalise(text).translate(_DASHES)))
    return [u for u in units if u != "..."]  # an ellipsis is a hesitation ("go to the... the bedroom")


def _tokens_en(text: str, table: WordTable, places: PlaceLexicon) -> list[Token]:
    units = english_units(text)
    kept = _without_fillers(_durations_en(units), table, places)
    seq = [u for u, _ in kept]
    out: list[Token] = []
    i = 0
    while i < len(seq):
        unit, start = kept[i]
        if isinstance(unit, Token):
            out.append(unit)
            i += 1
            continue
        hit = _longest(seq, i, table, places)
        if hit is not None:
            kind, value, n = hit
            end = kept[i + n - 1][1] + 1
            surface = " ".join(units[start:end]) if kind != "PLACE" else " ".join(str(u) for u in seq[i : i + n])
            if kind:
                words = (value,) if kind == "PLACE" else ()
                out.append(Token(kind, surface, words, start=start, end=end))
            i += n
            continue
        lemma = places.singular(unit)
        last = out[-1] if out else None
        if lemma is not None:
            out.append(Token("PLACE", unit, (lemma,), plural=True, start=start, end=start + 1))
        elif unit in table.nouns and last is not None and last.kind == "PLACE":
            out[-1] = Token("PLACE", f"{last.surface} {unit}", last.words, plural=last.plural, start=last.start,
                            end=start + 1)  # fmt: skip
        else:
            out.append(Token("WORD", unit, start=start, end=start + 1))
        i += 1
    return out


def _without_fillers(
    items: list[tuple[Token | str, int]], table: WordTable, places: PlaceLexicon
) -> list[tuple[Token | str, int]]:
    """Rule 3: the fillers left out, single words and phrases, again until none is left (a filler said inside
    another, "when could you you're ready", leaves the outer one whole once it is out). Place words stay."""
    while True:
        kept = [(u, p) for u, p in items if not isinstance(u, str) or u not in table.fillers or u in places.words]
        units = [u for u, _ in kept]
        out: list[tuple[Token | str, int]] = []
        i = 0
        while i < len(kept):
            n = _filler_at(units, i, table, places.words)
            if not n:
                out.append(kept[i])
            i += n or 1
        if len(out) == len(items):
            return out
        items = out


def _strip_fillers(
    units: tuple[str, ...], fillers: frozenset[str], keys: frozenset[tuple[str, ...]]
) -> tuple[str, ...]:
    """Rule 3 on a phrase of the table: its fillers left out as they would be from a sentence."""
    draft = WordTable("", False, fillers, {}, {}, {}, frozenset(), filler_keys=keys, filler_from=_longest_from(keys))
    items: list[Any] = list(units)
    while True:
        kept = [u for u in items if u not in fillers]
        out, i = [], 0
        while i < len(kept):
            n = _filler_at(kept, i, draft, frozenset())
            if not n:
                out.append(kept[i])
            i += n or 1
        if len(out) == len(items):
            return tuple(out)
        items = out


def _filler_at(units: Sequence[Any], i: int, table: WordTable, keep: frozenset[str]) -> int:
    """Units in the longest filler phrase starting at ``units[i]`` (0: none); never a place word or a token."""
    first = units[i]
    if not isinstance(first, str):
        return 0
    for n in range(min(table.filler_from.get(first, 0), len(units) - i), 1, -1):
        key = tuple(units[i : i + n])
        if key in table.filler_keys and all(isinstance(u, str) and u not in keep for u in key):
            return n
    return 0


def _longest(units: Sequence[Any], i: int, table: WordTable, places: PlaceLexicon) -> tuple[str, str, int] | None:
    """(class, place word, length) of the longest entry starting at ``units[i]`` (places win ties), or None."""
    first = units[i]
    if not isinstance(first, str):
        return None
    most = max(places.longest_from.get(first, 0), table.phrase_from.get(first, 0))
    for n in range(min(len(units) - i, most), 0, -1):
        key = tuple(units[i : i + n])
        if n > 1 and any(isinstance(u, Token) for u in key):
            continue
        if key in places.keys and not (key in places.glued and _dictionary_word(key[0])):
            return "PLACE", places.keys[key], n
        if key in table.phrases:
            return table.phrases[key], "", n
    return None


def _durations_en(units: list[str]) -> list[tuple[Token | str, int]]:
    """Rule 2: "(for) <number> <unit>" -> a DURATION token; "half a minute" is 30 s. Each item with the index of
    its first unit."""
    out: list[tuple[Token | str, int]] = []
    i = 0
    while i < len(units):
        j = i + (units[i] == "for")
        half = units[j : j + 2] in (["half", "a"], ["half", "an"])
        k = j + 1 if half else j
        number = _number(units[k]) if k < len(units) else None
        unit = _UNITS.get(units[k + 1]) if number is not None and k + 1 < len(units) else None
        if number is not None and unit is not None:
            seconds = number * unit * (0.5 if half else 1.0)
            out.append((Token("DURATION", " ".join(units[i : k + 2]), seconds=seconds, start=i, end=k + 2), i))
            i = k + 2
        else:
            out.append((units[i], i))
            i += 1
    return out


def _number(unit: str) -> float | None:
    if unit in _NUMBERS:
        return float(_NUMBERS[unit])
    if not unit[:1].isdigit():
        return None
    try:
        return float(unit)
    except ValueError:
        return None


def _tokens_ja(text: str, table: WordTable, places: PlaceLexicon) -> list[Token]:
    chars = [ch for ch in text if not ch.isspace()]
    out: list[Token] = []
    i = 0
    while i < len(chars):
        duration = _JA_DURATION.match("".join(chars[i : i + 12]))
        if duration:
            n = len(duration.group(0))
            out.append(Token("DURATION", duration.group(0), seconds=_ja_seconds(duration), start=i, end=i + n))
            i += n
            continue
        hit = _longest(chars, i, table, places)
        if hit is not None:
            kind, value, n = hit
            if kind:
                words = (value,) if kind == "PLACE" else ()
                out.append(Token(kind, "".join(chars[i : i + n]), words, start=i, end=i + n))
            i += n
            continue
        last = out[-1] if out else None
        noun = next((w for w in table.nouns if "".join(chars[i : i + len(w)]) == w), None)
        if noun is not None and last is not None and last.kind == "PLACE" and last.end == i:
            out[-1] = Token("PLACE", last.surface + noun, last.words, start=last.start, end=i + len(noun))
            i += len(noun)
            continue
        if last is not None and last.kind == "WORD" and last.end == i:
            out[-1] = Token("WORD", last.surface + chars[i], start=last.start, end=i + 1)
        else:
            out.append(Token("WORD", chars[i], start=i, end=i + 1))
        i += 1
    return out


_NO_WORD_START = frozenset("っゃゅょぁぃぅぇぉゎッャュョァィゥェォヮーんン")
"""Characters no Japanese word starts with (small kana, the long-vowel mark, ん): an unknown run starting with one
is glued to the one-character word before it, so that a message names the word as written (や+っばり: やっばり)."""


def _glue_ja(items: list[Token]) -> list[Token]:
    """Japanese: one-character words that belong to an unknown word around them (module docstring) become part of
    it; か is a choice only between two places (キッチンかトイレ), elsewhere a character of a word (静か)."""
    out: list[Token] = []
    for k, it in enumerate(items):
        nxt = items[k + 1] if k + 1 < len(items) else None
        prev = out[-1] if out else None
        loose = (
            it.kind == "ALTERNATIVE"
            and it.surface == "か"
            and not (prev is not None and prev.kind == "PLACE" and nxt is not None and nxt.kind == "PLACE")
        )
        starts_word = (
            it.kind == "WORD" and it.surface[0] in _NO_WORD_START and prev is not None
            and prev.kind not in ("PLACE", "WORD") and len(prev.surface) == 1 and prev.end == it.start
        )  # fmt: skip
        if starts_word and prev is not None:
            out[-1] = Token("WORD", prev.surface + it.surface, start=prev.start, end=it.end)
        elif loose or (it.kind == "WORD" and prev is not None and prev.kind == "WORD" and prev.end == it.start):
            if prev is not None and prev.kind == "WORD" and prev.end == it.start:
                out[-1] = Token("WORD", prev.surface + it.surface, start=prev.start, end=it.end)
            else:
                out.append(Token("WORD", it.surface, start=it.start, end=it.end))
        else:
            out.append(it)
    return out


def _ja_seconds(match: re.Match) -> float:
    """Seconds of a Japanese duration: digits or kanji numerals up to 九十九 (二十, 三十五), then 秒 / 分 / 時間."""
    number, unit = match.group(1), match.group(2)
    half = 0.5 * _JA_UNITS[unit] if match.group(3) else 0.0  # 1分半: a minute and a half
    if number[0].isdigit():
        return float(number) * _JA_UNITS[unit] + half
    tens, ten, ones = number.partition("十")
    if not ten:
        value = _KANJI_DIGITS.get(number, 0)
    else:
        value = _KANJI_DIGITS.get(tens, 1 if not tens else 0) * 10 + _KANJI_DIGITS.get(ones, 0)
    return float(value) * _JA_UNITS[unit] + half


def _join_no(items: list[Token]) -> list[Token]:
    """Japanese: two place names joined by a lone の are one name (玄関の廊下: the entrance corridor)."""
    out: list[Token] = []
    for it in items:
        if (
            it.kind == "PLACE" and len(out) >= 2 and out[-1].kind == "WORD" and out[-1].surface == "の"
            and out[-2].kind == "PLACE" and out[-1].start == out[-2].end and it.start == out[-1].end
        ):  # fmt: skip
            no = out.pop()
            last = out[-1]
            out[-1] = Token("PLACE", last.surface + no.surface + it.surface, last.words + it.words, start=last.start,
                            end=it.end)  # fmt: skip
        else:
            out.append(it)
    return out


def _merge(items: list[Token]) -> list[Token]:
    """Place words side by side (fillers between them left out) form one name (rule 5); a name no place has
    ("the hall please the entrance": "hall entrance") is refused where the planner checks names."""
    out: list[Token] = []
    for it in items:
        if it.kind == "PLACE" and out and out[-1].kind == "PLACE":
            last = out[-1]
            joiner = "" if _is_cjk(last.surface) else " "
            out[-1] = Token(
                "PLACE", last.surface + joiner + it.surface, last.words + it.words, plural=it.plural,
                start=last.start, end=it.end,
            )  # fmt: skip
        else:
            out.append(it)
    return out


def _is_cjk(text: str) -> bool:
    return any("\u3040" <= ch <= "\u9fff" for ch in text)

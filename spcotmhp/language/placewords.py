"""Place words as the units they match, with their spelling variants (rule 4 of :mod:`spcotmhp.language.lexicon`),
and the token a sentence is cut into."""

from __future__ import annotations

import functools
from collections.abc import Mapping, Sequence
from types import MappingProxyType
from typing import Any, NamedTuple

from spcotmhp.language.numbers import number_word, said_variants
from spcotmhp.language.table import WordTable, en_units, longest_from


class Token(NamedTuple):
    """One token of a sentence: its terminal (``kind``), its surface, the place words of a PLACE, the seconds of a
    DURATION, the floor of a FLOOR, and whether a place word was said in the plural (a tuple: made for every word
    of every instruction)."""

    kind: str
    surface: str
    words: tuple[str, ...] = ()
    seconds: float = 0.0
    plural: bool = False
    start: int = 0  # index of its first unit in the sentence (fillers included)
    end: int = 0  # index after its last unit
    floor: int | str | None = None  # the floor a FLOOR token says (spcotmhp.language.floors)
    number: int | None = None  # the instance number said with a PLACE ("bedroom 2": the screen's "bedroom #2")


class PlaceLexicon:
    """The place words of one vocabulary as the units they match, with their spelling variants (module docstring,
    rule 4), built once per table and vocabulary (:func:`place_lexicon`). An English entry of several words is a
    taught name holding a number ("aisle one", "room 101"): it matches whole, in the variants it may be said in
    (:func:`~spcotmhp.language.numbers.said_variants`: "aisle 1", "aisle number one"), and a number word is no
    place word alone ("bedroom 2" of bedrooms taught without numbers keeps naming the screen's "bedroom #2")."""

    def __init__(self, table: WordTable, place_words: Sequence[str]) -> None:
        names = [w for w in place_words if " " in w and not table.by_character]
        place_words = [w for w in place_words if " " not in w and (table.by_character or number_word(w) is None)]
        self.words = frozenset(place_words)
        keys: dict[tuple[str, ...], str] = {}
        for w in place_words:
            key = table.units(w) if table.by_character else tuple(en_units(w))
            if key:
                keys[key] = w
        for name in names:  # a taught name holding a number, matched whole in its variants (said_names.py)
            for key in said_variants(name.split()):
                keys.setdefault(key, name)
        variants: dict[tuple[str, ...], str] = {}
        glued: set[tuple[str, ...]] = set()
        for w in place_words:
            for key in _variants(w, table):
                if key and key not in keys:
                    variants.setdefault(key, w)
            glued.update((w + noun,) for noun in table.nouns if not table.by_character)
        named = _synonym_names(table, self.words)
        for other, order in table.senses.items():  # "hallway" beside a corridor and a hall: the corridor
            key = table.units(other) if table.by_character else tuple(en_units(other))
            if len(named.get(key, ())) > 1:
                named[key] = {next(w for w in order if w in named[key])} if set(order) & named[key] else named[key]
        synonyms = {key: next(iter(ws)) for key, ws in named.items() if len(ws) == 1 and key not in keys}
        self.ambiguous: Mapping[tuple[str, ...], tuple[str, ...]] = MappingProxyType(
            {key: tuple(sorted(ws)) for key, ws in named.items() if len(ws) > 1 and key not in keys}
        )  # "bathroom" beside a bath, a toilet and a washroom: which one is a guess
        variants.update(synonyms)  # "bathroom" is the table's other name of the bath, not "bath" glued to "room"
        glued -= synonyms.keys()
        self.keys: Mapping[tuple[str, ...], str] = MappingProxyType({**variants, **keys})
        self.glued = frozenset(glued - set(keys))
        self.longest = max(map(len, self.keys), default=1)
        self.longest_from: Mapping[str, int] = MappingProxyType(longest_from(self.keys))

    def misspelt(self, unit: str) -> str | None:
        """The place word an unknown English word is a typing error of, or None: a word
        that is no word of lemminflect's dictionary, of four letters or more, one edit (an insertion, a deletion, a
        change or two letters swapped) from exactly one place word of five letters or more ("kitchin", "dinning"), or
        that keeps its first letter and drops letters of exactly one place word, keeping over half of them
        ("kitchn", "livng", "bdrm", "washrm")."""
        from spcotmhp.language.english_words import known

        if len(unit) < 4 or not unit.isalpha() or known(unit):
            return None
        near = {w for w in self.words if len(w) >= 5 and w.isalpha() and _one_edit(unit, w)}
        near |= {w for w in self.words if w.isalpha() and w[:1] == unit[:1] and 2 * len(unit) > len(w) > len(unit)
                 and _within(unit, w)}  # fmt: skip
        return near.pop() if len(near) == 1 else None

    def singular(self, unit: str) -> str | None:
        """The place word ``unit`` is the plural of ("bedrooms" -> "bedroom"), or None (English)."""
        if not unit.endswith(("s", "i", "a")) or len(unit) <= 2:
            return None
        return next((lemma for lemma in _noun_lemmas(unit) if lemma in self.words and lemma != unit), None)


_COMPASS = frozenset({"east", "west", "north", "south"})


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
            if len(reading) >= 3:  # 廊下, ロウカ: the sound in katakana (learners, recognisers); not フロ of フロア
                spellings.append("".join(chr(ord(ch) + 0x60) for ch in reading))
            if len(word) >= 3 and "\u3041" <= word[-1] <= "\u3096" and "\u4e00" <= word[-2] <= "\u9fff":
                spellings.append(word[:-1])  # 物置き, 物置: okurigana written or left out
        return [tuple(p + w) for w in spellings for p in ("", *table.honorifics) if (p + w) != word]
    bare = word.replace("'", "")
    out: list[tuple[str, ...]] = [(bare,)] if bare != word and " " not in word else []
    if word.endswith("'s") and " " not in word:
        out += [(word[:-2], noun) for noun in table.nouns]  # "alice room": the possessive's 's not said or written
    if word in _COMPASS:
        out.append((word + "ern",))  # "the eastern corridor": the adjective of the compass point
    if word == "east":
        out.append(("e",))  # "the E corridor", as on signs; "n", "s" and "w" are texting's and, is and with
    if " " not in word and "'" not in word:
        out += [(word + noun,) for noun in table.nouns]
        out += [(word[:i], word[i:]) for i in range(3, len(word) - 2)]
    return out


def _synonym_names(table: WordTable, words: frozenset[str]) -> dict[tuple[str, ...], set[str]]:
    """The other names of the table's ``synonyms`` (as units, also after an honorific) -> the place words of
    ``words`` they may name (rule 4: "bathroom" is the bath only in a map without a toilet or a washroom; with
    several it names none, and is refused saying which it may be)."""
    named: dict[tuple[str, ...], set[str]] = {}
    for word, others in table.synonyms.items():
        if word not in words:
            continue
        for other in others:
            spellings = [other, *(p + other for p in table.honorifics)] if table.by_character else [other]
            for spelling in spellings:
                key = table.units(spelling) if table.by_character else tuple(en_units(spelling, restore_g=False))
                if key:  # the table's own phrase, in full spellings (WordTable.units)
                    named.setdefault(key, set()).add(word)
    return named


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


def longest_match(
    units: Sequence[Any], i: int, table: WordTable, places: PlaceLexicon, plain: bool = False
) -> tuple[str, str, int] | None:
    """(class, place word, length) of the longest entry starting at ``units[i]`` (places win ties), or None;
    ``plain``: the caller knows ``units`` holds no token (nothing to skip)."""
    first = units[i]
    if not isinstance(first, str):
        return None
    most = max(places.longest_from.get(first, 0), table.phrase_from.get(first, 0))
    for n in range(min(len(units) - i, most), 0, -1):
        key = tuple(units[i : i + n])
        if n > 1 and not plain and any(isinstance(u, Token) for u in key):
            continue
        if key in places.keys and not (key in places.glued and _dictionary_word(key[0])):
            return "PLACE", places.keys[key], n
        if key in table.phrases:
            return table.phrases[key], "", n
    return None


def _one_edit(a: str, b: str) -> bool:
    """Whether ``a`` and ``b`` differ by one insertion, deletion, change or swap of two neighbouring letters."""
    if a == b or abs(len(a) - len(b)) > 1:
        return False
    if len(a) == len(b):
        diff = [i for i in range(len(a)) if a[i] != b[i]]
        return (
            len(diff) == 1
            or len(diff) == 2
            and diff[1] == diff[0] + 1
            and a[diff[0]] == b[diff[1]]
            and a[diff[1]] == b[diff[0]]
        )
    short, long_ = (a, b) if len(a) < len(b) else (b, a)
    i = next((k for k in range(len(short)) if short[k] != long_[k]), len(short))
    return short[i:] == long_[i + 1 :]


def _within(short: str, word: str) -> bool:
    """Whether the letters of ``short`` appear in ``word`` in order (a word with letters left out)."""
    letters = iter(word)
    return all(c in letters for c in short)


_TELLING = frozenset({"with", "w", "where", "that", "which", "one"})
_GOING = frozenset({"TO", "GO", "VIA", "AVOID", "ENTER", "AT", "STOP_AT", "NEG", "WITHOUT", "NO"})
"""Classes right before a place that say it is where to go, pass or keep out of."""
"""Words after an ambiguous word that tell its place by what is in it (rewrite_en's contents rule, rule 9)."""


def contrasted(items: list[Token], places: PlaceLexicon, activities: frozenset[str]) -> list[Token]:
    """A word that may name places of several kinds ("bathroom": the bath or the toilet), said in a sentence that
    names one of those kinds by its own word ("go to the toilet, then the bathroom", "keep out of the toilet and
    the bathroom"), names another of them: a speaker who meant the toilet twice would not call it by two names in
    one breath. Where exactly one kind is left, the word is read as it. A place word that also names what is done
    there (``activities``: "bath" of "run a bath", "bath night") rules out nothing, nor does a place said as what
    is in it ("the bathroom where the toilet is": rule 9 reads it), said beside it ("the bathroom, the toilet") or
    after a verb of no class ("and use the toilet"); with a correction in the sentence ("the toilet, I mean the
    bathroom": a politer name, or another room) nothing is ruled out. Else the word stays, refused with "say
    which"."""
    if any(t.kind == "CORRECTION" for t in items):
        return items  # "the toilet, I mean the bathroom": a politer name for one room, or another room: a guess
    named = {
        t.words[0]
        for k, t in enumerate(items)
        if t.kind == "PLACE"
        and t.words
        and t.words[0] not in activities
        and k
        and (
            items[k - 1].kind in _GOING
            and not items[k - 1].surface.startswith("us")
            or items[k - 1].kind in ("AND", "OR")
            and k >= 2
            and items[k - 2].kind in ("PLACE", "WORD")  # "the bathroom or the toilet": a list of two rooms
        )
    }  # named as where to go, pass or keep out of ("go to the toilet"), not beside ("the bathroom, the toilet") and
    # not as a room used ("and use the toilet": the bathroom may be the room whose toilet is used)
    if not named:
        return items
    out: list[Token] = []
    for k, t in enumerate(items):
        kinds = places.ambiguous.get((t.surface,)) if t.kind == "WORD" else None
        left = [w for w in kinds if w not in named] if kinds else []
        told = any(u.surface in _TELLING for u in items[k + 1 : k + 4])  # "the bathroom where the toilet is"
        told |= (
            k >= 2
            and items[k - 1].kind == "COMMA"
            and items[k - 2].kind == "PLACE"
            and not (k >= 3 and items[k - 3].kind == "NEG")
        )  # "the loo, the bathroom" (but "not the toilet, the bathroom" names it again)
        if kinds and len(left) == 1 and len(left) < len(kinds) and not told:
            out.append(Token("PLACE", t.surface, (left[0],), start=t.start, end=t.end))
        else:
            out.append(t)
    return out

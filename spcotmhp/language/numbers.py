"""Numbers inside place names (rules 4 and 5 of :mod:`spcotmhp.language.said_names`): which words are numbers,
which labels hold one, and the variants a name holding a number may be said in. Kept apart from the name store so
that the lexicon and the teaching reader use it without importing either."""

from __future__ import annotations

import itertools
from collections.abc import Iterable, Sequence

MAX_NUMBER_DIGITS = 18
"""Most digits of a number in a name (int64 holds 18 whole): "room 101", "aisle 12"; a longer digit string (a
serial number) is a plain word, and is never converted (Python refuses int() of over 4,300 digits)."""

MAX_VARIANTS = 64
"""Most spellings of one name matched (rule 5): four number words of four spellings each."""

ORDINALS = {
    "first": 1, "second": 2, "third": 3, "fourth": 4, "fifth": 5, "sixth": 6, "seventh": 7, "eighth": 8,
    "ninth": 9, "tenth": 10, "eleventh": 11, "twelfth": 12, "thirteenth": 13, "fourteenth": 14, "fifteenth": 15,
    "sixteenth": 16, "seventeenth": 17, "eighteenth": 18, "nineteenth": 19, "twentieth": 20,
}  # fmt: skip
"""English ordinal words and their values (rule 5; floor ordinals, :mod:`spcotmhp.language.floors`)."""

CARDINALS = {
    "one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7, "eight": 8, "nine": 9, "ten": 10,
    "eleven": 11, "twelve": 12, "thirteen": 13, "fourteen": 14, "fifteen": 15, "sixteen": 16, "seventeen": 17,
    "eighteen": 18, "nineteen": 19, "twenty": 20,
}  # fmt: skip
"""English cardinal words and their values (rule 5; floor numbers, :mod:`spcotmhp.language.floors`)."""
_CARDINAL_WORDS = {n: w for w, n in CARDINALS.items()}
_ORDINAL_WORDS = {n: w for w, n in ORDINALS.items()}
_SUFFIXES = {1: "st", 2: "nd", 3: "rd"}


def number_word(word: str) -> tuple[str, int] | None:
    """("cardinal", n) for digits or a cardinal word ("101", "one"), ("ordinal", n) for an ordinal word or digits
    with their suffix as one word ("second", "2nd"), None otherwise.

    >>> number_word("one"), number_word("101"), number_word("second"), number_word("2nd"), number_word("aisle")
    (('cardinal', 1), ('cardinal', 101), ('ordinal', 2), ('ordinal', 2), None)
    """
    if len(word) > MAX_NUMBER_DIGITS + 2:  # digits and an ordinal's suffix
        return None
    if word.isascii() and word.isdigit():
        return ("cardinal", int(word)) if len(word) <= MAX_NUMBER_DIGITS else None
    if word in CARDINALS:
        return "cardinal", CARDINALS[word]
    if word in ORDINALS:
        return "ordinal", ORDINALS[word]
    if len(word) > 2 and word[:-2].isascii() and word[:-2].isdigit() and word[-2:] == _suffix(int(word[:-2])):
        return "ordinal", int(word[:-2])
    return None


def _suffix(n: int) -> str:
    return "th" if 10 <= n % 100 <= 20 else _SUFFIXES.get(n % 10, "th")


def numbered_labels(labels: Iterable[str]) -> list[str]:
    """The labels (space-separated words) that hold a number word and another word (rule 4: the names the
    instruction lexicon matches whole, :func:`said_variants`)."""
    out = []
    for label in labels:
        words = label.split()
        kinds = [number_word(w) for w in words]
        if len(words) > 1 and any(kinds) and not all(kinds):
            out.append(label)
    return list(dict.fromkeys(out))


def said_variants(words: Sequence[str]) -> list[tuple[str, ...]]:
    """Rule 5: the units an English name may be said in (the name itself first), at most :data:`MAX_VARIANTS`. A
    name that opens with a cardinal ("101 room", "two aisle": how a model folder written before names were kept
    labels "room 101" and "aisle two") is said with it last too.

    >>> said_variants(["aisle", "one"])
    [('aisle', 'one'), ('aisle', '1'), ('aisle', 'number', 'one'), ('aisle', 'number', '1')]
    >>> said_variants(["second", "bedroom"])
    [('second', 'bedroom'), ('2', 'nd', 'bedroom')]
    >>> said_variants(["101", "room"])[:3]
    [('101', 'room'), ('number', '101', 'room'), ('room', '101')]
    """
    out = _spellings(words)
    first = number_word(words[0]) if words else None
    if first is not None and first[0] == "cardinal" and len(words) > 1:
        out += _spellings([*words[1:], words[0]])
    return list(dict.fromkeys(out))[:MAX_VARIANTS]


def _spellings(words: Sequence[str]) -> list[tuple[str, ...]]:
    """The units of ``words`` with each number in each of its spellings (:func:`said_variants`)."""
    options: list[list[tuple[str, ...]]] = []
    for w in words:
        said = number_word(w)
        if said is None:
            options.append([(w,)])
        elif said[0] == "cardinal":
            forms: list[tuple[str, ...]] = [(w,), (str(said[1]),)]
            if said[1] in _CARDINAL_WORDS:
                forms.append((_CARDINAL_WORDS[said[1]],))
            forms = list(dict.fromkeys(forms))
            options.append(forms + [("number", *f) for f in forms])
        else:
            options.append(
                list(dict.fromkeys([(w,), (_ORDINAL_WORDS.get(said[1], w),), (str(said[1]), _suffix(said[1]))]))
            )
    return [
        tuple(u for part in combo for u in part)
        for combo in itertools.islice(itertools.product(*options), MAX_VARIANTS)
    ]

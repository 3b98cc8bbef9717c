"""Floor phrases: the words that say which floor of a building a place is on, read into one FLOOR token whose value
is the floor as said.

A value is an ``int`` (the floor's index as the words number it: "the second floor", "floor 2", "level two",
2階, 2F -> 2; "the Nth floor" is the floor of index N, whatever a country calls its ground floor), ``"upstairs"``
or ``"downstairs"`` (the next floor up or down from the start's: "upstairs", "on the floor above", 上の階), or a
floor's name as said (``"ground"``, ``"top"``, ``"basement"``, ``"bottom"``: "on the ground floor", 地下). A
building's planner resolves the value against its floors (:mod:`spcotmhp.building`); a one-floor map refuses it.

English (on word units, before the fillers are left out, as lengths of time are): an optional "on" / "at", then
"the <ordinal> floor|level|storey|story" ("the 2nd floor", "the ground floor", "the top floor"), "floor|level
<number>" ("floor 3", "level two"), "the floor above|below", "one floor up|down", "upstairs", "downstairs". A floor
phrase right before "to" / "into" is one FLOOR_TO token ("go upstairs to the bedroom"): the grammar accepts it only
after a verb of going, so "via the kitchen upstairs to the bedroom" (whose kitchen is upstairs?) is refused.

Japanese (on characters): a number or kanji numeral before 階 or F (2階, 二階, 3F), 地下(N)階, 上の階 / 下の階 (also
一つ上の階), each with an optional の or にある after it: 2階の寝室.

>>> floor_en(["on", "the", "second", "floor"], 0), floor_en(["floor", "3"], 0), floor_en(["upstairs"], 0)
((2, 4), (3, 2), ('upstairs', 1))
>>> floor_ja("2階の寝室"), floor_ja("上の階の寝室"), floor_ja("地下の倉庫")
((2, 3), ('upstairs', 4), ('basement', 3))
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from spcotmhp.language.numbers import CARDINALS, ORDINALS

FloorValue = int | str
"""A floor as said: its index, "upstairs" / "downstairs", or a name (module docstring)."""

MAX_FLOOR_INDEX = 200
"""Highest floor number a phrase may say (a larger one is no floor of a building)."""

_NOUNS = frozenset({"floor", "level", "storey", "story"})
_SUFFIXES = frozenset({"st", "nd", "rd", "th"})
_NAMES = frozenset({"ground", "top", "basement", "bottom"})
_UP = {"up": "upstairs", "above": "upstairs", "down": "downstairs", "below": "downstairs"}
_RELATIVE = frozenset({"upstairs", "downstairs"})
CUES = _NOUNS | _RELATIVE
"""Units without which an English sentence holds no floor phrase (a sentence with none is not scanned)."""
_ARTICLES = ("the", "a")


def floor_en(units: Sequence[object], i: int) -> tuple[FloorValue, int] | None:
    """(value, number of units) of the floor phrase starting at ``units[i]``, or None (module docstring)."""
    j = i + (_at(units, i) in ("on", "at"))
    k = j + (_at(units, j) in _ARTICLES)
    word, nxt = _at(units, k), _at(units, k + 1)
    if word.isdigit() and nxt in _SUFFIXES and _at(units, k + 2) in _NOUNS:  # "2nd floor": units "2", "nd"
        number = _number(word)
        return None if number is None else (number, k + 3 - i)
    if j == i and k == i and word in _RELATIVE:
        return word, 1
    if word in ORDINALS and nxt in _NOUNS:
        return ORDINALS[word], k + 2 - i
    if word in _NAMES and nxt in _NOUNS:
        return word, k + 2 - i
    if word in _NOUNS and k > j and nxt in _UP and nxt in ("above", "below"):
        return _UP[nxt], k + 2 - i  # "the floor above"
    if word in ("one", "a") and nxt in _NOUNS and _at(units, k + 2) in _UP:
        return _UP[_at(units, k + 2)], k + 3 - i  # "one floor up"
    if word in _NOUNS and k == j:
        number = _number(nxt)
        if number is not None:
            return number, k + 2 - i  # "floor 2", "on level three"
    return None


def _at(units: Sequence[object], i: int) -> str:
    return units[i] if i < len(units) and isinstance(units[i], str) else ""  # type: ignore[return-value]


def _number(unit: str) -> int | None:
    if unit in CARDINALS:
        return CARDINALS[unit]
    if unit.isdigit() and len(unit) <= 3 and 0 <= int(unit) <= MAX_FLOOR_INDEX:
        return int(unit)
    return None


_KANJI = "一二三四五六七八九十"
_JA_FLOOR = re.compile(
    rf"(?:(?P<n>\d{{1,3}}|[{_KANJI}]{{1,3}})(?:階|[Ff](?![A-Za-z]))"
    r"|(?P<b>地下)(?:(?P<bn>\d{1,2}|[一二三四五六七八九])階)?"
    r"|(?:一つ|ひとつ)?(?P<rel>上|下)の(?:階|フロア))"
    r"(?:の|にある)?"
)


def floor_ja(text: str) -> tuple[FloorValue, int] | None:
    """(value, number of characters) of the floor phrase at the start of ``text``, or None (module docstring);
    地下N階 is the name "basement" (a building numbers its floors; B1 and B2 are told apart by their names)."""
    m = _JA_FLOOR.match(text)
    if m is None:
        return None
    if m.group("rel"):
        return ("upstairs" if m.group("rel") == "上" else "downstairs"), len(m.group(0))
    if m.group("b"):
        return "basement", len(m.group(0))
    number = _kanji_number(m.group("n"))
    if number is None or not 0 <= number <= MAX_FLOOR_INDEX:
        return None
    return number, len(m.group(0))


def _kanji_number(text: str) -> int | None:
    """12, 十二, 二十 -> 12, 12, 20 (digits or kanji numerals up to 99)."""
    if text.isdigit():
        return int(text)
    if "十" not in text:
        return _KANJI.index(text) + 1 if len(text) == 1 else None
    tens, _, ones = text.partition("十")
    if len(tens) > 1 or len(ones) > 1 or "十" in ones:
        return None
    return (_KANJI.index(tens) + 1 if tens else 1) * 10 + (_KANJI.index(ones) + 1 if ones else 0)


def describe_floor(value: FloorValue) -> str:
    """E.g. "on floor 2", "upstairs", "on the ground floor"."""
    if isinstance(value, int):
        return f"on floor {value}"
    if value in _RELATIVE:
        return value
    return f"on the {value} floor"

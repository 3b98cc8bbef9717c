"""Talk said to someone else before the robot is addressed (issue 34): "Kids, watch this. Robot, go to the living
room!", "Jake, stop pushing it! Sorry. Robot, please go to the kitchen.", "えーこの人だれだっけ あロボット台所行ってて",
"え待ってこのCMかわいい ロボットは物置き行って".

A speaker who calls the robot by its name (the table's ``talk.robot_names``: "robot", ロボット, ロボ, with
さん / くん / ちゃん) turns to it there: what was said before the name, in the same utterance, was said to someone
else (the children, the television, a partner). It is passed over, and said in the explanation, when it names no
place, no length of time and no word of a class that says how or where to go (``_SAID_TO_OTHERS`` lists the classes
it may hold: words, pauses, a correction or a "stop" to someone else), no word of time, manner, way, number or order
(the table's ``talk.meaning``: "Tonight. Robot, go to the kitchen." may say when), and the part after the name
names a place.
English: the name opens a sentence (after a full stop, "!" or "?"), so a name said as a subject ("the robot is
blocking the door") is none. Japanese: the name is followed by a pause, a space, the topic's は or the instruction
itself, never by が / を / の / に (ロボットが動くよ: the robot as a subject, not addressed).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence

from spcotmhp.language.placewords import Token
from spcotmhp.language.rewrite_en import NUMBERS
from spcotmhp.language.table import WordTable

_SAID_TO_OTHERS = frozenset(
    {"WORD", "COMMA", "_STOP", "IS", "AND", "IT", "THAT", "OF", "LINK", "ALL", "HALT", "CORRECTION", "NO", "NEG",
     "DE", "ALTERNATIVE", "FROM"}
)  # fmt: skip
_SENTENCE_ENDS = frozenset({".", "!", "?"})
_JA_AFTER = r"(?:さん|はん|くん|君|ちゃん|公)?(?=[、,。！？!?\s]|は|(?![がをのにへとで]))"


def before_the_address(
    toks: Sequence[Token], table: WordTable, units: Sequence[str] | str
) -> tuple[list[Token], list[str]] | None:
    """``toks`` without what was said before the robot's name to someone else, and that talk as said; None when the
    sentence holds no such talk (module docstring). ``units``: the English units or the Japanese sentence (spaces
    left out when the tokens index it) that the tokens' ``start`` index."""
    names = tuple(table.talk.get("robot_names", ()))
    if not names or not toks:
        return None
    span = _address_ja(str(units), names) if table.by_character else _address_en(list(units), names)
    if span is None:
        return None
    at, end = span
    before = [t for t in toks if t.start < at]
    after = [t for t in toks if t.start >= at and not (t.kind == "WORD" and t.end <= end)]  # ロボットはん: はん
    named = len(after) < len([t for t in toks if t.start >= at])
    topic = table.by_character and bool(after) and after[0].kind == "WORD" and after[0].surface == "は"
    after = after[topic:]  # ロボットさんは リビングへ: the topic's は after the name says whom the speaker asks
    said_to = before or topic or named
    meaning = frozenset(table.talk.get("meaning", ())) | frozenset(table.talk.get("times_in_statements", ()))
    meaning -= {"this", "that", "am"}  # "Kids, watch this.", "Am I muted?": a time only with a noun or a number
    if not any(t.kind == "PLACE" for t in after) or not said_to or not all(_to_others(t) for t in before):
        return None
    if any(_means(t, meaning, table.by_character) for t in before):
        return None  # "Tonight. Robot, go to the kitchen.", "The short way.", 明日 ロボット: may be the robot's
    joiner = "" if table.by_character else " "
    said = joiner.join(t.surface for t in before if t.kind not in ("COMMA", "_STOP"))
    return after, [said] if said else ["は"]


def _means(tok: Token, meaning: frozenset[str], by_character: bool) -> bool:
    """Whether a word said before the name may carry navigation meaning for the robot: a time, a manner, a way, a
    number or an order word (the table's ``talk.meaning`` and ``times_in_statements``, checked in each word; in
    Japanese inside the run of characters)."""
    if tok.kind != "WORD":
        return False
    if by_character:
        return any(w in tok.surface for w in meaning if len(w) > 1) or any(ch.isdigit() for ch in tok.surface)
    from spcotmhp.language.english_words import base

    words = tok.surface.split()
    return any(w in meaning or base(w) in meaning or w in _WAYS or w.isdigit() or w in _NUMBER_WORDS for w in words)


_WAYS = frozenset({"way", "route", "short", "long", "usual", "backwards", "stairs", "round", "around", "number"})
_NUMBER_WORDS = (frozenset(NUMBERS) - {"a", "an"}) | {"first", "second", "third", "last"}


def _to_others(tok: Token) -> bool:
    """Whether a token may be said to someone else: a class of :data:`_SAID_TO_OTHERS`, or a bare に / へ
    (CMのうちに: while the advertisement runs), which marks no place of the map where none is said."""
    return tok.kind in _SAID_TO_OTHERS or tok.kind == "GOAL" and tok.surface in ("に", "へ")


def _address_en(units: list[str], names: tuple[str, ...]) -> tuple[int, int] | None:
    """The span of the last unit that calls the robot by name at a sentence's start (after "." "!" or "?")."""
    for p in range(len(units) - 1, 0, -1):
        if units[p] in names and units[p - 1] in _SENTENCE_ENDS:
            return p, p + 1
    return None


@functools.cache
def _name_pattern(names: tuple[str, ...]) -> re.Pattern[str]:
    """The robot's names, longest first, with what may follow an address (:data:`_JA_AFTER`), compiled once."""
    return re.compile("(?:" + "|".join(sorted(map(re.escape, names), key=len, reverse=True)) + ")" + _JA_AFTER)


def _address_ja(text: str, names: tuple[str, ...]) -> tuple[int, int] | None:
    """The span (character indices, spaces left out) of the last place the robot is called by name, with its
    honorific (ロボットはん, ロボ公) and the pause after it."""
    chars = "".join(ch for ch in text if not ch.isspace())
    pattern = _name_pattern(names)
    found = [(m.start(), m.end()) for m in pattern.finditer(chars)]
    return found[-1] if found else None

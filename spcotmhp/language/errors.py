"""The refusal of a sentence the grammar has no derivation for: one :class:`~spcotmhp.errors.InstructionError`
naming the first word it could not place, and why.

* Words of no class that are no place word (WORD tokens): :class:`~spcotmhp.errors.UnknownPlaceWord` naming all of
  them, with near misses ("did you mean 'bedroom'?") and, when the sentence also holds a refused word, its reason.
  A sentence with no place word at all says so.
* A word of a refusal class of the word table (conditions, corrections, ordinals, ...) where the grammar does not
  accept it, or the grammar's first unacceptable token when such a word comes before it ("no kitchen"):
  :class:`~spcotmhp.errors.UnsupportedPhrase` with the class's reason.
* A word of a class the table says why it cannot stand there ("in" between two places, "avoid" after "not"):
  that reason.
* A marker at the end ("go to the bedroom avoiding"): :class:`~spcotmhp.errors.MalformedInstruction`.
* Any other word the grammar does not accept where it stands: :class:`~spcotmhp.errors.UnsupportedPhrase` naming it
  and the word before it.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from typing import Any

from spcotmhp.errors import (
    AmbiguousPlace,
    InstructionError,
    MalformedInstruction,
    NotUnderstood,
    UnknownPlaceWord,
    UnsupportedPhrase,
)
from spcotmhp.language.lexicon import english_units
from spcotmhp.language.placewords import Token, place_lexicon
from spcotmhp.language.table import WordTable
from spcotmhp.language.wording import excerpt, named, not_understood, unknown_tail

_MODIFIER_BEFORE_PLACE = ("FIRST", "LAST")
_JA_MARKERS = ("GOAL", "GOAL_THEN", "ON_WAY_TO", "VIA", "VIA_THEN", "STOP", "STOP_THEN", "AVOID", "NOT_GOAL")
"""Japanese markers: they follow the place they mark."""
_BLAME_FIRST = ("BACK", "NO", "HERE", "INSTEAD", "HALT", "WAIT")
"""Words that make the word after them unacceptable rather than the other way round ("come back here": 'come
back' is what cannot be done)."""


MAX_MESSAGE = 400
"""Longest refusal message (characters): the words named and why come first, the lists last."""


def refusal(
    toks: Sequence[Token], bad: Any, table: WordTable, place_words: Sequence[str], text: str
) -> InstructionError:
    """The error for ``toks`` when the parser stopped at ``bad`` (a lark Token whose ``start_pos`` is its index in
    ``toks``; ``$END`` or None at the end), its message cut to :data:`MAX_MESSAGE` characters."""
    error = _refusal(toks, bad, table, place_words, text)
    message = str(error)
    if len(message) > MAX_MESSAGE:
        error = type(error)(message[: MAX_MESSAGE - 1] + "…")
    return error


def _refusal(
    toks: Sequence[Token], bad: Any, table: WordTable, place_words: Sequence[str], text: str
) -> InstructionError:
    at = bad.start_pos if bad is not None and getattr(bad, "type", "$END") != "$END" else len(toks)
    unknown = [t.surface for t in toks if t.kind == "WORD"]
    refused = _first_refused(toks, table)
    ambiguous = _ambiguous(toks, table, place_words)
    if ambiguous and refused is None and not any(t.kind in ("FLOOR", "FLOOR_TO") for t in toks):
        return AmbiguousPlace(ambiguous)
    if not any(t.kind == "PLACE" for t in toks):
        said = [w for w in unknown if w not in table.nouns]
        return UnknownPlaceWord(
            f"no known place word in {excerpt(text)}{not_understood(said)}{_also(toks, refused, table)}"
            f"{unknown_tail(unknown, place_words)}"
        )
    clock = _clock(toks, text) if not table.by_character else None
    if clock is not None:
        return UnsupportedPhrase(
            f"{excerpt(clock)} is a time of day, but a plan is for now: say it when the robot should go"
        )
    if refused is not None:
        tail = f" (not understood: {', '.join(unknown)})" if unknown else ""
        return UnsupportedPhrase(f"{_reason(toks, refused, table.reasons[toks[refused].kind])}{tail}")
    if unknown:
        where = [k for k, t in enumerate(toks) if t.kind == "WORD" and _place_expected(toks, k, table, text)]
        other = [k for k, t in enumerate(toks) if t.kind == "WORD" and k not in where]
        if not where:  # words of no class where no place is expected: not understood, not unknown places
            said = _phrases(toks, other, text, table.by_character)
            words = ", ".join(excerpt(p, 30) for p in said[:6])
            verb = "is" if len(said) == 1 else "are"
            return NotUnderstood(
                f"{words} {verb} not understood: no place, way of going or other part of an instruction this robot "
                "follows (it moves only: say where to go, what to pass and what to avoid)"
            )
        placed = [_placed(toks, k, table) for k in where]
        verb = "is not a known place word" if len(where) == 1 else "are not known place words"
        rest = f"; {', '.join(excerpt(toks[k].surface, 30) for k in other[:4])} not understood" if other else ""
        return UnknownPlaceWord(f"{', '.join(placed[:6])} {verb}{rest}{unknown_tail(unknown, place_words)}")
    if at >= len(toks):
        if toks and toks[-1].kind in _BLAME_FIRST and toks[-1].kind in table.misplaced:
            return UnsupportedPhrase(table.misplaced[toks[-1].kind].format(**_around(toks, len(toks) - 1)))
        last = toks[-1].surface if toks else text
        return MalformedInstruction(
            f"{excerpt(last)} is followed by no known place word; say which place, e.g. 'avoiding the kitchen'"
        )
    return _misplaced(toks, at, table, text)


def _misplaced(toks: Sequence[Token], at: int, table: WordTable, text: str) -> InstructionError:
    """The error for a known word the grammar does not accept where it stands (``toks[at]``)."""
    tok = toks[at]
    nxt = toks[at + 1] if at + 1 < len(toks) else None
    if tok.kind in _MODIFIER_BEFORE_PLACE and nxt is not None and nxt.kind == "PLACE":
        return UnsupportedPhrase(_reason(toks, at, table.reasons["MODIFIER"]))
    if tok.kind == "AT" and nxt is not None and nxt.kind == "DURATION":  # "in ten minutes": quoted whole
        said = {"word": excerpt(f"{tok.surface} {nxt.surface}")}
        return UnsupportedPhrase(table.misplaced["AT_DURATION"].format(**{**_around(toks, at), **said}))
    if table.by_character and tok.kind in _JA_MARKERS and (at == 0 or toks[at - 1].kind != "PLACE"):
        where = "say which place (廊下を通って)"
        return MalformedInstruction(f"{excerpt(tok.surface)} follows no known place word; {where}")
    if tok.kind == "PLACE" and at > 0 and toks[at - 1].kind == "PLACE":
        gap = _between(text, toks[at - 1], tok) if not table.by_character else []
        pair_said = f"{excerpt(toks[at - 1].surface)} and {excerpt(tok.surface)}"
        where = f"{named(gap)} between {pair_said}" if gap else f"{pair_said} side by side"
        return UnsupportedPhrase(
            f"{where} do not say how the two places relate; join places with 'and' or 'then', or give each its own "
            "word ('via the corridor', 'to the bedroom')"
        )
    if at >= 2 and toks[at - 2].kind == "FLOOR" and toks[at - 1].kind == "PLACE" and "FLOOR" in table.misplaced:
        return UnsupportedPhrase(table.misplaced["FLOOR"].format(**_around(toks, at - 2)))  # 2階の風呂に一番近い
    pair = f"{toks[at - 1].kind}>{tok.kind}" if at > 0 else ""
    if pair in table.misplaced:
        return UnsupportedPhrase(table.misplaced[pair].format(**_around(toks, at)))
    blame = [at - 1, at] if at > 0 and toks[at - 1].kind in _BLAME_FIRST else [at]
    for k in blame:
        if toks[k].kind in table.misplaced:
            return UnsupportedPhrase(table.misplaced[toks[k].kind].format(**_around(toks, k)))
    before = f" after {excerpt(toks[at - 1].surface)}" if at > 0 else " there"
    return UnsupportedPhrase(
        f"{excerpt(tok.surface)} cannot stand{before}; say where to go ('to the kitchen'), what to pass ('via the "
        "corridor') and what to avoid ('avoiding the bath')"
    )


_PLACE_MARKERS = frozenset(
    "TO VIA STOP_AT AVOID ENTER NEG END_AT ON_WAY_TO INSTEAD_OF WITHOUT CLOSEST FARTHEST NEXT_TO BETWEEN NEAREST "  # noqa: SIM905
    "LARGEST SMALLEST WHICHEVER ONE_OF ALL ANY_ONE BACK BEFORE AFTER AT OF".split()
)
"""Classes after which a place is expected ("go to the garage", "avoid the loft", "next to the porch")."""
_JOINS = ("AND", "THEN", "OR", "COMMA", "BUT")


def _noun(word: str) -> bool:
    """A word lemminflect knows as a noun and not as a verb's base form (an order starts with one), or does not
    know at all (a place's name may be a word of its own)."""
    from spcotmhp.language.english_words import infinitive, pos

    pos_ = pos(word)
    return not pos_ or "NOUN" in pos_ and not infinitive(word)


def _ambiguous(toks: Sequence[Token], table: WordTable, place_words: Sequence[str]) -> str:
    """The message for a word that may name places of several kinds ("bathroom"), or ""."""
    lexicon = place_lexicon(table, tuple(place_words))
    for t in toks:
        if t.kind != "WORD":
            continue
        key = table.units(t.surface) if table.by_character else (t.surface,)
        names = lexicon.ambiguous.get(key)
        if names:
            return f"{excerpt(t.surface)} may name the {', the '.join(names[:-1])} or the {names[-1]} here: say which"
    return ""


def _place_expected(toks: Sequence[Token], k: int, table: WordTable, text: str) -> bool:
    """Whether an unknown word stands where a place would: after a marker that takes one, before or after a place
    word (a name of two words), or, in Japanese, before a marker that follows its place (ガレージへ)."""
    before = toks[k - 1] if k > 0 else None
    after = toks[k + 1] if k + 1 < len(toks) else None
    if toks[k].surface[:1].isdigit():
        return False  # "at 6": a time, not a place
    if before is not None and (before.kind in _PLACE_MARKERS or before.kind == "PLACE"):
        return True
    if before is not None and before.kind in _JOINS and not table.by_character:
        units = english_units(text)
        said_the = 0 < toks[k].start <= len(units) and units[toks[k].start - 1] in ("the", "a", "an", "my", "our")
        if said_the or _noun(toks[k].surface):
            return True  # "the kitchen and the attic" (a noun), not "and open the fridge" (an order)
    if after is not None and after.kind == "PLACE":
        return True
    if table.by_character and after is not None and after.kind in _JA_MARKERS + ("CLOSEST", "FARTHEST", "NEXT_TO"):
        return True
    if table.by_character:  # a noun (or a word janome does not know) names a place where one may stand
        from spcotmhp.language.talk_ja import _analyse

        first = _analyse(toks[k].surface)[:1]
        return not first or first[0][1] == "名詞" and first[0][2] not in ("代名詞", "非自立", "数", "接尾")
    if (
        before is not None
        and before.kind == "WORD"
        and _place_expected(toks, k - 1, table, text)
        and not table.by_character
    ):
        return before.kind == "WORD" and k >= 2 and toks[k - 2].kind in _PLACE_MARKERS  # "to the laundry room"
    return False


def _first_refused(toks: Sequence[Token], table: WordTable) -> int | None:
    """The first word of a refusal class that the sentence cannot accept: not a modifier of an unknown word ("the
    front door": the unknown word is what is not understood)."""
    for k, tok in enumerate(toks):
        if tok.kind not in table.reasons:
            continue
        if tok.kind == "MODIFIER" and k + 1 < len(toks) and toks[k + 1].kind == "WORD":
            continue
        if tok.kind == "FROM" and table.by_character and (k == 0 or toks[k - 1].kind != "PLACE"):
            continue  # から after no place: "because" (赤ちゃん寝てるから), whose words are what is not understood
        return k
    return None


def _placed(toks: Sequence[Token], k: int, table: WordTable) -> str:
    """An unknown word with the word it stands next to: "'garage' (after 'to')", "'ガレージ' (before 'へ行って')"."""
    before_place = k + 1 < len(toks) and toks[k + 1].kind == "PLACE"
    j = k + 1 if table.by_character or before_place else k - 1
    if 0 <= j < len(toks) and toks[j].kind != "WORD":
        side = "before" if j > k else "after"
        return f"{excerpt(toks[k].surface, 30)} ({side} {excerpt(toks[j].surface, 30)})"
    return excerpt(toks[k].surface, 30)


def _reason(toks: Sequence[Token], k: int, reason: str) -> str:
    return f"{excerpt(toks[k].surface)} {reason.format(**_around(toks, k))}"


def _also(toks: Sequence[Token], refused: int | None, table: WordTable) -> str:
    return f"; and {_reason(toks, refused, table.reasons[toks[refused].kind])}" if refused is not None else ""


_CLOCK_WORDS = frozenset(
    "one two three four five six seven eight nine ten eleven twelve noon midnight".split()  # noqa: SIM905
)


_CLOCK_AFTER = frozenset({"am", "pm", "o'clock", "oclock", ":"})


def _clock(toks: Sequence[Token], text: str) -> str | None:
    """ "at 6", "at six", "at noon", "at 6pm": a time of day after "at" (never a place), as said, or None."""
    units = english_units(text)
    for k, t in enumerate(toks[:-1]):
        nxt = toks[k + 1]
        if (
            t.kind == "AT"
            and t.surface == "at"
            and nxt.kind == "WORD"
            and (nxt.surface in _CLOCK_WORDS or re.fullmatch(r"\d{1,2}(?::\d{2})?(?:am|pm)?", nxt.surface))
        ):
            end = nxt.end
            while end < len(units) and (units[end] in _CLOCK_AFTER or units[end].isdigit() and units[end - 1] == ":"):
                end += 1  # "at 6 pm", "at 6:30"
            return " ".join(units[t.start : end])
    return None


def _phrases(toks: Sequence[Token], ks: Sequence[int], text: str, by_character: bool) -> list[str]:
    """The words at token indices ``ks`` as the phrases they were said in: next to each other, or with only
    fillers between them, they are one ("'follow me'", "'open the door'", the fillers quoted as said)."""
    runs: list[list[int]] = []
    for k in ks:
        if runs and runs[-1][-1] == k - 1:
            runs[-1].append(k)
        else:
            runs.append([k])
    if by_character:
        return ["".join(toks[k].surface for k in run) for run in runs]
    units = english_units(text)
    return [
        " ".join(units[toks[_with(toks, run[0])].start : toks[run[-1]].end]) or toks[run[0]].surface for run in runs
    ]


def _with(toks: Sequence[Token], k: int) -> int:
    """The start of "with the (big) window" for the word at ``k``: a thing a place is told by is quoted with its
    "with" and its sizes."""
    j = k
    while j > 0 and toks[j - 1].kind in ("MODIFIER", "LARGEST", "SMALLEST"):
        j -= 1
    return j - 1 if j > 0 and toks[j - 1].kind == "LINK" and toks[j - 1].surface == "with" else k


def _between(text: str, a: Token, b: Token) -> list[str]:
    """The words left out between two tokens (fillers) of an English sentence."""
    return english_units(text)[a.end : b.start]


def _around(toks: Sequence[Token], at: int) -> dict[str, str]:
    """The words a misplaced-word message may quote: the word, the word before it, and the places around it."""
    before = next((t.surface for t in reversed(toks[:at]) if t.kind == "PLACE"), "")
    after = next((t.surface for t in toks[at + 1 :] if t.kind == "PLACE"), "")
    return {
        "word": excerpt(toks[at].surface),
        "prev": excerpt(toks[at - 1].surface) if at > 0 else "''",
        "before": excerpt(before),
        "after": excerpt(after),
        "choice": " or ".join(p for p in (before, after) if p),
        "place": after or before or "place",
    }

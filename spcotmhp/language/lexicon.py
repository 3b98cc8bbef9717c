"""Words -> terminals: a normalised sentence cut into the tokens its grammar reads (``grammars/<lang>.json`` gives the
word classes; the model gives the place words).

Rules, in this order (English; Japanese below):

1. The text is normalised (:func:`spcotmhp.language.text.normalise`) and cut into units: words (inner apostrophes
   kept) and the punctuation that separates clauses; a hyphen inside a word is a space ("living-room").
1b. A word written as a dialect says it is read as the word it spells (the table's ``spellings``: Scots "ye",
   "wi", "dinnae"), one unit for one unit (a refusal quotes the standard word).
2. Lengths of time become one DURATION token: an optional "for", a number (digits or a number word, "a", "an",
   "half a") and a unit (seconds, minutes, hours): "for two minutes" is 120 s. Floor phrases ("on the second
   floor", "upstairs") become one FLOOR token, or FLOOR_TO before "to" (:mod:`spcotmhp.language.floors`).
3. Fillers (the table's small closed class: articles, politeness, hesitations) are left out, single words first,
   then filler phrases; nothing else is ever left out.
4. Longest match, place words winning ties, against the place words and the table's phrases (each phrase as its
   units with the fillers left out, so "on the way" also matches "on way"). A place word also matches written
   without its apostrophe ("alices"), as its compound written open or glued ("bed room", "livingroom"), and in
   the plural ("bedrooms", by the noun lemmas of lemminflect), a compass point as its adjective ("eastern") and
   "east" by its initial as on signs ("the E corridor"; not "n", "s", "w": texting's and, is, with): spellings
   of the same word, not guesses.
5. A generic noun of the table ("room") right after a place word belongs to its name ("living room"); adjacent
   place words form one name ("east corridor"). Any other unit is a WORD: no rule of the grammar accepts it.
6. A number with a place word names the instance the robot shows with it ("bedroom 2", "bedroom #2", "bedroom
   number two", "number two bedroom", 寝室2, 2番の寝室: the plan's "bedroom #2";
   :func:`~spcotmhp.language.rewrite_en.instance_number`).
7. A relation said around the name is the relation after it ("the nearest bedroom to the kitchen", "the farthest
   bedroom from the bath", "of the three bedrooms, the one nearest the bath").
8. Commas that separate nothing are left out; "no, wait," is one correction; a number alone after a negation or
   a correction names that instance of the place said last.

Rules 6-8 in English: :mod:`spcotmhp.language.rewrite_en`.

Japanese: units are characters; the longest match (rule 4) runs on characters over the place words (also in
hiragana for a katakana name, and after an honorific お/ご) and the table's phrases; fillers are left out after
matching; a run of unmatched characters is one WORD. Digits before 秒, 分 or 時間 are a DURATION.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from spcotmhp.language.endings_en import along_only_en, asked_then_there_en, chosen_en, emphasis_en, go_and_come_en
from spcotmhp.language.floors import CUES, floor_en
from spcotmhp.language.forms_en import (
    any_but_en,
    located_en,
    loose_ends_en,
    motion_at_en,
    new_clause_en,
    no_stop_en,
    owners_and_sides,
    timed_stops_en,
    wait_by_en,
    withdrawals_en,
)
from spcotmhp.language.lexicon_ja import glue_ja, join_no, numbered_ja, tokens_ja
from spcotmhp.language.merging import merge
from spcotmhp.language.others import other_than_excluded
from spcotmhp.language.placewords import PlaceLexicon, Token, contrasted, longest_match, place_lexicon
from spcotmhp.language.repairs_en import apposed_en, echoes_en, taken_back_en
from spcotmhp.language.rewrite_en import NUMBERS as _NUMBERS
from spcotmhp.language.rewrite_en import (
    contents_en,
    corrections_en,
    master_en,
    numbered_en,
    relations_en,
    said_again,
    shared_head_en,
    sizes_en,
)
from spcotmhp.language.rewrite_ja import spoken_tokens
from spcotmhp.language.table import WordTable, en_units, filler_at, word_table
from spcotmhp.language.text import kana_lengths, normalise, without_pictographs

__all__ = ["MAX_WAIT_S", "PlaceLexicon", "Token", "WordTable", "english_units", "place_lexicon", "tokens", "word_table"]

MAX_WAIT_S = 3600.0
"""Longest wait an instruction may ask for (an hour); a longer one is refused (the planner's plans are for now)."""

_INNER_HYPHEN = re.compile(r"(?<=\w)-(?=\w)")
_DASHES = str.maketrans({"\u2013": "-", "\u2014": "-", "\u2015": "-"})
_UNITS = {"second": 1, "seconds": 1, "sec": 1, "secs": 1, "s": 1, "minute": 60, "minutes": 60, "min": 60, "mins": 60,
    "hour": 3600, "hours": 3600, "h": 3600}  # fmt: skip
# "s" and "h" are the SI symbols, as people write a length ("wait there for 3 s", "3s"); a unit counts only right
# after a number (_duration), so a lone "s" or "h" elsewhere is not read as one


def tokens(text: str, table: WordTable, place_words: Sequence[str]) -> list[Token]:
    """The tokens of ``text`` (module docstring)."""
    places = place_lexicon(table, tuple(place_words))
    if table.by_character:
        said = kana_lengths(without_pictographs(normalise(text)))
        out = glue_ja(join_no(merge(numbered_ja(tokens_ja(said, table, places)))))
        return spoken_tokens(out, said)  # rewrite_ja: what people say again, pauses and particles
    out = _tokens_en(normalise(text), table, places)
    kinds = {t.kind for t in out}  # the passes below look only at sentences that hold what they rewrite
    if kinds & {"GO", "TO"}:
        out = located_en(out)  # before a verb of going between two places opens a clause
    if kinds & {"STOP_AT", "AVOID", "GO", "ONE"} and (clauses := new_clause_en(out)) is not out:
        out, kinds = clauses, kinds | {"COMMA"}
    if "MODIFIER" in kinds and "NEG" in kinds:
        out = other_than_excluded(out)  # others.py: "not bedroom 1, one of the other bedrooms"
    if kinds & {"ANY_ONE", "NO", "AT", "ONE_OF"}:
        out = loose_ends_en(out)
    if "NEG" in kinds and kinds & {"STOP_AT", "HALT"}:
        out = no_stop_en(out)
    if "GO" in kinds and ("AT" in kinds or out[0].kind == "TO"):
        out = motion_at_en(out)
    if "WORD" in kinds and "PLACE" in kinds:  # "go to the toilet, then the bathroom": the bath
        out = contrasted(out, places, frozenset(table.talk.get("activities", ())))
    if kinds & {"CORRECTION", "NO", "CANCEL"} and kinds & {"WAIT", "VIA", "SLOW", "FAST", "AVOID"}:
        out = withdrawals_en(out)
    if "COMMA" in kinds or "CORRECTION" in kinds or "NO" in kinds and "WAIT" in kinds:
        out = corrections_en(out)
    if "WORD" in kinds:  # a room told by what is in it (rule 9) always holds a word of no class
        out = contents_en(out, table, places)
    units = english_units(text) if kinds & {"WORD", "ONE", "NEAREST", "CLOSEST", "FARTHEST"} else []
    if "WORD" in kinds or "ONE" in kinds:
        out = numbered_en(out, units)
    if "WORD" in kinds and "PLACE" in kinds:
        out = owners_and_sides(out, places.words)
    out = _said_again_en(merge(out), kinds)
    numbered = kinds & {"NEG", "NO", "CORRECTION"} or any(t.number is not None for t in out)
    if numbered and kinds & {"WORD", "ONE"}:
        out = said_again(out)
    if kinds & {"LARGEST", "SMALLEST"}:
        out = sizes_en(out)
    if "MODIFIER" in kinds:
        out = master_en(out)
    if "AND" in kinds:
        out = shared_head_en(out)
    out = _endings_en(out, kinds, table)
    if "HALT" in kinds and "DURATION" in kinds:
        out = timed_stops_en(out)
    if "WAIT" in kinds:
        out = wait_by_en(out)
    if "BUT" in kinds and "ONE_OF" in kinds:
        out = any_but_en(out)
    if kinds & {"NEAREST", "CLOSEST", "FARTHEST", "NEXT_TO"} and kinds & {"COMMA", "_STOP"}:
        out = apposed_en(out, units)  # repairs_en: "the bedroom, nearest the kitchen"
    if kinds & {"NEAREST", "MODIFIER", "OF"}:
        out = relations_en(out)
    return out


def _endings_en(out: list[Token], kinds: set[str], table: WordTable) -> list[Token]:
    """How an English sentence closes (endings_en): "and come", the emphatic "only", a question "go there"
    answers, and a place gone along alone ("go down the corridor": there)."""
    if kinds & {"AND", "THEN"} and "GO" in kinds:
        out = go_and_come_en(out)
    if "WORD" in kinds and "TO" in kinds:
        out = emphasis_en(out)
    if "VIA" in kinds:
        out = along_only_en(out, frozenset(table.senses))
    if "WORD" in kinds and "PLACE" in kinds:
        out = chosen_en(out)
    if "WORD" in kinds and "THERE" in kinds:
        out = asked_then_there_en(out)
    return out


def _said_again_en(out: list[Token], kinds: set[str]) -> list[Token]:
    """What is said again (repairs_en): a sentence that only echoes an earlier run ("... nearest the laundry. The
    laundry."), and "not X" after a correction, repeating the place it takes back ("X. Sorry, not X, Y")."""
    if "_STOP" in kinds:
        out = echoes_en(out)
    if kinds & {"CORRECTION", "WAIT"} and "NEG" in kinds:
        out = taken_back_en(out)
    return out


def english_units(text: str) -> list[str]:
    """Rule 1: the units of a normalised English sentence (:func:`~spcotmhp.language.table.en_units`)."""
    units = en_units(_INNER_HYPHEN.sub(" ", normalise(text).translate(_DASHES)))
    spelled = word_table("en").spellings  # rule 1b: a dialect's spelling of a word read as the word
    return [spelled.get(u, u) for u in units if u != "..."]  # an ellipsis is a hesitation ("go to the... the bedroom")


def _tokens_en(text: str, table: WordTable, places: PlaceLexicon) -> list[Token]:
    units = english_units(text)
    kept = _without_fillers(_floors_en(_durations_en(units, table.fillers)), table, places)
    if "right" in units:
        kept = [(u, k) for u, k in kept if not (u == "right" and _opening_right(units, k))]
    seq = [u for u, _ in kept]
    plain = all(type(u) is str for u in seq)  # no DURATION token among the units
    out: list[Token] = []
    i = 0
    while i < len(seq):
        unit, start = kept[i]
        if isinstance(unit, Token):
            out.append(unit)
            i += 1
            continue
        hit = longest_match(seq, i, table, places, plain)
        if hit is not None:
            kind, value, n = hit
            end = kept[i + n - 1][1] + 1
            surface = " ".join(units[start:end]) if kind != "PLACE" else " ".join(str(u) for u in seq[i : i + n])
            if kind:
                words = tuple(value.split()) if kind == "PLACE" else ()  # a taught name: its words
                out.append(Token(kind, surface, words, start=start, end=end))
            i += n
            continue
        lemma = places.singular(unit)
        last = out[-1] if out else None
        if unit.endswith("'s") and unit[:-2] in places.words:  # "whichever bedroom's nearest": the place, "is"
            out.append(Token("PLACE", unit[:-2], (unit[:-2],), start=start, end=start + 1))
            out.append(Token("IS", "'s", start=start, end=start + 1))
        elif lemma is not None:
            out.append(Token("PLACE", unit, (lemma,), plural=True, start=start, end=start + 1))
        elif unit in table.nouns and last is not None and last.kind == "PLACE":
            out[-1] = Token("PLACE", f"{last.surface} {unit}", last.words, plural=last.plural, start=last.start,
                            end=start + 1)  # fmt: skip
        elif (fixed := places.misspelt(unit)) is not None:  # "kitchin": the kitchen (PlaceLexicon.misspelt)
            out.append(Token("PLACE", fixed, (fixed,), start=start, end=start + 1))
        else:
            out.append(Token("WORD", unit, start=start, end=start + 1))
        i += 1
    return out


_AFTER_RIGHT = frozenset({",", "so", "then", "off", "ok", "okay", "now", "well", "listen", "let's"})


def _opening_right(units: Sequence[str], k: int) -> bool:
    """ "Right" opening a sentence before a pause or "so", "then", "off" ("Right, could you ...", "right off ye
    go"): the discourse marker of starting something (Cambridge: used to get attention before saying something),
    not the side; a side never opens a sentence so ("right, the bedroom" has no noun for it to qualify)."""
    opens = k == 0 or units[k - 1] in (".", "!", "?")
    return opens and k + 1 < len(units) and units[k + 1] in _AFTER_RIGHT


def _without_fillers(
    items: list[tuple[Token | str, int]], table: WordTable, places: PlaceLexicon, budget: list[int] | None = None
) -> list[tuple[Token | str, int]]:
    """Rule 3: the fillers left out, single words and phrases, again until none is left (a filler said inside
    another, "when could you you're ready", leaves the outer one whole once it is out; a phrase inside a longer one
    goes with it, "if you can"). Where several phrases are found, one may have been said inside another ("if you
    could you don't mind", "if you if you can don't mind"): each is tried first, and the reading that leaves the
    fewest words wins (at most :data:`_MAX_FILLER_TRIES` tries per sentence, then all at once). Place words
    stay."""
    budget = [_MAX_FILLER_TRIES] if budget is None else budget
    while True:
        kept = [(u, p) for u, p in items if not isinstance(u, str) or u not in table.fillers or u in places.words]
        units = [u for u, _ in kept]
        if table.filler_from.keys().isdisjoint(units):  # no unit opens a filler phrase
            return kept
        found = [(i, n) for i in range(len(units)) if (n := filler_at(units, i, table, places.words))]
        found = [(i, n) for i, n in found if not any(j <= i and i + n <= j + m and m > n for j, m in found)]
        if not found:
            return kept
        if len(found) == 1 or budget[0] < len(found):
            gone = {k for i, n in found for k in range(i, i + n)}
            items = [item for k, item in enumerate(kept) if k not in gone]
            continue
        budget[0] -= len(found)
        readings = [_without_fillers(_cut(kept, m), table, places, budget) for m in found]
        return min(readings, key=len)


_MAX_FILLER_TRIES = 32
"""Most alternative removals of crossing filler phrases tried for one sentence (rule 3)."""


def _cut(kept: list[tuple[Token | str, int]], match: tuple[int, int]) -> list[tuple[Token | str, int]]:
    return kept[: match[0]] + kept[match[0] + match[1] :]


def _durations_en(units: list[str], fillers: frozenset[str] = frozenset()) -> list[tuple[Token | str, int]]:
    """Rule 2: "(for) <number> <unit>" -> a DURATION token; "half a minute" is 30 s, "a quarter of an hour" 900 s,
    "a couple of minutes" 120 s, "two and a half minutes" 150 s, "a minute and a half" 90 s; fillers inside it are
    its own ("for like two minutes", "for a, um, minute": rule 3, a filler anywhere changes nothing). Each item
    with the index of its first unit."""
    if _UNITS.keys().isdisjoint(units):  # no unit of time: no duration
        return [(u, i) for i, u in enumerate(units)]
    view = [u for u in units if u not in fillers or u in ("a", "an")]  # "a" is a number here
    at = [i for i, u in enumerate(units) if u not in fillers or u in ("a", "an")]
    out: list[tuple[Token | str, int]] = []
    done = 0  # units before this are in ``out``
    p = 0
    while p < len(view):
        j = p + (view[p] == "for")
        found = _duration(view, j)
        while found is None and j > p and j < min(len(view), p + 4) and view[j] in fillers:
            j += 1  # "for a a minute": the filler "a" before the length
            found = _duration(view, j)
        if found is None:
            p += 1
            continue
        seconds, q = found
        start, end = at[p], at[q - 1] + 1
        out += [(units[i], i) for i in range(done, start)]
        out.append((Token("DURATION", " ".join(units[start:end]), seconds=seconds, start=start, end=end), start))
        done, p = end, q
    return out + [(units[i], i) for i in range(done, len(units))]


def _duration(units: list[str], j: int) -> tuple[float, int] | None:
    """(seconds, index after it) of a length of time said from ``units[j]`` (:func:`_durations_en`), or None."""
    if j >= len(units):
        return None
    if (quarters := _quarters(units, j)) is not None:
        return quarters
    j += units[j : j + 1] == ["a"] and units[j + 1 : j + 2] in (["quarter"], ["couple"])
    half = units[j : j + 2] in (["half", "a"], ["half", "an"])
    part = {"quarter": 0.25, "couple": 2.0}.get(units[j]) if j < len(units) else None  # a quarter of an hour
    k = j + 1 if half else j + 2 + (units[j + 2 : j + 3] in (["an"], ["a"])) if part else j
    number = (1.0 if part else _number(units[k])) if k < len(units) else None
    if part and units[j + 1 : j + 2] != ["of"]:
        number = None
    and_half = not (part or half) and number is not None and units[k + 1 : k + 4] == ["and", "a", "half"]
    if and_half and number is not None:  # "two and a half minutes"
        number, k = number + 0.5, k + 3
    unit = _UNITS.get(units[k + 1]) if number is not None and k + 1 < len(units) and not part else None
    unit = _UNITS.get(units[k]) if part and number is not None and k < len(units) else unit
    k -= 1 if part else 0
    if number is None or unit is None:
        return None
    seconds = number * unit * (0.5 if half else part if part else 1.0)
    if not (part or half or and_half) and units[k + 2 : k + 5] == ["and", "a", "half"]:
        seconds, k = seconds + unit / 2, k + 3  # "a minute and a half"
    return seconds, k + 2


def _quarters(units: list[str], j: int) -> tuple[float, int] | None:
    """Quarters of a unit said from ``units[j]``: "a quarter hour" (Merriam-Webster's quarter hour), "a quarter of an
    hour", "three quarters of an hour"; (seconds, index after it) or None."""
    count = 1.0 if units[j] in ("a", "an", "one") else _number(units[j])
    if count is None or units[j + 1 : j + 2] not in (["quarter"], ["quarters"]):
        return None
    k = j + 2
    k += units[k : k + 1] == ["of"]
    k += units[k : k + 1] in (["an"], ["a"])
    unit = _UNITS.get(units[k]) if k < len(units) else None
    return (count * 0.25 * unit, k + 1) if unit is not None else None


def _floors_en(items: list[tuple[Token | str, int]]) -> list[tuple[Token | str, int]]:
    """Rule 2: floor phrases -> a FLOOR token (FLOOR_TO when "to" / "into" follows)."""
    if CUES.isdisjoint(u for u, _ in items if isinstance(u, str)):
        return items
    units = [u for u, _ in items]
    out: list[tuple[Token | str, int]] = []
    i = 0
    while i < len(items):
        hit = floor_en(units, i)
        if hit is None:
            out.append(items[i])
            i += 1
            continue
        value, n = hit
        kind = "FLOOR_TO" if i + n < len(units) and units[i + n] in ("to", "into") else "FLOOR"
        n += kind == "FLOOR_TO"
        start = items[i][1]
        surface = " ".join(str(u) for u in units[i : i + n])
        out.append((Token(kind, surface, floor=value, start=start, end=items[i + n - 1][1] + 1), start))
        i += n
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

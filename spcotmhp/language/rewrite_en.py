"""English token rewrites of :mod:`spcotmhp.language.lexicon` (its rules 6-8): what people say that the grammar
reads in another order or form. Each takes the tokens of a sentence and gives them back rewritten; the lexicon runs
one only on a sentence that holds what it rewrites (rule 9, a room told by what is in it: :func:`contents_en`)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from spcotmhp.language.forms_en import correction_shapes
from spcotmhp.language.placewords import Token

if TYPE_CHECKING:
    from spcotmhp.language.placewords import PlaceLexicon
    from spcotmhp.language.table import WordTable

NUMBERS = {
    "a": 1, "an": 1, "one": 1, "two": 2, "three": 3, "four": 4, "five": 5, "six": 6, "seven": 7, "eight": 8,
    "nine": 9, "ten": 10, "eleven": 11, "twelve": 12, "fifteen": 15, "twenty": 20, "thirty": 30, "forty": 40,
    "forty-five": 45, "fifty": 50, "sixty": 60, "ninety": 90,
}  # fmt: skip
"""Number words and their values (lengths of time, :mod:`spcotmhp.language.lexicon` rule 2; instance numbers)."""
_INSTANCE_WORDS = 20
"""Largest number said in words that names an instance ("bedroom twenty"); "a" and "an" name none."""


MAX_INSTANCE = 99
"""Largest instance number a place phrase may say ("bedroom 2"); a larger number is no instance of a home's name."""


def instance_number(unit: str) -> int | None:
    """The instance number a unit says: digits ("2", "#2" is cut to "2") or a number word ("two"), 1 to
    :data:`MAX_INSTANCE`; None otherwise."""
    if unit.isdigit():
        n = int(unit)
    elif unit in NUMBERS and unit not in ("a", "an") and NUMBERS[unit] <= _INSTANCE_WORDS:
        n = NUMBERS[unit]
    else:
        return None
    return n if 1 <= n <= MAX_INSTANCE else None


def _apposition(items: list[Token]) -> list[Token]:
    """ "the corridor, the east one": a place word and "one" after a comma and another place name that place again,
    said more exactly (the east corridor), not a second place."""
    out: list[Token] = []
    for it in items:
        if (
            it.kind == "ONE" and len(out) >= 3 and out[-1].kind == "PLACE" and out[-2].kind == "COMMA"
            and out[-3].kind == "PLACE" and not set(out[-1].words) & set(out[-3].words)
        ):  # fmt: skip
            said, _, first = out.pop(), out.pop(), out.pop()
            out.append(first._replace(surface=f"{first.surface}, {said.surface} {it.surface}",
                                      words=said.words + first.words, end=it.end))  # fmt: skip
            continue
        out.append(it)
    return out


def numbered_en(items: list[Token], units: Sequence[str] = ()) -> list[Token]:
    """Rule 6: a number said with a place word names the instance the robot shows with it ("bedroom 2", "bedroom
    #2", "bedroom number two", "number two bedroom", "bedroom one": the plan's "bedroom #2"): the PLACE token
    carries it, with the words in its surface."""
    items = _apposition(items)
    out: list[Token] = []
    i = 0
    while i < len(items):
        it = items[i]
        if it.kind == "PLACE" and it.number is None:
            j = i + 1 + _number_word(items, i + 1)
            n = (_number_after if j > i + 1 else _said_number)(items[j]) if j < len(items) else None
            the = j < len(items) and "the" in units[it.end : items[j].start]  # "the bedroom, the one nearest ..."
            if n is not None and not the:
                said = " ".join(t.surface for t in items[i : j + 1])
                out.append(it._replace(surface=said, number=n, end=items[j].end))
                i = j + 1
                continue
        before = _said_number(it)
        after_number = out and out[-1].kind == "WORD" and out[-1].surface == "number"
        place = items[i + 1] if i + 1 < len(items) else None
        the = 0 < it.start <= len(units) and units[it.start - 1] == "the"  # "the #3 bedroom", not "go 2 bedroom"
        digits = it.kind == "WORD" and it.surface.isdigit() and the and place is not None and place.start == it.end
        if digits and before is not None and place is not None and place.kind == "PLACE" and not place.plural:
            out.append(place._replace(surface=f"{it.surface} {place.surface}", number=before, start=it.start))
            i += 2  # "the #3 bedroom": a screen number before the name
            continue
        if after_number and before is not None and place is not None and place.kind == "PLACE" and place.number is None:
            said = f"number {it.surface} {place.surface}"
            out[-1] = place._replace(surface=said, number=before, start=out[-1].start)
            i += 2
            continue
        out.append(it)
        i += 1
    return out


_NUMBER_WORDS = ("number", "hash", "num", "nr", "no")
"""Words that say a number follows ("bedroom number 2", "bedroom hash two": "#" said aloud, "bedroom no. 2")."""


def _number_word(items: list[Token], j: int) -> int:
    """How many tokens from ``items[j]`` say that a number follows (0 to 2: "no" and its full stop)."""
    if j >= len(items) or items[j].surface not in _NUMBER_WORDS or items[j].kind not in ("WORD", "NO"):
        return 0
    stop = j + 1 < len(items) and items[j + 1].kind == "_STOP" and items[j].surface == "no"
    k = j + 1 + stop
    return 1 + stop if k < len(items) and _number_after(items[k]) is not None else 0


_HEARD_AS = {"to": 2, "too": 2, "for": 4, "won": 1}
"""Words a speech recogniser writes for a number word it heard ("bedroom number to"): only after "number", where
a number must follow."""


def _number_after(tok: Token) -> int | None:
    """The number a token says after "number": a number, or a word a recogniser writes for one (:data:`_HEARD_AS`)."""
    n = _said_number(tok)
    return n if n is not None else _HEARD_AS.get(tok.surface)


def relations_en(items: list[Token]) -> list[Token]:
    """Rule 7: a relation said around the name says the same as after it: "the nearest bedroom to the kitchen" is
    "the bedroom nearest to the kitchen", "the farthest bedroom from the bath" is "the bedroom farthest from the
    bath"; "of the (three) bedrooms, (go to) the one nearest the bath" is "the bedroom nearest the bath", "the
    smaller of the two corridors" is "the smaller corridor" (the number only says how many there are)."""
    out: list[Token] = []
    i = 0
    while i < len(items):
        it = items[i]
        place = items[i + 1] if i + 1 < len(items) else None
        prep = items[i + 2] if i + 2 < len(items) else None
        if place is not None and prep is not None and place.kind == "PLACE":
            near = it.kind == "NEAREST" and prep.kind == "TO"
            far = it.kind == "MODIFIER" and it.surface in ("farthest", "furthest") and prep.kind == "FROM"
            if near or far:
                kind = "CLOSEST" if near else "FARTHEST"
                out += [place, Token(kind, f"{it.surface} .. {prep.surface}", start=prep.start, end=prep.end)]
                i += 3
                continue
        out.append(it)
        i += 1
    return _of_the(_of_the_n(out))


def _of_the_n(items: list[Token]) -> list[Token]:
    """Rule 7's "the smaller of the two corridors": a size picked among the places of a name said in the plural
    (the number only says how many there are) is that size of the place."""
    out: list[Token] = []
    i = 0
    while i < len(items):
        it = items[i]
        k = (
            i
            + 2
            + (i + 2 < len(items) and items[i + 2].kind == "WORD" and instance_number(items[i + 2].surface) is not None)
        )
        if it.kind in ("LARGEST", "SMALLEST") and i + 1 < len(items) and items[i + 1].kind == "OF" and k < len(items):
            place = items[k]
            if place.kind == "PLACE" and place.plural:
                out += [it, place._replace(plural=False, surface=place.words[0] if place.words else place.surface)]
                i = k + 1
                continue
        out.append(it)
        i += 1
    return out


def _of_the(items: list[Token]) -> list[Token]:
    """Rule 7's "of the bedrooms ... the one R": the place said in the plural after "of" opening a sentence
    stands for the "one" said after it."""
    if len(items) < 3 or items[0].kind != "OF":
        return items
    k = 1 + (items[1].kind == "WORD" and instance_number(items[1].surface) is not None)
    if k >= len(items) or items[k].kind != "PLACE" or not items[k].plural:
        return items
    ones = [j for j in range(k + 1, len(items)) if items[j].kind == "ONE"]
    if not ones:
        return items
    place = items[k]
    rest = [t for t in items[k + 1 :]]
    j = ones[0] - k - 1
    rest[j] = place._replace(surface=f"{rest[j].surface} of the {place.surface}", start=rest[j].start, end=rest[j].end)
    return [t for t in rest if t.kind != "COMMA" or rest.index(t) != 0]


def corrections_en(items: list[Token]) -> list[Token]:
    """Rule 8: commas that separate nothing are left out (before a full stop, at the end, twice in a row); "no,
    wait," and "wait, no," are one correction (the "wait" is no wait at a place), so is "wait, I meant"; a last
    "sorry" after a correction apologises for it ("the bath, I mean the toilet, sorry"): no second correction,
    left out."""
    out: list[Token] = []
    for it in items:
        if it.kind == "_STOP" and out and out[-1].kind == "COMMA":
            out.pop()
        if it.kind == "COMMA" and out and out[-1].kind == "COMMA":
            continue
        out.append(it)
    if out and out[-1].kind == "COMMA":
        out.pop()
    end = len(out) - (bool(out) and out[-1].kind == "_STOP")  # "the bath, I mean the toilet, sorry": an apology
    last = out[end - 1] if end >= 3 else None
    if last is not None and last.kind == "CORRECTION" and last.surface == "sorry" and out[end - 2].kind == "COMMA":
        out = out[: end - 2] + out[end:] if any(t.kind == "CORRECTION" for t in out[: end - 2]) else out
    merged: list[Token] = []
    i = 0
    while i < len(out):
        it = out[i]
        j = i + 1 + (i + 1 < len(out) and out[i + 1].kind == "COMMA")
        pair = {it.kind, out[j].kind} if j < len(out) else set()
        if pair == {"NO", "WAIT"} and it.kind != out[j].kind or pair == {"WAIT", "CORRECTION"} and it.kind == "WAIT":
            merged.append(Token("CORRECTION", f"{it.surface} {out[j].surface}", start=it.start, end=out[j].end))
            i = j + 1
            continue
        merged.append(it)
        i += 1
    kept = [  # "Toilet. No, wait. Washroom.": the stop after a correction, a comma after a stop, mark nothing
        t
        for k, t in enumerate(merged)
        if not (k and (t.kind == "_STOP" and merged[k - 1].kind == "CORRECTION"
                       or t.kind == "COMMA" and merged[k - 1].kind == "_STOP"))
    ]  # fmt: skip
    return correction_shapes(kept) if any(t.kind == "CORRECTION" for t in kept) else kept


_SIZED = ("PLACE", "ONE", "OF")
_POSITIVE_SIZES = frozenset({"big", "large", "small", "little", "wee", "tiny", "bigger", "larger", "smaller"})


def sizes_en(items: list[Token]) -> list[Token]:
    """A size said in the positive degree ("the big bedroom", "little") picks by size only right before a place's
    name, "one" or "of" ("the smaller of the two"); elsewhere ("off to the kitchen, little robot") it names no
    place and is a modifier, refused."""
    return [
        t._replace(kind="MODIFIER")
        if t.kind in ("LARGEST", "SMALLEST") and t.surface in _POSITIVE_SIZES
        and not (k + 1 < len(items) and items[k + 1].kind in _SIZED)
        else t
        for k, t in enumerate(items)
    ]  # fmt: skip


def shared_head_en(items: list[Token]) -> list[Token]:
    """ "Alice's and Bob's rooms": two owners joined by "and" before one noun in the plural share it (the plural
    names both rooms), so the first owner's place is "alice's room" and the second is one room, not several."""
    out = list(items)
    for k in range(len(out) - 2):
        a, joint, b = out[k], out[k + 1], out[k + 2]
        if (
            a.kind == "PLACE" and joint.kind == "AND" and b.kind == "PLACE" and b.plural and not a.plural
            and a.words and a.words[-1].endswith("'s") and len(b.words) == 2 and b.words[0].endswith("'s")
        ):  # fmt: skip
            out[k] = a._replace(words=(*a.words, b.words[1]))
            out[k + 2] = b._replace(plural=False)
    return out


_MASTER = frozenset({"master", "main"})


def master_en(items: list[Token]) -> list[Token]:
    """ "The master bedroom" (British and Australian "main bedroom") is the largest bedroom of a home: so the
    dictionaries define it (Merriam-Webster, Cambridge, Collins), and so 8 of 10 blind-corpus writers read it. Said
    right before a place whose name holds "bedroom", the word picks by size; before any other place ("the main
    hall") it stays a modifier, refused."""
    return [
        t._replace(kind="LARGEST")
        if t.kind == "MODIFIER" and t.surface in _MASTER and k + 1 < len(items) and items[k + 1].kind == "PLACE"
        and "bedroom" in items[k + 1].words
        else t
        for k, t in enumerate(items)
    ]  # fmt: skip


def said_again(items: list[Token]) -> list[Token]:
    """Rule 6 again: a number alone after a negation or a correction ("any bedroom except number 1", "bedroom two,
    no, three") names that instance of the place said last; said again right after it ("bedroom number one number
    one", "bedroom two. Two.") it is that number repeated."""
    out: list[Token] = []
    for it in items:
        n = _said_number(it)
        before = out[-1] if out else None
        if before is not None and before.kind == "WORD" and before.surface == "number" and n is not None:
            out.pop()
            before = out[-1] if out else None
        elif it.kind == "ONE":  # "not the one next to the toilet": "one" is a number only after "number"
            n = None
        if before is not None and before.kind == "COMMA" and len(out) >= 2 and out[-2].kind in ("NO", "CORRECTION"):
            before = out[-2]  # "bedroom 2, no, 3"
        cue = before is not None and before.kind in ("NEG", "NO", "CORRECTION")
        place = next((t for t in reversed(out) if t.kind == "PLACE"), None)
        said = out[-2:] if out and out[-1].kind == "_STOP" else out[-1:]
        if n is not None and place is not None and place.number == n and said and said[0] is place:
            continue  # "bedroom number one number one", "bedroom two. Two.": the number said again
        if place is not None and before is not None and before.kind != "NEG" and place.number is None:
            place = None  # "wait ten minutes, no, make that five": a correction of a number said before, not a place
        if n is not None and cue and place is not None:
            out.append(place._replace(surface=it.surface, number=n, start=it.start, end=it.end))
            continue
        out.append(it)
    return out


def _said_number(tok: Token) -> int | None:
    return instance_number(tok.surface) if tok.kind in ("WORD", "ONE") else None


_ROOM_HEADS = ("room", "one", "place", "area")
_CONTENT_LINKS = ("with", "where", "that has", "which has")


def contents_en(items: list[Token], table: WordTable, places: PlaceLexicon) -> list[Token]:
    """Rule 9: a room told by what is in it ("the bathroom with the tub", "the bathroom, the one with the washing
    machine", "the room where the toilet is", "go where the washing machine is", "the room with the sink and the
    washing machine": the one holding both) is the place of the map that holds that thing (``contents`` in
    ``en.json``), among those the word before may name ("bathroom": bath, toilet or washroom; "room", "one" or
    nothing: any); a thing said as where to go ("go to the sofa", "over to the dining table") is the room that holds
    it, as "go where the sofa is" is; where no place or several do, the words stay as said, to be refused."""
    out: list[Token] = []
    i = 0
    while i < len(items):
        head = items[i]
        ambiguous = head.kind == "WORD" and (head.surface,) in places.ambiguous
        j = i + 1
        if ambiguous and j + 1 < len(items) and items[j].kind == "COMMA" and items[j + 1].kind == "ONE":
            j += 2  # "the bathroom, the one with the tub"
        elif ambiguous and j < len(items) and items[j].kind == "ONE":
            j += 1  # spoken without the pause: "the bathroom the one with the tub"
        going = i > 0 and items[i - 1].kind in ("GO", "HURRY") or len(head.surface.split()) > 1  # not "about to"
        if head.kind == "TO" and going and (thing := _content(items, i + 1, table)) is not None:
            meant = sorted(set(thing[0]) & set(places.words))
            if len(meant) == 1 and (thing[1] == len(items) or items[thing[1]].kind not in ("WORD", "PLACE")):
                out += [
                    head,
                    Token("PLACE", meant[0], (meant[0],), start=items[i + 1].start, end=items[thing[1] - 1].end),
                ]
                i = thing[1]  # "go to the sofa": to the room that holds it, as "go where the sofa is"
                continue
        if not (ambiguous or head.surface in _ROOM_HEADS or head.surface == "where"):
            out.append(head)
            i += 1
            continue
        link = j if head.surface == "where" else j + 1
        linked = head.surface == "where" or (j < len(items) and items[j].surface in _CONTENT_LINKS)
        found = _content(items, link, table) if linked else None
        while found is not None and found[1] + 1 < len(items) and items[found[1]].kind == "AND":
            more = _content(items, found[1] + 1, table)  # "the sink and the washing machine": the room with both
            if more is None:
                break
            found = (tuple(w for w in found[0] if w in more[0]), more[1])
        if found is not None:
            names, k = found
            if k + 1 < len(items) and items[k].kind == "AT" and items[k + 1].kind == "IT":
                k += 2  # "with the bath in it"
            allowed = set(places.ambiguous[(head.surface,)]) if ambiguous else set(places.words)
            allowed |= set(table.told_senses.get(head.surface, ())) if ambiguous else set()  # "bathroom with the sink"
            meant = sorted(set(names) & allowed & set(places.words))
            if len(meant) == 1:
                k += k < len(items) and items[k].kind in ("IS", "WORD") and items[k].surface in ("is", "are", "'s")
                out.append(Token("PLACE", meant[0], (meant[0],), start=head.start, end=items[k - 1].end))
                i = k
                continue
        out.append(head)
        i += 1
    return out


def _content(items: list[Token], at: int, table: WordTable) -> tuple[tuple[str, ...], int] | None:
    """The place words of the thing said from ``items[at]`` (a place word's other name, "tub", or words of the
    table's ``contents``, "washing machine") and the index after it."""
    if at >= len(items):
        return None
    if items[at].kind == "PLACE" and items[at].surface in table.contents:
        return table.contents[items[at].surface], at + 1
    for n in (2, 1):
        said = items[at : at + n]
        words = " ".join(t.surface for t in said)
        if len(said) == n and all(t.kind in ("WORD", "PLACE") for t in said) and words in table.contents:
            return table.contents[words], at + n
    return None

"""English repairs and references eased before the grammar reads a sentence (rules 5-8 of
:mod:`spcotmhp.language.asides_en`, which runs them only on a sentence with no derivation as said): whose room a
pronoun names, the place said as the answer, repairs said without a correction word, words said in pieces."""

from __future__ import annotations

from collections.abc import Iterable, Sequence

from spcotmhp.language import english_words as ew
from spcotmhp.language.forms_en import RELATION_KINDS
from spcotmhp.language.placewords import Token
from spcotmhp.language.rewrite_en import instance_number
from spcotmhp.language.wording import excerpt

BOUNDS = ("_STOP", "COMMA")
"""Tokens that end a clause (a full stop, a comma): one home for the English asides and repairs."""


_OWNED = ("bedroom", "bedrooms", "room", "rm")
_TITLES = frozenset(
    "uncle aunt auntie aunty miss mister mr mrs ms dr cousin brother sister grandma grandpa granny nana".split()  # noqa: SIM905
)
"""Titles and kin words said before a first name ("Uncle Bob", "Miss Alice", Southern US for an adult): they say who
the person is to the speaker, not which room; before an owner's room they are left out."""
_PRONOUNS = ("my", "his", "her", "their")
_SPEAKER = ("it's", "i'm", "im", "this is")


def owner_names(words: Iterable[str]) -> frozenset[str]:
    """The people a map's place words name as owners: "alice" of "alice's" (rule 5, the talk's subjects, who asks)."""
    return frozenset(w[:-2] for w in words if w.endswith("'s"))


def owners(toks: list[Token], words: frozenset[str]) -> list[Token]:
    """Rule 5: whose room. A map whose places are named by their owners ("alice's room"): "alice's bedroom" is her
    room; "her / his / my room" is the room of the one person the sentence names ("Alice wants you in her room",
    "Alice here, go to my room": for "my", named as the speaker: "X here", "it's X"); a name said alone before
    its owner's room ("alice alice's room") is a false start, a title before it ("uncle bob's room") who the owner
    is. With no such person, or several, the words stay."""
    owners = owner_names(words)
    if not owners:
        return toks
    named = {t.surface for t in toks if t.kind == "WORD" and t.surface in owners}
    named |= {t.words[0][:-2] for t in toks if t.kind == "PLACE" and t.words and t.words[0][:-2] in owners}
    speakers = {
        t.surface for k, t in enumerate(toks) if t.surface in owners and (
            k + 1 < len(toks) and toks[k + 1].kind == "HERE" or k > 0 and toks[k - 1].surface in _SPEAKER
        )
    }  # fmt: skip
    out: list[Token] = []
    for k, t in enumerate(toks):
        nxt = toks[k + 1] if k + 1 < len(toks) else None
        if t.kind == "WORD" and t.surface in _OWNED and out and out[-1].kind == "PLACE" and "room" in words:
            owner = out[-1]
            if owner.words == (f"{owner.words[0]}",) and owner.words[0].endswith("'s"):
                out[-1] = owner._replace(surface=f"{owner.surface} room", words=(owner.words[0], "room"), end=t.end)
                continue  # "alice's bedroom": her room
        if t.kind == "MODIFIER" and t.surface in _PRONOUNS and nxt is not None and nxt.kind == "PLACE":
            who = speakers if t.surface == "my" else named
            if nxt.words == ("room",) and len(who) == 1 and f"{next(iter(who))}'s" in words:
                out.append(Token("MODIFIER_OWNER", t.surface, start=t.start, end=t.end))
                continue
        if out and out[-1].kind == "MODIFIER_OWNER":
            who = speakers if out[-1].surface == "my" else named
            whose = f"{next(iter(who))}'s"
            out[-1] = t._replace(surface=f"{whose} room", words=(whose, "room"), start=out[-1].start)
            continue
        if (
            t.kind == "WORD"
            and t.surface in owners
            and nxt is not None
            and nxt.kind == "PLACE"
            and nxt.words[:1] == (f"{t.surface}'s",)
        ):
            continue  # "alice alice's room"
        titled = t.kind == "WORD" and t.surface in _TITLES and nxt is not None and nxt.kind == "PLACE"
        if titled and nxt is not None and nxt.words[0].endswith("'s") and nxt.words[0][:-2] in owners:
            continue  # "uncle bob's room"
        if (
            t.kind == "WORD"
            and t.surface in owners
            and nxt is not None
            and nxt.kind == "TO"
            and nxt.surface.split()[0] in ("wants", "needs", "would")
        ):
            continue  # "Alice wants you in ...": who asks, said with the request
        out.append(t)
    return out


def pieces(toks: list[Token], words: frozenset[str], units: Sequence[str]) -> list[Token]:
    """Rule 8, a word said in pieces: letters or syllables that spell a place word ("d-i-n-i-n-g", "kit-chen",
    fillers among them: "b-a-t-h") are that place, spelling "robot" a vocative, left out; a false start, the first
    letters of the place word said next ("go to the st... stor... storeroom", "the b... bed-room"), is left out;
    a place said again with its number ("bed-room. bedroom number two") is said once, with it."""
    out: list[Token] = []
    i = 0
    while i < len(toks):
        j = i
        while j < len(toks) and toks[j].kind == "WORD" and toks[j].surface.isalpha() and len(toks[j].surface) <= 4:
            j += 1
        joined = "".join(units[toks[i].start : toks[j - 1].end]) if j > i else ""
        if j - i >= 2 and (joined in words or joined == "robot"):
            if joined != "robot":
                out.append(Token("PLACE", joined, (joined,), start=toks[i].start, end=toks[j - 1].end))
            i = j
            continue
        t = toks[i]
        nxt = next((x for x in toks[i + 1 :] if not (x.kind == "WORD" and len(x.surface) < 6)), None)
        starts = nxt is not None and nxt.kind == "PLACE" and bool(nxt.words) and t.kind == "WORD"
        if starts and nxt is not None and t.surface.isalpha() and _false_start(t.surface, nxt.words[0]):
            i += 1
            continue  # "st... stor... storeroom": false starts of the place said next
        again = len(out) >= 2 and out[-1].kind == "_STOP" and out[-2].kind == "PLACE" and t.kind == "PLACE"
        if again and out[-2].words == t.words and out[-2].number is None and t.number is not None:
            out[-2:] = [t]  # "bed-room. bedroom number two": the place said again, more exactly
            i += 1
            continue
        out.append(t)
        i += 1
    return out


def _false_start(word: str, place: str) -> bool:
    """``word`` is the first letters of ``place`` and no function word ("st" of "storeroom"; not "to")."""
    return place.startswith(word) and place != word and ew.pos(word).keys() <= {"NOUN", "VERB", "ADJ"}


_WHERE_WANTED = frozenset("i we need want you would like 'd".split())  # noqa: SIM905


def answer(toks: list[Token]) -> list[Token]:
    """Rule 6: the place said as the answer. After a place at the end of a clause, "there" points at that place
    ("go on into the kitchen there"), "it is" says it is the one ("dining room it is") and "is where I need you"
    that it is where to go ("the kitchen's where I need you"): left out, the place stays."""
    out: list[Token] = []
    i = 0
    while i < len(toks):
        t = toks[i]
        if out and out[-1].kind == "PLACE":
            j = i
            if t.kind == "THERE":
                j = i + 1
            elif t.kind == "IT" and i + 1 < len(toks) and toks[i + 1].kind == "IS":
                j = i + 2
            elif t.kind == "IS" and i + 1 < len(toks) and toks[i + 1].surface == "where":
                j = i + 2
                while j < len(toks) and toks[j].kind == "WORD" and toks[j].surface in _WHERE_WANTED:
                    j += 1
            if j > i and (j == len(toks) or toks[j].kind in BOUNDS):
                i = j
                continue
        out.append(t)
        i += 1
    return out


_HESITATIONS = frozenset({"er", "erm", "um", "uh", "uhm", "ah", "hmm", "hm"})
_CUES = ("NO", "CORRECTION", "COMMA")


def repairs(toks: list[Token], units: Sequence[str], notes: list[str]) -> list[Token]:
    """Rule 7, repairs said without a correction word's help: a place said again of the same name after only a
    hesitation ("bedroom one er bedroom two") replaces it; "one" after a size ("the smallest one") is the place
    said before; a length of time or a bare number after a correction replaces the length said before ("wait five
    minutes, no, make it ten": ten minutes)."""
    out: list[Token] = []
    for t in toks:
        last = out[-1] if out else None
        if t.kind == "ONE" and last is not None and last.kind in ("LARGEST", "SMALLEST"):
            if len(out) >= 3 and out[-2].kind == "COMMA" and out[-3].kind == "PLACE":
                out[-3:] = [last, out[-3]]  # "bedroom, the big one": the big bedroom, one place said more exactly
            continue  # "no, the smallest one": the smallest (of the place said before)
        gap = set(units[last.end : t.start]) if last is not None else set()
        again = t.kind == "PLACE" and last is not None and last.kind == "PLACE" and t.words[:1] == last.words[:1]
        if again and last is not None and gap and gap <= _HESITATIONS:
            notes.append(f"{excerpt(t.surface)} said instead of {excerpt(last.surface)}")
            out[-1] = t
            continue
        k = len(out)
        while k > 0 and (out[k - 1].kind in _CUES or out[k - 1].surface in ("make", "it", "that")):
            k -= 1
        cued = k < len(out) and any(x.kind in ("NO", "CORRECTION") for x in out[k:])
        if cued and k > 0 and out[k - 1].kind == "DURATION" and (length := _length(t, out[k - 1])) is not None:
            notes.append(f"{excerpt(length.surface)} said instead of {excerpt(out[k - 1].surface)}")
            out[k - 1 :] = [length]
            continue
        out.append(t)
    return out


def _length(t: Token, before: Token) -> Token | None:
    """The length of time ``t`` says, as a DURATION: itself, or a bare number in the unit of ``before``."""
    if t.kind == "DURATION":
        return t
    n = instance_number(t.surface) if t.kind in ("WORD", "ONE") else None
    said = next((instance_number(w) for w in before.surface.split() if instance_number(w)), None)
    if n is None or not said:
        return None
    unit = before.surface.split()[-1]
    return Token("DURATION", f"{t.surface} {unit}", seconds=before.seconds / said * n, start=t.start, end=t.end)


_GREETINGS = frozenset({"hey", "hi", "hello", "hiya", "howdy"})


def restarts(toks: list[Token], units: Sequence[str]) -> list[Token]:
    """Phrases said again as a speaker restarts them, said once: "go to the go to the dining room" and "go to the to
    the hall" (a verb of going or its "to" with no place yet, then said again: the first is a false start); "a
    bedroom any bedroom" (the place said again with "any": the choice the planner makes anyway); and "hey there"
    opening the sentence ("there" calls the one spoken to, as "you there" does: no place)."""
    out = list(toks)
    opening = bool(out) and out[0].kind == "THERE" and out[0].surface == "there" and 0 < out[0].start <= len(units)
    if opening and units[out[0].start - 1] in _GREETINGS:
        out = out[1:]
    k = 0
    while k < len(out):
        kinds = [t.kind for t in out[k : k + 4]]
        if kinds == ["GO", "TO", "GO", "TO"] or kinds[:2] == ["TO", "TO"]:
            del out[k : k + (2 if kinds[0] == "GO" else 1)]
            continue
        if (
            kinds[:3] == ["PLACE", "ONE_OF", "PLACE"]
            and out[k + 1].surface == "any"
            and out[k].words == out[k + 2].words
        ):
            del out[k + 1 : k + 3]
            continue
        k += 1
    return out


_ASKING = ("wants", "needs", "would")
_PERSONS = frozenset({"he", "she", "they", "everyone", "everybody", "someone", "somebody"})


def requesters(toks: list[Token], people: frozenset[str]) -> list[Token]:
    """Who asks, said with a relayed request, is left out: "my mom wants you in the dining room", "Nana wants you to
    go into the sitting room" (a person: ``people``, the table's kin words and the map's owners, a pronoun, or a noun
    after a possessive) before "wants / needs you in" or "wants / needs you to" and a verb of going: the request
    is the speaker's to pass on."""
    k = 1 if toks and toks[0].kind == "MODIFIER" and toks[0].surface in ("my", "our", "your", "his", "her") else 0
    if k >= len(toks) or toks[k].kind != "WORD":
        return toks
    who = toks[k].surface
    if not (who in people or who in _PERSONS or k == 1 and "NOUN" in ew.pos(who)):
        return toks
    rest = toks[k + 1 :]
    if rest and rest[0].kind == "TO" and rest[0].surface.split()[0] in _ASKING:
        return rest  # "my mom wants you in the dining room"
    said = [t.surface for t in rest[:3]]
    if len(rest) > 3 and said[0] in _ASKING and said[1] == "you" and rest[2].kind == "TO" and rest[3].kind == "GO":
        return rest[3:]  # "Nana wants you to go into the sitting room"
    return toks


def taken_back_en(items: list[Token]) -> list[Token]:
    """A correction that names what it takes back: "X. Sorry, not X, Y", "X no sorry not the X the Y", "X, actually
    scratch that, not the X, the Y": "not X" right after the correction word repeats the place the correction
    replaces (the last place said before it), so it is no place not to end in of its own: left out, and Y replaces
    X as any correction's place does ("wait," opening the sentence is such a correction word: "Go to the hall.
    Wait, not the hall, the corridor."). With no pause between them ("not the X the Y") the two were read as one name
    (merging's rule 5); the name is split where X ends. Any other "not" stays as said."""
    out: list[Token] = []
    k = 0
    while k < len(items):
        it = items[k]
        before = [t for t in out if t.kind != "COMMA"]
        place = items[k + 1] if k + 1 < len(items) else None
        said = next((t for t in reversed(before[:-1]) if t.kind == "PLACE"), None) if before else None
        waited = (
            bool(before)
            and before[-1].kind == "WAIT"
            and before[-1].surface == "wait"
            and len(before) > 1
            and (out[-1].kind == "COMMA" and before[-2].kind == "_STOP")
        )  # "Go to the hall. Wait, not the hall, the corridor.": "wait," opening a sentence is a correction
        corrected = bool(before) and (before[-1].kind == "CORRECTION" or waited)
        if it.kind == "NEG" and corrected and place is not None and said is not None:
            n = len(said.words)
            again = place.kind == "PLACE" and place.words[:n] == said.words and place.number == said.number
            rest = place.words[n:] if again else ()
            after = items[k + 2 : k + 4]
            if (
                again
                and not rest
                and any(t.kind == "PLACE" for t in after)
                and all(t.kind in ("PLACE", "COMMA") for t in after[: 1 + (after[0].kind == "COMMA")])
            ):
                _as_correction(out, before[-1])
                k += 2 + (after[0].kind == "COMMA")  # "not the hall, the family room": the family room replaces it
                continue
            if again and rest and place.surface.startswith(said.surface + " ") and place.number is None:
                _as_correction(out, before[-1])
                out.append(place._replace(surface=place.surface[len(said.surface) + 1 :], words=rest))
                k += 2
                continue
        out.append(it)
        k += 1
    return out


def _as_correction(out: list[Token], word: Token) -> None:
    """The "wait" opening the sentence of a correction (taken_back_en) made the correction word it is."""
    if word.kind == "WAIT":
        out[next(k for k in range(len(out) - 1, -1, -1) if out[k] is word)] = word._replace(kind="CORRECTION")


def echoes_en(items: list[Token]) -> list[Token]:
    """A sentence that only says again part of what was said before it ("Go to the bedroom nearest the laundry. The
    laundry. Nearest the laundry.", "Go to the kitchen. The kitchen!"): the same tokens, in the same order, as a run
    of an earlier sentence, said for emphasis or to a listener who did not hear. It adds nothing and is left out;
    read alone, a bare place in it would be a second goal. A place said again alone is left to the walk (one visit)
    unless it was said as a relation's place; a sentence that says anything new stays."""
    sentences: list[list[Token]] = [[]]
    for t in items:
        sentences[-1].append(t)
        if t.kind == "_STOP":
            sentences.append([])
    if len(sentences) < 2:
        return items
    out: list[Token] = []
    said: list[tuple[str, tuple[str, ...], int | None]] = []
    for sentence in sentences:
        key = [_said(t) for t in sentence if t.kind not in ("COMMA", "_STOP")]
        fragment = all(k[0] in _ECHOED for k in key)  # with a verb or an order it says something of its own
        at = [k for k in range(len(said) - len(key) + 1) if key and fragment and said[k : k + len(key)] == key]
        lone = len(key) == 1 and key[0][0] == "PLACE"  # a place said again alone is one visit (walk's _once)
        if out and at and (not lone or any(k and said[k - 1][0] in _RELATIONS for k in at)):
            continue
        out += sentence
        said += key
    return out


_RELATIONS = RELATION_KINDS | {"BETWEEN", "AS_FAR_FROM"}
_ECHOED = _RELATIONS | {"PLACE", "ONE", "AND", "LARGEST", "SMALLEST", "OF"}
"""What an echo may hold: places and their relations ("The laundry. Nearest the laundry."), no verb or order."""


def _said(tok: Token) -> tuple[str, tuple[str, ...], int | None]:
    return tok.kind, tok.words if tok.kind == "PLACE" else (tok.surface.lower(),), tok.number


_APPOSED = RELATION_KINDS - {"NEXT_TO"}
"""Relations that may follow a place after a pause ("next to the hall, then ..." may be "next, to the hall")."""


def apposed_en(items: list[Token], units: Sequence[str] = ()) -> list[Token]:
    """A relation said after a pause that follows a place ("go to the bedroom, nearest the kitchen", "goto bedroom
    --nearest kitchen") picks that place, as "the bedroom nearest the kitchen" does: read as a place of its own
    ("the nearest kitchen") it would make the bedroom a waypoint nobody asked for. And a question naming a place
    answered by "the one ..." ("Which bedroom? The one nearest the storeroom.") is that place with the answer's
    relation: the question is no place to visit."""
    out: list[Token] = []
    k = 0
    while k < len(items):
        t = items[k]
        nxt = items[k + 1] if k + 1 < len(items) else None
        prev = out[-1] if out else None
        the = nxt is not None and 0 < nxt.start <= len(units) and units[nxt.start - 1] in ("the", "a")
        if (
            prev is not None
            and prev.kind == "PLACE"
            and t.kind == "COMMA"
            and nxt is not None
            and nxt.kind in _APPOSED
            and not the  # "the kitchen, the nearest bedroom": a place of its own
        ):
            k += 1  # "bedroom, nearest the kitchen": the pause between the place and its relation
            continue
        asked = t.kind == "_STOP" and t.surface == "?" and prev is not None and prev.kind == "PLACE"
        if (
            asked
            and nxt is not None
            and nxt.kind == "ONE"
            and k + 2 < len(items)
            and items[k + 2].kind in RELATION_KINDS
        ):
            k += 2  # "Which bedroom? The one nearest ...": the answer's relation picks the place asked about
            continue
        out.append(t)
        k += 1
    return out

"""English said around and inside an instruction that the grammar reads once eased (issue 34), tried only on a
sentence with no derivation as said. Each rule has its reason; the classes are data (``talk`` in ``en.json``):

1. **Verbs of going by their manner** (``talk.motion``: manner-of-motion verbs after Levin 1993, *English Verb
   Classes and Alternations*, §51.3 roll and run verbs, with verbs of moving oneself; their inflections by
   lemminflect): such a verb, maybe with "yourself" and particles of direction (over, on, along, down, ...), right
   before a word of destination or passage ("slide over to the kitchen", "scooting into the hall") says how the robot
   goes there: it is read as "go". A verb whose manner is a speed says it (``fast``: dash, hustle, sprint; ``slow``:
   crawl, creep, tiptoe); other manners (a hop, a roll) are nothing a wheeled robot can do differently. "skip",
   "avoid", "pass", "return" and the like are no such verbs (they are other classes, or refused). In texts, "2"
   between a verb of going and a place is "to" ("go 2 the kitchen").
1b. **Taking a position at the goal** (``talk.posture``: verbs of assuming a position, Levin 1993 §50, with verbs
   of putting oneself somewhere): such a verb, maybe with "yourself" and "down" or "up", right before "in" or "at"
   a place ("go stand at the front door", "go and sit yourself down in the lounge", "park yourself at the
   entrance") says where the robot is to end up: it is read as "to", and a "go (and)" before it is that going.
2. **Addresses and interjections** (``talk.address``, ``talk.interjections``, ``talk.kin``): a part of the sentence
   between its edges, commas and full stops made only of terms of address ("love", "my dude", "you little rascal"),
   interjections ("huh", "nah", "g'day") or a name introducing its speaker ("Gran here") names whom the speaker
   talks to or how they feel, never where to go: passed over; so are such words opening a part ("bro just go
   kitchen", "yeah nah go to ...") and terms of address or interjections closing it ("go to the dining room love",
   "... eh"), and a word of no
   dictionary alone at the sentence's edge before a comma, the robot's name ("Robbie, the front door").
3. **Talk without an instruction's form**: a part between such marks with no place, no word of a class that carries
   navigation meaning (:mod:`spcotmhp.language.talk`'s admissible words, also by their lemmas: "faster"), no word
   that refers back to a place ("it", "there", "one", "that"), opening with thanks, an interjection or an address
   ("thanks a bunch") or with an auxiliary verb as a question does ("did you hear me?"), is talk: passed over. A bare
   noun phrase may name a place the map lacks ("the garage") and an order opens with a verb ("turn that down"):
   both stay, to be read or refused.
3b. **Statements of someone else** (:mod:`spcotmhp.language.statements_en`): a part opening with a subject other
   than the robot and holding a verb, with no place and no class of the instruction ("my grandson is coming over",
   "I'll join you in a minute", "you are blocking the door") says how things are: passed over.
4. **Until told**: "until / till I say (so) / tell you (otherwise) / told / further notice / call you / come and
   get you / need you / I'm back" after a wait names the event that ends a wait with no length, the speaker's next
   word to the robot (its next instruction): the wait is until told, as "wait there" alone; so is a wait "for a
   bit", "for a while" or "for now", which says no length.
Rules 5-8 live in :mod:`spcotmhp.language.repairs_en`:

5. **Whose room**: in a map whose places are named by their owners, "alice's bedroom" is her room, "her / his /
   my room" that of the one person the sentence names (as its speaker, for "my").
6. **The place as the answer**: after a place at the end of a clause, "there" (pointing at it), "it is" ("dining
   room it is") and "is where I need you" say only that it is where to go: left out.
7. **Repairs**: the same place's name said again after only a hesitation ("bedroom one er bedroom two") replaces
   it, "one" after a size is the place said before ("no, the smallest one"), and a length of time or a bare number
   after a correction replaces the length said before ("five minutes, no, make it ten").
8. **A word said in pieces**: letters or syllables spelling a place word ("d-i-n-i-n-g", "kit-chen") are that
   place; false starts of the place said next ("the st... stor... storeroom") are left out.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from spcotmhp.language import english_words as ew
from spcotmhp.language.placewords import Token
from spcotmhp.language.repairs_en import BOUNDS as _BOUNDS
from spcotmhp.language.repairs_en import answer, owner_names, owners, pieces, repairs, requesters, restarts
from spcotmhp.language.statements_en import CLOCK, about_places, stated
from spcotmhp.language.table import WordTable, filler_at
from spcotmhp.language.talk import admissible

_DESTINATION = ("TO", "VIA", "ENTER")
_VERBS = ("GO", "TO", "VIA", "AVOID", "WAIT", "ENTER", "HURRY")
"""Classes that open an instruction: a word of address or interjection before one of them is said to someone."""
_SEGMENT_NEUTRAL = frozenset({"IS", "AND", "LINK", "OF", "NOW", "ALL"})
_BACK_REFERENCE = frozenset({"it", "there", "one", "that", "them", "this", "those", "these"})
_TELLING = frozenset(
    [
        "say",
        "says",
        "said",
        "tell",
        "tells",
        "told",
        "notice",
        "call",
        "calls",
        "called",
        "come",
        "comes",
        "back",
        "get",
        "fetch",
        "collect",
        "need",
        "needs",
        "want",
        "wants",
        "hear",
        "shout",
        "holler",
        "yell",
    ]  # noqa: SIM905
)
"""What ends a wait with no length: the speaker telling, calling, coming for or needing the robot, which reaches it as
its next instruction (the robot cannot observe the act itself, and does not need to)."""
_AWHILE = frozenset({"bit", "while"})
"""A length not said ("for a bit", "for a while"): the wait lasts until the speaker says otherwise."""
_UNTIL_TOLD_WORDS = _TELLING | frozenset(
    [
        "i",
        "i'm",
        "im",
        "you",
        "someone",
        "somebody",
        "anyone",
        "she",
        "he",
        "they",
        "we",
        "you're",
        "are",
        "so",
        "otherwise",
        "further",
        "go",
        "and",
        "to",
        "move",
        "me",
        "from",
        "again",
    ]  # noqa: SIM905
)


def ease_en(
    toks: Sequence[Token], table: WordTable, units: Sequence[str], place_words: Sequence[str] = ()
) -> tuple[list[Token], list[str], list[str]] | None:
    """``toks`` with the rules applied, what was passed over and notes on what else changed (for the explanation);
    None when no rule applies (module docstring). ``units``: the sentence's units, fillers included (a token's
    ``start`` indexes them)."""
    talk = table.talk
    if not talk or table.by_character:
        return None
    notes: list[str] = []
    people = frozenset(talk.get("kin", ())) | owner_names(place_words)
    out = answer(owners(pieces(restarts(list(toks), units), frozenset(place_words), units), frozenset(place_words)))
    out = requesters(out, people)  # after owners: "alice wants you in her room" says whose room first
    out = repairs(_until_told(_manner(_posture(_text_speak(_fronted(out)), talk), talk), units), units, notes)
    subjects = frozenset(talk.get("subjects", ())) | people
    times = frozenset(talk.get("times_in_statements", ())) | CLOCK
    stated_places: list[str] = []
    for _ in range(4):  # rule 3c, before addresses are cut ("grandma is in the bath": her statement); a few of them
        if (places := about_places(out, subjects, frozenset(talk.get("meaning", ())), times, units)) is None:
            break
        out, stated_places = places[0], [*stated_places, *places[1]]
    kept, said = _asides(out, talk, units, table)
    said = [*stated_places, *said]
    if said or kept != list(toks):
        return kept, said, notes
    return None


def _manner(toks: list[Token], talk: Mapping[str, Any]) -> list[Token]:
    """Rule 1: a manner-of-motion verb (and its particles) before a destination, as GO, HURRY or SLOW GO."""
    motion = talk.get("motion", {})
    if not motion:
        return toks
    particles = frozenset(talk.get("particles", ()))
    out: list[Token] = []
    i = 0
    while i < len(toks):
        t = toks[i]
        verb = ew.lemma(t.surface, "VERB") if t.kind == "WORD" else None
        manner = next((m for m in ("go", "fast", "slow") if verb in motion.get(m, ())), None)
        going = t.kind == "GO" or t.kind == "VIA" and t.surface.split()[0] in ("go", "head", "come", "walk", "get")
        manner = "go" if going else manner  # "mosey on down to", "go down to": a verb of going and its particles
        j = i + 1
        while manner and j < len(toks) and (toks[j].surface in particles or toks[j].surface == "yourself"):
            j += 1
        if going and (j == i + 1) == (t.kind == "GO"):
            manner = None  # a GO word with no particle after it, or "go down" not before "to": as it is
        if manner and j < len(toks) and toks[j].kind in _DESTINATION:
            said = " ".join(x.surface for x in toks[i:j])
            a, b = t.start, toks[j - 1].end
            if manner == "fast":
                out.append(Token("HURRY", said, start=a, end=b))
            else:
                out.append(Token("GO", said, start=a, end=b))
                if manner == "slow":
                    out.append(Token("SLOW", said, start=a, end=b))
            i = j
            continue
        out.append(t)
        i += 1
    return out


def _posture(toks: list[Token], talk: Mapping[str, Any]) -> list[Token]:
    """Rule 1b: a posture verb ("yourself", "down", "up" after it) before "in" / "at" and a place, as TO; a "go
    (and)" right before it is that going ("go and stand at the entrance": go to the entrance)."""
    posture = frozenset(talk.get("posture", ()))
    out: list[Token] = []
    i = 0
    while i < len(toks):
        t = toks[i]
        j = i + 1
        verb = t.kind == "WORD" and ew.lemma(t.surface, "VERB") in posture
        while verb and j < len(toks) and toks[j].surface in ("yourself", "urself", "down", "up"):
            j += 1
        if verb and j + 1 < len(toks) and toks[j].kind in ("AT", "TO") and toks[j + 1].kind == "PLACE":
            if len(out) > 1 and out[-1].kind == "AND" and out[-2].kind == "GO":
                out.pop()  # "go and stand at": the going is the standing's
            said = " ".join(x.surface for x in toks[i : j + 1])
            if not (out and out[-1].kind == "GO"):
                out.append(Token("GO", said, start=t.start, end=toks[j].end))
            out.append(Token("TO", said, start=t.start, end=toks[j].end))
            i = j + 1
            continue
        out.append(t)
        i += 1
    return out


def _fronted(toks: list[Token]) -> list[Token]:
    """Rule 4 too: a place said first and its wait after a comma ("In the living room, wait a quarter of an hour") is
    the wait at that place."""
    kinds = [t.kind for t in toks[:4]]
    return [toks[3], toks[0], toks[1], *toks[4:]] if kinds == ["AT", "PLACE", "COMMA", "WAIT"] else toks


def _text_speak(toks: list[Token]) -> list[Token]:
    """Rule 1 too: "2" between a verb of going and a place is "to", as texts write it ("go 2 the kitchen"; a number
    after a place, "bedroom 2", names an instance and is read before this), and so are "two" and "too", as speech
    recognisers write the homophone ("go two the kitchen")."""
    return [
        Token("TO", t.surface, start=t.start, end=t.end)
        if t.kind == "WORD" and t.surface in ("2", "two", "too") and 0 < k < len(toks) - 1
        and toks[k - 1].kind == "GO" and toks[k + 1].kind == "PLACE" else t
        for k, t in enumerate(toks)
    ]  # fmt: skip


def _until_told(toks: list[Token], units: Sequence[str]) -> list[Token]:
    """Rule 4: "till I say" after a wait left out (the wait, with no length, lasts until told). The words after
    "till" are read from the units, fillers included ("I say" is one)."""
    out: list[Token] = []
    i = 0
    while i < len(toks):
        t = toks[i]
        nxt = toks[i + 1] if i + 1 < len(toks) else None
        if (
            t.kind == "LINK" and t.surface == "for" and nxt is not None and any(x.kind == "WAIT" for x in out)
            and (nxt.kind == "WORD" and nxt.surface in _AWHILE or nxt.kind == "NOW")
            and (i + 2 == len(toks) or toks[i + 2].kind in _BOUNDS)
        ):  # fmt: skip
            i += 2  # "wait there for a bit / for a while / for now": a wait of no length said, until told
            continue
        first, *rest = t.surface.split()
        if t.kind == "UNBOUNDED_WAIT" and first in ("until", "till", "til") and any(x.kind == "WAIT" for x in out):
            j = next((k for k in range(i + 1, len(toks)) if toks[k].kind in _BOUNDS), len(toks))
            words = set(rest) | set(units[t.end : toks[j].start if j < len(toks) else len(units)])
            if words and words <= _UNTIL_TOLD_WORDS and words & _TELLING:
                i = j
                continue
        out.append(t)
        i += 1
    return out


def _asides(
    toks: list[Token], talk: Mapping[str, Any], units: Sequence[str], table: WordTable | None = None
) -> tuple[list[Token], list[str]]:
    """Rules 2 and 3: the parts between edges, commas and full stops that are addresses, interjections or talk."""
    neutral = frozenset(talk.get("neutral", ()))
    meaning = frozenset(talk.get("meaning", ()))
    subjects = frozenset(talk.get("subjects", ())) | frozenset(talk.get("kin", ()))
    address = frozenset(talk.get("address", ())) | frozenset(talk.get("kin", ()))
    interjections = frozenset(talk.get("interjections", ()))
    times = frozenset(talk.get("times_in_statements", ())) | CLOCK
    social = interjections | address  # a filler before a part's opener ("please, thanks a bunch") opens nothing
    kept: list[Token] = []
    said: list[str] = []
    start = 0
    for end in [k for k, t in enumerate(toks) if t.kind in _BOUNDS] + [len(toks)]:
        part = toks[start:end]
        aside = (
            bool(part)
            and (
                _addressing(part, address, interjections)
                or _calling(part, toks, start, end)
                or stated(part, subjects, toks, times)  # rule 3b
                or _talk(
                    part,
                    neutral,
                    meaning,
                    subjects,
                    interjections | address,
                    _opening(units[toks[start - 1].end if start else 0 :], table, social),
                )
            )
        )
        mark = end < len(toks)
        if aside:
            said.append(" ".join(t.surface for t in part))
            if mark and kept and kept[-1].kind in _BOUNDS:
                kept.pop()  # "kitchen, love." -> "kitchen."; "bro. kitchen." -> "kitchen."
            elif mark and not kept:
                mark = False  # a leading aside takes its mark with it
        else:
            a, b = 0, len(part)
            while (
                a < b
                and part[a].surface in interjections | address
                and (part[a].kind == "WORD" or a + 1 < b and part[a + 1].kind in _VERBS)
            ):
                a += 1  # "bro just go kitchen", "yeah nah go to the dining room", "right erm could you pop to"
            while b > a and part[b - 1].kind == "WORD" and part[b - 1].surface in address | interjections:
                b -= 1  # "go to the dining room love", "go to the dining room eh": a tag closing the request
            if 0 < b - a < len(part) and part[a].kind != "WORD" and part[b - 1].kind != "WORD":  # not "mum says"
                said += [" ".join(t.surface for t in edge) for edge in (part[:a], part[b:]) if edge]
                part = part[a:b]
            kept += part
        if mark:
            kept.append(toks[end])
        start = end + 1
    while kept and kept[0].kind in _BOUNDS:
        kept.pop(0)
    return kept, said


def _opening(said: Sequence[str], table: WordTable | None, social: frozenset[str]) -> list[str]:
    """The units of a part from its first word that is not a filler or a comma, unless a social word ("please,
    thanks a bunch", "if you can, thanks a bunch": the opener is "thanks")."""
    i = 0
    while i < len(said) and table is not None and said[i] not in social:
        n = filler_at(said, i, table, frozenset()) or (said[i] in table.fillers or said[i] == ",")
        if not n:
            break
        i += n
    return list(said[i:])


def _addressing(part: Sequence[Token], address: frozenset[str], interjections: frozenset[str]) -> bool:
    """Rule 2: only terms of address and interjections ("my dude", "you little rascal", "yeah nah"), or a name
    introducing its speaker ("gran here", "bob here"), whatever classes their words have elsewhere."""
    words = [t.surface for t in part]
    if len(part) == 2 and part[1].kind == "HERE":  # not "(I need) you here": the robot asked to be here
        return part[0].kind == "WORD" and _name(words[0]) and words[0] not in ("you", "u", "ya", "ye", "yourself")
    if words[-1] in address and all(w in ("my", "you", "little", "old", "young", "dear") for w in words[:-1]):
        return all(t.kind != "PLACE" for t in part)
    return all(w in interjections for w in words)


def _calling(part: Sequence[Token], toks: Sequence[Token], start: int, end: int) -> bool:
    """Rule 2 too: one word of no dictionary, alone between a sentence's edge and a comma or full stop ("Robbie, the
    front door", "Hall, please, Robbie."), with a place elsewhere in the sentence, is the name the robot is called by
    (a place the map lacks is a dictionary word: "garage, please" stays)."""
    edge = all(t.kind in _BOUNDS for t in toks[:start]) or all(t.kind in _BOUNDS for t in toks[end:])
    if len(part) != 1 or part[0].kind != "WORD" or not edge:
        return False
    word = part[0].surface
    return word.isalpha() and not ew.known(word) and any(t.kind == "PLACE" for t in toks)


def _name(word: str) -> bool:
    """A word that may be a person's name: not a number, and no word of lemminflect's or a noun ("gran", "alice",
    "bob")."""
    return not word[:1].isdigit() and (not ew.known(word) or "PROPN" in ew.pos(word) or "NOUN" in ew.pos(word))


def _talk(
    part: Sequence[Token],
    neutral: frozenset[str],
    meaning: frozenset[str],
    subjects: frozenset[str],
    social: frozenset[str],
    said: Sequence[str],
) -> bool:
    """Rule 3: no place or other class, no word referring back or carrying meaning by its lemma ("faster"), and
    opening (the first unit ``said``, fillers included) with thanks, an interjection or an address ("thanks a
    bunch") or an auxiliary verb, as a question does ("did you hear me?"): a bare noun phrase may name a place the
    map lacks ("the garage"), an order opens with a verb ("turn that down"), and both stay."""
    if any(t.kind != "WORD" and t.kind not in _SEGMENT_NEUTRAL for t in part):
        return False
    words = [t for t in part if t.kind == "WORD"]
    if not words or any(t.surface in _BACK_REFERENCE for t in words):
        return False
    for t in words:
        lemmas = {lemma for forms in ew.pos(t.surface).values() for lemma in forms}
        if lemmas & meaning or not (t.surface in social or admissible(t, neutral, meaning, subjects)):
            return False
    first = said[0] if said else part[0].surface
    return first in social or "AUX" in ew.pos(first)

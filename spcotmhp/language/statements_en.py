"""Rule 3b of :mod:`spcotmhp.language.asides_en`: a clause that states something of someone other than the robot.

A part of a sentence between its edges, commas and full stops that opens with a subject other than "you" ("I'll
join you in a minute", "my grandson is coming over", "my taxi is here", "it's quieter there", "the kids left a
mess there"; "you are" only before what the robot is doing now: "you are blocking the door") and holds a verb says
how things are, or why the speaker asks: it names no place and none of the classes that make an instruction, so it
asks nothing of the robot, and its words of position and time ("over", "here", "in a minute") are its subject's,
not the robot's. It is passed over, and said. What keeps a part in the instruction, to be read or refused there:

* a place, a floor, or a class of the instruction (a way to go, a waypoint, an avoidance, a negation, a speed, a
  wait, a correction, a relation, a size; ``_ALLOWED`` lists the classes a statement may hold);
* "to" or "in" before anything but a length of time ("we're going to the garage", "I need you in the garage"),
  and "here" or "there" after the robot ("I need you here");
* a length of time where the instruction waits without one ("wait in the kitchen, I'll be back in ten minutes":
  the length may be the wait's);
* words referring back to a place or naming one without its name ("one", "room"): "the big one is mine", "he
  wants his room";
* a time of day or an order in time ("go to the bath, it's for tonight": when to go), where the subject may stand
  for the instruction ("it", "that") or the robot is in the clause ("I need you there tonight"); after someone
  else ("my taxi should be here soon", "I'll be there in a moment") the time is theirs.

A noun that also qualifies a room ("guest" of "guest room") is a subject after a possessive and before a verb ("our
guest is staying there"); "be along" (will come) is no passage when no place follows it.
"""

from __future__ import annotations

from collections.abc import Sequence

from spcotmhp.language import english_words as ew
from spcotmhp.language.placewords import Token

_ALLOWED = frozenset({"WORD", "IS", "GO", "AND", "LINK", "OF", "THAT", "IT", "THERE", "HERE", "NOW", "ALL", "TO", "AT"})
"""Classes a statement may hold: none carries navigation meaning without a place (and a statement has none)."""
_POSSESSIVES = frozenset({"my", "our", "his", "her", "their", "your"})
_OBJECTS = frozenset({"one", "ones", "room", "rooms", "place", "spot"})
"""Words that refer back to a place, or name one of no name ("he wants his room"): a part holding one is kept."""
_INSTRUCTION_SUBJECTS = frozenset({"it's", "its", "that's", "that'd", "that'll", "this", "this's"})
"""Subjects that may stand for the instruction itself ("it's for tonight"): a time word after them keeps the part."""
CLOCK = frozenset(
    {"noon", "midnight", "o'clock", "am", "pm", "till", "til", "while", "during", "after", "before", "until"}
)
"""Time words a statement may not hold besides the table's ``talk.times_in_statements``."""


def stated(part: Sequence[Token], subjects: frozenset[str], sentence: Sequence[Token], times: frozenset[str]) -> bool:
    """Whether ``part`` (a clause of ``sentence``) is a statement of someone other than the robot (module
    docstring); ``subjects``: the table's subject words (``talk.subjects`` and ``talk.kin``); ``times``: words of a
    time of day or of an order in time ("tonight", "after"), which keep it ("go to the bath, it's for tonight")."""
    toks = [t for t in part if not (t.kind == "MODIFIER" and t.surface in _POSSESSIVES)]  # "my grandson"
    owned = part[0].kind == "MODIFIER" and part[0].surface in _POSSESSIVES
    if len(toks) < 2 or not _opens(toks, subjects, owned):
        return False
    durations = sum(t.kind == "DURATION" for t in sentence) - sum(t.kind == "DURATION" for t in part)
    waits_without_length = any(t.kind == "WAIT" for t in sentence) and not durations
    # a time word is the subject's when the subject is someone and the robot is not in the clause ("my taxi should
    # be here soon"); after "it" or "that", which may stand for the instruction, it may say when to go
    someone = toks[0].kind != "IT" and toks[0].surface not in _INSTRUCTION_SUBJECTS
    times = frozenset() if someone and not any(t.surface == "you" for t in toks) else times
    robot = [k for k, t in enumerate(toks) if t.surface in ("you", "u", "yourself")]
    if robot and any(t.kind in ("HERE", "THERE") for t in toks[robot[0] :]):
        return False  # "I need you here": where the robot is asked to be
    verb = False
    for k, t in enumerate(toks):
        nxt = toks[k + 1] if k + 1 < len(toks) else None
        prev = toks[k - 1] if k else None
        if k == 0 and t.kind == "MODIFIER" and owned:
            continue  # "our guest is staying there": a noun that also qualifies a room ("guest room"), here a subject
        if t.kind == "MID_CORRECTION" and prev is not None and prev.kind == "AT":
            continue  # "I'll be there in a moment": the subject's time, not a pause of the instruction
        if t.kind == "VIA" and t.surface == "along" and prev is not None and prev.surface == "be" and _no_place(nxt):
            continue  # "we'll be along (shortly)": will come, no place passed
        if t.kind == "AT" and nxt is not None and nxt.kind == "MID_CORRECTION":
            continue
        if t.kind == "DURATION":
            if waits_without_length or k == 0 or toks[k - 1].kind not in ("TO", "AT"):
                return False  # "for ten minutes" is a wait's; "in ten minutes" after a verb is the subject's time
            continue
        if t.kind not in _ALLOWED or t.kind == "WORD" and (t.surface in _OBJECTS or ew.base(t.surface) in times):
            return False
        if t.kind in ("TO", "AT") and (nxt is None or nxt.kind != "DURATION"):
            return False  # "going to the garage", "I need you in": a place follows or is left out
        if t.kind == "GO" and nxt is not None and nxt.kind in ("TO", "AT"):
            return False
        if (k > 0 or "'" in t.surface) and (t.kind in ("IS", "GO") or t.kind == "WORD" and _verb(t.surface)):
            verb = True
    return verb


def _opens(toks: Sequence[Token], subjects: frozenset[str], owned: bool) -> bool:
    """A subject first: a subject word but "you" ("you are" before a verb's -ing form), or a noun after a
    possessive (``owned``: "my taxi"), before a finite verb ("lunch is") or that is no verb's base form ("kids")."""
    first = toks[0]
    if first.kind == "IT":
        return True  # "it's quieter there"
    if first.kind == "MODIFIER" and owned:
        return _finite(toks[1]) and "NOUN" in ew.pos(first.surface)  # "our guest is"
    if first.kind != "WORD":
        return False
    word = first.surface
    if word == "you":
        return toks[1].kind == "IS" and len(toks) > 2 and toks[2].kind == "WORD" and toks[2].surface.endswith("ing")
    if word in subjects:
        return True
    pos = ew.pos(word)
    noun = "NOUN" in pos or "PROPN" in pos or word.endswith("'s") and ew.known(word[:-2])
    return noun and (owned or _finite(toks[1]) or not ew.infinitive(word))  # not "speed it up", "park there"


def _no_place(tok: Token | None) -> bool:
    """Nothing, or an adverb of no class ("shortly"), after a particle: no place follows it."""
    return tok is None or tok.kind == "WORD" and "ADV" in ew.pos(tok.surface)


def _finite(tok: Token) -> bool:
    """A verb right after a noun that makes the noun its subject: "is", an auxiliary, an inflected form ("left")."""
    if tok.kind == "IS":
        return True
    pos = ew.pos(tok.surface) if tok.kind in ("WORD", "GO") else {}
    return "AUX" in pos or any(lemma != tok.surface for lemma in pos.get("VERB", ()))


def _verb(word: str) -> bool:
    """A verb or an auxiliary ("left", "coming", "want"), or a word with a verb's contraction ("i'll", "footy's")."""
    pos = ew.pos(word)
    return "AUX" in pos or "VERB" in pos or "'" in word and word.rsplit("'", 1)[1] in ("ll", "re", "ve", "d", "m", "s")


_ROBOT = frozenset({"you", "u", "yourself", "ya", "ye"})
_ANAPHORS = frozenset({"IT", "THERE"})
_AFTER_ANAPHOR = frozenset({"AVOID", "GO", "VIA", "HURRY", "ENTER", "NOT_ENTER", "AT"})
"""Classes before "it" / "there" that make them the place gone to, passed or avoided ("avoid it", "go there")."""
_IN_A_PLACE_STATEMENT = _ALLOWED | {"PLACE", "MODIFIER"}


def about_places(
    toks: Sequence[Token],
    subjects: frozenset[str],
    meaning: frozenset[str],
    times: frozenset[str],
    units: Sequence[str] = (),
) -> tuple[list[Token], list[str]] | None:
    """Rule 3c of :mod:`spcotmhp.language.asides_en`: a statement of someone other than the robot that names a
    place ("I'm mopping the kitchen, go to the hall", "guests will be in the living room tonight, so head to the
    washroom", "could you go to the hall please i'm vacuuming the corridor") says why the speaker asks, as the
    writers of every corpus label it: its place is neither avoided nor gone to unless the instruction refers back
    to it. Passed over, when the rest of the sentence names a place of its own; "it" or "there" right after a verb
    of going, passing or avoiding with no place before it in the rest ("the dog made a mess in the corridor, so
    avoid it"; "I left my phone in the kitchen, go there") is the statement's one place, put in its stead. The
    statement opens where a part opens or with a subject word ("i'm") after a place or a word, holds a verb and
    only words a statement may hold (:func:`stated`'s classes, places and possessives; "to" only before a place;
    no word of ``meaning``, no robot, no length of time, no time after "it's"), and ends before the first word that
    may not stand in it. A third person's motion with a modal, after "so" or "because" (``units`` show them: "go
    to the hallway so the aide can get the wheelchair through the living room") is theirs, and may stand in it.
    None when no statement is found or the rest would be no instruction."""
    toks = list(toks)
    for s in range(len(toks)):
        if not _may_open(toks, s, subjects, units):
            continue
        e = _statement_end(toks, s, meaning, times, _theirs(toks, s))
        clause = toks[s:e]
        places = [t for t in clause if t.kind == "PLACE"]
        verb = any((k > 0 or "'" in t.surface) and (t.kind == "IS" or t.kind == "GO" and t.surface in _BE or
                                                      t.kind == "WORD" and _verb(t.surface))
                   for k, t in enumerate(clause))  # fmt: skip
        if not places or not verb or not (_opens(clause, subjects, False) or _place_first(clause)) or e - s < 2:
            continue
        if e < len(toks) and not (toks[e].kind in _OPENERS and not toks[e].surface.endswith("ing")):
            continue  # "... bath is | running": a statement ends where a part ends or an instruction opens
        rest = toks[:s] + toks[e:]
        anaphors = [k for k, t in enumerate(rest) if t.kind in _ANAPHORS and k >= s]
        names = {(t.words, t.number) for t in places}
        for k in anaphors:
            if any(t.kind == "PLACE" for t in rest[s:k]):
                continue  # "... go to the toilet, avoiding the bedroom next to it": the nearest place said before it
            if len(names) != 1 or k == 0 or rest[k - 1].kind not in _AFTER_ANAPHOR:
                return None  # "it" may stand for several places ("bedroom 1 and bedroom 2 ... out of there")
            rest[k] = places[-1]._replace(start=rest[k].start, end=rest[k].end)
            break
        while rest and rest[0].kind in ("COMMA", "_STOP", "AND"):
            rest.pop(0)
        while rest and rest[-1].kind in ("COMMA", "AND"):
            rest.pop()
        if not any(t.kind == "PLACE" for t in rest):
            return None
        return rest, [" ".join(t.surface for t in clause)]
    return None


_BE = frozenset({"be", "been", "being"})
_PASSABILITY = frozenset(
    {"closed", "locked", "shut", "blocked", "barricaded", "flooded", "cordoned", "sealed", "impassable", "forbidden",
     "inaccessible", "unsafe", "hazardous", "dangerous", "danger", "restricted", "obstructed", "unreachable",
     "quarantined", "limits", "bounds", "quicker", "quickest", "shorter", "shortest", "shortcut", "faster",
     "fastest", "slower", "longer"}
)  # fmt: skip
"""Words that say whether a place can be entered or passed ("the bath is closed", "off limits", "unsafe"), or that
a way through it is better ("the corridor is quicker", "a shortcut"): navigation meaning the planner cannot take
from a statement (it avoids and passes only what it is told to), so they keep the statement, refused."""
_OPENERS = frozenset({"COMMA", "_STOP", "AND", "GO", "HURRY", "VIA", "AVOID", "NEG", "WAIT", "ENTER", "NO", "WITHOUT"})


def _place_first(clause: Sequence[Token]) -> bool:
    """A place as the subject: before "is" or a word with its contraction ("the kitchen is being cleaned", "the
    living room's a mess")."""
    second = clause[1]
    return clause[0].kind == "PLACE" and (second.kind == "IS" or second.kind == "WORD" and (
        second.surface.endswith(("'s", "'re")) and second.surface.split("'")[0] in ("room", "rooms")))  # fmt: skip


def _may_open(toks: Sequence[Token], s: int, subjects: frozenset[str], units: Sequence[str] = ()) -> bool:
    """Where a statement may open: a part's start, a subject word right after a place or a word ("... the hall
    i'm vacuuming the corridor"), or a word after "so" or "because" (and a determiner: "so the aide can ..."),
    never a word for the robot."""
    t = toks[s]
    if t.kind == "WORD" and t.surface.split("'")[0] in _ROBOT and not _robot_doing(toks, s):
        return False
    if s == 0 or toks[s - 1].kind in ("COMMA", "_STOP"):
        return True
    before = [u for u in units[max(0, t.start - 2) : t.start] if u not in _DETERMINERS] if t.start <= len(units) else []
    if t.kind == "WORD" and before and before[-1] in _CONNECTIVES:
        return True
    return t.kind == "WORD" and t.surface in subjects and toks[s - 1].kind in ("PLACE", "WORD")


_CONNECTIVES = frozenset({"so", "because", "cos", "coz", "cause", "since", "while"})
_DETERMINERS = frozenset({"the", "a", "an", "my", "our", "his", "her", "their", "that"})
_MODALS = frozenset({"can", "could", "will", "would", "might", "may", "must", "needs", "wants", "has"})
_OWN_PEOPLE = ("i", "i'", "we", "let", "us", "you", "u", "ya", "ye")


def _theirs(toks: Sequence[Token], s: int) -> bool:
    """Whether the clause opening at ``s`` is a third person's with a modal after its subject ("the aide can",
    "grandma will"): a motion in it is theirs. Not "I", "we", "let's" (they may take the robot along) or "you"."""
    first = toks[s]
    if first.kind != "WORD" or first.surface.startswith(_OWN_PEOPLE) and first.surface not in ("uncle", "usher"):
        return False
    return any(t.kind == "WORD" and t.surface.split("'")[0] in _MODALS for t in toks[s + 1 : s + 3])


def _robot_doing(toks: Sequence[Token], s: int) -> bool:
    """ "you're" (or "you are") before a verb's -ing form that is no verb of going: what the robot is doing where
    it stands ("you're blocking the kitchen"), which the plan's start (the robot's pose) already holds."""
    k = s + 1 + (toks[s].surface == "you" and s + 1 < len(toks) and toks[s + 1].kind == "IS")
    if toks[s].surface not in ("you're", "youre") and k == s + 1:
        return False
    return k < len(toks) and toks[k].kind == "WORD" and toks[k].surface.endswith("ing")


def _statement_end(
    toks: Sequence[Token], s: int, meaning: frozenset[str], times: frozenset[str], theirs: bool = False
) -> int:
    """The end of a statement opening at ``s``: the first token that may not stand in one (:func:`about_places`)."""
    someone = toks[s].kind != "IT" and toks[s].surface not in _INSTRUCTION_SUBJECTS and not _robot_doing(toks, s)
    # "you're vacuuming the hall later": a time in the robot's own statement may be when it is to go
    e = s
    while e < len(toks):
        t = toks[e]
        nxt = toks[e + 1] if e + 1 < len(toks) else None
        after = (
            t.kind == "AFTER"
            and e > s
            and _verb(toks[e - 1].surface)
            and nxt is not None
            and (nxt.kind == "WORD" and nxt.surface.endswith("ing"))
        )  # "I'm after mopping the kitchen": Irish English for "I have just mopped"
        motion = theirs and t.kind in ("GO", "VIA", "TO", "ENTER") and not any(u.kind == "PLACE" for u in toks[s:e])
        # "so the aide can get the wheelchair through the lounge": their motion, before the place it takes
        if (
            not after
            and not motion
            and (t.kind not in _IN_A_PLACE_STATEMENT or t.kind == "GO" and t.surface not in _BE)
        ):
            break
        timed = ew.base(t.surface) in times
        robot = t.surface.split("'")[0] in _ROBOT and not (e == s and _robot_doing(toks, s))
        if t.kind == "WORD" and (
            robot or t.surface in _OBJECTS or t.surface in meaning and not timed or timed and not someone
            or t.surface in CLOCK or t.surface in _PASSABILITY
        ):  # fmt: skip
            break
        if t.kind == "TO" and (nxt is None or nxt.kind != "PLACE"):
            break
        if t.kind == "AND" and (nxt is None or nxt.kind not in ("PLACE", "WORD", "MODIFIER")):
            break
        e += 1
    while e > s and toks[e - 1].kind in ("AND", "TO", "AT", "OF", "LINK", "THAT"):
        e -= 1  # "... the kitchen and | go": a connector at its end belongs to what follows
    return e

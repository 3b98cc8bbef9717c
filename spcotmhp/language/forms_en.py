"""English forms the grammar reads once reshaped (issue 34), each with its reason: corrections said in other
shapes, a wait by a place, "any X but Y", and a new clause begun without a pause. Run by
:func:`spcotmhp.language.lexicon.tokens` (and :func:`~spcotmhp.language.rewrite_en.corrections_en`) only on
sentences holding what they rewrite."""

from __future__ import annotations

from spcotmhp.language.placewords import Token


def correction_shapes(items: list[Token]) -> list[Token]:
    """Corrections said in other shapes: words side by side, one said last, a relation said alone."""
    return _relation_again(_said_after(_one_correction(items)))


def _one_correction(items: list[Token]) -> list[Token]:
    """Correction words side by side ("oops, I meant") are one correction."""
    out: list[Token] = []
    for it in items:
        k = len(out) - (bool(out) and out[-1].kind == "COMMA")
        if it.kind == "CORRECTION" and k > 0 and out[k - 1].kind == "CORRECTION":
            del out[k:]
            out[-1] = out[-1]._replace(surface=f"{out[-1].surface} {it.surface}", end=it.end)
            continue
        out.append(it)
    return out


def _said_after(items: list[Token]) -> list[Token]:
    """A correction word said last, after what replaces: after another correction it only apologises ("make that
    the dining room, sorry": left out); alone, it marks the phrase after the last pause as the replacement ("through
    the kitchen, er, through the hall I mean": the correction stands at that pause)."""
    end = len(items) - (bool(items) and items[-1].kind == "_STOP")
    if end >= 3 and items[end - 1].kind == "CORRECTION" and items[end - 2].kind == "COMMA":
        items = [*items[: end - 2], *items[end - 1 :]]  # "the bathroom, the toilet, I mean": the pause before it
        end -= 1
    if end < 2 or items[end - 1].kind != "CORRECTION" or items[end - 2].kind != "PLACE":
        return items
    last, before = items[end - 1], items[: end - 1]
    if any(t.kind == "CORRECTION" for t in before):
        return [*before, *items[end:]]
    pause = next((k for k in range(len(before) - 1, -1, -1) if before[k].kind == "COMMA"), None)
    if pause is None or not any(t.kind == "PLACE" for t in before[:pause]):
        return items
    return [*before[: pause + 1], last, *before[pause + 1 :], *items[end:]]


RELATION_KINDS = frozenset({"NEAREST", "CLOSEST", "FARTHEST", "NEXT_TO"})
"""The English classes of a relation said with its place ("nearest the kitchen"); one home for forms and repairs."""


def _relation_again(items: list[Token]) -> list[Token]:
    """A relation said alone after a correction ("the bedroom nearest the bath, no wait, nearest the toilet")
    corrects the relation of the place said with one before it: that place's name is said again with it."""
    heads: dict[int, Token] = {}
    for k, it in enumerate(items[:-2]):
        if it.kind != "CORRECTION":
            continue
        j = k + 1 + (items[k + 1].kind == "COMMA")
        if j + 1 < len(items) and items[j].kind in RELATION_KINDS and items[j + 1].kind == "PLACE":
            head = next((items[m] for m in range(k - 1, -1, -1)
                         if items[m].kind == "PLACE" and items[m + 1].kind in RELATION_KINDS), None)  # fmt: skip
            if head is not None:
                heads[j] = head._replace(start=items[j].start, end=items[j].start)
    if not heads:
        return items
    return [t for k, it in enumerate(items) for t in ((heads[k], it) if k in heads else (it,))]


_BESIDE = frozenset({"by", "near", "next to", "beside", "close to", "near to", "right by", "nearby"})


def wait_by_en(items: list[Token]) -> list[Token]:
    """A wait "by / near / next to" a place ("go wait by the front door", "stay near the kitchen") is a wait at it:
    after a verb of staying the words say where the robot stands, and the robot stands at a place's goal point,
    inside it (a person by the front door is in the entrance); no relation picks one place of several there."""
    out = list(items)
    for k in range(1, len(out) - 1):
        beside = out[k].kind in ("CLOSEST", "NEXT_TO") and out[k].surface in _BESIDE
        if beside and out[k - 1].kind == "WAIT" and out[k + 1].kind == "PLACE":
            out[k] = out[k]._replace(kind="AT")
    return out


def any_but_en(items: list[Token]) -> list[Token]:
    """ "any corridor but the south one": "but" after "any X" and before a place, a size or a relation is "except"
    (Merriam-Webster's preposition "but": with the exception of), as "any corridor except the south one" and "any
    bedroom except the smallest" read."""
    return [
        t._replace(kind="NEG") if t.kind == "BUT" and 1 < k < len(items) - 1 and items[k - 2].kind == "ONE_OF"
        and items[k - 1].kind == "PLACE" and items[k + 1].kind in _EXCEPTED else t
        for k, t in enumerate(items)
    ]  # fmt: skip


_CLAUSE_VERBS = frozenset({"STOP_AT", "AVOID", "GO"})
_LOCATING = frozenset({"off", "just off", "towards", "toward"})
"""Words of going that, between two places with no pause, say where the first lies ("the bedroom off the kitchen",
"the bedroom towards the kitchen"): a relation the map does not answer, refused, never a second stop."""
_PICKS = frozenset({"NEAREST", "CLOSEST", "FARTHEST", "NEXT_TO", "BETWEEN", "LARGEST", "SMALLEST"})
_EXCEPTED = _PICKS | {"PLACE", "ONE"}
"""What "but" after "any X" may take out: a place, a size or relation, "the one ..." (:func:`any_but_en`)."""


def located_en(items: list[Token]) -> list[Token]:
    """A word of :data:`_LOCATING` between two places ("the bedroom off the kitchen": where the bedroom is) is a
    relation the map does not answer (UNSUPPORTED_RELATION, refused with its reason), never a second stop."""
    located = [
        k for k in range(1, len(items) - 1) if items[k - 1].kind == "PLACE" and items[k].kind in ("GO", "TO")
        and items[k].surface in _LOCATING and items[k + 1].kind == "PLACE"
    ]  # fmt: skip
    if not located:
        return items  # most sentences
    return [t._replace(kind="UNSUPPORTED_RELATION") if k in located else t for k, t in enumerate(items)]


def new_clause_en(items: list[Token]) -> list[Token]:
    """A verb that opens a clause right after a place ("go to the living room stop at the kitchen on the way") begins
    a new clause, as the pause a transcript leaves out would: a comma is put between them, so that what the clause
    says ("on the way") applies to its own places; so does "the one" + a relation right after a place ("the bedroom
    the one nearest the front door"). Returns ``items`` itself when no clause begins so."""
    starts = [
        k for k in range(1, len(items)) if items[k - 1].kind == "PLACE" and (items[k].kind in _CLAUSE_VERBS or
        items[k].kind == "ONE" and k + 1 < len(items) and items[k + 1].kind in _PICKS)
    ]  # fmt: skip  # "the bedroom the one nearest the front door": the pause before "the one" left out too
    if not starts:
        return items  # the same list: nothing to rewrite (most sentences)
    out: list[Token] = []
    for k, t in enumerate(items):
        if k in starts:
            out.append(Token("COMMA", ",", start=t.start, end=t.start))
        out.append(t)
    return out


_COMPASS = frozenset({"east", "west", "north", "south"})


def owners_and_sides(items: list[Token], words: frozenset[str]) -> list[Token]:
    """A place's owner or side said after it or apart, put before it, where rule 5 joins place words side by side
    into one name: "the room of Bob" (the genitive's other form: Bob's room), "alice s room" (a recogniser's
    "alice's"), "the corridor on the east side" and "the east side corridor" (the east corridor). Only where the
    possessive or the compass point is a place word of the map (``words``); anything else is left as said."""
    out: list[Token] = []
    k = 0
    while k < len(items):
        t, rest = items[k], items[k + 1 : k + 4]
        kinds = [r.kind for r in rest]
        if t.kind == "PLACE" and kinds[:2] == ["OF", "WORD"] and f"{rest[1].surface}'s" in words:
            out += [_owner(rest[1]), t]  # "the room of bob"
            k += 3
            continue
        if t.kind == "WORD" and rest and rest[0].surface == "s" and f"{t.surface}'s" in words:
            out.append(_owner(t, rest[0].end))  # "alice s room"
            k += 2
            continue
        side = kinds == ["AT", "PLACE", "WORD"] and rest[0].surface == "on" and rest[2].surface == "side"
        if t.kind == "PLACE" and side and rest[1].words[-1] in _COMPASS and rest[1].number is None:
            out += [rest[1]._replace(end=rest[2].end), t]  # "the corridor on the east side"
            k += 4
            continue
        compass = t.kind == "PLACE" and t.words[-1] in _COMPASS
        if compass and kinds[:2] == ["WORD", "PLACE"] and rest[0].surface == "side":
            out += [t._replace(end=rest[0].end), rest[1]]  # "the east side corridor"
            k += 3
            continue
        out.append(t)
        k += 1
    return out


def _owner(tok: Token, end: int | None = None) -> Token:
    """The possessive place word of a name said without its 's (or with the 's apart)."""
    word = f"{tok.surface}'s"
    return Token("PLACE", word, (word,), start=tok.start, end=tok.end if end is None else end)


_TAKE_BACK = frozenset({"CORRECTION", "NO", "CANCEL"})
_RESTATED = frozenset({"GO", "THERE", "COMMA", "_STOP", "NOW"})
_WAIT_PARTS = frozenset({"WAIT", "THERE", "DURATION", "UNBOUNDED_WAIT"})


def withdrawals_en(items: list[Token]) -> list[Token]:
    """A part of the instruction taken back after a correction, leaving the rest as said: a wait ("wait there, oh
    actually don't wait", "don't bother waiting", "no need to wait"), a waypoint ("through the kitchen. Actually,
    skip the kitchen", "no need to go through it"), a speed ("slowly, no, never mind the slowly"), an avoidance
    ("avoid the hall, actually the hall's fine", then what is said instead). A correction
    replaces what it names with nothing, as it replaces a place with another; a restatement after it ("just go",
    "go straight there") says the goal again. "not via the hall" after "via the hall" may take it back or forbid
    it (writers split): left to the grammar, which refuses it. Anything else after the correction is left too."""
    for c in range(len(items) - 1, 0, -1):
        if items[c].kind in _TAKE_BACK:
            break
    else:
        return items
    before, after = items[:c], [t for t in items[c + 1 :] if t.kind not in ("COMMA", "_STOP")]
    while before and before[-1].kind in (*_TAKE_BACK, "COMMA", "_STOP"):
        before = before[:-1]  # "no, never mind"
    rest = _withdrawn(before, [items[c], *after] if items[c].kind == "CANCEL" else after)
    return items if rest is None else rest


def _withdrawn(before: list[Token], after: list[Token]) -> list[Token] | None:
    """``before`` without the part ``after`` takes back, or None if it takes none back or says more."""
    kinds = [t.kind for t in after]
    words = [t.surface for t in after]
    if kinds[:2] in (["NEG", "WAIT"], ["WAIVER", "WAIT"]):
        n, kept = 2, _without_wait(before)
    elif kinds[:1] == ["NEG"] and words[1:3] == ["bother", "waiting"]:
        n, kept = 3, _without_wait(before)
    elif kinds[:1] == ["CANCEL"] and kinds[1:2] in (["SLOW"], ["FAST"]):
        n, kept = 2, [t for t in before if t.kind != kinds[1]]
        kept = None if len(kept) == len(before) else kept
    elif kinds[:2] == ["AVOID", "PLACE"] and words[0] in ("skip", "skipping"):
        n, kept = 2, _without_said(before, "VIA", after[1])
    elif kinds[:3] == ["WAIVER", "VIA", "PLACE"]:
        n, kept = 3, _without_said(before, "VIA", after[2])
    elif kinds[:2] == ["PLACE", "ANY_OK"] or kinds[:3] == ["PLACE", "IS", "WORD"] and words[2] in _FINE:
        n = 2 if kinds[1] == "ANY_OK" else 3  # "actually, the hall's fine(, avoid the corridor instead)"
        kept = _without_said(before, "AVOID", after[0])
        if kept is not None and any(t.kind not in _RESTATED for t in after[n:]):
            return [*kept, Token("COMMA", ",", start=after[n].start, end=after[n].start),
                    *(t for t in after[n:] if t.kind != "INSTEAD")]  # fmt: skip
    else:
        return None
    return None if kept is None or any(t.kind not in _RESTATED for t in after[n:]) else kept


_FINE = frozenset({"fine", "ok", "okay", "alright", "all right"})
"""Words saying a place taken back from the avoided will do ("the hall's fine")."""


def _without_wait(before: list[Token]) -> list[Token] | None:
    """``before`` without its last wait (its verb, "there", its length, and the "and" before it)."""
    waits = [k for k, t in enumerate(before) if t.kind == "WAIT"]
    if not waits:
        return None
    k = end = waits[-1]
    while end + 1 < len(before) and before[end + 1].kind in _WAIT_PARTS:
        end += 1
    start = k - (k > 0 and before[k - 1].kind in ("AND", "THEN"))
    return [*before[:start], *before[end + 1 :]]


def _without_said(before: list[Token], kind: str, place: Token) -> list[Token] | None:
    """``before`` without the last ``kind`` + ``place`` pair said in it ("via the kitchen", "avoid the hall")."""
    said = [k for k in range(len(before) - 1) if before[k].kind == kind and before[k + 1].words == place.words]
    return None if not said else [*before[: said[-1]], *before[said[-1] + 2 :]]


_MANNER = frozenset({"NOW", "SLOW", "FAST"})
_PARTICLES = frozenset({"on", "out"})
"""Particles of direction said between a verb of going and "in" ("get on in that kitchen", "go on out in the hall",
"go on in to the toilet"): with "in" after them they say only that the motion goes in."""


def motion_at_en(items: list[Token]) -> list[Token]:
    """After a verb of motion, "in" or "at" before a place says where the motion ends, as "to" does ("move in the
    toilet room", "please go now in the kitchen", "go at the living room": colloquial and learners' English), where
    the verb opens its clause as an order; particles of direction before "in" go with it (:data:`_PARTICLES`; "in
    to" is "to", "in that kitchen" "to that kitchen"); an infinitive's "to" opening the request before the verb
    ("please to go to the living room") marks nothing."""
    out = items[1:] if len(items) > 1 and items[0].kind == "TO" and items[1].kind == "GO" else list(items)
    for k, t in enumerate(out):
        if t.kind != "GO" or k > 0 and out[k - 1].kind not in ("COMMA", "_STOP") or t.surface.endswith("ing"):
            continue  # an order opening its clause: not "I'm going in the kitchen", "walking in the hallway"
        j = k + 1
        while j < len(out) and out[j].kind in _MANNER:
            j += 1
        p = j
        while p < len(out) and out[p].kind in ("AT", "WORD") and out[p].surface in _PARTICLES:
            p += 1
        inward = p + 1 < len(out) and out[p].kind == "AT" and out[p].surface == "in"
        if inward and (out[p + 1].kind == "TO" or out[p + 1].kind == "THAT" and out[p + 2 : p + 3] != []):
            if out[p + 1].kind == "TO":
                return [*out[:j], *out[p + 1 :]]  # "go on in to the toilet"
            if out[p + 2].kind == "PLACE":  # "get on in that kitchen"
                return [*out[:j], out[p]._replace(kind="TO"), *out[p + 2 :]]
        if p > j and inward and out[p + 1].kind == "PLACE":
            return [*out[:j], out[p]._replace(kind="TO"), *out[p + 1 :]]  # "go on out in the hall"
        at = j + 1 < len(out) and out[j].kind == "AT" and out[j].surface in ("in", "at") and out[j + 1].kind == "PLACE"
        if at:
            out[j] = out[j]._replace(kind="TO")
    return out


def no_stop_en(items: list[Token]) -> list[Token]:
    """ "Don't stop" at a place passed on the way says what a waypoint is already (the robot stops only where told
    to wait): "go through the kitchen to the dining room but don't stop in the kitchen" is the waypoint alone;
    "go to the hall but don't stop there, keep going to the entrance" makes the hall a place passed on the way.
    Elsewhere "don't stop in X" keeps its reading (X avoided)."""
    out = list(items)
    for k in range(len(out) - 2):
        if out[k].kind != "NEG":
            continue
        if out[k + 1].kind == "STOP_AT" and out[k + 2].kind == "PLACE":
            place = out[k + 2]
            passed = any(out[j].kind == "VIA" and out[j + 1].words == place.words for j in range(k - 1))
            if passed:
                start = k - (k > 0 and out[k - 1].kind in ("BUT", "AND", "COMMA"))
                return [*out[:start], *out[k + 3 :]]
        if out[k + 1].kind == "HALT" and out[k + 1].surface.endswith("there") and k >= 2:
            j = k - 1 - (out[k - 1].kind in ("BUT", "AND", "COMMA"))
            rest = [t for t in out[k + 2 :] if t.kind != "COMMA"]
            if out[j].kind == "PLACE" and out[j - 1].kind == "TO" and rest[:1] and rest[0].kind == "TO":
                via = out[j - 1]._replace(kind="VIA")
                return [*out[: j - 1], via, out[j], *rest]  # the place passed, then "keep going to" the goal
    return out


def loose_ends_en(items: list[Token]) -> list[Token]:
    """Four shapes of speech around a whole instruction: "a bedroom, any of them, except ..." (the choice left
    open is the planner's own, so "any of them" between pauses adds nothing to what follows it); a tag question
    closing it ("go to the kitchen, no?": asking agreement, as "right?" does); and a place said with "in" alone
    ("In the dining room, please.": where to be, with no verb to take another reading); and "either" closing a
    clause after a place in a negated clause ("not the kitchen either", "don't go through the bath either": the
    negative "too", one more place not to go to, where before a place it picks any one: "either corridor")."""
    out = list(items)
    for k in range(len(out) - 1, 1, -1):
        closes = k + 1 == len(out) or out[k + 1].kind in ("COMMA", "_STOP")
        if out[k].surface == "either" and closes and out[k - 1].kind == "PLACE" and _negated(out[:k]):
            del out[k]
    for k in range(1, len(out) - 2):
        if [t.kind for t in out[k - 1 : k + 3]] == ["PLACE", "COMMA", "ANY_ONE", "COMMA"]:
            out = [*out[:k], *out[k + 2 :]]
            break
    if len(out) > 2 and [t.kind for t in out[-3:]] == ["COMMA", "NO", "_STOP"] and out[-1].surface == "?":
        out = [*out[:-3], out[-1]]
    kinds = [t.kind for t in out]
    if kinds[:2] == ["AT", "PLACE"] and out[0].surface == "in" and not {"GO", "TO", "ENTER", "WAIT"} & set(kinds):
        out[0] = out[0]._replace(kind="TO")
    return out


def _negated(before: list[Token]) -> bool:
    """Whether the clause ending ``before`` (from the last comma, full stop or "but") holds a negation."""
    for t in reversed(before):
        if t.kind in ("COMMA", "_STOP", "BUT"):
            return False
        if t.kind == "NEG":
            return True
    return False


def timed_stops_en(items: list[Token]) -> list[Token]:
    """A stop at a place with a length ("then stop at the washroom for thirty seconds") is a wait of that length
    there, as "wait at the washroom for thirty seconds" is: the robot stops only where it is told to wait. Without a
    length "stop" between places stays refused (a correction, or a stop the planner cannot time)."""
    out = list(items)
    for k in range(len(out) - 3):
        t = out[k]
        timed = [x.kind for x in out[k + 1 : k + 4]] == ["AT", "PLACE", "DURATION"]
        if t.kind == "HALT" and t.surface in ("stop", "then stop") and timed:
            wait = Token("WAIT", "stop", start=t.start, end=t.end)
            then = [Token("THEN", "then", start=t.start, end=t.start + 1)] if t.surface == "then stop" else []
            return [*out[:k], *then, wait, *out[k + 1 :]]
    return out

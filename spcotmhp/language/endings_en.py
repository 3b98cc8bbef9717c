"""What closes an English sentence after the place gone to, read by :mod:`spcotmhp.language.lexicon`: "and come"
(there and back, refused as "come back" is) and the emphatic "only" / "itself" (left out); and the question a
"go there" answers ("Where's the kitchen? Go there.")."""

from __future__ import annotations

from spcotmhp.language.placewords import Token


def go_and_come_en(items: list[Token]) -> list[Token]:
    """ "Go to the kitchen and come": Indian English's "go and come" is going there and coming back (as "go and
    come" is glossed in Indian English usage guides); a "come" that ends the sentence (a full stop after it at
    most) right after "and" or "then", with a place before it, names no place of its own: it asks to come back,
    refused as "come back" is (BACK), naming the words said, never dropped."""
    end = len(items) - (1 if items and items[-1].kind == "_STOP" else 0)
    if (
        end < 3
        or items[end - 1].kind != "GO"
        or items[end - 1].surface != "come"
        or items[end - 2].kind not in ("AND", "THEN")
    ):
        return items
    if not any(t.kind == "PLACE" for t in items[: end - 2]):
        return items
    said, come = items[end - 2], items[end - 1]
    back = Token("BACK", f"{said.surface} {come.surface}", start=said.start, end=come.end)
    return [*items[: end - 2], back, *items[end:]]


_EMPHASIS = frozenset({"only", "itself"})


def emphasis_en(items: list[Token]) -> list[Token]:
    """Indian English's emphatic "only" and "itself" closing a sentence right after the place gone to ("go to the
    washroom only", "go to the corridor itself": that place and no other, which is what a plan to it is) are left
    out; after a place passed or avoided ("via the kitchen only": no other way) they would constrain the route,
    and stay, refused."""
    end = len(items) - (1 if items and items[-1].kind == "_STOP" else 0)
    last = items[end - 1] if end >= 3 else None
    if last is None or last.kind != "WORD" or last.surface not in _EMPHASIS:
        return items
    if items[end - 2].kind != "PLACE" or items[end - 3].kind != "TO":
        return items
    return [*items[: end - 1], *items[end:]]


_ASKING = frozenset({"where", "where's", "which"})


def asked_then_there_en(items: list[Token]) -> list[Token]:
    """A question that names a place, answered by "go there" after it ("Where's the kitchen? Go there.", "do you
    know where the kitchen is go there", "which bedroom is closest to the dining room? go there"): "there" is the
    place the question names, so the question's own words (where, which, the "is" beside the place) are left out
    and the place stays, with its relation. Only where the sentence opens with the question and holds "go there"."""
    if len(items) < 4 or items[0].kind != "WORD" or items[0].surface not in _ASKING:
        return items
    if not any(t.kind == "THERE" and k > 0 and items[k - 1].kind == "GO" for k, t in enumerate(items)):
        return items
    stop = next((k for k, t in enumerate(items) if t.kind in ("_STOP", "GO")), len(items))
    head = items[1:stop]
    if not head or not any(t.kind == "PLACE" for t in head):
        return items
    kept = [t for k, t in enumerate(head) if not (t.kind == "IS" and (k == 0 or head[k - 1].kind == "PLACE"))]
    return [*kept, *items[stop:]]


_ALONG = ("down", "along", "up")


def along_only_en(items: list[Token], senses: frozenset[str] = frozenset()) -> list[Token]:
    """ "Go down the hallway", "head along the corridor": a place gone along with no other place in the sentence
    is where to go (five writers of six label it so): along a corridor the robot ends in it, as no place beyond
    was named. "Through", "via" and "past" still say a place passed on the way to another, and alone are refused;
    so is a place named by a word of two senses (``senses``: "hallway", a corridor or a hall), which the frozen
    held-out corpus refuses there ("head down the hallway")."""
    places = [k for k, t in enumerate(items) if t.kind == "PLACE"]
    if len(places) != 1 or places[0] == 0:
        return items
    k = places[0]
    via = items[k - 1]
    if items[k].surface in senses:
        return items
    if via.kind != "VIA" or via.surface.split()[-1] not in _ALONG or len(via.surface.split()) < 2:
        return items
    if any(t.kind in ("VIA", "GO", "TO", "AVOID", "STOP_AT", "WAIT") for t in items[: k - 1] + items[k + 1 :]):
        return items
    verb, _, particle = via.surface.rpartition(" ")
    go = Token("GO", verb, start=via.start, end=via.end)
    return [*items[: k - 1], go, Token("TO", particle, start=via.end, end=via.end), *items[k:]]


_CHOOSING = frozenset({"pick", "choose", "select"})
_CHOSEN = frozenset({"PLACE", "ONE_OF", "WHICHEVER", "ANY_ONE", "LARGEST", "SMALLEST", "NEAREST", "MODIFIER"})


def chosen_en(items: list[Token]) -> list[Token]:
    """ "Pick the bedroom closest to the hall (and go there)", "choose whichever bedroom is nearest the dining room":
    a verb of choosing opening a clause, right before the place chosen, asks the robot to go there, the one thing it
    can do with a place (six writers of six label it so); read as "go to". Before anything else ("pick up the
    towel") it stays a word, refused."""
    out: list[Token] = []
    for k, t in enumerate(items):
        opens = k == 0 or items[k - 1].kind in ("COMMA", "_STOP")
        nxt = items[k + 1] if k + 1 < len(items) else None
        if t.kind == "WORD" and t.surface in _CHOOSING and opens and nxt is not None and nxt.kind in _CHOSEN:
            out.append(Token("GO", t.surface, start=t.start, end=t.end))  # as "go kitchen" is read
        else:
            out.append(t)
    return out

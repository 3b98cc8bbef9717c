"""Place tokens side by side made one (rule 5 of :mod:`spcotmhp.language.lexicon`): a name of several words, a name
said twice, a place said bare then narrowed by size, and lengths of time said in parts. Kept apart from the
tokeniser so each stays one readable file."""

from __future__ import annotations

from spcotmhp.language.placewords import Token


def merge(items: list[Token]) -> list[Token]:
    """Place words side by side (fillers between them left out) form one name (rule 5); a name no place has
    ("the hall please the entrance": "hall entrance") is refused where the planner checks names; a name said twice
    in a row is one (:func:`_once`). Lengths of time
    side by side, each shorter than the one before (maybe joined by "and"), are one length: "1 minute 30 seconds",
    1分30秒 (a longer or equal one after it is not a part of it, and is refused where it stands)."""
    out: list[Token] = []
    for it in _summed(items):
        if (
            it.kind == "PLACE"
            and out
            and out[-1].kind == "PLACE"
            and it.words == out[-1].words
            and it.number == out[-1].number
        ):
            continue  # "the kitchen, the kitchen", 玄関 玄関: the same place said again is one place
        if it.kind == "PLACE" and out and out[-1].kind == "PLACE" and it.number is None and out[-1].number is None:
            last = out[-1]
            joiner = "" if _is_cjk(last.surface) else " "
            out[-1] = Token(
                "PLACE", last.surface + joiner + it.surface, last.words + it.words, plural=it.plural,
                start=last.start, end=it.end,
            )  # fmt: skip
        else:
            out.append(it)
    return _refined([_once(t) if t.kind == "PLACE" else t for t in out])


_BEFORE_BARE = frozenset({"GO", "TO", "COMMA", "_STOP"})
"""What may come before a place said bare that :func:`_refined` drops: nothing said of the place itself."""


def _refined(items: list[Token]) -> list[Token]:
    """A place said bare, then right after (a pause or 関西 や between) the same name with a size that picks one
    ("the bedroom, the biggest bedroom", 寝室、一番広い寝室, 寝室や 一番広い寝室や) is one place, the one picked:
    the speaker names the kind, then narrows it. Read as two, the plan would pass through another bedroom on the
    way, which nobody asked for."""
    out: list[Token] = []
    k = 0
    while k < len(items):
        t, j = items[k], k + 1
        if j < len(items) and (items[j].kind == "COMMA" or items[j].kind == "AND" and items[j].surface == "や"):
            j += 1
        if (
            t.kind == "PLACE"
            and t.number is None
            and (not out or out[-1].kind in _BEFORE_BARE)
            and j + 1 < len(items)
            and items[j].kind in ("LARGEST", "SMALLEST")
            and items[j + 1].kind == "PLACE"
            and items[j + 1].words == t.words
        ):
            k = j
            continue
        out.append(t)
        k += 1
    return out


def _once(tok: Token) -> Token:
    """A name of several words said twice in a row is said once ("alice's room alice's room"), as a one-word name
    said again is (:func:`merge`)."""
    n = len(tok.words) // 2
    if n < 2 or len(tok.words) != 2 * n or tok.words[:n] != tok.words[n:]:
        return tok
    joiner = "" if _is_cjk(tok.surface) else " "
    return tok._replace(surface=joiner.join(tok.words[:n]), words=tok.words[:n])


def _summed(items: list[Token]) -> list[Token]:
    out: list[Token] = []
    for it in items:
        joined = len(out) >= 2 and out[-1].kind == "AND" and out[-2].kind == "DURATION"
        last = out[-2] if joined else out[-1] if out else None
        if it.kind == "DURATION" and last is not None and last.kind == "DURATION" and it.seconds < last.seconds:
            del out[-2 if joined else -1 :]
            joiner = "" if _is_cjk(last.surface) else " "
            surface = joiner.join((last.surface, *(["and"] if joined else []), it.surface))
            out.append(Token("DURATION", surface, seconds=last.seconds + it.seconds, start=last.start, end=it.end))
        else:
            out.append(it)
    return out


def _is_cjk(text: str) -> bool:
    return any("\u3040" <= ch <= "\u9fff" for ch in text)

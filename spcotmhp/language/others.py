""" "Another X" after an X was turned down (issue 34): "not bedroom 1, one of the other bedrooms", "not bedroom 3, not
bedroom 1, the other one", 寝室#1じゃなくて、他の寝室ならどこでも, 一番小さい寝室はやめて、他の寝室に行って. The
exclusion already says which X not to end in, so "other" (another, 他の, ほかの, 別の) adds nothing to it and is
left out; "the other one" is the X. Without an X turned down before it, "other" stays, to be refused (it picks by
something the map does not hold)."""

from __future__ import annotations

from spcotmhp.language.placewords import Token

_OTHER = frozenset({"other", "another", "他の", "ほかの", "別の"})


def other_than_excluded(items: list[Token]) -> list[Token]:
    """``items`` with "other" before an X turned down earlier left out (module docstring)."""
    excluded: list[Token] = []
    out: list[Token] = []
    skip = -1
    for k, t in enumerate(items):
        if k == skip:
            continue
        nxt = items[k + 1] if k + 1 < len(items) else None
        if t.kind == "PLACE" and (k and items[k - 1].kind == "NEG" or nxt is not None and nxt.kind == "NOT_GOAL"):
            excluded.append(t)
        if t.surface in _OTHER and t.kind in ("MODIFIER", "WORD") and nxt is not None and excluded:
            if nxt.kind == "PLACE" and any(x.words == nxt.words for x in excluded):
                continue  # "the other bedrooms": the bedrooms, less those turned down
            if nxt.kind == "ONE":
                x = excluded[-1]
                out.append(Token("PLACE", x.words[-1], x.words, start=t.start, end=nxt.end))
                skip = k + 1  # "the other one": the X
                continue
        out.append(t)
    return out

"""Apologies and reasons in Japanese tokens (:func:`spcotmhp.language.lexicon_ja.tokens_ja`): an apology between two
place phrases of the same role corrects the first (キッチンごめんリビング, お風呂にごめん洗面所に), elsewhere it is a
filler; ので before a pause is a reason's connector, not the particle で of "then"; ちょっと待って opening a sentence or
after a correction word holds nothing to correct or stop at (:func:`held`)."""

from __future__ import annotations

import re

from spcotmhp.language.placewords import Token

NUMBER_AGAIN = re.compile(
    r"^(?:の)?(?:#|ナンバー|シャープ)?(\d+|[一二三四五六七八九]|十[一二三四五六七八九]?)(?:番|ばん)?(?:だ|じゃ|や|です)?$"
)
"""A number alone after a correction (寝室 #1 いや #2 だ, 寝室の3番 いや 1番): the instance of the place just
corrected (rule 8); a copula after it says "it is #2"."""


def reasons(out: list[Token]) -> list[Token]:
    """A word ending in の before "で、" (then) says a reason with ので (床が濡れてるので、玄関まで): の and で are one
    connector, the pause after it a pause, as "から、" is."""
    if not any(t.kind == "THEN" and t.surface == "で、" for t in out):
        return out
    kept: list[Token] = []
    for t in out:
        after_no = bool(kept) and kept[-1].kind == "WORD" and kept[-1].surface[-1:] == "の"
        if t.kind == "THEN" and t.surface == "で、" and after_no:
            last = kept[-1]
            kept[-1] = last._replace(surface=last.surface + "で", end=t.start + 1)
            kept.append(Token("COMMA", "、", start=t.start + 1, end=t.end))
            continue
        kept.append(t)
    return kept


APOLOGIES = frozenset({"ごめん", "ごめんね", "ごめんなさい", "すみません", "すいません", "すまん"})
"""Apologies, fillers elsewhere (ごめん、キッチン行って), that correct when said with no pause between two places or
two numbers of one place (寝室の1番ごめん2番, キッチンごめんリビング, お風呂にごめん洗面所に), as "、ごめん、" does (the
table's CORRECTION)."""


def _named(tok: Token) -> bool:
    """A place, or a number said after one (寝室の1番)."""
    return tok.kind == "PLACE" or tok.kind == "WORD" and NUMBER_AGAIN.match(tok.surface) is not None


_MARKED = {"GOAL": "goal", "GOAL_THEN": "goal", "GO": "goal", "VIA": "via", "VIA_THEN": "via", "STOP": "stop"}
_MARKED |= {"AVOID": "avoid", "NOT_GOAL": "not_goal"}
"""Markers a place phrase ends with (お風呂に, 廊下を通って, 洗面所行って), by the role they give the place: an
apology after one still follows the place."""


_TRAILING = frozenset({"_STOP", "COMMA", "WORD", "AND"})
"""What may follow a place that ends a sentence (玄関やった: や, then った; a full stop): no part of an instruction."""


def after_a_place(out: list[Token]) -> bool:
    """Whether the tokens so far end with a place phrase: a place or its number (:func:`_named`), or a place with
    its marker (お風呂に ごめん 洗面所に: the apology corrects the phrase, its particle with it)."""
    if not out:
        return False
    return _named(out[-1]) or out[-1].kind in _MARKED and len(out) > 1 and _named(out[-2])


def apologies(out: list[Token]) -> list[Token]:
    """Each apology kept by :func:`tokens_ja` a correction where it stands between two place phrases
    (:func:`corrects`), else left out as the filler it is."""
    if not any(t.kind == "_APOLOGY" for t in out):
        return out
    return [
        t._replace(kind="CORRECTION") if t.kind == "_APOLOGY" else t
        for k, t in enumerate(out)
        if t.kind != "_APOLOGY" or corrects(out, k)
    ]


def corrects(out: list[Token], k: int) -> bool:
    """Whether the apology ``out[k]`` stands between two place phrases it corrects: a place (or number) follows it,
    and where a marker ended the phrase before it, a marker of the same role ends the phrase after it (お風呂にごめん
    洗面所に, 洗面所行って: the goal said again; after a goal's marker, a place ending the sentence, which is a goal
    unmarked: リビング行ってごめん玄関; リビングを避けてすみません寝室へ says another part: a filler)."""
    if k + 1 >= len(out) or not _named(out[k + 1]):
        return False
    if out[k - 1].kind not in _MARKED:
        return True
    if _MARKED[out[k - 1].kind] == "goal" and all(t.kind in _TRAILING for t in out[k + 2 :]):
        return True  # リビング行って ごめん玄関(やった): a place that ends the sentence is its goal, said again
    return k + 2 < len(out) and _MARKED.get(out[k + 2].kind) == _MARKED[out[k - 1].kind]


def held(out: list[Token]) -> list[Token]:
    """ちょっと待って (MID_CORRECTION: "hold on") opening a sentence (ちょっと待って、玄関じゃなくて廊下に行って) or
    said right after a correction word (いやちょっと待って、居間にして) is the speaker holding on before saying what
    they mean: left out, with its pause; between two places it stays, a correction or a stop (refused)."""
    if not any(t.kind == "MID_CORRECTION" for t in out):
        return out
    kept: list[Token] = []
    k = 0
    while k < len(out):
        t = out[k]
        opening = not kept or kept[-1].kind in ("_STOP", "CORRECTION")
        if t.kind == "MID_CORRECTION" and opening:
            k += 2 if k + 1 < len(out) and out[k + 1].kind == "COMMA" else 1
            continue
        kept.append(t)
        k += 1
    return kept

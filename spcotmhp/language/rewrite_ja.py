"""Japanese pauses and repetitions as people say them, written so the grammar can read them (issue 34).

* **Pauses** (:func:`pauses_ja`): an ellipsis (…, ‥, ... after NFKC) is a pause, written 、 (a hesitation carries
  no meaning: "リビング…間違えた、玄関" is "リビング、間違えた、玄関"). A negation of a place said *after a pause*
  (X、じゃなくて Y; X…じゃなくて Y; and, in a transcript with no punctuation at all, where a space is the only mark
  a speech recogniser leaves of a pause, X じゃなくて Y) takes back what was just said: it is a self-correction,
  written as the correction word 、じゃなくて、 (Y replaces X). Said straight after the place (Xじゃなくて Y) it
  is a contrast, X not the goal, as before. じゃない glued to the word after it is adnominal (寝室 #3 じゃない寝室:
  a bedroom that is not #3) and stays as said.
* **さ of direction** (:func:`pauses_ja`): in 東北 and 北海道 speech さ after a noun marks where one goes, as へ
  does (台所さ行って, 玄関さ来て); it is read as へ where it stands between a noun written in kanji or katakana
  and a verb of going or coming (行, い[っくけこ], 来, き[てた], 向か, 戻). Elsewhere さ is left as said (だからさ、).
* **A copula after a place** (:func:`said_once`): だ, じゃ (広島, 九州) and や (関西), and their past forms だった,
  じゃった, やった (a correction: 寝室やった, "it was the bedroom"), with an emphasis (関西 やで, やねん; やって,
  だって, だってば: "I said it is X"), polite でした, and の間違い(でした) ("X, by mistake", a correction's "I
  meant X"), right after a place and
  before the end, a 。/、, another place or a correction say "it is X" (台所だ, 居間だ。, リビングじゃ,
  キッチンだキッチンに行って): the place is what was asked for, as a bare place is, and the copula is left out.
* **Mood and topic particles** (:func:`said_once`): わ, ぞ, ぜ, さ, や (関西: 行ってや), のよ, わよ,
  わね, よね before the end, a 。 or a 、 (お手洗いじゃなかったわ。, 掃除当番だからさ、) say the
  speaker's mood; は right after a place's marker (物置きにはそーっと行って, トイレまではゆっくり)
  sets it off as a topic without changing its role, and so does は between a place and a verb of passing,
  stopping or avoiding said apart from it (トイレは えー 通らないで); both are left out. A bare marker cut off by a
  correction (キッチンで、違う、リビングで) goes with what the correction takes back. A 、 right after another
  (洗面所、あ、違った: the filler between them left out) or opening the sentence separates nothing
  and is left out.
* **Back to a place named** (:func:`said_once`): 戻って / 帰って right after a place (リビング もどって) says where to
  go back to, as に戻って does; after a person (パパが帰ってくるから, じいちゃん帰ってきた) someone else comes home, a
  statement for the talk rule (talk_ja); only with neither before it does it ask for the start, and stays refused.
* **"Xでいい"** (:func:`said_once`): a place followed by でいい(よ / から) says the place will do (一番近い寝室でいいよ,
  廊下でいいから行って): the place is the one asked for, as a bare place is.
* **"There" for the place just named** (:func:`there_ja`): そこ(へ / に) before a verb of going, when the last
  place said before it was said bare (no marker: 物置きの隣の寝室、わかる？そこ行って; 寝室の2番、…、そこへ行け)
  and nothing but talk and pauses came between, is that place, already the goal: そこ is left out and the verb
  goes with it. After a place with a role (キッチンを通って、そこへ) it stays as said.
* **Repetitions** (:func:`said_once`): the same place said twice in a row, with nothing but a space or a filler
  between (トイレ トイレまで, 風呂場 風呂場行って: a speaker restarting the phrase), is said once.

Only sentences that hold what a rewrite looks for are rewritten (a character test first), so the planning latency
of an ordinary instruction is unchanged.
"""

from __future__ import annotations

import re

from spcotmhp.language.excluded_ja import asked_there_ja, contrasted_numbers, excluded_ja
from spcotmhp.language.lexicon_ja import of_the_places_ja, said_again_ja
from spcotmhp.language.others import other_than_excluded
from spcotmhp.language.placewords import Token
from spcotmhp.language.spoken_ja import (
    any_first,
    avoid_marker,
    cancel_corrects,
    in_order_verb,
    quoted_whole,
    waits_ja,
)
from spcotmhp.language.talk_ja import PEOPLE
from spcotmhp.language.withdrawals_ja import withdrawals_ja

_ELLIPSIS = re.compile(r"(?:\.{2,}|…+|‥+)[、,]?")
_NEGATIONS = (
    "じゃなくて",
    "じゃなく",
    "ではなくて",
    "ではなく",
    "じゃない",
    "ではない",
    "やなくて",
    "やのうて",
    "じゃのうて",
)  # the longer of two forms first: the pattern below tries them in this order
_AFTER_PAUSE = re.compile(r"(?:、|(?P<space>\s+))(?P<neg>" + "|".join(_NEGATIONS) + r")(?P<after>\s*、?)")
_PUNCTUATION = frozenset("、。,.!?！？「」")


_DIRECTION_SA = re.compile(
    r"(?:(?<=[\u4e00-\u9fff\u30a1-\u30ff])|(?<=ほう)|(?<=とこ))さ"
    r"(?=(?:ゆっくり|すぐ|はやく|早く|急いで|静かに)?(?:行|い[っくけこ]|来|き[てた]|向か|戻|もど))"
)
"""The さ of direction (Tohoku and Hokkaido: へ) after a place, its ほう or とこ, before a verb of going, an adverb of
manner maybe between (食堂のほうさ行って, 食堂さゆっくり行って)."""
_COPULAS = frozenset(
    {
        "だ",
        "じゃ",
        "や",
        "だった",
        "じゃった",
        "やった",
        "やで",
        "やねん",
        "やって",
        "だって",
        "だってば",
        "でした",
        "でしたわ",
        "の間違い",
        "の間違いでした",
        "の間違いです",
        "の間違いだった",
        "のまちがい",
    }
)
_AFTER_COPULA = frozenset({"_STOP", "COMMA", "PLACE", "CORRECTION"})
_MOOD = frozenset({"わ", "ぞ", "ぜ", "さ", "や", "のよ", "わよ", "わね", "よね"})
_BARE_MARKERS = frozenset({"に", "へ", "まで", "で"})
_ROLE_AFTER_TOPIC = frozenset({"AVOID", "VIA", "STOP"})


_MAY_PAUSE = re.compile(r"[…‥]|[.．]{2}|じゃな|ではな|やな|のうて|さ")
"""What :func:`pauses_ja` may rewrite, looked for in the text as said (before NFKC: full-width dots included)."""


def may_pause(text: str) -> bool:
    """Whether ``text`` (as said) holds anything :func:`pauses_ja` rewrites: only then is it normalised for it."""
    return _MAY_PAUSE.search(text) is not None


def pauses_ja(text: str) -> str:
    """``text`` (normalised) with its pauses written as 、, negations after a pause as corrections and the さ of
    direction as へ (module docstring)."""
    if "さ" in text:
        text = _DIRECTION_SA.sub("へ", text)
    if "." in text or "…" in text or "‥" in text:
        text = _ELLIPSIS.sub("、", text)
    if not any(n in text for n in _NEGATIONS):
        return text
    transcript = not any(ch in _PUNCTUATION for ch in text)
    return _AFTER_PAUSE.sub(lambda m: _corrected(m, text, transcript), text)


def _corrected(m: re.Match, text: str, transcript: bool) -> str:
    """A negation after a pause as the correction word, or as said (module docstring)."""
    if m.group("space") and not transcript:
        return m.group(0)  # spaces between words in a punctuated text are no pause
    end = m.end()
    glued = not m.group("after") and end < len(text)
    if m.group("neg").endswith("ない") and glued:
        return m.group(0)  # じゃない寝室: the bedroom that is not X
    return f"、{m.group('neg')}、"


_SAID_AGAIN = frozenset({"WORD", "CORRECTION", "BACK", "COMMA", "AND"})
_RELATION_KINDS = frozenset({"CLOSEST", "FARTHEST", "NEXT_TO", "LARGEST", "SMALLEST"})
_WAITS = frozenset({"DURATION", "UNBOUNDED_WAIT", "THERE"})


def false_starts(items: list[Token]) -> list[Token]:
    """A place word begun and said again whole (キッキッチン: the start as the word is written, right before it): the
    broken start is left out, as English rule 8 does ("the st... storeroom")."""
    return [
        t for k, t in enumerate(items)
        if not (
            t.kind == "WORD" and k + 1 < len(items) and items[k + 1].kind == "PLACE" and t.end == items[k + 1].start
            and t.surface != items[k + 1].surface and items[k + 1].surface.startswith(t.surface)
        )
    ]  # fmt: skip


def spoken_tokens(items: list[Token], text: str = "") -> list[Token]:
    """The token rewrites of this module and of :mod:`spcotmhp.language.lexicon_ja` (numbers said again after a
    correction, relations said after the place), each run only on tokens holding what it looks for: an ordinary
    instruction pays one look at its kinds. ``text``: the sentence the tokens index (spaces left out)."""
    kinds = {t.kind for t in items}
    if "WORD" in kinds and "PLACE" in kinds:
        items = false_starts(items)
    if kinds & {"WITHDRAW_WAIT", "WITHDRAW", "ALLOW"}:
        items = withdrawals_ja(items)  # withdrawals_ja: 待たなくていいや, 洗面所は通らなくていい
        kinds = {t.kind for t in items}
    if "CANCEL" in kinds:
        items = cancel_corrects(items)
        kinds = {t.kind for t in items}
    if "CORRECTION" in kinds:
        items = said_again_ja(items)
    closing = "DE" in kinds and (items[-1].kind == "DE" or "_STOP" in kinds)  # 行き先はトイレで
    if (
        kinds & _SAID_AGAIN
        or closing
        or any(a.kind == b.kind == "PLACE" for a, b in zip(items, items[1:], strict=False))
    ):
        items = said_once(items)
    if kinds & _RELATION_KINDS and kinds & {"WORD", "DE"}:  # 寝室の一番大きいとこ, 寝室で一番大きいの
        items = of_the_places_ja(items)
    if kinds & {"CONDITION", "PROPERTY"} and "WORD" in kinds:
        items = quoted_whole(items, text)
    if "IN_ORDER" in kinds:
        items = in_order_verb(items)
    if "ANY_AFTER" in kinds:
        items = any_first(items)
    if "AVOID" in kinds and "GOAL" in kinds:
        items = avoid_marker(items)
    if kinds & _WAITS or "DE" in kinds and "WORD" in kinds:
        items = waits_ja(items)  # spoken_ja: lengths said after or corrected, いて, until told
    if "NOT_GOAL" in kinds and "WORD" in kinds:
        items = contrasted_numbers(items)
    other_than = kinds & {"AVOID", "NOT_GOAL"} and any(t.surface.startswith("以外") for t in items)
    if kinds & {"EXCLUDED", "CANCEL"} or other_than:
        items = excluded_ja(items)  # excluded_ja: 風呂に一番近いのはやめて, 2番以外で
    if any(t.kind == "NOT_GOAL" for t in items) and "WORD" in kinds:
        items = other_than_excluded(items)  # others.py: 寝室#1じゃなくて、他の寝室
    if "WHICH" in kinds and "THERE" in kinds:
        items = asked_there_ja(items)
    return there_ja(items) if "THERE" in kinds else items


def _person(word: str) -> bool:
    """A word naming a person, or ending in が (the subject's marker): before 帰る someone else comes home."""
    return word.endswith("が") or PEOPLE.search(word) is not None


def said_once(items: list[Token]) -> list[Token]:
    """Copulas, mood and topic particles, empty pauses and cut-off markers left out, "Xでいい" read as X, and the
    same place said twice in a row said once (module docstring)."""
    out: list[Token] = []
    skip = 0
    for k, it in enumerate(items):
        if skip:
            skip -= 1
            continue
        last = out[-1] if out else None
        nxt = items[k + 1] if k + 1 < len(items) else None
        if _left_out(last, it, nxt):
            continue
        if it.kind == "DE" and _will_do(last, nxt):  # 一番近い寝室でいいよ, 廊下でいいから
            skip = 1 + (k + 2 < len(items) and items[k + 2].kind == "FROM")
            continue
        if it.kind == "BACK" and last is not None and last.kind == "PLACE" and last.end == it.start:
            out.append(it._replace(kind="GOAL"))  # リビング もどって: back to the place named, not to the start
            continue
        if it.kind == "BACK" and last is not None and last.kind == "WORD" and _person(last.surface):
            out.append(it._replace(kind="WORD"))  # パパが帰ってくるから: someone else comes home (talk_ja)
            continue
        if (
            last is not None and it.kind == last.kind == "PLACE" and it.words == last.words
            and it.number == last.number and it.floor == last.floor
        ):  # fmt: skip
            out[-1] = it
        else:
            out.append(it)
    return out


def _left_out(last: Token | None, it: Token, nxt: Token | None) -> bool:
    """Whether ``it`` (after ``last`` as kept, before ``nxt``) carries nothing the grammar needs (module
    docstring): a pause after a pause, a marker cut off by a correction, a topic は, a mood particle, a copula."""
    ends = nxt is None or nxt.kind in ("_STOP", "COMMA")
    after_place = last is not None and last.kind == "PLACE"
    if it.kind == "COMMA":
        return last is None or last.kind == "COMMA"
    if it.kind == "DE" and it.surface == "で" and after_place and (nxt is None or nxt.kind == "_STOP"):
        return True  # 行き先はトイレで, やっぱり洗面所で: "X, please" (でお願い), the request left unsaid
    if it.kind in ("DE", "GOAL"):  # キッチンで、違う、リビングで
        return it.surface in _BARE_MARKERS and nxt is not None and nxt.kind == "CORRECTION"
    if it.kind not in ("WORD", "AND"):
        return False
    if it.surface in _MOOD and ends:
        return True
    if it.kind == "WORD" and it.surface == "は":  # 物置きには, トイレは えー 通らないで
        return _marked(last) or after_place and nxt is not None and nxt.kind in _ROLE_AFTER_TOPIC
    glued = last is not None and last.end == it.start
    return it.kind == "WORD" and it.surface in _COPULAS and after_place and glued and (
        nxt is None or nxt.kind in _AFTER_COPULA)  # fmt: skip


def _will_do(last: Token | None, nxt: Token | None) -> bool:
    """Whether で after ``last`` and before ``nxt`` says "Xでいい": the place X will do."""
    return (
        last is not None and last.kind == "PLACE" and nxt is not None and nxt.kind == "WORD" and nxt.surface == "いい"
    )


def _marked(last: Token | None) -> bool:
    """Whether ``last`` is a place's bare marker (に, へ, まで, で), which a topic は may follow."""
    return last is not None and last.kind in ("GOAL", "DE") and last.surface in _BARE_MARKERS


_BETWEEN_THERE = frozenset({"COMMA", "_STOP", "WORD"})


def there_ja(items: list[Token]) -> list[Token]:
    """そこ(へ) before a verb of going as the bare place said last (module docstring)."""
    for k, it in enumerate(items):
        if it.kind != "THERE" or it.surface not in ("そこ", "そこに") or k + 1 >= len(items):
            continue
        verb = items[k + 1]
        going = verb.kind == "GO" or verb.kind == "GOAL" and verb.surface[:1] in "へに" and len(verb.surface) > 1
        last = next((j for j in range(k - 1, -1, -1) if items[j].kind == "PLACE"), None)
        if not going or last is None or any(t.kind not in _BETWEEN_THERE for t in items[last + 1 : k]):
            continue
        if last + 1 == k or items[last + 1].kind not in _BETWEEN_THERE:
            continue  # the place is right before そこ, or said with a marker (a role of its own)
        said = verb._replace(kind="GO", surface=verb.surface.lstrip("へに") if verb.kind == "GOAL" else verb.surface)
        return [*items[:k], said, *items[k + 2 :]]
    return items

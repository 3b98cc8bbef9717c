"""Japanese as people say it (issue 34, wave 4): rooms told by what is in them, the master bedroom, requests said
as "it would help if", and waits said in the order speech puts them. Each rule says why it keeps the meaning.

Text rewrites (:func:`spoken_text`, before the sentence is cut into tokens):

* **A room told by its contents**: a thing of the table's ``contents`` (洗濯機, 冷蔵庫, ソファ, テレビ, ダイニング
  テーブル) followed by の / のある / がある and a word for its place (とこ, 前, 部屋, 辺り, 近く, 横, 方) is the
  room that holds it (洗濯機のとこ: the washroom, 冷蔵庫の前: the kitchen, テレビの部屋: the living room), as English
  rule 9 (:func:`~spcotmhp.language.rewrite_en.contents_en`) reads "the room with the washing machine": only where
  exactly one place word of the map holds the thing; else the words stay as said, to be refused.
* **The master bedroom**: 主寝室 (and マスターベッドルーム) is by definition a home's largest bedroom (広辞苑: 主寝室,
  the main bedroom of a house, the couple's), read as 一番大きい寝室, as English reads "master bedroom".
* **"It would help if you went"**: a たら clause after a favour (行ってくれたら, 行ってもらえたら) whose main clause is
  助かる / 嬉しい / ありがたい says what would please the speaker, which is how a polite request is said, not a
  condition the robot should check: it is read as the favour asked (行ってくれる). Any other たら stays a condition.

Token rewrites (:func:`waits_ja`):

* **A length said after its wait** (リビングで待っててくれる？15分ぐらい): the length of that wait, as an afterthought.
* **A length before そこで or before the place of its wait** (10分そこで待って, 90秒だけダイニングで待って): the order
  of the adverbs changes nothing (そこで10分待って, ダイニングで90秒待って).
* **A length corrected** (5分待って、いや10分(で)): the new length replaces the one said before it, as a corrected
  place replaces the place of the same role (issue 34, rule 2).
* **いて after a length or そこに** (1時間いて, そこにいて): "stay", a wait.
* **A marker parted from its avoiding verb** (台所には絶対入らないで: an adverb between に and 入らないで): に / へ go
  with the verb, as 台所に入らないで.
* **いて / おって after a place's で** (廊下でおって): staying there, a wait with no length.
* **A cancel between two places** (:func:`cancel_corrects`: 取り消し、リビングにして): a correction.
* **An order word before a bare verb of passing** (:func:`in_order_verb`: 廊下、広場の順に通って): the list's order.
* **"Anywhere" before the place** (:func:`any_first`: どこでもいいから寝室): the place's name alone.
* **Until told** (呼ぶまで, 次の指示まで, 私が来るまで) said in the clause of a wait: the wait lasts until the next
  instruction, as a wait with no length does (the speaker's call or return is how that instruction comes); said
  anywhere else it stays, refused.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence

from spcotmhp.language.placewords import Token
from spcotmhp.language.table import WordTable
from spcotmhp.language.text import normalise

_HEADS = r"(?:とこ(?:ろ)?|前|部屋|辺り|辺|あたり|近く|横|そば|方|ほう|場所)"
_LINKS = r"(?:の(?:ある|置いてある|おいてある)?|が(?:ある|置いてある|おいてある))"
_MASTER = {"主寝室": "寝室", "マスターベッドルーム": "寝室", "メインベッドルーム": "寝室"}
_PLEASED = re.compile(
    r"(くれ|もらえ|貰え|いただけ|頂け)たら(?:本当に|ほんとに|とても|すごく|めっちゃ|超)?"
    r"(?:助かる|助かります|嬉しい|うれしい|ありがたい|有難い|有り難い)(?:んだけど|んですけど|んですが|のですが|んだが|けど|です|なあ|なー|な|[よわね])*"
)


@functools.cache
def _contents_pattern(things: tuple[str, ...]) -> re.Pattern:
    alternatives = "|".join(re.escape(t) for t in sorted(things, key=len, reverse=True))
    return re.compile(f"(?P<thing>{alternatives}){_LINKS}{_HEADS}")


@functools.cache
def _looked_for(things: tuple[str, ...]) -> re.Pattern:
    """One search for anything :func:`spoken_text` rewrites: a thing of the table, a master bedroom, たら."""
    return re.compile("|".join(re.escape(w) for w in (*things, *_MASTER, "たら")))


def spoken_text(text: str, table: WordTable, place_words: Sequence[str]) -> str:
    """``text`` with the text rewrites of the module docstring; unchanged (and not normalised) when it holds
    nothing they look for (one search)."""
    things = tuple(table.contents)
    if _looked_for(things).search(text) is None:
        return text
    text = normalise(text)
    words = set(place_words)
    if things:
        text = _contents_pattern(things).sub(lambda m: _holder(m, table, words), text)
    for said, word in _MASTER.items():
        if word in words:
            text = text.replace(said, f"一番大きい{word}")
    return _PLEASED.sub(lambda m: f"{m.group(1)}る", text) if "たら" in text else text


def _holder(m: re.Match, table: WordTable, words: set[str]) -> str:
    """The one place word of the map holding the thing, or the words as said."""
    held = sorted(set(table.contents[m.group("thing")]) & words)
    return held[0] if len(held) == 1 else m.group(0)


_TOLD = re.compile(r"(?:呼ぶ|よぶ|声を?かける|言う|いう|来る|くる|戻る|もどる|指示.*)まで$")
_STAY = frozenset(
    {
        "いて",
        "いてね",
        "いてて",
        "いといて",
        "いておいて",
        "いてください",
        "おって",
        "おってね",
        "おってや",
        "おっといて",
    }
)
"""いる and (西日本) おる, "be, stay", in the te-form."""
_SEPARATORS = frozenset({"_STOP", "COMMA"})
_WILL_DO = frozenset({"いい", "いいよ", "ええ", "よい", "結構"})
"""What "Xでいい" says after a length (3分でいい): that length will do."""


def waits_ja(items: list[Token]) -> list[Token]:
    """The token rewrites of the module docstring, each only on a sentence holding what it looks for."""
    items = [_stay(items, k) for k in range(len(items))]
    if any(t.kind == "WAIT" and t.surface in _STAY for t in items):
        items = _stay_at(items)
    if any(t.kind == "UNBOUNDED_WAIT" for t in items):
        items = _until_told(items)
    if not any(t.kind == "DURATION" for t in items):
        return items
    return _length_after(_length_corrected(_length_before_there(_length_first(items))))


def _length_first(items: list[Token]) -> list[Token]:
    """DURATION PLACE で WAIT (90秒だけダイニングで待って): the length said first is that wait's (ダイニングで90秒)."""
    out = list(items)
    for k in range(len(out) - 3):
        if [t.kind for t in out[k : k + 4]] == ["DURATION", "PLACE", "DE", "WAIT"]:
            out[k : k + 3] = [out[k + 1], out[k + 2], out[k]]
    return out


def avoid_marker(items: list[Token]) -> list[Token]:
    """A bare に / へ right before an AVOID said apart from it is part of the avoiding (module docstring)."""
    out: list[Token] = []
    for it in items:
        last = out[-1] if out else None
        if it.kind == "AVOID" and last is not None and last.kind == "GOAL" and last.surface in ("に", "へ"):
            out[-1] = it._replace(surface=last.surface + it.surface, start=last.start)
        else:
            out.append(it)
    return out


_CLAUSE_CONDITIONS = frozenset({"たら", "なら", "ならば", "ば", "だったら"})


def quoted_whole(items: list[Token], text: str = "") -> list[Token]:
    """A condition ending a clause (雨降ってたら, 6時になったら) or a property said of a place (窓のある) takes the
    words said before it in its clause (fillers between them included, as said in ``text``) into its token: a
    refusal quotes the whole phrase, not its ending (風呂が空いてたら: with the place it is said of, which stays a
    token of its own)."""
    chars = [ch for ch in text if not ch.isspace()]
    out: list[Token] = []
    for it in items:
        whole = it.kind == "PROPERTY" or it.kind == "CONDITION" and it.surface.lstrip("っ") in _CLAUSE_CONDITIONS
        k = len(out)
        while whole and k > 0 and (
            out[k - 1].kind == "WORD" or out[k - 1].kind == "GOAL" and out[k - 1].surface in ("に", "へ") and k > 1
        ):  # fmt: skip
            k -= 1
        if k < len(out) and out[k].kind == "WORD":
            first = out[k - 1] if k > 0 and out[k - 1].kind == "PLACE" and out[k].surface[0] in "がはの" else out[k]
            said = "".join(chars[first.start : it.end]) if chars else "".join(t.surface for t in [*out[k:], it])
            it = it._replace(surface=said, start=out[k].start)
            del out[k:]
        out.append(it)
    return out


def in_order_verb(items: list[Token]) -> list[Token]:
    """ "A、Bの順に通って / 寄って" (廊下、広場の順に通って): the order word before a verb of passing or stopping said
    without を is that verb's list in the order said, as "A、Bを通って" is (a list's order is the order said)."""
    out: list[Token] = []
    for k, it in enumerate(items):
        nxt = items[k + 1] if k + 1 < len(items) else None
        if it.kind == "IN_ORDER" and nxt is not None and nxt.kind in ("VIA", "STOP") and nxt.surface[0] not in "をにへ":
            continue
        out.append(it)
    return out


def any_first(items: list[Token]) -> list[Token]:
    """ "どこでもいいから寝室" (anywhere will do, a bedroom): said before the place it is about, "any" adds nothing
    to the place's name, which goes to the closest of its places: left out."""
    return [
        t
        for k, t in enumerate(items)
        if not (
            t.kind == "ANY_AFTER"
            and t.surface.startswith("どこでも")
            and (k == 0 or items[k - 1].kind in _SEPARATORS)
            and k + 1 < len(items)
            and items[k + 1].kind == "PLACE"
        )
    ]


def _stay(items: list[Token], k: int) -> Token:
    """いて after a length or そこ(に) as a wait."""
    it = items[k]
    before = items[k - 1] if k else None
    if it.kind == "WORD" and it.surface in _STAY and before is not None and before.kind in ("DURATION", "THERE"):
        return it._replace(kind="WAIT")
    at_place = before is not None and before.kind == "DE" and k > 1 and items[k - 2].kind == "PLACE"
    if it.kind == "WORD" and it.surface in _STAY and at_place:
        return it._replace(kind="WAIT")  # 廊下でおって: staying at the corridor
    return it


_CANCELS = frozenset({"取り消し", "とりけし", "キャンセル", "取り消して"})


def cancel_corrects(items: list[Token]) -> list[Token]:
    """A cancel said between two places (寝室に行って、えっと、取り消し、リビングにして) takes back what was said
    before it, as a correction word does: the place said after it replaces the one before. With no place after it
    (or none before), it stays a cancel, refused."""
    out = list(items)
    for k, it in enumerate(out):
        if it.kind != "CANCEL" or it.surface not in _CANCELS:
            continue
        if any(t.kind == "PLACE" for t in out[:k]) and any(t.kind == "PLACE" for t in out[k + 1 :]):
            out[k] = it._replace(kind="CORRECTION")
    return out


def _stay_at(items: list[Token]) -> list[Token]:
    """ "X に (length) いて": いる takes に for where one is, so X is where the robot waits (X で待って)."""
    out = list(items)
    for k in range(2, len(out)):
        marker = out[k - 2] if out[k - 1].kind == "DURATION" else out[k - 1]
        at = k - 2 if out[k - 1].kind == "DURATION" else k - 1
        said = out[k].kind == "WAIT" and out[k].surface in _STAY
        if said and marker.kind == "GOAL" and marker.surface == "に" and at > 0 and out[at - 1].kind == "PLACE":
            out[at] = marker._replace(kind="DE")
    return out


def _clause(items: list[Token], k: int) -> list[Token]:
    """The tokens of the clause around ``items[k]``: between the separators before and after it."""
    start = max((j + 1 for j in range(k) if items[j].kind in _SEPARATORS), default=0)
    end = next((j for j in range(k + 1, len(items)) if items[j].kind in _SEPARATORS), len(items))
    return items[start:end]


def _until_told(items: list[Token]) -> list[Token]:
    return [
        t
        for k, t in enumerate(items)
        if not (
            t.kind == "UNBOUNDED_WAIT"
            and _TOLD.search(t.surface)
            and (any(x.kind == "WAIT" for x in _clause(items, k)) or _after_wait(items, k))
        )
    ]


def _after_wait(items: list[Token], k: int) -> bool:
    """Whether ``items[k]`` closes the sentence right after a wait's clause (待ってて、呼ぶまで)."""
    j = k - 1
    while j >= 0 and items[j].kind == "COMMA":
        j -= 1
    rest = items[k + 1 :]
    return j < k - 1 and j >= 0 and items[j].kind == "WAIT" and all(t.kind in _SEPARATORS for t in rest)


def _length_before_there(items: list[Token]) -> list[Token]:
    out = list(items)
    for k in range(len(out) - 2):
        if out[k].kind == "DURATION" and out[k + 1].kind == "THERE" and out[k + 2].kind == "WAIT":
            out[k], out[k + 1] = out[k + 1], out[k]
    return out


def _length_corrected(items: list[Token]) -> list[Token]:
    """DURATION (WAIT) (、|。) CORRECTION DURATION (で(いい) | WAIT | にして), or DURATION WAIT (、|。) DURATION にして
    (make it ...): the second length in place of the first."""
    for k in range(len(items) - 3):
        if items[k].kind != "DURATION":
            continue
        if items[k + 1].kind != "WAIT":  # 物置きで5分、じゃなくて10分待って
            c = k + 1 + (items[k + 1].kind == "COMMA")
            if c + 2 < len(items) and items[c].kind == "CORRECTION" and items[c + 1].kind == "DURATION":
                return [*items[:k], *items[c + 1 :]]
            continue
        c = k + 2 + (items[k + 2].kind in ("COMMA", "_STOP"))  # 5分待って。いや10分
        while c + 1 < len(items) and items[c].kind == items[c + 1].kind == "CORRECTION":
            c += 1  # いや、やっぱ: one correction
        made = c + 1 < len(items) and items[c].kind == "DURATION" and _make_it(items, c + 1)  # 、10分にして
        if made:
            return [*items[:k], items[c], items[k + 1], *items[c + 2 :]]
        if c + 1 >= len(items) or items[c].kind != "CORRECTION" or items[c + 1].kind != "DURATION":
            continue
        if _make_it(items, c + 2):
            return [*items[:k], items[c + 1], items[k + 1], *items[c + 3 :]]  # 5分待って、いや10分にして
        after = c + 2
        if after < len(items) and items[after].kind == "WAIT":
            return [*items[:k], *items[c + 1 :]]  # 5分待って、いや10分待って
        if after < len(items) and items[after].kind == "DE" and items[after].surface == "で":
            after += 1  # 10分で: "with ten minutes"
            after += after < len(items) and items[after].kind == "WORD" and items[after].surface in _WILL_DO
        if after < len(items) and items[after].kind not in (*_SEPARATORS, "THEN"):
            continue
        return [*items[:k], items[c + 1], items[k + 1], *items[after:]]
    return items


def _make_it(items: list[Token], k: int) -> bool:
    """にして (make it ...) right after a length, closing the sentence: the length said in place of the wait's."""
    return k < len(items) and items[k].surface == "にして" and all(t.kind in _SEPARATORS for t in items[k + 1 :])


def _length_after(items: list[Token]) -> list[Token]:
    """WAIT (。|、)* DURATION (。|、)* at the end: the length of that wait, unless it has one."""
    d = next((j for j in range(len(items) - 1, -1, -1) if items[j].kind == "DURATION"), None)
    if d is None or any(t.kind not in _SEPARATORS for t in items[d + 1 :]):
        return items
    w = d - 1
    while w >= 0 and items[w].kind in _SEPARATORS:
        w -= 1
    if w < 0 or items[w].kind != "WAIT" or (w > 0 and items[w - 1].kind == "DURATION"):
        return items
    return [*items[:w], items[d], items[w], *items[d + 1 :]]

"""Japanese: the place excluded after the place asked for, and the place asked about before そこ (issue 34, wave 4).

* **"X, but not the one nearest Y"** (:func:`excluded_ja`): after a place X was said (寝室に行って), a relation, a
  size or a number with a pro-form (の, ところ, とこ, やつ) and a word that turns it down (はやめて, は嫌, は除いて,
  はなし: ``EXCLUDED`` and ``CANCEL`` in ja.json) says which X not to end in: 風呂に一番近いのはやめて is
  風呂に一番近い寝室じゃなくて, 一番狭いのは嫌 is 一番狭い寝室じゃなくて, 3番はやめて is 寝室3番じゃなくて. The pro-form
  stands for X as it does in "寝室の、トイレに一番近いところ" (:func:`~spcotmhp.language.lexicon_ja.of_the_places_ja`).
  A place said and turned down (キッチンはやめて, 便所の近くの寝室はやめて) is that place not to end in. A number
  before 以外 (2番以外で, 1番以外の寝室, 1番以外ならどれでも) is likewise that instance not to end in. With no X
  said, the words stay as said, to be refused.
* **A number beside じゃなくて** (:func:`contrasted_numbers`): another instance of the numbered place before it.
* **"Which is X? Go there"** (:func:`asked_there_ja`): a question asking which place X is (ってどれ, はどこ, どれだっけ,
  ってあるじゃん: ``WHICH`` in ja.json) followed by そこ(に / へ) and a verb of going asks to go to X: the question is
  left out (a pause in its place) and そこ is read as X by :func:`~spcotmhp.language.rewrite_ja.there_ja`. A
  question with no そこ after it stays refused (the robot answers no questions).
"""

from __future__ import annotations

from spcotmhp.language.lexicon_ja import number_said_ja
from spcotmhp.language.placewords import Token

_RELATIONS = frozenset({"CLOSEST", "FARTHEST", "NEXT_TO"})
_SIZES = frozenset({"LARGEST", "SMALLEST"})
_TURNED_DOWN = frozenset({"はやめて", "やめて"})
_NOT = "じゃなくて"


def excluded_ja(items: list[Token]) -> list[Token]:
    """The exclusions of the module docstring written as X NOT_GOAL (じゃなくて)."""
    out = list(items)
    k = 0
    while k < len(out):
        it = out[k]
        down = it.kind == "EXCLUDED" or it.kind == "CANCEL" and it.surface in _TURNED_DOWN
        if down and k > 0:
            mended = _exclusion(out, k)
            if mended is not None:
                out, k = mended
                continue
        if it.kind in ("AVOID", "NOT_GOAL") and it.surface.startswith("以外") and k > 0 and out[k - 1].kind == "WORD":
            mended = _other_than(out, k)
            if mended is not None:
                out, k = mended
                continue
        k += 1
    return out


def contrasted_numbers(items: list[Token]) -> list[Token]:
    """A number said alone beside じゃなくて and a numbered place names another instance of that place, as after a
    correction (rule 8): 寝室#3のほうね、#2じゃなくて (寝室 #2 not the goal), 寝室の1番じゃなくて2番 (寝室 #2, the
    goal; said twice, 2番 2番, it is said once). With no numbered place before it, it stays as said."""
    out = list(items)
    for k, it in enumerate(out):
        if it.kind != "WORD" or (n := _alone(it.surface)) is None:
            continue
        nxt = out[k + 1] if k + 1 < len(out) else None
        before = out[k - 1] if k else None
        contrast = nxt is not None and nxt.kind == "NOT_GOAL" or before is not None and before.kind == "NOT_GOAL"
        head = next((t for t in reversed(out[:k]) if t.kind == "PLACE"), None)
        if contrast and head is not None and head.number is not None and head.words:
            out[k] = head._replace(number=n, surface=f"{head.words[-1]} #{n}", start=it.start, end=it.end)
    return out


def _alone(surface: str) -> int | None:
    """The number a word says alone, said once or twice in a row (2番2番)."""
    half = len(surface) // 2
    if len(surface) % 2 == 0 and surface[:half] == surface[half:]:
        surface = surface[:half]
    return number_said_ja(surface)


def _head(items: list[Token], before: int) -> Token | None:
    """The place X said before ``items[before]``, which a pro-form stands for."""
    return next((t for t in reversed(items[:before]) if t.kind == "PLACE"), None)


def _not_goal(at: Token) -> Token:
    return at._replace(kind="NOT_GOAL", surface=_NOT)


def _exclusion(out: list[Token], k: int) -> tuple[list[Token], int] | None:
    down, end = out[k], k + 1
    said = out[k - 1]
    if said.kind == "WORD" and said.surface in ("の", "ところ", "とこ", "やつ", "ほう", "方") and k > 1:
        k -= 1  # 風呂に一番近い の はやめて
        said = out[k - 1]
    if said.kind in _RELATIONS and k >= 2 and out[k - 2].kind == "PLACE":
        head = _head(out, k - 2)
        start = k - 2
    elif said.kind in _SIZES:
        head = _head(out, k - 1)
        start = k - 1
    elif said.kind == "WORD" and (n := number_said_ja(said.surface)) is not None:
        head = _head(out, k - 1)
        if head is None or head.number is None and not head.words:
            return None
        x = head._replace(number=n, surface=f"{head.words[-1]} #{n}", start=said.start, end=said.end)
        return [*out[: k - 1], x, _not_goal(down), *out[end:]], k + 1
    elif said.kind == "PLACE" and down.kind == "CANCEL":  # 便所の近くの寝室はやめて: that one not
        return [*out[:k], _not_goal(down), *out[end:]], k + 1
    else:
        return None
    if head is None:
        return None
    x = head._replace(number=None, start=said.end, end=down.start)
    mended = [*out[:start], *out[start:k], x, _not_goal(down), *out[end:]]
    return mended, k + 2


def _other_than(out: list[Token], k: int) -> tuple[list[Token], int] | None:
    """2番以外で (after 寝室), 1番以外の寝室: that instance not to end in."""
    n = number_said_ja(out[k - 1].surface)
    if n is None:
        return None
    after = out[k + 1] if k + 1 < len(out) else None
    if out[k].kind == "NOT_GOAL" and after is not None and after.kind == "PLACE":
        head: Token | None = after  # 1番以外の寝室: the bedroom after it
    else:
        head = _head(out, k - 1)
    if head is None or not head.words:
        return None
    said = out[k - 1]
    x = head._replace(number=n, surface=f"{head.words[-1]} #{n}", start=said.start, end=said.end)
    end = k + 1 + (after is not None and after.kind in ("DE", "ANY_AFTER") and out[k].kind == "AVOID")  # 2番以外で
    return [*out[: k - 1], x, _not_goal(out[k]), *out[end:]], k + 1


def asked_there_ja(items: list[Token]) -> list[Token]:
    """A question asking which place X is, before そこ and a verb of going, left out (module docstring)."""
    out: list[Token] = []
    for k, it in enumerate(items):
        if it.kind == "WHICH" and out and _before_there(items, k):
            if out[-1].kind not in ("_STOP", "COMMA"):
                out.append(it._replace(kind="COMMA", surface="、"))  # the question is a clause of its own
            continue
        out.append(it)
    return out


def _before_there(items: list[Token], k: int) -> bool:
    """Whether only talk (a filler word, a pause, a stop) stands between ``items[k]`` and a そこ."""
    for t in items[k + 1 :]:
        if t.kind == "THERE":
            return True
        if t.kind not in ("_STOP", "COMMA", "WHICH"):
            return False
    return False

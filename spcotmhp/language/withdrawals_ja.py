"""Japanese parts of an instruction taken back (issue 34), as in English (``forms_en.withdrawals_en``): a wait
(トイレで待ってて、いや待たなくていいや; 待機はいいや), a place to pass (洗面所通ってお風呂、いや、やっぱ洗面所は
通らなくていい; 廊下はいいや), an avoidance (リビング避けて…あ、やっぱり通っていいよ). A correction replaces what it
names with nothing, as it replaces a place with another; "just go" after it (行くだけで) and the goal said again
(そのままキッチン) restate the rest. Where nothing before it is what it takes back, its token stays, and is refused
with the table's reason (ja.json WITHDRAW_WAIT, WITHDRAW, ALLOW)."""

from __future__ import annotations

from spcotmhp.language.placewords import Token

_BETWEEN = frozenset({"COMMA", "_STOP", "CORRECTION"})
_WAIT_PARTS = frozenset({"WAIT", "DURATION", "UNBOUNDED_WAIT"})


def withdrawals_ja(items: list[Token]) -> list[Token]:
    """``items`` with each part taken back left out with what takes it back (module docstring)."""
    out = list(items)
    for _ in range(len(items)):
        k = next((k for k, t in enumerate(out) if t.kind in ("WITHDRAW_WAIT", "WITHDRAW", "ALLOW")), None)
        if k is None:
            break
        taken = _taken_back(out, k)
        if taken is None:  # nothing to take back: refused where it stands, a 〜なくていい as what need not be done
            waiver = "なくて" in out[k].surface or "んで" in out[k].surface
            said = out[k].surface.removeprefix("は")
            return [*out[:k], out[k]._replace(kind="WAIVER", surface=said) if waiver else out[k], *out[k + 1 :]]
        again = (
            out[k].kind == "ALLOW"
            and k > 0
            and out[k - 1].kind == "PLACE"
            and any(out[j].kind == "PLACE" and out[j].words == out[k - 1].words for j in taken)
        )  # リビング避けて、いや、リビング通ってもいいや: the place allowed, said again with it
        start = k - (out[k].kind == "WITHDRAW" or again)  # the place said with は
        while start > 0 and out[start - 1].kind in _BETWEEN:
            start -= 1
        out = [t for j, t in enumerate(out) if j not in taken and not start <= j <= k]
    return _just_go(out)


def _taken_back(out: list[Token], k: int) -> set[int] | None:
    """The indices of the part ``out[k]`` takes back, before it, or None."""
    kind = out[k].kind
    if kind == "WITHDRAW_WAIT":
        w = next((j for j in range(k - 1, -1, -1) if out[j].kind == "WAIT"), None)
        if w is None:
            return None
        first, last = w, w
        while first > 0 and out[first - 1].kind in ("DURATION", "DE"):
            first -= 1  # (で)(5分)待って: the place stays, its marker and length go
        while last + 1 < k and out[last + 1].kind in _WAIT_PARTS:
            last += 1
        return set(range(first, last + 1))
    if kind == "WITHDRAW":
        if k == 0 or out[k - 1].kind != "PLACE":
            return None
        words = out[k - 1].words
        via = [j for j in range(k - 2) if out[j].kind == "PLACE" and out[j].words == words and out[j + 1].kind == "VIA"]
        return {via[-1], via[-1] + 1} if via else None
    avoid = [j for j in range(1, k) if out[j].kind == "AVOID" and out[j - 1].kind == "PLACE"]
    if not avoid:
        return None
    a = avoid[-1]
    return {a - 1, a, a + 1} if out[a + 1].surface == "..." else {a - 1, a}  # リビング避けて…


def _just_go(out: list[Token]) -> list[Token]:
    """行くだけ(で) ending the sentence, after a part taken back: "just go", nothing more to read."""
    kinds = [t.kind for t in out]
    for n in (3, 2):
        tail = out[-n:]
        if len(out) > n and tail[0].kind == "GO" and tail[1].surface == "だけ" and (n == 2 or tail[2].kind == "DE"):
            rest = out[:-n]
            while rest and rest[-1].kind in ("COMMA", "_STOP"):
                rest = rest[:-1]
            return rest if "PLACE" in kinds else out
    return out

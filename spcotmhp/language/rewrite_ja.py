"""Japanese pauses and repetitions as people say them, written so the grammar can read them (issue 34).

* **Pauses** (:func:`pauses_ja`): an ellipsis (…, ‥, ... after NFKC) is a pause, written 、 (a hesitation carries
  no meaning: "リビング…間違えた、玄関" is "リビング、間違えた、玄関"). A negation of a place said *after a pause*
  (X、じゃなくて Y; X…じゃなくて Y; and, in a transcript with no punctuation at all, where a space is the only mark
  a speech recogniser leaves of a pause, X じゃなくて Y) takes back what was just said: it is a self-correction,
  written as the correction word 、じゃなくて、 (Y replaces X). Said straight after the place (Xじゃなくて Y) it
  is a contrast, X not the goal, as before. じゃない glued to the word after it is adnominal (寝室 #3 じゃない寝室:
  a bedroom that is not #3) and stays as said.
* **Repetitions** (:func:`said_once`): the same place said twice in a row, with nothing but a space or a filler
  between (トイレ トイレまで, 風呂場 風呂場行って: a speaker restarting the phrase), is said once.

Only sentences that hold what a rewrite looks for are rewritten (a character test first), so the planning latency
of an ordinary instruction is unchanged.
"""

from __future__ import annotations

import re

from spcotmhp.language.placewords import Token

_ELLIPSIS = re.compile(r"(?:\.{2,}|…+|‥+)[、,]?")
_NEGATIONS = ("じゃなくて", "じゃなく", "ではなくて", "ではなく", "じゃない", "ではない")
_AFTER_PAUSE = re.compile(
    r"(?:、|(?P<space>\s+))(?P<neg>じゃなくて|じゃなく|ではなくて|ではなく|じゃない|ではない)(?P<after>\s*、?)"
)
_PUNCTUATION = frozenset("、。,.!?！？「」")


def pauses_ja(text: str) -> str:
    """``text`` (normalised) with its pauses written as 、 and negations after a pause as corrections (module
    docstring)."""
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


def said_once(items: list[Token]) -> list[Token]:
    """The same place said twice in a row said once (module docstring): the first saying is left out."""
    out: list[Token] = []
    for it in items:
        last = out[-1] if out else None
        if (
            last is not None and it.kind == last.kind == "PLACE" and it.words == last.words
            and it.number == last.number and it.floor == last.floor
        ):  # fmt: skip
            out[-1] = it
        else:
            out.append(it)
    return out

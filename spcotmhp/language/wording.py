"""The wording of instruction errors: short excerpts of the input, the list of known place words, and near-miss
suggestions ("did you mean 'bedroom'?").

Every instruction error is one line: it names the offending words (each cut to :data:`WORD_CHARS` characters, at
most :data:`MAX_NAMED` of them), quotes at most :data:`EXCERPT_CHARS` characters of the input, and lists what is
accepted (at most :data:`MAX_LISTED` place words). Suggestions are only ever suggestions: the parser never
replaces a word by its near miss.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from itertools import pairwise

from spcotmhp.language.numbers import number_word

EXCERPT_CHARS = 60
"""Longest excerpt of an instruction quoted in an error message (longer inputs end in "…")."""
WORD_CHARS = 30
"""Longest single word quoted in an error message."""
MAX_NAMED = 6
"""Most not-understood words named in one message."""
MAX_LISTED = 30
"""Most known place words listed in one message."""
SUGGEST_SCORE = 80.0
"""A word is a near miss of a place word when rapidfuzz's normalised Indel similarity (``fuzz.ratio``, 0-100)
is at least this: one or two letters inserted, dropped or swapped in a word of 6+ letters ("bedrom",
"dinning", "alices"); short words need closer matches (a 4-letter word with one letter changed scores 75)."""
GENERIC_NOUNS = ("room", "area", "place")
"""Nouns people glue to a place word ("bathroom" for "bath"); tried as suffixes when looking for a near miss."""


def excerpt(value: object, limit: int = EXCERPT_CHARS) -> str:
    """A short, single-line, quoted rendering of a user value: ``'go to the ki…'`` or ``a dict``."""
    if isinstance(value, str):
        flat = " ".join(value.split())
        text = repr(flat if len(flat) <= limit else flat[:limit] + "…")
        # escapes of unprintable characters (\U0001342f) can make the repr ten times longer: cut it too
        return text if len(text) <= limit + 4 else text[:limit] + "…'"
    if isinstance(value, (int, float, bool)) or value is None:
        text = repr(value)
        return text if len(text) <= limit else text[:limit] + "…"
    return f"a {type(value).__name__}"


def named(words: Iterable[str]) -> str:
    """ "'a', 'b'" for at most :data:`MAX_NAMED` words, each cut to :data:`WORD_CHARS` characters."""
    words = list(dict.fromkeys(words))
    shown = [excerpt(w, WORD_CHARS) for w in words[:MAX_NAMED]]
    return ", ".join(shown) + (f" and {len(words) - MAX_NAMED} more" if len(words) > MAX_NAMED else "")


def not_understood(words: Sequence[str]) -> str:
    """ " (not understood: a, b)" or ""."""
    if not words:
        return ""
    words = list(dict.fromkeys(words))
    shown = [w if len(w) <= WORD_CHARS else w[:WORD_CHARS] + "…" for w in words[:MAX_NAMED]]
    more = f" and {len(words) - MAX_NAMED} more" if len(words) > MAX_NAMED else ""
    return f" (not understood: {', '.join(shown)}{more})"


def known_words(place_words: Sequence[str]) -> str:
    """ "known place words: a, b, ..." (at most :data:`MAX_LISTED` shown) for error messages; a number word or
    digits alone are left out (said only inside a taught name, "aisle one": :mod:`spcotmhp.language.numbers`)."""
    words = sorted({w for w in place_words if number_word(w) is None})
    if not words:
        return "the model knows no place words"
    shown = ", ".join(words[:MAX_LISTED]) + (f", ... ({len(words)} in all)" if len(words) > MAX_LISTED else "")
    return f"known place words: {shown}"


def suggestions(unknown: Sequence[str], place_words: Sequence[str]) -> list[str]:
    """Place words that the not-understood words (in sentence order) nearly spell: each word alone, each pair of
    neighbours written together ("bed room" -> "bedroom"), and each word without a generic noun glued to it
    ("bathroom" -> "bath"). Compared case-insensitively and without apostrophes ("alices" -> "alice's")."""
    if not place_words or not unknown:
        return []
    from rapidfuzz import fuzz, process  # here, not at import: only an instruction with unknown words needs it

    keys = {_key(w): w for w in place_words}
    choices = list(keys)
    candidates = [_key(w) for w in unknown[: 2 * MAX_NAMED]]
    spelled_right = {c for c, w in zip(candidates, unknown, strict=False) if w in place_words}
    candidates += [a + b for a, b in pairwise(candidates)]
    candidates += [c[: -len(n)] for c in candidates for n in GENERIC_NOUNS if c.endswith(n) and len(c) > len(n) + 2]
    out: list[str] = []
    for cand in candidates:
        if not cand or len(cand) > 4 * WORD_CHARS or cand in spelled_right:
            continue
        hit = process.extractOne(cand, choices, scorer=fuzz.ratio, score_cutoff=SUGGEST_SCORE)
        if hit and keys[hit[0]] not in out:
            out.append(keys[hit[0]])
    return out[:3]


def unknown_tail(unknown: Sequence[str], place_words: Sequence[str]) -> str:
    """The end of an unknown-word message: "; did you mean 'bedroom'? known place words: ..." (no suggestion
    part when nothing is close)."""
    near = suggestions(unknown, place_words)
    quoted = " or ".join("'" + w + "'" for w in near)
    guess = f"; did you mean {quoted}?" if near else ""
    return f"{guess}{' ' if near else '; '}{known_words(place_words)}"


def _key(word: str) -> str:
    return word.lower().replace("'", "").replace("\u2019", "").replace(" ", "")

"""Pronunciations for the recogniser: CMUdict (shipped with pocketsphinx) plus letter-to-sound rules.

* A word in CMUdict keeps all its dictionary pronunciations.
* Every *place* word also gets a spelling pronunciation from :func:`letter_to_sound` when that differs from
  the dictionary's: CMUdict lists one or two common forms, and a spelling form covers other ways people say
  a name (corridor as "corri-dor", K AO R IH D AO R, next to CMUdict's K AO R AH D ER). The grammar words
  are closed-class words that CMUdict has, so they get no extra variant.
* A place word missing from CMUdict ("washroom" is there; an on-site name such as "robolab" may not be) gets
  its spelling pronunciation only; with ``unknown="error"`` it is rejected instead, naming every such word.

The letter-to-sound rules are a deliberately small, documented approximation of English spelling (greedy
longest match over the table :data:`RULES`; a silent final "e" lengthening the vowel of a one-syllable word;
"c" before e/i/y and a final "-ge" read soft; doubled consonants read once); they are a fallback, not a
grapheme-to-phoneme model. Kept rather than a registry package: g2p-en (last release December 2019) fetches NLTK
data at first use, which a robot without network cannot, and gruut gives IPA, not the acoustic model's ARPAbet.
"""

from __future__ import annotations

import re
from collections.abc import Callable

# 39 ARPAbet phones of the CMU en-us acoustic model
PHONES = frozenset(
    [
        "AA",
        "AE",
        "AH",
        "AO",
        "AW",
        "AY",
        "B",
        "CH",
        "D",
        "DH",
        "EH",
        "ER",
        "EY",
        "F",
        "G",
        "HH",
        "IH",
        "IY",
        "JH",
        "K",
        "L",
        "M",
        "N",
        "NG",
        "OW",
        "OY",
        "P",
        "R",
        "S",
        "SH",
        "T",
        "TH",
        "UH",
        "UW",
        "V",
        "W",
        "Y",
        "Z",
        "ZH",
    ]
)

RULES: tuple[tuple[str, str], ...] = (
    ("tion", "SH AH N"),
    ("sion", "ZH AH N"),
    ("ough", "AO"),
    ("augh", "AO"),
    ("eigh", "EY"),
    ("igh", "AY"),
    ("tch", "CH"),
    ("dge", "JH"),
    ("sch", "S K"),
    ("sh", "SH"),
    ("ch", "CH"),
    ("th", "TH"),
    ("ph", "F"),
    ("ng", "NG"),
    ("ck", "K"),
    ("qu", "K W"),
    ("wh", "W"),
    ("kn", "N"),
    ("wr", "R"),
    ("gh", "G"),
    ("ee", "IY"),
    ("ea", "IY"),
    ("oo", "UW"),
    ("ou", "AW"),
    ("ow", "OW"),
    ("ai", "EY"),
    ("ay", "EY"),
    ("oi", "OY"),
    ("oy", "OY"),
    ("au", "AO"),
    ("aw", "AO"),
    ("ew", "UW"),
    ("ie", "IY"),
    ("ei", "EY"),
    ("oa", "OW"),
    ("ue", "UW"),
    ("er", "ER"),
    ("ir", "ER"),
    ("ur", "ER"),
    ("ar", "AA R"),
    ("or", "AO R"),
    ("a", "AE"),
    ("b", "B"),
    ("c", "K"),
    ("d", "D"),
    ("e", "EH"),
    ("f", "F"),
    ("g", "G"),
    ("h", "HH"),
    ("i", "IH"),
    ("j", "JH"),
    ("k", "K"),
    ("l", "L"),
    ("m", "M"),
    ("n", "N"),
    ("o", "AA"),
    ("p", "P"),
    ("q", "K"),
    ("r", "R"),
    ("s", "S"),
    ("t", "T"),
    ("u", "AH"),
    ("v", "V"),
    ("w", "W"),
    ("x", "K S"),
    ("y", "IH"),
    ("z", "Z"),
)
"""Grapheme -> phones, longest grapheme first (the first match at a position wins)."""
_LONG = {
    "a": "EY",
    "e": "IY",
    "i": "AY",
    "o": "OW",
    "u": "UW",
    "y": "AY",
}  # vowel before consonant + silent e
_SOFT = {"c": "S", "g": "JH"}  # before e, i, y
_VOWELS = set("aeiouy")
SPEAKABLE = re.compile(r"[a-z]+(?:'[a-z]+)*")
"""Words the English recogniser can take: lower-case Latin letters, with inner apostrophes."""


def letter_to_sound(word: str) -> str:
    """A spelling pronunciation of ``word`` as space-separated ARPAbet phones (rules in the module docstring).

    >>> letter_to_sound("corridor")
    'K AO R IH D AO R'
    >>> letter_to_sound("robolab")
    'R AA B AA L AE B'
    """
    w = word.lower().replace("'", "")
    if not w.isascii() or not w.isalpha():
        raise ValueError(f"cannot spell {word!r}: only the letters a-z are supported")
    w = re.sub(r"([b-df-hj-np-tv-z])\1", r"\1", w)  # doubled consonants are read once
    silent_e = len(w) > 2 and w[-1] == "e" and w[-2] not in _VOWELS
    # c before e, i, y reads S ("entrance", "office"); g only in a final "-ge" reads JH ("storage")
    soft = {
        i
        for i in range(len(w) - 1)
        if (w[i] == "c" and w[i + 1] in "eiy") or (w[i] == "g" and silent_e and i == len(w) - 2)
    }
    # in a one-syllable word a silent final e lengthens the vowel before its consonant ("white", "rote")
    one_vowel = len(re.findall(r"[aeiouy]+", w[:-1])) == 1
    long_vowel = (
        len(w) - 3 if (silent_e and one_vowel and len(w) > 3 and w[-3] in _VOWELS and w[-4] not in _VOWELS) else -1
    )
    if silent_e:
        w = w[:-1]
    phones: list[str] = []
    i = 0
    while i < len(w):
        ch = w[i]
        if i == long_vowel:
            phones.append(_LONG[ch])
        elif i in soft:
            phones.append(_SOFT[ch])
        elif ch == "y" and i == 0:
            phones.append("Y")
        elif ch == "y" and i == len(w) - 1:
            phones.append("IY")
        else:
            for graphemes, out in RULES:
                if w.startswith(graphemes, i):
                    phones.extend(out.split())
                    i += len(graphemes) - 1
                    break
        i += 1
    return " ".join(phones)


def dictionary_pronunciations(word: str, lookup: Callable[[str], str | None]) -> list[str]:
    """CMUdict's pronunciations of ``word``: ``lookup`` (the decoder's ``lookup_word``) asked for ``word``,
    ``word(2)``, ``word(3)``, ... until one is missing."""
    found = []
    name, k = word, 1
    while (phones := lookup(name)) is not None:
        found.append(phones)
        k += 1
        name = f"{word}({k})"
    return found

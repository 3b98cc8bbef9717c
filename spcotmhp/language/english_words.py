"""English words as lemminflect's dictionary knows them (the source the place words' noun lemmas already come from):
their parts of speech and lemmas, one home for talk (:mod:`spcotmhp.language.talk`), asides
(:mod:`spcotmhp.language.asides_en`) and refusals (:mod:`spcotmhp.language.errors`).

>>> infinitive("go"), infinitive("went"), known("kichen")
(True, False, False)
>>> lemma("scooting", "VERB"), base("baby's")
('scoot', 'baby')
"""

from __future__ import annotations

import functools

CONTRACTIONS = ("'s", "'re", "'m", "'ll", "'d", "'ve", "n't")


@functools.lru_cache(maxsize=4096)
def pos(word: str) -> dict[str, tuple[str, ...]]:
    """lemminflect's lemmas of ``word`` by universal part of speech (NOUN, VERB, ADJ, ADV, AUX, ...); empty when
    the dictionary does not hold the word."""
    import lemminflect

    return dict(lemminflect.getAllLemmas(word))


def infinitive(word: str) -> bool:
    """Whether ``word`` is a verb's base form ("go", not "went")."""
    return word in pos(word).get("VERB", ())


def known(word: str) -> bool:
    """A word of lemminflect's dictionary (a misspelt place word is not: "kichen")."""
    return bool(pos(word))


def lemma(word: str, upos: str) -> str | None:
    """The lemma of ``word`` as a ``upos`` ("scooting" -> "scoot" as a VERB), None when it is no such word."""
    lemmas = pos(word).get(upos, ())
    return lemmas[0] if lemmas else None


def base(word: str) -> str:
    """A word without its contraction ("baby's" -> "baby", "we're" -> "we")."""
    for c in CONTRACTIONS:
        if word.endswith(c) and len(word) > len(c):
            return word[: -len(c)]
    return word

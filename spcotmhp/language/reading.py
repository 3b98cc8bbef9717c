"""Reading an instruction: its tokens (:mod:`spcotmhp.language.lexicon`) parsed by the grammar of its language
(``grammars/<lang>.lark``: LALR(1) with no conflict, so a sentence has one derivation or none), the derivation read
into a :class:`~spcotmhp.language.meaning.Reading` (:mod:`spcotmhp.language.walk_en`,
:mod:`spcotmhp.language.walk_ja`), and a sentence with no derivation refused naming the first word that could not
be placed (:mod:`spcotmhp.language.errors`).

>>> r = read("go to the bedroom closest to the bath via the corridor, slowly", ["bath", "bedroom", "corridor"], "en")
>>> [p.describe() for p in r.visit], r.speed
(['corridor', 'bedroom (closest to the bath)'], 'slow')
>>> [p.label for p in read("廊下を通って風呂に一番近い寝室へ", ["廊下", "風呂", "寝室"], "ja").visit]
['廊下', '寝室']
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from importlib import resources

from lark import Lark
from lark import Token as LarkToken
from lark.exceptions import UnexpectedInput

from spcotmhp.errors import EmptyInstruction
from spcotmhp.language.errors import refusal
from spcotmhp.language.lexicon import tokens, word_table
from spcotmhp.language.meaning import Reading
from spcotmhp.language.walk_en import EnglishWalk
from spcotmhp.language.walk_ja import JapaneseWalk

LANGUAGES = ("en", "ja")
"""Languages with a grammar (``grammars/<lang>.lark`` and ``grammars/<lang>.json``)."""
_WALKS = {"en": EnglishWalk, "ja": JapaneseWalk}


@functools.cache
def grammar(lang: str) -> Lark:
    """The LALR(1) parser of ``grammars/<lang>.lark``, built once per process (Lark refuses reduce/reduce
    conflicts; ``tests/language/test_reading.py`` checks there is no shift/reduce conflict either)."""
    text = (resources.files("spcotmhp.language") / "grammars" / f"{lang}.lark").read_text(encoding="utf-8")
    return Lark(text, parser="lalr", lexer="basic")  # type: ignore[arg-type]  # lark's stub lacks "basic"


def read(text: str, place_words: Sequence[str], lang: str) -> Reading:
    """The meaning of ``text``; raises an :class:`~spcotmhp.errors.InstructionError` saying what was not
    understood (module docstring)."""
    if not text.strip():
        raise EmptyInstruction("the instruction is empty; say where to go, e.g. 'go to the kitchen'")
    table = word_table(lang)
    toks = tokens(text, table, place_words)
    interactive = grammar(lang).parse_interactive("")
    try:
        for i, t in enumerate(toks):
            interactive.feed_token(LarkToken(t.kind, t.surface, start_pos=i))
        root = interactive.feed_eof()
    except UnexpectedInput as exc:
        raise refusal(toks, getattr(exc, "token", None), table, place_words, text) from None
    return _WALKS[lang](toks, text, table).read(root)

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
import hashlib
import json
from collections.abc import Sequence
from dataclasses import replace
from importlib import resources
from pathlib import Path
from typing import Any, cast

from lark import Lark, Tree
from lark import Token as LarkToken

from spcotmhp.errors import EmptyInstruction, InstructionError
from spcotmhp.language.asides_en import ease_en
from spcotmhp.language.errors import refusal
from spcotmhp.language.lexicon import english_units, tokens
from spcotmhp.language.meaning import Reading
from spcotmhp.language.repairs_en import owner_names
from spcotmhp.language.rewrite_ja import may_pause, pauses_ja
from spcotmhp.language.spoken_ja import spoken_text
from spcotmhp.language.table import word_table
from spcotmhp.language.talk import pass_over
from spcotmhp.language.talk_ja import plain_verbs
from spcotmhp.language.text import normalise
from spcotmhp.language.walk_en import EnglishWalk
from spcotmhp.language.walk_ja import JapaneseWalk
from spcotmhp.language.wording import excerpt

LANGUAGES = ("en", "ja")
"""Languages with a grammar (``grammars/<lang>.lark`` and ``grammars/<lang>.json``)."""
_WALKS = {"en": EnglishWalk, "ja": JapaneseWalk}


@functools.cache
def grammar(lang: str) -> Lark:
    """The LALR(1) parser of ``grammars/<lang>.lark``, built once per process (Lark refuses reduce/reduce
    conflicts; ``tests/language/test_reading.py`` checks there is no shift/reduce conflict either)."""
    return Lark(_source(lang), parser="lalr", lexer="basic")  # type: ignore[arg-type]  # lark's stub lacks "basic"


def read(text: str, place_words: Sequence[str], lang: str) -> Reading:
    """The meaning of ``text``; raises an :class:`~spcotmhp.errors.InstructionError` saying what was not
    understood (module docstring)."""
    if not text.strip():
        raise EmptyInstruction("the instruction is empty; say where to go, e.g. 'go to the kitchen'")
    table = word_table(lang)
    spoken = pauses_ja(normalise(text)) if table.by_character and may_pause(text) else text  # rewrite_ja
    if table.by_character:
        spoken = spoken_text(spoken, table, place_words)  # spoken_ja: rooms by contents, requests said as thanks
    toks = tokens(spoken, table, place_words)
    try:
        root = _shape(lang, tuple(t.kind for t in toks))  # read-only: the walks take each leaf's words from toks
        return _WALKS[lang](toks, text, table).read(root)
    except _NoDerivation as exc:
        first, said_as = exc.at, toks
    except InstructionError:
        if lang == "en" and (again := _restarted(toks, english_units(text), place_words)) is not None:
            return again
        raise
    # no derivation as said: Japanese verb endings in their plain form, then talk passed over (talk.py, talk_ja.py)
    source: Sequence[str] = english_units(text) if lang == "en" else normalise(spoken)  # what the tokens index
    if table.by_character:
        plain_text = plain_verbs(normalise(spoken), table)
        plain = tokens(plain_text, table, place_words)
        if [t.kind for t in plain] != [t.kind for t in toks]:
            try:
                return _WALKS[lang](plain, text, table).read(_shape(lang, tuple(t.kind for t in plain)))
            except _NoDerivation:
                pass
            toks, source = plain, plain_text
    eased: list[str] = []
    notes: list[str] = []
    if lang == "en" and (again := _restarted(toks, source, place_words)) is not None:
        return again
    if lang == "en" and (asides := ease_en(toks, table, source, place_words)) is not None:  # asides_en.py
        toks, eased, notes = asides
        try:
            reading = _WALKS[lang](toks, text, table).read(_shape(lang, tuple(t.kind for t in toks)))
            return _heard(reading, eased, notes)
        except _NoDerivation:
            pass
    people = owner_names(place_words) if lang == "en" else frozenset()
    passed = pass_over(toks, table, source, people)
    if passed is not None:
        kept, said = passed
        try:
            root = _shape(lang, tuple(t.kind for t in kept))
        except _NoDerivation as again:
            raise _refused(kept, again.at, table, place_words, text) from None
        return _heard(_WALKS[lang](kept, text, table).read(root), [*eased, *said], notes)
    raise _refused(said_as, first, table, place_words, text) from None  # the words as said, not their plain form


_RESTARTS = frozenset({"scratch that", "change of plan", "let me rephrase", "on second thought", "on second thoughts",
                       "hang on", "hold on", "no hang on", "hang on no", "no hold on", "hold on no"})  # fmt: skip
"""Corrections that take back all that was said before them (with the CANCEL class: "never mind", "forget that")."""


def _restarted(toks: Sequence[Any], units: Sequence[str], place_words: Sequence[str]) -> Reading | None:
    """A sentence said again after taking all of it back: "go to the kitchen, oh never mind, go to the living room",
    "Head to the toilet. Oh, hang on, the storeroom instead", "kitchen. no. living room.": after the last word that
    cancels (or a "no" said alone between full stops), a part that reads on its own with a place to go to is the
    instruction, and what came before it is taken back (said in the explanation). "forget the kitchen, ..." takes
    back its place too; a place said right after "forget" with nothing after it ("go to the bath and forget the
    kitchen") is what is taken back, so no restart ("go to the kitchen nvm the lounge" restarts: writers say so).
    Anything else (nothing to go to after it: "never mind, the kitchen's fine") stays refused."""
    fillers = word_table("en").fillers
    marks = [
        k for k, t in enumerate(toks)
        if t.kind == "CANCEL" or " ".join(w for w in t.surface.split() if w not in fillers) in _RESTARTS
        or t.kind in ("NO", "CORRECTION") and _alone(toks, k)
    ]  # fmt: skip
    if not marks or not any(t.kind == "PLACE" for t in toks[: marks[-1]]):
        return None
    k = marks[-1] + 1
    while k < len(toks) and toks[k].kind in ("COMMA", "_STOP", "IT", "THAT", "CORRECTION", "NO"):
        k += 1  # "never mind that,", "hang on, no,"
    j = marks[-1] + 1  # "forget the kitchen, go to the washroom": the place right after it is taken back too
    taken = toks[marks[-1]].kind == "CANCEL" and j < len(toks) and toks[j].kind == "PLACE"
    if (
        taken
        and j + 1 < len(toks)
        and toks[j + 1].kind in ("COMMA", "_STOP")
        and any(t.kind == "PLACE" for t in toks[j + 2 :])
    ):
        k = j + 2
    elif taken and toks[marks[-1]].surface.startswith("forget"):
        return None  # "go to the bath and forget the kitchen": the place is taken back, not the one to go to
    if k >= len(toks) or not any(t.kind == "PLACE" for t in toks[k:]):
        return None
    rest = " ".join(units[toks[k].start :])
    try:
        reading = read(rest, place_words, "en")
    except InstructionError:
        return None
    if not reading.visit:
        return None
    said = " ".join(w for t in toks[: marks[-1] + 1] for w in t.surface.split() if w not in fillers)  # as read
    return replace(reading, heard=(f"took back {excerpt(said)}", *reading.heard))


def _alone(toks: Sequence[Any], k: int) -> bool:
    """Whether ``toks[k]`` is a part of its own: between full stops or the sentence's edges ("kitchen. no. ...")."""
    before = k == 0 or toks[k - 1].kind == "_STOP"
    after = k + 1 == len(toks) or toks[k + 1].kind == "_STOP"
    return before and after


def _heard(reading: Reading, said: Sequence[str], notes: Sequence[str] = ()) -> Reading:
    """``reading`` noting the talk passed over to read it and what else was eased (the plan's explanation says
    it)."""
    heard = (*notes, *(f"passed over {excerpt(t)} (no navigation meaning)" for t in said))
    return replace(reading, heard=(*heard, *reading.heard)) if heard else reading


def _refused(toks: list, at: int, table: Any, place_words: Sequence[str], text: str) -> Exception:
    bad = LarkToken(toks[at].kind, toks[at].surface, start_pos=at) if at < len(toks) else None
    return refusal(toks, bad, table, place_words, text)


class _NoDerivation(Exception):
    """The grammar accepts no sentence with the tokens read so far and ``kinds[at]`` next (``at == len``: the end)."""

    def __init__(self, at: int) -> None:
        self.at = at


def derive(lang: str, kinds: Sequence[str], values: Sequence[str]) -> Tree:
    """The derivation of a token sequence (:func:`_shape`) with each token's value at its leaf: the shape of a
    derivation depends on the terminals alone, so it is kept per terminal sequence (a bounded cache; ordinary
    instructions share a few shapes whichever places and words they say) and filled with this sentence's values.

    Raises:
        _NoDerivation: at the first token (or the end) the table has no action for.
    """
    return _filled(_shape(lang, tuple(kinds)), values)


def _filled(node: Tree, values: Sequence[str]) -> Tree:
    """A copy of the shape ``node`` with the value of token i at each leaf of index i (the shapes stay unchanged)."""
    children: list[Any] = []
    for c in node.children:
        if isinstance(c, LarkToken):
            children.append(LarkToken(c.type, values[c.start_pos or 0], start_pos=c.start_pos))
        else:
            children.append(_filled(cast(Tree, c), values))
    return Tree(node.data, children)


@functools.lru_cache(maxsize=1024)
def _shape(lang: str, kinds: tuple[str, ...]) -> Tree:
    """The derivation of a terminal sequence by the LALR(1) table of ``grammar(lang)``: the tree Lark itself builds
    (rules named with ``_`` inlined into their parent, terminals named with ``_`` left out, aliases as names), by a
    driver that only shifts and reduces (Lark's own per-token parser state costs several times more, which a plan
    would pay on every instruction). Tokens carry their index as ``start_pos``.

    Raises:
        _NoDerivation: at the first token (or the end) the table has no action for.
    """
    states, start, end, rules = _table(lang)
    state_stack: list[int] = [start]
    value_stack: list[Any] = []
    for i in range(len(kinds) + 1):
        kind = kinds[i] if i < len(kinds) else "$END"
        while True:
            action = states[state_stack[-1]].get(kind)
            if action is None:
                raise _NoDerivation(i)
            shift, arg = action
            if shift:
                if kind == "$END":  # pragma: no cover - the end is accepted by a reduction into the end state
                    break
                state_stack.append(arg)
                value_stack.append(None if kind.startswith("_") else LarkToken(kind, "", start_pos=i))
                break
            name, size, inline, origin = rules[arg]
            popped = value_stack[len(value_stack) - size :] if size else []
            if size:
                del state_stack[-size:]
                del value_stack[-size:]
            children: list = []
            for v in popped:
                if type(v) is list:
                    children.extend(v)
                elif v is not None:
                    children.append(v)
            value = children if inline else Tree(name, children)
            goto = states[state_stack[-1]][origin]
            state_stack.append(goto[1])
            value_stack.append(value)
            if kind == "$END" and state_stack[-1] == end:
                return cast(Tree, value_stack[-1])
    raise _NoDerivation(len(kinds))  # pragma: no cover - the table accepts or refuses before


@functools.cache
def _table(lang: str) -> tuple[dict, int, int, dict]:
    """The LALR(1) table of ``grammar(lang)`` as plain dictionaries (:func:`build_table`): read from
    ``grammars/<lang>.table.json`` when that file was written from the grammar as it is (its SHA-256 says so; about
    30 times faster than building the table, which every process's first instruction would pay), else built."""
    source = _source(lang)
    path = resources.files("spcotmhp.language") / "grammars" / f"{lang}.table.json"
    try:
        stored = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        stored = None
    if not isinstance(stored, dict) or stored.get("source_sha256") != hashlib.sha256(source.encode()).hexdigest():
        return build_table(lang)
    states = {int(k): {sym: (bool(a[0]), int(a[1])) for sym, a in row.items()} for k, row in stored["states"].items()}
    rules = {i: (str(r[0]), int(r[1]), bool(r[2]), str(r[3])) for i, r in enumerate(stored["rules"])}
    return states, int(stored["start"]), int(stored["end"]), rules


def build_table(lang: str) -> tuple[dict, int, int, dict]:
    """The LALR(1) table Lark builds from ``grammars/<lang>.lark``: state -> {terminal or rule name: (shift?, next
    state or rule id)}, the start and end states, rule id -> (tree name, size, inlined?, origin)."""
    from lark.parsers.lalr_analysis import Shift

    lalr = cast(Any, grammar(lang)).parser.parser.parser  # lark's LALR _Parser: its parse table
    table = lalr.parse_table
    rule_ids: dict = {}
    rules: dict[int, tuple[str, int, bool, str]] = {}
    states: dict[int, dict[str, tuple[bool, int]]] = {}
    for state, actions in table.states.items():
        row: dict[str, tuple[bool, int]] = {}
        for sym, (action, arg) in actions.items():
            if action is Shift:
                row[sym] = (True, arg)
            else:
                rid = rule_ids.setdefault(arg, len(rule_ids))
                origin = str(arg.origin.name)
                name = str(arg.alias or origin)
                rules[rid] = (name, len(arg.expansion), origin.startswith("_") and not arg.alias, origin)
                row[sym] = (False, rid)
        states[state] = row
    return states, table.start_states["start"], table.end_states["start"], rules


def table_json(lang: str) -> str:
    """The text of ``grammars/<lang>.table.json``: :func:`build_table` with the SHA-256 of the grammar it is of
    (``python -m spcotmhp.language.reading`` writes both; a test checks they are current)."""
    states, start, end, rules = build_table(lang)
    body = {
        "source_sha256": hashlib.sha256(_source(lang).encode()).hexdigest(),
        "start": start,
        "end": end,
        "rules": [list(rules[i]) for i in range(len(rules))],
        "states": {str(k): {sym: [int(a[0]), a[1]] for sym, a in row.items()} for k, row in states.items()},
    }
    return json.dumps(body, separators=(",", ":"), sort_keys=True) + "\n"


def _source(lang: str) -> str:
    return (resources.files("spcotmhp.language") / "grammars" / f"{lang}.lark").read_text(encoding="utf-8")


if __name__ == "__main__":  # python -m spcotmhp.language.reading: write the tables of the grammars
    for _lang in LANGUAGES:
        target = Path(__file__).with_name("grammars") / f"{_lang}.table.json"
        target.write_text(table_json(_lang), encoding="utf-8")
        print(f"wrote {target}")
